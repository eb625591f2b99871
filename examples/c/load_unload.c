/* Load, unload and pull-off under displacement control: a thin adhesive sheet (a layer on a fluid
 * foundation, W = w/lambda_s) pressed onto a self-affine substrate by prescribing the mean position
 * of its surface, stepped down into contact and back up until it comes off; each step relaxed from
 * the last.  Prints and writes (CSV) the mean pressure, A/A0, mean gap, U_el and U_ad of every
 * step, then the pull-off pressure (the most tensile mean pressure on retraction) and the
 * hysteresis (the work of the loop per area, sum of sigma dd around it).
 *
 *   gfmd_load_unload [--n 128] [--W 0.25] [--gamma0 5e-4] [--rho 1] [--steps 40] [--csv FILE]
 *
 * Surface: H = 0.8, lambda_s = 4a, lambda_r = n a/4, rms gradient 1, seed 1; E* = 1.
 * Plot: gnuplot -e "csv='load_unload.csv'" examples/load_unload.gp  -> load_unload.png */
#include <gfmd.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int check(gfmd_sim *s, int32_t st, const char *what) {
    if (st == GFMD_OK) return 0;
    char msg[256] = "";
    if (s) gfmd_last_error(s, msg, sizeof msg);
    fprintf(stderr, "gfmd_load_unload: %s failed: %s: %s\n", what, gfmd_status_string(st), msg);
    return 1;
}

int main(int argc, char **argv) {
    long n = 128, steps = 40;
    double W = 0.25, gamma0 = 5e-4, rho = 1.0;
    const char *csv = "load_unload.csv";
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--n") && i + 1 < argc) n = strtol(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--W") && i + 1 < argc) W = strtod(argv[++i], NULL);
        else if (!strcmp(argv[i], "--gamma0") && i + 1 < argc) gamma0 = strtod(argv[++i], NULL);
        else if (!strcmp(argv[i], "--rho") && i + 1 < argc) rho = strtod(argv[++i], NULL);
        else if (!strcmp(argv[i], "--steps") && i + 1 < argc) steps = strtol(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--csv") && i + 1 < argc) csv = argv[++i];
        else {
            fprintf(stderr, "usage: %s [--n N] [--W W] [--gamma0 G] [--rho R] [--steps K] [--csv FILE]\n", argv[0]);
            return 2;
        }
    }
    if (n < 16 || steps < 2 || !(W >= 0.0)) return 2;
    gfmd_sim *s = NULL;
    const double l = (double)n;
    if (check(NULL, gfmd_sim_create(n, n, l, l, &s), "create")) return 1;
    int bad = check(s, gfmd_generate_selfaffine(s, 0.8, l / 4.0, 4.0, 1.0, 1, GFMD_DIST_UNIFORM), "substrate");
    if (W > 0.0) bad |= check(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, W * 4.0), "green");
    bad |= check(s, gfmd_set_adhesion(s, gamma0, rho), "adhesion");
    double *h = malloc(sizeof(double) * (size_t)(n * n));
    if (bad || h == NULL || check(s, gfmd_get_heights(s, h), "heights")) return 1;
    double hmax = -INFINITY, hmean = 0.0;
    for (long i = 0; i < n * n; ++i) hmax = fmax(hmax, h[i]), hmean += h[i] / (double)(n * n);
    free(h);
    /* from 2 rho above the highest peak down to a third of the way to the mean height, and back */
    const double top = hmax + 2.0 * rho, bottom = hmax - (hmax - hmean) / 3.0;
    FILE *f = fopen(csv, "w");
    if (f == NULL) return 1;
    fprintf(f, "branch,mean_z,mean_pressure,rel_area,mean_gap,u_el,u_ad,steps\n");
    printf("gfmd %s: load-unload of a W = %g sheet, gamma0 = %g, rho = %g, %ldx%ld\n", gfmd_version(), W, gamma0, rho,
           n, n);
    printf("%8s %12s %14s %9s %10s %12s %12s %7s\n", "branch", "mean z", "mean pressure", "A/A0", "mean gap", "U_el",
           "U_ad", "steps");
    double pull_off = INFINITY, loop = 0.0, prev_d = NAN, prev_p = NAN;
    for (long k = 0; k <= 2 * steps && !bad; ++k) {
        const int loading = k <= steps;
        const double t = loading ? (double)k / (double)steps : (double)(2 * steps - k) / (double)steps;
        const double d = top + t * (bottom - top);
        int64_t taken = 0;
        double p = 0, a = 0, g = 0, el = 0, ad = 0;
        bad |= check(s, gfmd_set_mean_displacement(s, d), "mean displacement");
        bad |= check(s, gfmd_relax(s, 0.0, 10000000, &taken), "relax");
        bad |= check(s, gfmd_get_mean_pressure(s, &p), "mean pressure");
        gfmd_get_contact_area(s, &a);
        gfmd_get_mean_gap(s, &g);
        gfmd_get_energies(s, &el, &ad);
        if (!loading) pull_off = fmin(pull_off, p);
        if (k > 0) loop += 0.5 * (p + prev_p) * (prev_d - d); /* work done on the body per area */
        prev_d = d, prev_p = p;
        const char *branch = loading ? "load" : "unload";
        printf("%8s %12.6f %14.6e %9.5f %10.5f %12.5e %12.5e %7lld\n", branch, d, p, a, g, el, ad, (long long)taken);
        fprintf(f, "%s,%.10e,%.10e,%.10e,%.10e,%.10e,%.10e,%lld\n", branch, d, p, a, g, el, ad, (long long)taken);
    }
    fclose(f);
    gfmd_sim_destroy(&s);
    if (bad) return 1;
    printf("pull-off pressure (most tensile on retraction): %.6e E*\n", pull_off);
    printf("hysteresis (work of the loop per area, energy lost to the jumps): %.6e E* a\n", loop);
    return 0;
}
