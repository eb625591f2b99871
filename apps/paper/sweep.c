/* Load sweeps: one body on the study's surface, loads rising, each relaxation continuing from the
 * previous equilibrium. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>

#include "study.h"

/* Loads: those at which Persson's theory predicts these areas for each body, so every body is
 * swept over the same range of contact area although the loads differ by orders of magnitude. */
static const double AREA_GRID[] = {0.004, 0.008, 0.016, 0.03, 0.05, 0.08, 0.12, 0.18, 0.27, 0.4};
enum { N_LOADS = (int)(sizeof AREA_GRID / sizeof AREA_GRID[0]) };


long long sweep_steps(const sweep *s) {
    long long n = 0;
    for (int k = 0; k < s->n; ++k) n += s->p[k].steps;
    return n;
}

double sweep_seconds(const sweep *s) {
    double t = 0.0;
    for (int k = 0; k < s->n; ++k) t += s->p[k].seconds;
    return t;
}

/* A sweep's printed block, in pieces (printed as the loads relax) or whole (a body read back from
 * its checkpoint, resume.c): the same text either way. */
void print_sweep_head(FILE *log, double W, int adhesive) {
    fprintf(log, "\n%s%s, W = w/lambda_s = %g\n", W > 0 ? "layer on a fluid foundation" : "half-space",
            adhesive ? " with adhesion" : "", W);
    fprintf(log, "%12s %10s %10s %10s %12s %12s %7s %7s\n", "sigma0/E*g", "A/A0", "Persson", "s", "U_el", "U_ad", "steps",
            "seconds");
}

void print_point(FILE *log, const point *p) {
    fprintf(log, "%12.4e %10.5f %10.5f %10.5f %12.5e %12.5e %7lld %7.2f\n", p->sigma0 / (E_STAR * GRADIENT), p->area,
            p->persson, p->sep, p->u_el, p->u_ad, p->steps, p->seconds);
}

void print_sweep_tail(FILE *log, const sweep *s, int levels) {
    fprintf(log, "this body: %lld steps, %.2f s; its first load (%s) %lld steps, %.2f s\n", sweep_steps(s), sweep_seconds(s),
            levels > 1 ? "from coarser grids" : "from flat", s->p[0].steps, s->p[0].seconds);
}

void print_sweep(FILE *log, const sweep *s, int adhesive, int levels) {
    print_sweep_head(log, s->W, adhesive);
    for (int k = 0; k < s->n; ++k) print_point(log, &s->p[k]);
    print_sweep_tail(log, s, levels);
}

/* The shared surface is one handle: one thread at a time may use it (gfmd.h's thread contract),
 * and the bodies' threads clone it as they start. */
static pthread_mutex_t surface_lock = PTHREAD_MUTEX_INITIALIZER;

gfmd_sim *make_body(const gfmd_sim *surface, double W, int32_t solver) {
    gfmd_sim *s = NULL;
    pthread_mutex_lock(&surface_lock);
    const int32_t st = gfmd_sim_clone(surface, &s);
    pthread_mutex_unlock(&surface_lock);
    CHECK(surface, st);
    CHECK(s, gfmd_set_solver(s, solver));
    if (W > 0.0) CHECK(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, W * LAMBDA_S));
    return s;
}

void sweep_load_range(const gfmd_sim *body, double *first, double *last) {
    CHECK(body, gfmd_persson_load(body, AREA_GRID[0], first));
    CHECK(body, gfmd_persson_load(body, AREA_GRID[N_LOADS - 1], last));
}

/* Relax to the default tolerance: first (--approach) at most o->approach mass-weighted FIRE steps,
 * then the sweep's solver from there; steps counts both. */
static void relax_with_approach(gfmd_sim *s, int32_t solver, const options *o, int64_t *steps) {
    int64_t first = 0, rest = 0;
    if (o->approach > 0) {
        CHECK(s, gfmd_set_solver(s, GFMD_SOLVER_MASS_WEIGHTED_FIRE));
        const int32_t st = gfmd_relax(s, 0.0, o->approach, &first);
        if (st != GFMD_ERR_NOT_CONVERGED) CHECK(s, st);
        CHECK(s, gfmd_set_solver(s, solver));
    }
    CHECK(s, gfmd_relax(s, 0.0, 2000000, &rest));
    *steps = first + rest;
}

void run_sweep(const gfmd_sim *surface, double W, int adhesive, double u_max, const options *o, sweep *out,
               FILE *log) {
    const int levels = o->levels;
    gfmd_sim *s = make_body(surface, W, o->solver);
    if (adhesive) CHECK(s, gfmd_set_adhesion(s, GAMMA0, RHO));
    out->W = W;
    out->n = N_LOADS;
    print_sweep_head(log, W, adhesive);
    for (int k = 0; k < N_LOADS; ++k) {
        point *p = &out->p[k];
        p->W = W;
        CHECK(s, gfmd_persson_load(s, AREA_GRID[k], &p->sigma0)); /* untimed: one FFT of h */
        int64_t steps = 0;
        const double t0 = now();
        CHECK(s, gfmd_set_pressure(s, p->sigma0));
        if (k == 0 && levels > 1) { /* the first load starts flat: from coarser grids (--multilevel) */
            int64_t coarse = 0;
            CHECK(s, gfmd_relax_multilevel(s, 0.0, 2000000, levels, &steps, &coarse));
        } else {
            relax_with_approach(s, o->solver, o, &steps);
        }
        p->seconds = now() - t0;
        p->steps = (long long)steps;
        CHECK(s, gfmd_get_contact_area(s, &p->area));
        CHECK(s, gfmd_persson_contact_area(s, p->sigma0, &p->persson));
        CHECK(s, gfmd_get_mean_gap(s, &p->gap));
        CHECK(s, gfmd_get_energies(s, &p->u_el, &p->u_ad));
        p->sep = p->gap / u_max; /* s = 1 - <u>/u_max = mean gap / (max h - <h>) */
        print_point(log, p);
        fflush(log);
    }
    print_sweep_tail(log, out, levels);
    gfmd_sim_destroy(&s);
}
