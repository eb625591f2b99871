/* A measurement, not part of the library: a thin sheet's continuing load solved by an active-set
 * Newton method whose CG is preconditioned by one multigrid V(nu,nu)-cycle for the real-space
 * stencil's block on the free points (stencil_mg.h), timed against the library's default relax
 * of the same load in the same run (docs/performance.md, *What was tried*, a real-space stencil
 * for the sheet between its contacts; bench/two_level_prototype.py --newton --stencil 0
 * --stencil-mg NU is its numpy model, which counts iterations only).
 *
 * The body: the study's substrate (H = 0.8, lambda_s = 4a, lambda_r = n a/8, rms gradient 1, seed
 * 1), E* = 1, a layer of width w = 4 W a on a fluid foundation, adhesion gamma0, rho if given; the
 * loads sigma0 -> sigma1 those for which Persson's theory gives A/A0 = --areas A0,A1 (the study's
 * first two: 0.004, 0.008).  The library relaxes sigma0 (from --levels grids: the study's
 * multilevel first load), then sigma1 by its default solver (timed); the Newton method starts
 * from the same equilibrium at sigma0 (timed):
 *   each step   the gradient g = K u + sigma1 + (gamma0/rho) e, e = exp(-(u - h)/rho); the held
 *               points those at the wall with g >= 0, the rest free; stop when the library's
 *               residual criterion holds (rms of g, of min(g, 0) at the wall, <= tol (|sigma1| +
 *               gamma0/rho + 1e-8));
 *   the step d  CG on (K - (gamma0/rho^2) e)_FF d = -g_F to a tenth of its right-hand side (at
 *               most 500 iterations; stopped where the curvature is not positive, as Steihaug's),
 *               preconditioned by (1/c0) V(L^2_FF), c0 L^2 the 13-point stencil fitted to k(q);
 *               the coarse operators assembled for the first held set, then updated where it
 *               changes (mg_update);
 *   the search  u + alpha d cut at the substrate, alpha halved from 1 until the energy falls by
 *               1e-4 of the gradient's prediction; every trial costs an FFT pair (counted), the
 *               accepted one's gradient is the next step's.
 * --methods also runs, from the same start, FIRE with the cycle as its mass matrix (fire: the
 * library's control and update, fire_control.hpp and kernels' mass_update, its unit time step
 * 1/sqrt(lambda_max(V K_FF)) by 15 power iterations, counted) and the library's projected surface
 * CG (cg.hpp) with the cycle as its preconditioner (pcg: a t.K.t pair counted where the library
 * spends half one); --no-curvature drops the adhesive curvature from the Newton method's matrix.
 * --trust R0,RMIN keeps the Newton method's CG within a trust region, max |d| <= radius over the free
 * points (Steihaug's CG: stopped where its next iterate would leave it, and at non-positive curvature
 * stepped along that direction, downhill for the model, to its edge), the radius R0 rho at first,
 * doubled after a full step to the edge, else the search's accepted step but at least RMIN rho: where
 * the sheet sags near the wall the model is poor and the CG's iterate, grown along its softest
 * directions, left the search 1e-2-1e-4 of it; rho is the scale on which the adhesive law changes.
 * --first: the methods relax the first load instead, from the library's flat start, and are timed
 * against the library's first load (from --levels grids, coarser ones included) and compared with
 * its equilibrium there (the library's continuing load is then not run).
 * --coarse-start (with --first and --levels L >= 2): the methods start the first load instead where
 * the library's multilevel start leaves its finest grid, the body relaxed by the library on the grid
 * coarsened by 2 (itself from L - 2 coarser grids; substrate filtered through its spectrum, the
 * surface interpolated by zero padding and lifted onto the substrate, as gfmd_relax_multilevel
 * does) — that coarse part timed and counted in each method's seconds.
 * The cycle runs in single precision (stencil_mg.h).
 * It prints each method's time beside the library's, its parts (FFT pairs, cycles, assembly) in
 * bare pairs of the same run, and fails (exit 1) unless each meets the criterion and its contact
 * area agrees with the library's to 1e-3 relative and, without adhesion, its surface to 1e-3 a
 * (both stopped at the same residual; at 1e-6 a sheet's softest modes leave displacements of
 * ~1e-4 a).
 *
 *   stencil_newton [--n N] [--W W] [--areas A0,A1] [--gamma0 G --rho R] [--nu S] [--tol T]
 *                  [--levels L] [--methods M,..] [--no-curvature] [--rtol R] [--trust R0,RMIN] [--first]
 *                  [--verbose]
 *                  (defaults 2048, 0.088, 0.004,0.008, no adhesion, 1, 1e-6, 4, newton, 0.1) */
#include <fftw3.h>
#include <gfmd.h>
#include <stdint.h>
#include <stdio.h>

#include "pair_clock.h"
#include "stencil_mg.h"

static int n;
static fftw_plan r2c, c2r;
static fftw_complex *spec;
static double *kq;        /* k(q) / N on the r2c half spectrum */
static long pairs;        /* FFT pairs spent by the Newton method */
static double sigma, gam, rho_;
/* --methods: the Newton method; FIRE with the cycle as its mass matrix (the library's control and
 * update, fire_control.hpp and mass_update); the library's projected surface CG (cg.hpp) with the
 * cycle as its preconditioner */
static const char *const NAMES[] = {"newton", "fire", "pcg"};
static int verbose = 0;     /* --verbose: a line a step on stderr */
static double cg_rtol = 0.1; /* the Newton method's CG: to this fraction of its right-hand side (--rtol) */
static int curvature = 1; /* the adhesive law's curvature in the Newton method's matrix (--no-curvature: 0) */
/* --trust R0,RMIN: the CG's iterate kept within max |d| <= radius, radius from R0 rho, never below RMIN rho
 * (0: off) */
static double trust = 0.0, trust_min = 0.0;
static int first_load = 0; /* --first: the methods relax the first load from the library's flat start */
static int coarse_start = 0; /* --coarse-start: ... from the library's coarser grids' start instead */
static const double *h;   /* the substrate */

/* y = K x (x and y may not alias: out of place as the library's step) */
static void stiffness(const double *x, double *y) {
    const size_t nc = (size_t)n * (n / 2 + 1);
    fftw_execute_dft_r2c(r2c, (double *)x, spec);
    for (size_t k = 0; k < nc; k++) {
        spec[k][0] *= kq[k];
        spec[k][1] *= kq[k];
    }
    fftw_execute_dft_c2r(c2r, spec, y);
    pairs++;
}

static double slack; /* the last energy's rounding: 1e-12 of the sum of its terms' magnitudes */

/* g = K u + sigma + (gamma0/rho) e, e = exp(-(u - h)/rho) (NULL without adhesion); returns the
 * energy 1/2 u.Ku + sigma sum u - gamma0 sum e and sets its slack */
static double gradient(const double *u, double *g, double *e) {
    const size_t N = (size_t)n * n;
    stiffness(u, g);
    double energy = 0.0, size = 0.0;
    for (size_t p = 0; p < N; p++) {
        energy += 0.5 * u[p] * g[p] + sigma * u[p];
        size += fabs(0.5 * u[p] * g[p]) + fabs(sigma * u[p]);
        g[p] += sigma;
        if (gam > 0) {
            e[p] = exp(-(u[p] - h[p]) / rho_);
            g[p] += (gam / rho_) * e[p];
            energy -= gam * e[p];
            size += gam * e[p];
        }
    }
    slack = 1e-12 * size;
    return energy;
}

static double dot(const double *a, const double *b, size_t N) {
    double s = 0.0;
    for (size_t p = 0; p < N; p++) s += a[p] * b[p];
    return s;
}

static double t_cycles, c0;
static long cycles;

/* V(r) on the free points (zero on the held ones, as r is), in single precision (stencil_mg.h);
 * the result, lv[0].x, is returned (the preconditioner is (1/c0) V: the caller scales) */
static const mgreal *precondition(const double *r) {
    const size_t N = (size_t)n * n;
    const double t0 = now();
    for (size_t p = 0; p < N; p++) lv[0].b[p] = (mgreal)r[p];
    cycle(0);
    cycles++;
    t_cycles += now() - t0;
    return lv[0].x;
}

/* lambda_max of (1/c0) V K_FF by 15 power iterations from a pseudo-random start (FIRE's unit time
 * step); x, y: scratch */
static double lambda_max(double *x, double *y) {
    const size_t N = (size_t)n * n;
    double lambda = 0.0;
    for (size_t p = 0; p < N; p++) x[p] = held[p] ? 0.0 : sin(0.7 * (double)p) + 0.2;
    for (int it = 0; it < 15; it++) {
        stiffness(x, y);
        for (size_t p = 0; p < N; p++) y[p] = held[p] ? 0.0 : y[p];
        const mgreal *v = precondition(y);
        double x2 = 0.0, y2 = 0.0;
        for (size_t p = 0; p < N; p++) {
            x2 += x[p] * x[p];
            x[p] = v[p] / c0;
            y2 += x[p] * x[p];
        }
        lambda = sqrt(y2 / x2);
    }
    return lambda;
}

/* a surface u with its energy's gradient g and the adhesive law's factors e (gradient()) */
typedef struct {
    double *u, *g, *e;
} surface;

/* The projected search along t from *cur: the trial max(h, u + alpha t) for alpha = alpha0, alpha0/2,
 * ..., taken (its state swapped with *cur's) once the energy falls by 1e-4 of the gradient's
 * prediction, the energy's rounding as slack, or once alpha < alpha_min, or at once where no point
 * met the wall and unstopped is set.  Every trial costs an FFT pair (counted in *trials).  Returns
 * the alpha taken; *hits the points the wall stopped and *predicted the prediction, at that alpha. */
static double search(surface *cur, surface *tri, const double *t, double alpha0, double alpha_min, int unstopped,
                     double *energy, long *trials, size_t *hits, double *predicted) {
    const size_t N = (size_t)n * n;
    for (double alpha = alpha0;; alpha *= 0.5) {
        *predicted = 0.0, *hits = 0;
        for (size_t p = 0; p < N; p++) {
            const double zn = cur->u[p] + alpha * t[p];
            *hits += zn < h[p];
            tri->u[p] = fmax(h[p], zn);
            *predicted += cur->g[p] * (tri->u[p] - cur->u[p]);
        }
        ++*trials;
        const double e_trial = gradient(tri->u, tri->g, tri->e);
        if ((*hits == 0 && unstopped) || e_trial <= *energy + 1e-4 * *predicted + slack || alpha < alpha_min) {
            const surface taken = *tri;
            *tri = *cur, *cur = taken;
            *energy = e_trial;
            return alpha;
        }
    }
}

/* the largest t >= 0 with max |d + t s| <= radius on the free points (|d| <= radius there); 0 if s
 * is 0 on all of them */
static double to_boundary(const double *d, const double *s, double radius) {
    const size_t N = (size_t)n * n;
    double t = INFINITY;
    for (size_t p = 0; p < N; p++) {
        if (held[p] || s[p] == 0.0) continue;
        t = fmin(t, s[p] > 0 ? (radius - d[p]) / s[p] : (radius + d[p]) / -s[p]);
    }
    return isfinite(t) ? fmax(t, 0.0) : 0.0;
}

/* The Newton step d: CG on (K - (gamma0/rho^2) e)_FF d = -g_F from d = 0, preconditioned by the
 * cycle, to cg_rtol of its right-hand side, at most 500 iterations, stopped at non-positive
 * curvature (d the first direction if it came first); with radius > 0 Steihaug's: stopped where the
 * next iterate would leave max |d| <= radius (*edge = 1) and at non-positive curvature stepped along
 * it, downhill for the model, to that edge (*edge = *negative = 1).  r, pp, kp: scratch.  Returns
 * the CG iterations. */
static long newton_direction(const double *g, const double *e, double radius, double *d, double *r, double *pp,
                             double *kp, int *edge, int *negative) {
    const size_t N = (size_t)n * n;
    for (size_t p = 0; p < N; p++) {
        d[p] = 0.0;
        r[p] = held[p] ? 0.0 : -g[p];
    }
    const double b0 = sqrt(dot(r, r, N));
    const mgreal *v = precondition(r);
    double rz = 0.0;
    for (size_t p = 0; p < N; p++) {
        pp[p] = v[p] / c0;
        rz += r[p] * pp[p];
    }
    for (int it = 1; it <= 500; it++) {
        stiffness(pp, kp);
        double pkp = 0.0;
        for (size_t p = 0; p < N; p++) {
            if (held[p]) kp[p] = 0.0;
            else if (gam > 0 && curvature) kp[p] -= (gam / (rho_ * rho_)) * e[p] * pp[p];
            pkp += pp[p] * kp[p];
        }
        if (!(pkp > 0)) {
            if (radius > 0) {
                const double sgn = dot(r, pp, N) >= 0 ? 1.0 : -1.0;
                for (size_t p = 0; p < N; p++) kp[p] = sgn * pp[p];
                const double t = to_boundary(d, kp, radius);
                for (size_t p = 0; p < N; p++) d[p] += t * kp[p];
                *edge = *negative = 1;
            } else if (it == 1) memcpy(d, pp, N * sizeof(double));
            return it;
        }
        const double a = rz / pkp;
        if (radius > 0) {
            const double t = to_boundary(d, pp, radius);
            if (a > t) {
                for (size_t p = 0; p < N; p++) d[p] += t * pp[p];
                *edge = 1;
                return it;
            }
        }
        double rr = 0.0;
        for (size_t p = 0; p < N; p++) {
            d[p] += a * pp[p];
            r[p] -= a * kp[p];
            rr += r[p] * r[p];
        }
        if (sqrt(rr) < cg_rtol * b0) return it;
        v = precondition(r);
        double rz_new = 0.0;
        for (size_t p = 0; p < N; p++) rz_new += r[p] * v[p];
        rz_new /= c0;
        const double beta = rz_new / rz;
        rz = rz_new;
        for (size_t p = 0; p < N; p++) pp[p] = v[p] / c0 + beta * pp[p];
    }
    return 500;
}

static void usage(const char *name) {
    fprintf(stderr,
            "usage: %s [--n N] [--W W] [--areas A0,A1] [--gamma0 G --rho R] [--nu S] [--tol T] [--levels L]\n"
            "       [--methods newton,fire,pcg] [--no-curvature] [--rtol R] [--trust R0,RMIN] [--first [--coarse-start]] [--verbose]\n",
            name);
    exit(2);
}

#define CHECK(call)                                                                                                    \
    do {                                                                                                               \
        const int32_t st_ = (call);                                                                                    \
        if (st_ != GFMD_OK && st_ != GFMD_ERR_NOT_CONVERGED) {                                                         \
            fprintf(stderr, "stencil_newton: %s: %s\n", #call, gfmd_status_string(st_));                               \
            return 1;                                                                                                  \
        }                                                                                                              \
    } while (0)

/* The modes two grids share (strictly below the smaller grid's Nyquist frequencies), from the half
 * spectrum of a side nf grid to that of a side nt grid, scaled; the rest of the target zeroed (as the
 * library's multilevel start: restriction filters, prolongation pads with zeros). */
static void shared_modes(int nf, const fftw_complex *from, int nt, fftw_complex *to, double scale) {
    const int ns = nf < nt ? nf : nt;
    memset(to, 0, (size_t)nt * (nt / 2 + 1) * sizeof(fftw_complex));
    for (int ky = -(ns / 2 - 1); ky <= ns / 2 - 1; ky++) {
        const size_t rf = (size_t)(ky < 0 ? nf + ky : ky) * (nf / 2 + 1), rt = (size_t)(ky < 0 ? nt + ky : ky) * (nt / 2 + 1);
        for (int kx = 0; 2 * kx < ns; kx++) {
            to[rt + kx][0] = scale * from[rf + kx][0];
            to[rt + kx][1] = scale * from[rf + kx][1];
        }
    }
}

/* --coarse-start: the surface with which gfmd_relax_multilevel(levels) starts its finest grid — the
 * body (the substrate filtered to the grid coarsened by 2, at the load sigma0) relaxed by the
 * library from levels - 1 grids, interpolated to this grid and lifted onto the substrate — into z;
 * the seconds it took (planning included) and the coarse grids' steps. */
static int coarse_surface(double W, int levels, double sigma0, double tol, double *z, double *seconds,
                          int64_t *steps) {
    const double t0 = now();
    const int m = n / 2;
    const size_t N = (size_t)n * n, M = (size_t)m * m;
    double *buf = fftw_alloc_real(N), *zc = fftw_alloc_real(M);
    fftw_complex *fs = fftw_alloc_complex((size_t)n * (n / 2 + 1)), *cs = fftw_alloc_complex((size_t)m * (m / 2 + 1));
    if (!buf || !zc || !fs || !cs) return 1;
    const fftw_plan fwd = fftw_plan_dft_r2c_2d(n, n, buf, fs, FFTW_ESTIMATE),
                    bwd = fftw_plan_dft_c2r_2d(n, n, fs, buf, FFTW_ESTIMATE),
                    cfwd = fftw_plan_dft_r2c_2d(m, m, zc, cs, FFTW_ESTIMATE),
                    cbwd = fftw_plan_dft_c2r_2d(m, m, cs, zc, FFTW_ESTIMATE);
    memcpy(buf, h, N * sizeof(double));
    fftw_execute(fwd);
    shared_modes(n, fs, m, cs, 1.0 / (double)N);
    fftw_execute(cbwd); /* zc: the substrate filtered */
    gfmd_sim *c = NULL;
    int64_t own = 0, below = 0;
    CHECK(gfmd_sim_create_ex(m, m, n, n, 1, GFMD_PLANNER_ESTIMATE, &c));
    CHECK(gfmd_set_modulus(c, 1.0));
    CHECK(gfmd_set_green(c, GFMD_GREEN_LAYER_FLUID, 4.0 * W));
    CHECK(gfmd_set_heights(c, zc));
    if (gam > 0) CHECK(gfmd_set_adhesion(c, gam, rho_));
    CHECK(gfmd_set_pressure(c, sigma0));
    CHECK(gfmd_relax_multilevel(c, tol, 10000000, levels - 1, &own, &below));
    CHECK(gfmd_get_surface(c, zc));
    gfmd_sim_destroy(&c);
    fftw_execute(cfwd);
    shared_modes(m, cs, n, fs, 1.0 / (double)M);
    fftw_execute(bwd);
    for (size_t p = 0; p < N; p++) z[p] = fmax(buf[p], h[p]);
    const fftw_plan plans[] = {fwd, bwd, cfwd, cbwd};
    for (int k = 0; k < 4; k++) fftw_destroy_plan(plans[k]);
    fftw_free(buf), fftw_free(zc), fftw_free(fs), fftw_free(cs);
    *steps = own + below;
    *seconds = now() - t0;
    return 0;
}

int main(int argc, char **argv) {
    double W = 0.088, area0 = 0.004, area1 = 0.008, tol = 1e-6;
    int levels = 4, methods[3] = {0}, n_methods = 1;
    n = 2048, nu = 1, rho_ = 1.0;
    setvbuf(stdout, NULL, _IOLBF, 0); /* each line as it is printed, also into a file */
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--n") && i + 1 < argc) n = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--W") && i + 1 < argc) W = atof(argv[++i]);
        else if (!strcmp(argv[i], "--areas") && i + 1 < argc) {
            if (sscanf(argv[++i], "%lf,%lf", &area0, &area1) != 2) usage(argv[0]);
        } else if (!strcmp(argv[i], "--gamma0") && i + 1 < argc) gam = atof(argv[++i]);
        else if (!strcmp(argv[i], "--rho") && i + 1 < argc) rho_ = atof(argv[++i]);
        else if (!strcmp(argv[i], "--nu") && i + 1 < argc) nu = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--tol") && i + 1 < argc) tol = atof(argv[++i]);
        else if (!strcmp(argv[i], "--levels") && i + 1 < argc) levels = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--no-curvature")) curvature = 0;
        else if (!strcmp(argv[i], "--trust") && i + 1 < argc) {
            if (sscanf(argv[++i], "%lf,%lf", &trust, &trust_min) != 2) usage(argv[0]);
        }
        else if (!strcmp(argv[i], "--rtol") && i + 1 < argc) cg_rtol = atof(argv[++i]);
        else if (!strcmp(argv[i], "--first")) first_load = 1;
        else if (!strcmp(argv[i], "--coarse-start")) coarse_start = 1;
        else if (!strcmp(argv[i], "--verbose")) verbose = 1;
        else if (!strcmp(argv[i], "--methods") && i + 1 < argc) {
            n_methods = 0;
            for (char *tok = strtok(argv[++i], ","); tok; tok = strtok(NULL, ",")) {
                int m = 0;
                while (m < 3 && strcmp(tok, NAMES[m])) m++;
                if (m == 3 || n_methods == 3) usage(argv[0]);
                methods[n_methods++] = m;
            }
        }
        else usage(argv[0]);
    }
    if (n < 32 || (n & (n - 1)) || !(W > 0) || !(area0 > 0 && area0 < area1 && area1 < 1) || !(gam >= 0) ||
        !(rho_ > 0) || nu < 1 || nu > 8 || !(tol > 0) || !(cg_rtol > 0 && cg_rtol < 1) || levels < 1 || levels > 8 ||
        !(trust >= 0 && trust_min >= 0 && trust_min <= trust) || (coarse_start && (!first_load || levels < 2))) {
        fprintf(stderr, "stencil_newton: N a power of 2 >= 32, W > 0, 0 < A0 < A1 < 1, G >= 0, R > 0, 1 <= S <= 8, "
                        "T > 0, 0 < R < 1, 1 <= L <= 8, 0 <= RMIN <= R0, --coarse-start with --first and L >= 2\n");
        return 2;
    }
    const size_t N = (size_t)n * n, nc = (size_t)n * (n / 2 + 1);
    /* the library's run */
    gfmd_sim *s = NULL;
    CHECK(gfmd_sim_create_ex(n, n, n, n, 1, GFMD_PLANNER_MEASURE, &s));
    CHECK(gfmd_set_modulus(s, 1.0));
    CHECK(gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 4.0 * W));
    CHECK(gfmd_generate_selfaffine(s, 0.8, n / 8.0, 4.0, 1.0, 1, GFMD_DIST_UNIFORM));
    if (gam > 0) CHECK(gfmd_set_adhesion(s, gam, rho_));
    double sigma0, sigma1, area_lib = 0.0;
    CHECK(gfmd_persson_load(s, area0, &sigma0));
    CHECK(gfmd_persson_load(s, area1, &sigma1));
    double *hh = fftw_alloc_real(N), *u = fftw_alloc_real(N), *z0 = fftw_alloc_real(N), *z1 = fftw_alloc_real(N),
           *zf = fftw_alloc_real(N), *g = fftw_alloc_real(N),
           *e = fftw_alloc_real(N), *d = fftw_alloc_real(N), *r = fftw_alloc_real(N),
           *pp = fftw_alloc_real(N), *kp = fftw_alloc_real(N), *trial = fftw_alloc_real(N), *gt = fftw_alloc_real(N),
           *et = fftw_alloc_real(N);
    kq = fftw_alloc_real(nc);
    spec = fftw_alloc_complex(nc);
    held = malloc(N);
    unsigned char *was = malloc(N), *dirty[MAXL] = {0};
    size_t *changed = malloc(N * sizeof(size_t));
    if (!hh || !u || !z0 || !z1 || !zf || !g || !e || !d || !r || !pp || !kp || !trial || !gt || !et || !kq || !spec ||
        !held ||
        !was || !changed) {
        fprintf(stderr, "stencil_newton: out of memory\n");
        return 1;
    }
    CHECK(gfmd_get_heights(s, hh));
    h = hh;
    CHECK(gfmd_set_pressure(s, sigma0));
    CHECK(gfmd_get_surface(s, zf)); /* the flat start */
    int64_t steps0 = 0, steps1 = 0, coarse = 0;
    double area_first, t0 = now();
    if (levels > 1) CHECK(gfmd_relax_multilevel(s, tol, 10000000, levels, &steps0, &coarse));
    else CHECK(gfmd_relax(s, tol, 10000000, &steps0));
    const double t_first = now() - t0;
    CHECK(gfmd_get_surface(s, z0));
    CHECK(gfmd_get_contact_area(s, &area_first));
    double t_lib = 0.0;
    int32_t solver = 0;
    if (!first_load) { /* the continuing load (--first compares with the first: not needed) */
        CHECK(gfmd_set_pressure(s, sigma1));
        t0 = now();
        CHECK(gfmd_relax(s, tol, 10000000, &steps1));
        t_lib = now() - t0;
        CHECK(gfmd_get_solver(s, &solver));
        CHECK(gfmd_get_surface(s, z1));
        CHECK(gfmd_get_contact_area(s, &area_lib));
    }
    gfmd_sim_destroy(&s);
    printf("n = %d, W = %g, gamma0 = %g, rho = %g, sigma0 %.4e -> %.4e (Persson's A/A0 %g -> %g), tol %g, one thread\n",
           n, W, gam, rho_, sigma0, sigma1, area0, area1, tol);
    printf("library: the first load %lld steps (%lld on coarser grids), %.2f s, A/A0 = %.6f", (long long)steps0,
           (long long)coarse, t_first, area_first);
    if (!first_load)
        printf("; the continuing load %lld steps, %.2f s (solver %d), A/A0 = %.6f", (long long)steps1, t_lib,
               (int)solver, area_lib);
    printf("\n");
    /* what the methods relax and are compared with: the continuing load from the first's equilibrium,
     * or (--first) the first load from the flat start */
    const double *start = first_load ? zf : z0, *ref = first_load ? z0 : z1;
    double t_coarse = 0.0;
    if (coarse_start) {
        int64_t coarse_steps = 0;
        if (coarse_surface(W, levels, sigma0, tol, zf, &t_coarse, &coarse_steps)) {
            fprintf(stderr, "stencil_newton: the coarse start failed\n");
            return 1;
        }
        printf("coarse start (the library on %d grids from %d^2, interpolated): %lld steps, %.2f s, "
               "counted in each method's seconds\n",
               levels - 1, n / 2, (long long)coarse_steps, t_coarse);
    }
    const double area_ref = first_load ? area_first : area_lib, t_ref = first_load ? t_first : t_lib;

    /* the stiffness on the half spectrum, and the stencil's scale c0: least squares in the relative
     * error of c0 lambda^2 against k(q), lambda = 4 - 2 cos qx - 2 cos qy */
    r2c = fftw_plan_dft_r2c_2d(n, n, trial, spec, FFTW_MEASURE);
    c2r = fftw_plan_dft_c2r_2d(n, n, spec, gt, FFTW_MEASURE);
    double s1 = 0.0, s2 = 0.0, lo = INFINITY, hi = 0.0; /* lo, hi: the range of lambda^2 / k */
    for (int i = 0; i < n; i++)
        for (int j = 0; j <= n / 2; j++) {
            const double qy = 2 * M_PI * (i <= n / 2 ? i : i - n) / n, qx = 2 * M_PI * j / n, q = hypot(qx, qy);
            double f = 1.0;
            if (q > 0 && gfmd_green_factor(GFMD_GREEN_LAYER_FLUID, q * 4.0 * W, 0.0, &f) != GFMD_OK) return 1;
            const double k = q > 0 ? q / (2 * f) : 0.0, lam = 4 - 2 * cos(qx) - 2 * cos(qy);
            kq[(size_t)i * (n / 2 + 1) + j] = k / (double)N;
            if (q > 0) {
                const double y = lam * lam / k;
                s1 += y, s2 += y * y;
                lo = fmin(lo, y), hi = fmax(hi, y);
            }
        }
    c0 = s1 / s2; /* the stencil c0 L^2's symbol is then c0 lo .. c0 hi of k(q) */
    /* the multigrid levels, each with its dirty marks for mg_update */
    if (mg_alloc(n)) {
        fprintf(stderr, "stencil_newton: out of memory\n");
        return 1;
    }
    for (int l = 0; l < nl; l++)
        if (!(dirty[l] = calloc((size_t)lv[l].m * lv[l].m, 1))) {
            fprintf(stderr, "stencil_newton: out of memory\n");
            return 1;
        }
    /* the bare pair, timed */
    memcpy(trial, z0, N * sizeof(double));
    const double t_pair = pair_seconds(r2c, c2r, trial, spec, gt);

    sigma = first_load ? sigma0 : sigma1;
    const double scale = tol * (fabs(sigma) + gam / rho_ + 1e-8);
    int fail = 0;
    printf("stencil c0 L^2, c0 = %.4e, its symbol %.2f-%.2f of k(q); V(%d,%d)-cycles on %d grids, l1-Jacobi\n", c0,
           c0 * lo, c0 * hi, nu, nu, nl);
    surface cur = {u, g, e}, tri = {trial, gt, et};
    for (int k = 0; k < n_methods; k++) {
        const int fire = methods[k] == 1, pcg = methods[k] == 2;
        memcpy(cur.u, start, N * sizeof(double));
        memset(held, 0, N);
        pairs = 0, cycles = 0, t_cycles = 0.0;
        long newton_steps = 0, cg_its = 0, trials = 0, rows = 0, edges = 0, negatives = 0;
        double radius = trust * rho_;
        double t_assembly = 0.0, res = 0.0;
        int first = 1;
        /* FIRE's state (the library's control, fire_control.hpp: dt a fraction of the unit step
         * 1/sqrt(lambda_max(V K_FF)), growing by 1.1 after 5 downhill steps, halved uphill) */
        double *vel = d, lambda = 0.0, fdt = 0.5, alpha = 0.1;
        long positive = 0;
        memset(vel, 0, N * sizeof(double));
        /* the projected CG's state: its direction (in vel) restarts after a step the wall stopped */
        double rz_prev = 0.0;
        int fresh = 1;
        t0 = now();
        double energy = gradient(cur.u, cur.g, cur.e);
        for (;;) {
            double r2 = 0.0;
            size_t count = 0;
            for (size_t p = 0; p < N; p++) {
                const int wall = cur.u[p] - h[p] <= 0.0;
                const double gp = wall ? fmin(cur.g[p], 0.0) : cur.g[p];
                r2 += gp * gp;
                was[p] = held[p];
                held[p] = wall && cur.g[p] >= 0.0;
                if (!first && held[p] != was[p]) changed[count++] = p;
            }
            res = sqrt(r2 / (double)N);
            if (res <= scale || newton_steps >= (fire || pcg ? 1000000 : 200)) break;
            newton_steps++;
            if (verbose)
                fprintf(stderr, "%s step %ld: residual %.3e, %zu held points changed; %ld CG its, %ld trials so far\n",
                        NAMES[methods[k]], newton_steps, res / scale * tol, count, cg_its, trials);
            const double ta = now();
            if (first || count > N / 16) {
                mg_assemble();
                rows += (long)N;
            } else rows += (long)mg_update(changed, count, dirty);
            t_assembly += now() - ta;
            first = 0;
            if (pcg) {
                for (size_t p = 0; p < N; p++) r[p] = held[p] ? 0.0 : -cur.g[p];
                const mgreal *v = precondition(r);
                double rz = 0.0;
                for (size_t p = 0; p < N; p++) rz += r[p] * v[p];
                rz /= c0;
                const double beta = (fresh || count > 0 || !(rz_prev > 0)) ? 0.0 : rz / rz_prev;
                double rt = 0.0;
                for (size_t p = 0; p < N; p++) {
                    vel[p] = held[p] ? 0.0 : v[p] / c0 + beta * vel[p];
                    rt += r[p] * vel[p];
                }
                if (!(rt > 0)) {
                    rt = rz;
                    for (size_t p = 0; p < N; p++) vel[p] = held[p] ? 0.0 : v[p] / c0;
                }
                rz_prev = rz;
                stiffness(vel, kp); /* t.K.t (the library: half a pair, by Parseval) */
                double tkt = 0.0, tat = 0.0;
                for (size_t p = 0; p < N; p++) {
                    tkt += vel[p] * kp[p];
                    if (gam > 0) tat += (gam / (rho_ * rho_)) * cur.e[p] * vel[p] * vel[p];
                }
                /* a step the wall did not stop minimizes the quadratic energy along t: not checked (as the
                 * library's) */
                size_t hits = 0;
                double predicted;
                search(&cur, &tri, vel, (tkt - tat > 0) ? rt / (tkt - tat) : rt / tkt, 1e-12, gam == 0, &energy,
                       &trials, &hits, &predicted);
                fresh = hits > 0;
                continue;
            }
            if (fire) {
                if (lambda == 0.0) lambda = lambda_max(pp, kp);
                double power = 0.0, v2 = 0.0;
                for (size_t p = 0; p < N; p++) {
                    power -= held[p] ? 0.0 : cur.g[p] * vel[p];
                    v2 += vel[p] * vel[p];
                    r[p] = held[p] ? 0.0 : -cur.g[p];
                }
                int uphill = 0;
                if (power > 0) {
                    if (++positive > 5) fdt = fmin(fdt * 1.1, 1.0), alpha *= 0.99;
                } else positive = 0, fdt *= 0.5, alpha = 0.1, uphill = 1;
                const mgreal *a = precondition(r);
                double a2 = 0.0;
                for (size_t p = 0; p < N; p++) a2 += (double)a[p] * a[p];
                const double dt = fdt / sqrt(lambda), a_norm = sqrt(a2) / c0;
                const double mix = (a_norm > 0 && !uphill) ? alpha * sqrt(v2) / a_norm : 0.0,
                             keep = uphill ? 0.0 : 1.0 - alpha, back = uphill ? 0.5 * dt : 0.0;
                for (size_t p = 0; p < N; p++) { /* the library's mass_update */
                    const double ai = held[p] ? 0.0 : a[p] / c0, vi = keep * vel[p] + (mix + dt) * ai,
                                 zn = cur.u[p] - back * vel[p] + dt * vi;
                    vel[p] = zn < h[p] ? 0.0 : vi;
                    cur.u[p] = zn < h[p] ? h[p] : zn;
                }
                energy = gradient(cur.u, cur.g, cur.e);
                continue;
            }
            int boundary = 0, negative = 0;
            cg_its += newton_direction(cur.g, cur.e, trust > 0 ? radius : 0.0, d, r, pp, kp, &boundary, &negative);
            /* the search along d, cut at the substrate */
            const double before = energy;
            double predicted;
            size_t hits;
            const double alpha = search(&cur, &tri, d, 1.0, 1e-6, 0, &energy, &trials, &hits, &predicted);
            if (verbose)
                fprintf(stderr, "  alpha %.3g, energy %.6e -> %.6e, predicted %.3e%s%s, radius %.3g\n", alpha, before,
                        energy, predicted, negative ? ", negative curvature" : "", boundary ? ", at the edge" : "",
                        radius);
            edges += boundary, negatives += negative;
            if (trust > 0) { /* the radius: doubled after a full step to its edge, else the step taken */
                double dmax = 0.0;
                for (size_t p = 0; p < N; p++) dmax = fmax(dmax, fabs(d[p]));
                if (alpha == 1.0 && boundary) radius *= 2.0;
                else if (alpha < 1.0) radius = fmax(alpha * dmax, trust_min * rho_);
            }
        }
        const double t_newton = now() - t0 + t_coarse;
        /* against the library's equilibrium */
        size_t contacts = 0;
        double dz = 0.0;
        for (size_t p = 0; p < N; p++) {
            contacts += cur.u[p] - h[p] <= 0.0;
            dz = fmax(dz, fabs(cur.u[p] - ref[p]));
        }
        const double area = (double)contacts / (double)N;
        printf("%s: %ld steps, %ld CG its, %ld line-search trials, %ld FFT pairs, %ld V-cycles, %ld rows assembled; "
               "A/A0 = %.6f, max |z - z_library| = %.1e\n",
               NAMES[methods[k]], newton_steps, cg_its, trials, pairs, cycles, rows, area, dz);
        if (trust > 0 && methods[k] == 0)
            printf("  %ld steps at the trust region's edge, %ld of them at non-positive curvature\n", edges, negatives);
        printf("  pair %.3e s; %s %.2f s = %.0f pairs (FFT pairs %.0f, cycles %.2f s = %.0f, assembly %.2f s = %.0f, "
               "the rest %.0f); library %.2f s = %.0f pairs: %.2fx\n",
               t_pair, NAMES[methods[k]], t_newton, t_newton / t_pair, (double)pairs, t_cycles, t_cycles / t_pair,
               t_assembly,
               t_assembly / t_pair, (t_newton - t_coarse - t_cycles - t_assembly) / t_pair - (double)pairs, t_ref, t_ref / t_pair,
               t_ref / t_newton);
        if (!(res <= scale))
            fprintf(stderr, "stencil_newton: %s not converged (residual %g > %g)\n", NAMES[methods[k]], res, scale),
                fail = 1;
        if (!(fabs(area - area_ref) <= 1e-3 * area_ref))
            fprintf(stderr, "stencil_newton: A/A0 %g against the library's %g\n", area, area_ref), fail = 1;
        /* with adhesion the energy is not convex: two methods may stop in different local minima (at
         * 2048^2, W = 0.088, the Newton method's surface differed from the library's by 0.77 a at
         * one patch, A/A0 by 1e-5 relative), so there the surface is printed, not checked */
        if (!(dz <= 1e-3) && gam == 0) fprintf(stderr, "stencil_newton: the surface differs by %g a\n", dz), fail = 1;
    }
    double *const arrays[] = {hh, cur.u, z0, z1, zf, cur.g, cur.e, d, r, pp, kp, tri.u, tri.g, tri.e, kq};
    for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; k++) fftw_free(arrays[k]);
    fftw_free(spec);
    fftw_destroy_plan(r2c);
    fftw_destroy_plan(c2r);
    fftw_cleanup();
    for (int l = 0; l < nl; l++) free(dirty[l]);
    mg_free();
    free(held);
    free(was);
    free(changed);
    return fail;
}
