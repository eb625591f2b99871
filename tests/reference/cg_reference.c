#include "cg_reference.h"

#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/mman.h>

#include "gfmd.h"

void *cg_grid_alloc(size_t bytes) {
    void *p = NULL;
    if (posix_memalign(&p, (size_t)2 << 20, bytes) != 0) return NULL;
#ifdef MADV_HUGEPAGE
    (void)madvise(p, bytes, MADV_HUGEPAGE);
#endif
    memset(p, 0, bytes);
    return p;
}

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* 1/G(q) = q E* / (2 f(q w)); 0 at q = 0 and where f cannot be evaluated */
static double stiffness(int32_t kind, double width, double nu, double e_star, double qx, double qy) {
    double q = sqrt(qx * qx + qy * qy), f = 1.0;
    if (q == 0.0) return 0.0;
    if (kind != GFMD_GREEN_HALFSPACE && gfmd_green_factor(kind, q * width, nu, &f) != GFMD_OK) return 0.0;
    return 0.5 * q * e_star / f;
}

typedef struct {
    int64_t nx, ny, n, nxh;
    double *compliance; /* G(q) on the half-spectrum, 0 at q = 0 */
    double *rbuf;
    fftw_complex *cbuf;
    fftw_plan fwd, bwd;
} conv_t;

/* out = G * in (periodic convolution with the Green's function, zero mean) */
static void convolve(conv_t *c, const double *in, double *out) {
    memcpy(c->rbuf, in, sizeof(double) * (size_t)c->n);
    fftw_execute(c->fwd);
    for (int64_t i = 0; i < c->ny * c->nxh; ++i) {
        double g = c->compliance[i] / (double)c->n;
        c->cbuf[i][0] *= g;
        c->cbuf[i][1] *= g;
    }
    fftw_execute(c->bwd);
    memcpy(out, c->rbuf, sizeof(double) * (size_t)c->n);
}

cg_result cg_solve(int64_t nx, int64_t ny, double lx, double ly, const double *h, int32_t kind, double width,
                   double nu, double e_star, double sigma0, double tol, int64_t max_iter, double *p_out,
                   double *gap_out) {
    cg_options opt = {tol, max_iter, 0.0, 1, FFTW_ESTIMATE, 0.0, 0.0};
    return cg_solve_opts(nx, ny, lx, ly, h, kind, width, nu, e_star, sigma0, &opt, p_out, gap_out);
}

cg_result cg_solve_opts(int64_t nx, int64_t ny, double lx, double ly, const double *h, int32_t kind, double width,
                        double nu, double e_star, double sigma0, const cg_options *opt, double *p_out, double *gap_out) {
    conv_t c = {nx, ny, nx * ny, nx / 2 + 1, NULL, NULL, NULL, NULL, NULL};
    int64_t n = c.n;
    const double tol = opt->tol;
    const int64_t max_iter = opt->max_iter;
    c.compliance = cg_grid_alloc(sizeof(double) * (size_t)(c.ny * c.nxh));
    c.rbuf = cg_grid_alloc(sizeof(double) * (size_t)n);
    c.cbuf = cg_grid_alloc(sizeof(fftw_complex) * (size_t)(c.ny * c.nxh));
    if (opt->threads > 1) {
        fftw_init_threads();
        fftw_plan_with_nthreads(opt->threads);
    }
    c.fwd = fftw_plan_dft_r2c_2d((int)ny, (int)nx, c.rbuf, c.cbuf, opt->fftw_flags);
    c.bwd = fftw_plan_dft_c2r_2d((int)ny, (int)nx, c.cbuf, c.rbuf, opt->fftw_flags);
    if (opt->threads > 1) fftw_plan_with_nthreads(1);
    for (int64_t ky = 0; ky < ny; ++ky)
        for (int64_t kx = 0; kx < c.nxh; ++kx) {
            double qx = 2.0 * M_PI * (double)kx / lx;
            double qy = 2.0 * M_PI * (double)((2 * ky > ny) ? ky - ny : ky) / ly;
            double k = stiffness(kind, width, nu, e_star, qx, qy);
            c.compliance[ky * c.nxh + kx] = (k > 0.0) ? 1.0 / k : 0.0;
        }

    const size_t bytes = sizeof(double) * (size_t)n;
    double *p = cg_grid_alloc(bytes), *pold = cg_grid_alloc(bytes);
    double *u = cg_grid_alloc(bytes), *g = cg_grid_alloc(bytes);
    double *t = cg_grid_alloc(bytes), *r = cg_grid_alloc(bytes);
    for (int64_t i = 0; i < n; ++i) p[i] = sigma0;
    double g_old = 1.0;
    int delta = 0;
    cg_result res = {0, 0, 0, 0, 0, 0.0, -1.0, -1};
    const double t0 = now();
    for (res.iterations = 0; res.iterations < max_iter; ++res.iterations) {
        /* gap up to the rigid-body approach: g = u - h, shifted to zero mean on the contact set */
        convolve(&c, p, u);
        double gbar = 0.0;
        int64_t nc = 0;
        for (int64_t i = 0; i < n; ++i) {
            g[i] = u[i] - h[i];
            if (p[i] > 0.0) {
                gbar += g[i];
                ++nc;
            }
        }
        gbar /= (double)nc;
        double gnorm = 0.0;
        for (int64_t i = 0; i < n; ++i) {
            g[i] -= gbar;
            if (p[i] > 0.0) gnorm += g[i] * g[i];
        }
        /* conjugate direction on the contact set */
        for (int64_t i = 0; i < n; ++i) t[i] = (p[i] > 0.0) ? g[i] + (delta ? gnorm / g_old : 0.0) * t[i] : 0.0;
        g_old = gnorm;
        convolve(&c, t, r);
        double rbar = 0.0;
        for (int64_t i = 0; i < n; ++i)
            if (p[i] > 0.0) rbar += r[i];
        rbar /= (double)nc;
        double num = 0.0, den = 0.0;
        for (int64_t i = 0; i < n; ++i)
            if (p[i] > 0.0) {
                r[i] -= rbar;
                num += g[i] * t[i];
                den += r[i] * t[i];
            }
        double tau = (den != 0.0) ? num / den : 0.0;
        memcpy(pold, p, sizeof(double) * (size_t)n);
        for (int64_t i = 0; i < n; ++i) {
            if (p[i] > 0.0) p[i] -= tau * t[i];
            if (p[i] < 0.0) p[i] = 0.0;
        }
        /* points out of contact that penetrate join the contact set */
        int overlap = 0;
        for (int64_t i = 0; i < n; ++i)
            if (p[i] == 0.0 && pold[i] == 0.0 && g[i] < 0.0) {
                p[i] -= tau * g[i];
                overlap = 1;
            }
        delta = !overlap;
        double mean = 0.0;
        for (int64_t i = 0; i < n; ++i) mean += p[i];
        mean /= (double)n;
        double change = 0.0;
        for (int64_t i = 0; i < n; ++i) {
            p[i] *= sigma0 / mean;
            change += fabs(p[i] - pold[i]);
        }
        double elapsed = now() - t0;
        if (opt->target_area > 0.0) {
            int64_t k = 0;
            for (int64_t i = 0; i < n; ++i) k += p[i] > 0.0;
            int inside = fabs((double)k / (double)n - opt->target_area) <= opt->target_band * opt->target_area;
            if (!inside) {
                res.seconds_to_target = -1.0;
                res.iterations_to_target = -1;
            } else if (res.seconds_to_target < 0.0) {
                res.seconds_to_target = elapsed;
                res.iterations_to_target = res.iterations + 1;
            }
        }
        if (change / (sigma0 * (double)n) < tol) {
            res.converged = 1;
            ++res.iterations;
            break;
        }
        if (opt->max_seconds > 0.0 && elapsed > opt->max_seconds) {
            ++res.iterations;
            break;
        }
    }
    res.seconds = now() - t0;
    /* observables of the final pressure */
    convolve(&c, p, u);
    double dbar = 0.0, ubar = 0.0, hbar = 0.0;
    int64_t nc = 0;
    for (int64_t i = 0; i < n; ++i) {
        ubar += u[i];
        hbar += h[i];
        if (p[i] > 0.0) {
            dbar += h[i] - u[i];
            ++nc;
        }
    }
    dbar /= (double)nc;
    ubar /= (double)n;
    hbar /= (double)n;
    double el = 0.0, gsum = 0.0;
    for (int64_t i = 0; i < n; ++i) {
        double gi = dbar + u[i] - h[i];
        if (p[i] > 0.0 || gi < 0.0) gi = 0.0; /* in contact; or penetration at the tolerance level */
        gsum += gi;
        el += p[i] * (u[i] - ubar);
        if (gap_out) gap_out[i] = gi;
        if (p_out) p_out[i] = p[i];
    }
    res.rel_area = (double)nc / (double)n;
    res.mean_gap = gsum / (double)n;
    res.elastic = 0.5 * el * lx * ly / (double)n;

    fftw_destroy_plan(c.fwd);
    fftw_destroy_plan(c.bwd);
    free(c.rbuf);
    free(c.cbuf);
    free(c.compliance);
    free(p);
    free(pold);
    free(u);
    free(g);
    free(t);
    free(r);
    return res;
}
