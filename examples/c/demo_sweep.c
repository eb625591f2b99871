/* gfmd demonstration: a self-affine substrate pressed by an elastic half-space and by thin layers
 * on a fluid foundation, the load stepped up, each step continuing from the last equilibrium.
 *
 *   gfmd_demo [--n N] [--csv FILE] [--loads K]
 *
 * Prints per load: sigma0/(E* g), A/A0, mean gap, U_el, steps and seconds; writes the same as CSV
 * (columns: body,W,sigma0_over_Eg,rel_area,mean_gap,u_el,steps,seconds). */
#include <gfmd.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int check(gfmd_sim *s, int32_t st, const char *what) {
    if (st == GFMD_OK) return 0;
    char msg[256] = "";
    if (s) gfmd_last_error(s, msg, sizeof msg);
    fprintf(stderr, "%s failed: %s: %s\n", what, gfmd_status_string(st), msg);
    return 1;
}

int main(int argc, char **argv) {
    long n = 256, nloads = 10;
    const char *csv_path = "demo.csv";
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--n") && i + 1 < argc) n = strtol(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--csv") && i + 1 < argc) csv_path = argv[++i];
        else if (!strcmp(argv[i], "--loads") && i + 1 < argc) nloads = strtol(argv[++i], NULL, 10);
        else {
            fprintf(stderr, "usage: %s [--n N] [--csv FILE] [--loads K]\n", argv[0]);
            return 2;
        }
    }
    if (n < 32 || nloads < 2) {
        fprintf(stderr, "need --n >= 32 and --loads >= 2\n");
        return 2;
    }
    /* The seed paper's surface (Putignano, Dapp & Mueser 2016): H = 0.8, lambda_s = 4 a,
     * lambda_r = L/8, rms gradient g = 1, E* = 1, uniform random amplitudes. */
    const double a = 1.0, l = (double)n * a, lambda_s = 4.0 * a, lambda_r = l / 8.0, g = 1.0;
    const double widths_w[] = {0.0, 4.0, 1.0}; /* W = w / lambda_s; 0 = half-space */
    FILE *csv = fopen(csv_path, "w");
    if (!csv) {
        perror(csv_path);
        return 1;
    }
    fprintf(csv, "body,W,sigma0_over_Eg,rel_area,mean_gap,u_el,steps,seconds\n");
    printf("gfmd %s demo: %ldx%ld grid, H = 0.8, lambda_s = %.0f a, lambda_r = %.0f a, g = %.1f, E* = 1\n",
           gfmd_version(), n, n, lambda_s, lambda_r, g);
    for (int b = 0; b < 3; ++b) {
        const double W = widths_w[b];
        gfmd_sim *s = NULL;
        if (check(NULL, gfmd_sim_create(n, n, l, l, &s), "create")) return 1;
        if (check(s, gfmd_generate_selfaffine(s, 0.8, lambda_r, lambda_s, g, 2016, GFMD_DIST_UNIFORM), "substrate"))
            return 1;
        if (W > 0.0 && check(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, W * lambda_s), "green")) return 1;
        if (W > 0.0)
            printf("\nlayer on a fluid foundation, W = w/lambda_s = %g\n", W);
        else
            printf("\nhalf-space\n");
        printf("%12s %10s %10s %12s %7s %8s\n", "sigma0/E*g", "A/A0", "mean gap", "U_el", "steps", "seconds");
        for (long k = 0; k < nloads; ++k) {
            /* loads from 1e-3 to 0.3 E* g, logarithmically spaced */
            const double load = 1e-3 * pow(300.0, (double)k / (double)(nloads - 1));
            int64_t steps = 0;
            double area, gap, u_el, u_ad, t0 = now();
            if (check(s, gfmd_set_pressure(s, load * g), "pressure")) return 1;
            if (check(s, gfmd_relax(s, 0.0, 1000000, &steps), "relax")) return 1;
            double dt = now() - t0;
            gfmd_get_contact_area(s, &area);
            gfmd_get_mean_gap(s, &gap);
            gfmd_get_energies(s, &u_el, &u_ad);
            printf("%12.4e %10.5f %10.5f %12.5e %7lld %8.3f\n", load, area, gap, u_el, (long long)steps, dt);
            fprintf(csv, "%s,%g,%.8e,%.8e,%.8e,%.8e,%lld,%.4f\n", W > 0 ? "layer" : "halfspace", W, load, area, gap,
                    u_el, (long long)steps, dt);
        }
        gfmd_sim_destroy(&s);
    }
    fclose(csv);
    printf("\nwrote %s\n", csv_path);
    return 0;
}
