/* Pull-off of the adhesive sheets of Fig. 7 (same surface, gamma0, rho): the figure a reader of the
 * paper asks for next.  Each sheet's mean position is stepped down into contact and back up until
 * it has come off, under displacement control, every step relaxed from the last; the pull-off
 * stress is the most tensile mean pressure on the way back, resolved to the step. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "study.h"

/* Down from 2 rho above the highest peak to a third of the way to the mean height in PULL_STEPS
 * steps, back up with the same step to the start; a sheet that still touches there peels on, and
 * the step then grows by PEEL_GROWTH per step (a thin sheet peels over many times the roughness),
 * for at most PEEL_STEPS more. */
enum { PULL_STEPS = 12, PEEL_STEPS = 40 };
#define PEEL_GROWTH 1.25

static double highest(const gfmd_sim *s) {
    int64_t nx = 0, ny = 0;
    CHECK(s, gfmd_get_grid(s, &nx, &ny, NULL, NULL));
    double *h = malloc(sizeof(double) * (size_t)(nx * ny));
    if (!h) die(NULL, GFMD_ERR_NOMEM, "heights");
    CHECK(s, gfmd_get_heights(s, h));
    double top = -INFINITY;
    for (int64_t i = 0; i < nx * ny; ++i) top = fmax(top, h[i]);
    free(h);
    return top;
}

/* Prescribes the mean position d, relaxes, adds the step to the record; returns A/A0. */
static double relax_at(gfmd_sim *s, double d, int loading, pulloff *out) {
    int64_t taken = 0;
    double p = 0.0, a = 0.0;
    CHECK(s, gfmd_set_mean_displacement(s, d));
    CHECK(s, gfmd_relax(s, 0.0, 10000000, &taken));
    CHECK(s, gfmd_get_mean_pressure(s, &p));
    CHECK(s, gfmd_get_contact_area(s, &a));
    out->steps += (long long)taken;
    ++out->points;
    if (loading) out->area_max = fmax(out->area_max, a);
    else out->pull_off = fmin(out->pull_off, p);
    printf("%8s %10.4f %14.6e %10.5f %8lld\n", loading ? "load" : "unload", d, p, a, (long long)taken);
    fflush(stdout);
    return a;
}

void run_pulloff(const gfmd_sim *surface, double W, double u_max, int32_t solver, pulloff *out) {
    gfmd_sim *s = make_body(surface, W, solver);
    CHECK(s, gfmd_set_adhesion(s, GAMMA0, RHO));
    const double hmax = highest(s);
    const double top = hmax + 2.0 * RHO, bottom = hmax - u_max / 3.0, dz = (top - bottom) / PULL_STEPS;
    *out = (pulloff){W, INFINITY, 0.0, 0.0, 0.0, 0, 0, 0};
    const double t0 = now();
    printf("\npull-off, W = %g: mean z from %.3f down to %.3f and back, step %.3f\n", W, top, bottom, dz);
    printf("%8s %10s %14s %10s %8s\n", "branch", "mean z", "mean pressure", "A/A0", "steps");
    for (int k = 0; k <= PULL_STEPS; ++k) relax_at(s, top - k * dz, 1, out);
    double a = 1.0, d = bottom, step = dz;
    for (int k = 1; k <= PULL_STEPS; ++k) a = relax_at(s, d = bottom + k * dz, 0, out);
    for (int k = 0; k < PEEL_STEPS && a > 0.0; ++k) {
        step *= PEEL_GROWTH;
        a = relax_at(s, d += step, 0, out);
    }
    out->detached = (a == 0.0);
    out->lift = d - top;
    out->seconds = now() - t0;
    printf("pull-off stress %.4e E* = %.4f gamma0/rho (%s at %.3g above the start), %lld relaxation steps, %.1f s\n",
           out->pull_off, out->pull_off / (GAMMA0 / RHO), out->detached ? "came off" : "still touching", out->lift,
           out->steps, out->seconds);
    gfmd_sim_destroy(&s);
}
