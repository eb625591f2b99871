#include "cg_reference.h"

#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test_support.h"

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
    conv_t c = {nx, ny, nx * ny, nx / 2 + 1, NULL, NULL, NULL, NULL, NULL};
    int64_t n = c.n;
    c.compliance = malloc(sizeof(double) * (size_t)(c.ny * c.nxh));
    c.rbuf = fftw_alloc_real((size_t)n);
    c.cbuf = fftw_alloc_complex((size_t)(c.ny * c.nxh));
    c.fwd = fftw_plan_dft_r2c_2d((int)ny, (int)nx, c.rbuf, c.cbuf, FFTW_ESTIMATE);
    c.bwd = fftw_plan_dft_c2r_2d((int)ny, (int)nx, c.cbuf, c.rbuf, FFTW_ESTIMATE);
    for (int64_t ky = 0; ky < ny; ++ky)
        for (int64_t kx = 0; kx < c.nxh; ++kx) {
            double k = ts_stiffness(kind, width, nu, e_star, ts_qx(kx, nx, lx), ts_qy(ky, ny, ly));
            c.compliance[ky * c.nxh + kx] = (k > 0.0) ? 1.0 / k : 0.0;
        }

    double *p = malloc(sizeof(double) * (size_t)n), *pold = malloc(sizeof(double) * (size_t)n);
    double *u = malloc(sizeof(double) * (size_t)n), *g = malloc(sizeof(double) * (size_t)n);
    double *t = calloc((size_t)n, sizeof(double)), *r = malloc(sizeof(double) * (size_t)n);
    for (int64_t i = 0; i < n; ++i) p[i] = sigma0;
    double g_old = 1.0;
    int delta = 0;
    cg_result res = {0, 0, 0, 0, 0};
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
        if (change / (sigma0 * (double)n) < tol) {
            res.converged = 1;
            break;
        }
    }
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
    fftw_free(c.rbuf);
    fftw_free(c.cbuf);
    free(c.compliance);
    free(p);
    free(pold);
    free(u);
    free(g);
    free(t);
    free(r);
    return res;
}
