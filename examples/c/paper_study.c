/* The seed paper's study (Putignano, Dapp & Mueser, Biomimetics 1, 7 (2016)) with the library:
 * load sweeps of a half-space and of layers on a fluid foundation pressed onto one self-affine
 * substrate, the collapse factor c(W), the separation, and the adhesive energy ratio theta.
 *
 *   gfmd_paper [--n N] [--bandwidth R] [--full | --quick] [--out DIR] [--seed S] [--threads T]
 *              [--no-adhesion] [--widths 0,W1,W2,...] [--solver fire|mass]
 *
 * Surface: H = 0.8, lambda_s = 4a, lambda_r = R lambda_s, cell L = N a (default N = 256, R = 32,
 * L = 2 lambda_r; --full: N = 2048, R = 64, L = 8 lambda_r as in the paper; --quick, the test's
 * mode: N = 128, R = 16, half of the bodies; options after --full/--quick override), g = 1,
 * E* = 1, uniform random amplitudes.  Every load step continues from the last equilibrium.
 * Writes CSV tables into DIR (one per figure, see docs/paper/README.md) and prints the fits:
 *   kappa      A/A0 = kappa sigma0/(E* g), least squares over the half-space points with A/A0 <= 0.1
 *   c(W)       A_W(sigma0) = A_hs(c(W) sigma0): the mean horizontal log-shift of each layer's
 *              points onto the half-space curve (least squares), then c ~ W^alpha for W <= 0.25
 *   theta      U_el/U_ad at three contact areas with adhesion, theta ~ W^beta for W <= 0.25
 * Fits use gfmd_least_squares (LAPACKE_dgels); the theory curves gfmd_persson_contact_area. */
#include <gfmd.h>

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

enum { MAX_LOADS = 16, MAX_BODIES = 16, N_TARGETS = 3 };

static const double LAMBDA_S = 4.0, HURST = 0.8, GRADIENT = 1.0, E_STAR = 1.0;
static const double GAMMA0 = 5e-4, RHO = 1.0;      /* adhesion: the paper's gamma0; rho = a */
/* Upper ends of the small-W fits.  c(W): the thin-plate limit f = 6/t^3 (1 + t^2/5 + ...) holds at
 * the shortest roughness wavelength, t = q_s w = 2 pi W, to about 10 % only for W <= 1/8.  theta:
 * with adhesion the thinnest sheets are sticky (their area at vanishing load exceeds the target
 * areas), so its fit spans W <= 1/4 where the targets are reached. */
static const double SMALL_W_C = 0.125 + 1e-9, SMALL_W_THETA = 0.25 + 1e-9;
static const double KAPPA_MAX_AREA = 0.1;          /* the linear (small-load) regime */
static const double COLLAPSE_MAX_AREA = 0.3;       /* points used for c(W) */
static const double TARGETS[N_TARGETS] = {0.05, 0.1, 0.2}; /* contact areas of the theta fits */

/* Bodies: W = w/lambda_s, 0 = half-space.  W <= 0.25 are the thin sheets of the W^-3 regime
 * (with lambda_s = 4a, q_s w = 2 pi W is small only there). */
static const double ALL_WIDTHS[] = {0.0, 100.0, 10.0, 4.0, 2.0, 1.0, 0.5, 0.25, 0.177, 0.125, 0.088, 0.0625, 0.044};
static const double ALL_ADH_WIDTHS[] = {0.0, 4.0, 1.0, 0.5, 0.25, 0.177, 0.125, 0.088, 0.0625};
/* --quick (the test's mode): fewer bodies, still three or more in each small-W fit */
static const double QUICK_WIDTHS[] = {0.0, 4.0, 1.0, 0.25, 0.125, 0.088, 0.0625};
static const double QUICK_ADH_WIDTHS[] = {0.25, 0.177, 0.125, 0.088, 0.0625};
static double USER_WIDTHS[MAX_BODIES];
static const double *WIDTHS = ALL_WIDTHS, *ADH_WIDTHS = ALL_ADH_WIDTHS;
static int N_WIDTHS = (int)(sizeof ALL_WIDTHS / sizeof ALL_WIDTHS[0]);
static int N_ADH = (int)(sizeof ALL_ADH_WIDTHS / sizeof ALL_ADH_WIDTHS[0]);
/* Loads: those at which Persson's theory predicts these areas for each body, so every body is
 * swept over the same range of contact area although the loads differ by orders of magnitude. */
static const double AREA_GRID[] = {0.004, 0.008, 0.016, 0.03, 0.05, 0.08, 0.12, 0.18, 0.27, 0.4};
static const int N_LOADS = (int)(sizeof AREA_GRID / sizeof AREA_GRID[0]);

typedef struct {
    double W, sigma0, area, persson, gap, sep, u_el, u_ad, seconds;
    long long steps;
} point;

typedef struct {
    double W;
    int n;
    point p[MAX_LOADS];
} sweep;

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void die(const gfmd_sim *s, int32_t st, const char *what) {
    char msg[512] = "";
    if (s) gfmd_last_error(s, msg, sizeof msg);
    fprintf(stderr, "gfmd_paper: %s failed: %s: %s\n", what, gfmd_status_string(st), msg);
    exit(1);
}
#define CHECK(s, call)                                \
    do {                                              \
        int32_t st_ = (call);                         \
        if (st_ != GFMD_OK) die((s), st_, #call);     \
    } while (0)

static FILE *open_csv(const char *dir, const char *name, const char *header) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "gfmd_paper: cannot write %s: %s\n", path, strerror(errno));
        exit(1);
    }
    fprintf(f, "%s\n", header);
    return f;
}

static const char *body_name(double W) { return W > 0.0 ? "layer" : "halfspace"; }

/* The load at which Persson's A/A0 = erf(sigma0/sqrt(2V)) equals a target: bisection on erf. */
static double persson_load(double v, double area) {
    double lo = 0.0, hi = 10.0;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (erf(mid) < area) lo = mid; else hi = mid;
    }
    return 0.5 * (lo + hi) * sqrt(2.0 * v);
}

static int32_t solver = GFMD_SOLVER_FIRE; /* --solver mass: FIRE with mass weighting */

static gfmd_sim *body(const gfmd_sim *surface, double W) {
    gfmd_sim *s = NULL;
    CHECK(surface, gfmd_sim_clone(surface, &s));
    CHECK(s, gfmd_set_solver(s, solver));
    if (W > 0.0) CHECK(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, W * LAMBDA_S));
    return s;
}

/* One body, loads rising, each relaxation starting from the previous equilibrium. */
static void run_sweep(const gfmd_sim *surface, double W, int adhesive, double u_max, sweep *out) {
    gfmd_sim *s = body(surface, W);
    if (adhesive) CHECK(s, gfmd_set_adhesion(s, GAMMA0, RHO));
    out->W = W;
    out->n = N_LOADS;
    double variance = 0.0; /* Persson's full-contact pressure variance: one FFT per body */
    CHECK(s, gfmd_persson_variance(s, &variance));
    printf("\n%s%s, W = w/lambda_s = %g\n", W > 0 ? "layer on a fluid foundation" : "half-space",
           adhesive ? " with adhesion" : "", W);
    printf("%12s %10s %10s %10s %12s %12s %7s %7s\n", "sigma0/E*g", "A/A0", "Persson", "s", "U_el", "U_ad", "steps",
           "seconds");
    for (int k = 0; k < N_LOADS; ++k) {
        point *p = &out->p[k];
        p->W = W;
        p->sigma0 = persson_load(variance, AREA_GRID[k]);
        int64_t steps = 0;
        const double t0 = now();
        CHECK(s, gfmd_set_pressure(s, p->sigma0));
        CHECK(s, gfmd_relax(s, 0.0, 2000000, &steps));
        p->seconds = now() - t0;
        p->steps = (long long)steps;
        CHECK(s, gfmd_get_contact_area(s, &p->area));
        CHECK(s, gfmd_persson_contact_area(s, p->sigma0, &p->persson));
        CHECK(s, gfmd_get_mean_gap(s, &p->gap));
        CHECK(s, gfmd_get_energies(s, &p->u_el, &p->u_ad));
        p->sep = p->gap / u_max; /* s = 1 - <u>/u_max = mean gap / (max h - <h>) */
        printf("%12.4e %10.5f %10.5f %10.5f %12.5e %12.5e %7lld %7.2f\n", p->sigma0 / (E_STAR * GRADIENT), p->area,
               p->persson, p->sep, p->u_el, p->u_ad, p->steps, p->seconds);
        fflush(stdout);
    }
    gfmd_sim_destroy(&s);
}

/* Least squares through gfmd_least_squares.  Too few points (a reduced --widths list) leave the
 * result NaN, reported as such; any other failure ends the program. */
static void fit(int m, int n, const double *a, const double *b, double *x, const char *what) {
    if (m < n + 1) {
        printf("  (%s: %d points for %d parameters, not fitted)\n", what, m, n);
        for (int j = 0; j < n; ++j) x[j] = NAN;
        return;
    }
    CHECK(NULL, gfmd_least_squares(m, n, a, b, x, NULL));
}

/* Fit y = exp(x0) W^x1 over the given points (log-log line). */
static void power_law(int m, const double *w, const double *y, double *x, const char *what) {
    double a[2 * MAX_BODIES * N_TARGETS], b[MAX_BODIES * N_TARGETS];
    for (int i = 0; i < m; ++i) {
        a[i] = 1.0;
        a[m + i] = log(w[i]);
        b[i] = log(y[i]);
    }
    fit(m, 2, a, b, x, what);
}

/* A positive field of the points (its offset in point), interpolated log-log along a sweep to a
 * contact area; NAN outside the sweep. */
static double at_area(const sweep *c, double area, size_t field) {
    for (int k = 0; k + 1 < c->n; ++k) {
        const double a0 = c->p[k].area, a1 = c->p[k + 1].area;
        if (a0 > 0.0 && area >= a0 && area <= a1 && a1 > a0) {
            const double t = (log(area) - log(a0)) / (log(a1) - log(a0));
            const double y0 = *(const double *)((const char *)&c->p[k] + field);
            const double y1 = *(const double *)((const char *)&c->p[k + 1] + field);
            return exp((1.0 - t) * log(y0) + t * log(y1));
        }
    }
    return NAN;
}

static void usage(const char *argv0) {
    fprintf(stderr, "usage: %s [--n N] [--bandwidth R] [--full | --quick] [--out DIR] [--seed S] [--threads T] [--no-adhesion] [--widths 0,W1,...] [--solver fire|mass]\n",
            argv0);
    exit(2);
}

int main(int argc, char **argv) {
    long n = 256, threads = 0;
    double bandwidth = 32.0;
    unsigned long long seed = 2016;
    int adhesion = 1;
    const char *dir = ".";
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--n") && i + 1 < argc) n = strtol(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--bandwidth") && i + 1 < argc) bandwidth = strtod(argv[++i], NULL);
        else if (!strcmp(argv[i], "--full")) n = 2048, bandwidth = 64.0;
        else if (!strcmp(argv[i], "--quick")) {
            n = 128, bandwidth = 16.0;
            WIDTHS = QUICK_WIDTHS, N_WIDTHS = (int)(sizeof QUICK_WIDTHS / sizeof QUICK_WIDTHS[0]);
            ADH_WIDTHS = QUICK_ADH_WIDTHS, N_ADH = (int)(sizeof QUICK_ADH_WIDTHS / sizeof QUICK_ADH_WIDTHS[0]);
        }
        else if (!strcmp(argv[i], "--out") && i + 1 < argc) dir = argv[++i];
        else if (!strcmp(argv[i], "--seed") && i + 1 < argc) seed = strtoull(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) threads = strtol(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--no-adhesion")) adhesion = 0;
        else if (!strcmp(argv[i], "--solver") && i + 1 < argc) {
            ++i;
            if (!strcmp(argv[i], "fire")) solver = GFMD_SOLVER_FIRE;
            else if (!strcmp(argv[i], "mass")) solver = GFMD_SOLVER_FIRE_MASS;
            else usage(argv[0]);
        }
        else if (!strcmp(argv[i], "--widths") && i + 1 < argc) {
            /* comma-separated W list for the sweeps without adhesion, 0 = half-space first */
            int k = 0;
            for (char *tok = strtok(argv[++i], ","); tok && k < MAX_BODIES; tok = strtok(NULL, ","))
                USER_WIDTHS[k++] = strtod(tok, NULL);
            if (k < 1 || USER_WIDTHS[0] != 0.0) {
                fprintf(stderr, "gfmd_paper: --widths must start with 0 (the half-space)\n");
                return 2;
            }
            WIDTHS = USER_WIDTHS, N_WIDTHS = k;
        }
        else usage(argv[0]);
    }
    const double l = (double)n, lambda_r = bandwidth * LAMBDA_S;
    if (n < 32 || !(bandwidth >= 1.0) || lambda_r > l || threads < 0) {
        fprintf(stderr, "gfmd_paper: need --n >= 32 and 1 <= bandwidth <= n/4 (lambda_r = R * 4a within the cell)\n");
        return 2;
    }
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "gfmd_paper: cannot create %s: %s\n", dir, strerror(errno));
        return 1;
    }
    printf("gfmd %s: the study of Putignano, Dapp & Mueser (2016)\n", gfmd_version());
    printf("grid %ldx%ld, L = %.0f a, lambda_s = %.0f a, lambda_r = %.0f a (= %.0f lambda_s, L = %.3g lambda_r), "
           "H = %.1f, g = %.0f, E* = %.0f, seed %llu\n",
           n, n, l, LAMBDA_S, lambda_r, bandwidth, l / lambda_r, HURST, GRADIENT, E_STAR, seed);

    gfmd_sim *surface = NULL;
    CHECK(NULL, gfmd_sim_create(n, n, l, l, &surface));
    CHECK(surface, gfmd_set_threads(surface, (int32_t)threads));
    CHECK(surface, gfmd_generate_selfaffine(surface, HURST, lambda_r, LAMBDA_S, GRADIENT, seed, GFMD_DIST_UNIFORM));
    double *h = malloc(sizeof(double) * (size_t)(n * n));
    if (!h) return 1;
    CHECK(surface, gfmd_get_heights(surface, h));
    double hmax = -INFINITY, hmean = 0.0;
    for (long i = 0; i < n * n; ++i) hmax = fmax(hmax, h[i]), hmean += h[i] / (double)(n * n);
    free(h);
    const double u_max = hmax - hmean;
    const double t_start = now();

    /* ---- Figs. 3, 4, 6: load sweeps without adhesion */
    static sweep sw[MAX_BODIES];
    for (int b = 0; b < N_WIDTHS; ++b) run_sweep(surface, WIDTHS[b], 0, u_max, &sw[b]);

    FILE *f3 = open_csv(dir, "fig3_area.csv",
                        "body,W,sigma0,sigma0_over_Eg,rel_area,persson_area,mean_gap,separation,u_el,steps,seconds");
    FILE *f4 = open_csv(dir, "fig4_area_complement.csv", "body,W,sigma0_over_Eg,rel_area,a_times_complement");
    FILE *f6 = open_csv(dir, "fig6_separation.csv", "body,W,sigma0_over_Estar,mean_gap,separation");
    for (int b = 0; b < N_WIDTHS; ++b)
        for (int k = 0; k < sw[b].n; ++k) {
            const point *p = &sw[b].p[k];
            const double load = p->sigma0 / (E_STAR * GRADIENT);
            fprintf(f3, "%s,%g,%.10e,%.10e,%.10e,%.10e,%.10e,%.10e,%.10e,%lld,%.4f\n", body_name(p->W), p->W, p->sigma0,
                    load, p->area, p->persson, p->gap, p->sep, p->u_el, p->steps, p->seconds);
            fprintf(f4, "%s,%g,%.10e,%.10e,%.10e\n", body_name(p->W), p->W, load, p->area, p->area * (1.0 - p->area));
            fprintf(f6, "%s,%g,%.10e,%.10e,%.10e\n", body_name(p->W), p->W, p->sigma0 / E_STAR, p->gap, p->sep);
        }
    fclose(f3);
    fclose(f4);
    fclose(f6);

    /* Persson's curves, smooth, for the plots (same substrate, each body's G(q)). */
    FILE *fp = open_csv(dir, "persson_curves.csv", "body,W,sigma0_over_Eg,persson_area");
    for (int b = 0; b < N_WIDTHS; ++b) {
        gfmd_sim *s = body(surface, WIDTHS[b]);
        const double lo = sw[b].p[0].sigma0 / 3.0, hi = sw[b].p[sw[b].n - 1].sigma0 * 3.0;
        for (int k = 0; k <= 60; ++k) {
            const double sig = lo * pow(hi / lo, k / 60.0);
            double a = 0.0;
            CHECK(s, gfmd_persson_contact_area(s, sig, &a));
            fprintf(fp, "%s,%g,%.10e,%.10e\n", body_name(WIDTHS[b]), WIDTHS[b], sig / (E_STAR * GRADIENT), a);
        }
        gfmd_sim_destroy(&s);
    }
    fclose(fp);

    /* ---- kappa: A = kappa sigma0/(E* g) over the half-space's small-load points */
    double a1[MAX_LOADS], b1[MAX_LOADS], kappa = 0.0;
    int m = 0;
    for (int k = 0; k < sw[0].n; ++k)
        if (sw[0].p[k].area <= KAPPA_MAX_AREA) {
            a1[m] = sw[0].p[k].sigma0 / (E_STAR * GRADIENT);
            b1[m++] = sw[0].p[k].area;
        }
    fit(m, 1, a1, b1, &kappa, "kappa");

    /* ---- Fig. 5: c(W) by least squares on the collapse: each layer point with
     * A <= COLLAPSE_MAX_AREA inside the half-space sweep gives ln c = ln sigma_hs(A) - ln sigma_W */
    double cw[MAX_BODIES];
    cw[0] = 1.0;
    for (int b = 1; b < N_WIDTHS; ++b) {
        double ones[MAX_LOADS], shift[MAX_LOADS], lnc = 0.0;
        m = 0;
        for (int k = 0; k < sw[b].n; ++k) {
            const double ls = log(at_area(&sw[0], sw[b].p[k].area, offsetof(point, sigma0)));
            if (sw[b].p[k].area <= COLLAPSE_MAX_AREA && isfinite(ls)) {
                ones[m] = 1.0;
                shift[m++] = ls - log(sw[b].p[k].sigma0);
            }
        }
        fit(m, 1, ones, shift, &lnc, "c(W)");
        cw[b] = exp(lnc);
    }
    double wv[MAX_BODIES], cv[MAX_BODIES], cfit[2];
    m = 0;
    for (int b = 1; b < N_WIDTHS; ++b)
        if (WIDTHS[b] <= SMALL_W_C) wv[m] = WIDTHS[b], cv[m++] = cw[b];
    power_law(m, wv, cv, cfit, "c(W) exponent");

    FILE *f5a = open_csv(dir, "fig5a_collapse.csv", "body,W,c,scaled_load,rel_area");
    FILE *f5b = open_csv(dir, "fig5b_cW.csv", "W,c,c_fit");
    for (int b = 0; b < N_WIDTHS; ++b) {
        for (int k = 0; k < sw[b].n; ++k)
            fprintf(f5a, "%s,%g,%.10e,%.10e,%.10e\n", body_name(WIDTHS[b]), WIDTHS[b], cw[b],
                    cw[b] * sw[b].p[k].sigma0 / (E_STAR * GRADIENT), sw[b].p[k].area);
        if (b > 0) fprintf(f5b, "%g,%.10e,%.10e\n", WIDTHS[b], cw[b], exp(cfit[0]) * pow(WIDTHS[b], cfit[1]));
    }
    fclose(f5a);
    fclose(f5b);

    /* ---- Fig. 7: theta = U_el/U_ad with adhesion at three contact areas */
    double tfit[N_TARGETS][2] = {{NAN, NAN}, {NAN, NAN}, {NAN, NAN}}, common = NAN;
    if (adhesion) {
        static sweep ad[MAX_BODIES];
        for (int b = 0; b < N_ADH; ++b) run_sweep(surface, ADH_WIDTHS[b], 1, u_max, &ad[b]);
        FILE *fa = open_csv(dir, "fig7_adhesion_sweep.csv", "body,W,sigma0,rel_area,u_el,u_ad,steps");
        for (int b = 0; b < N_ADH; ++b)
            for (int k = 0; k < ad[b].n; ++k) {
                const point *p = &ad[b].p[k];
                fprintf(fa, "%s,%g,%.10e,%.10e,%.10e,%.10e,%lld\n", body_name(p->W), p->W, p->sigma0, p->area, p->u_el,
                        p->u_ad, p->steps);
            }
        fclose(fa);
        FILE *f7 = open_csv(dir, "fig7_theta.csv", "W,target_area,u_el,u_ad,theta");
        /* common exponent: one intercept per area, one slope (columns: 3 indicators, ln W) */
        double ac[(N_TARGETS + 1) * MAX_BODIES * N_TARGETS], bc[MAX_BODIES * N_TARGETS];
        int rows[MAX_BODIES * N_TARGETS] = {0}, mc = 0;
        double lw[MAX_BODIES * N_TARGETS];
        for (int t = 0; t < N_TARGETS; ++t) {
            double w[MAX_BODIES], th[MAX_BODIES];
            int mt = 0;
            for (int b = 0; b < N_ADH; ++b) {
                const double ue = at_area(&ad[b], TARGETS[t], offsetof(point, u_el));
                const double ua = at_area(&ad[b], TARGETS[t], offsetof(point, u_ad));
                if (!isfinite(ue) || !isfinite(ua)) continue; /* the area is outside this sweep */
                fprintf(f7, "%g,%g,%.10e,%.10e,%.10e\n", ADH_WIDTHS[b], TARGETS[t], ue, ua, ue / ua);
                if (ADH_WIDTHS[b] > 0.0 && ADH_WIDTHS[b] <= SMALL_W_THETA) {
                    w[mt] = ADH_WIDTHS[b], th[mt++] = ue / ua;
                    rows[mc] = t, lw[mc] = log(ADH_WIDTHS[b]), bc[mc++] = log(ue / ua);
                }
            }
            if (mt >= 3) power_law(mt, w, th, tfit[t], "theta exponent");
        }
        fclose(f7);
        int used[N_TARGETS] = {0}, ncol = 0, col[N_TARGETS];
        for (int i = 0; i < mc; ++i) used[rows[i]] = 1;
        for (int t = 0; t < N_TARGETS; ++t) col[t] = used[t] ? ncol++ : -1;
        if (mc >= ncol + 2) {
            for (int i = 0; i < (ncol + 1) * mc; ++i) ac[i] = 0.0;
            for (int i = 0; i < mc; ++i) {
                ac[col[rows[i]] * mc + i] = 1.0;
                ac[ncol * mc + i] = lw[i];
            }
            double x[N_TARGETS + 1];
            fit(mc, ncol + 1, ac, bc, x, "common theta exponent");
            common = x[ncol];
        }
    }

    FILE *ff = open_csv(dir, "fits.csv", "quantity,value,detail");
    fprintf(ff, "kappa_halfspace,%.6f,A/A0 = kappa sigma0/(E* g) for A/A0 <= %g\n", kappa, KAPPA_MAX_AREA);
    fprintf(ff, "persson_kappa,%.6f,sqrt(8/pi) (small-load slope of erf)\n", sqrt(8.0 / 3.14159265358979323846));
    fprintf(ff, "c_exponent,%.6f,c(W) ~ W^alpha for W <= 0.125\n", cfit[1]);
    fprintf(ff, "c_prefactor,%.6e,c(W) = prefactor W^alpha for W <= 0.125\n", exp(cfit[0]));
    for (int t = 0; t < N_TARGETS; ++t)
        fprintf(ff, "theta_exponent_A%g,%.6f,theta ~ W^beta at A/A0 = %g for W <= 0.25\n", TARGETS[t], tfit[t][1],
                TARGETS[t]);
    fprintf(ff, "theta_exponent,%.6f,common beta of the three areas (one intercept each)\n", common);
    fclose(ff);

    printf("\nFits (gfmd_least_squares):\n");
    printf("  kappa (half-space, A/A0 <= %g)  = %.3f   (Persson: sqrt(8/pi) = %.3f)\n", KAPPA_MAX_AREA, kappa,
           sqrt(8.0 / 3.14159265358979323846));
    printf("  c(W) ~ W^alpha, W <= 0.125      : alpha = %.3f (paper: -3)\n", cfit[1]);
    for (int b = 1; b < N_WIDTHS; ++b) {
        printf("    W = %-7g c = %-10.4g", WIDTHS[b], cw[b]);
        if (b > 1) printf(" local exponent to the previous W: %.2f", log(cw[b] / cw[b - 1]) / log(WIDTHS[b] / WIDTHS[b - 1]));
        printf("\n");
    }
    if (adhesion) {
        for (int t = 0; t < N_TARGETS; ++t)
            printf("  theta ~ W^beta at A/A0 = %-5g : beta = %.3f\n", TARGETS[t], tfit[t][1]);
        printf("  theta, common exponent          : beta = %.3f (paper: +3)\n", common);
    }
    printf("total %.1f s; tables in %s\n", now() - t_start, dir);
    gfmd_sim_destroy(&surface);
    return 0;
}
