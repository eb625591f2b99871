/* A measurement, not part of the library: what one coarse solve of the two-level preconditioner
 * (bench/two_level_prototype.py, docs/performance.md *What was tried*, a coarse space at the
 * contacts' spacing) would cost beside a bare r2c + c2r FFT pair, done the way a C implementation
 * would do it:
 *   restriction  y = Z (f x): bilinear hats of a grid coarsened 4 times (7-point weights per
 *                direction, applied separably), f the free points' mask;
 *   coarse solve Jacobi-preconditioned CG, a fixed number of iterations, on an operator with a 7x7
 *                stencil of float coefficients per coarse point (what the windowed kernel R = 8 and
 *                c = 4 give: 49 entries a row);
 *   prolongation x = f Z^T c, separably.
 * It prints, per repetition, the times of the pair and of each part, and the solve in pairs.
 * Before timing it checks its own parts (exit 1 if not): the restriction and the prolongation are
 * adjoint (<Z f x, c> = <x, f Z^T c> to 1e-12 relative) and the stencil product equals the
 * product with the stencil indexed modulo the grid, at every coarse point.
 *
 *   coarse_solve_timing [--n N] [--its K] [--reps R]   (defaults 2048, 3, 3; N a multiple of 4)
 *
 * The coarse operator's values are arbitrary (diagonally dominant): the time does not depend on
 * them.  The passes are built for the baseline and for AVX2 + FMA (target_clones on x86-64). */
#include <fftw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_clock.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define CLONES __attribute__((target_clones("default", "arch=x86-64-v3")))
#else
#define CLONES
#endif

enum { C = 4, H = 3, S = 2 * H + 1 }; /* coarsening, stencil half-width, stencil side */
static const double w[2 * C - 1] = {0.25, 0.5, 0.75, 1.0, 0.75, 0.5, 0.25};
static int n, nc, np_; /* fine side, coarse side, padded coarse side */

/* y = Z (f x); t: n x nc */
CLONES static void restrict_free(const double *x, const unsigned char *f, double *m, double *t, double *y) {
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) m[j + C] = f[(size_t)i * n + j] ? x[(size_t)i * n + j] : 0.0;
        for (int j = 0; j < C; j++) {
            m[j] = m[n + j];
            m[n + C + j] = m[C + j];
        }
        for (int J = 0; J < nc; J++) {
            const double *q = m + C + C * J - (C - 1);
            double s = 0.0;
            for (int d = 0; d < 2 * C - 1; d++) s += w[d] * q[d];
            t[(size_t)i * nc + J] = s;
        }
    }
    memset(y, 0, sizeof(double) * (size_t)nc * nc);
    for (int i = 0; i < n; i++) {
        const int I0 = i / C, r = i % C;
        const double *tr = t + (size_t)i * nc;
        double *y0 = y + (size_t)I0 * nc, a = w[C - 1 + r];
        for (int J = 0; J < nc; J++) y0[J] += a * tr[J];
        if (r) {
            double *y1 = y + (size_t)((I0 + 1) % nc) * nc, b = w[r - 1];
            for (int J = 0; J < nc; J++) y1[J] += b * tr[J];
        }
    }
}

/* x = f Z^T c */
CLONES static void prolong_free(const double *c, const unsigned char *f, double *t, double *x) {
    for (int i = 0; i < n; i++) {
        const int I0 = i / C, r = i % C;
        const double *c0 = c + (size_t)I0 * nc, *c1 = c + (size_t)((I0 + 1) % nc) * nc;
        const double a = w[C - 1 + r], b = r ? w[r - 1] : 0.0;
        for (int J = 0; J < nc; J++) t[(size_t)i * nc + J] = a * c0[J] + b * c1[J];
    }
    for (int i = 0; i < n; i++) {
        const double *tr = t + (size_t)i * nc;
        for (int J = 0; J < nc; J++) {
            const double c0 = tr[J], c1 = tr[(J + 1) % nc];
            for (int k = 0; k < C; k++) {
                const size_t p = (size_t)i * n + (size_t)C * J + k;
                x[p] = f[p] ? (1.0 - 0.25 * k) * c0 + 0.25 * k * c1 : 0.0;
            }
        }
    }
}

static void pad(const double *p, double *pp) {
    for (int I = -H; I < nc + H; I++)
        for (int J = -H; J < nc + H; J++) pp[(size_t)(I + H) * np_ + J + H] = p[(size_t)((I + nc) % nc) * nc + (J + nc) % nc];
}

/* y = A p, A's S x S stencil per coarse point in floats */
CLONES static void matvec(const float *A, const double *p, double *pp, double *y) {
    pad(p, pp);
    for (int I = 0; I < nc; I++)
        for (int J = 0; J < nc; J++) {
            const float *a = A + ((size_t)I * nc + J) * S * S;
            double s = 0.0;
            for (int u = 0; u < S; u++) {
                const double *row = pp + (size_t)(I + u) * np_ + J;
                for (int v = 0; v < S; v++) s += a[u * S + v] * row[v];
            }
            y[(size_t)I * nc + J] = s;
        }
}

/* its iterations of Jacobi-preconditioned CG on A x = b from 0 */
CLONES static void jacobi_cg(const float *A, const double *dinv, const double *b, double *x, double *r, double *p,
                             double *pp, double *Ap, int its) {
    const size_t m = (size_t)nc * nc;
    double ry = 0.0;
    for (size_t k = 0; k < m; k++) {
        x[k] = 0.0;
        r[k] = b[k];
        p[k] = dinv[k] * r[k];
        ry += r[k] * p[k];
    }
    for (int it = 0; it < its; it++) {
        matvec(A, p, pp, Ap);
        double pAp = 0.0, ry_new = 0.0;
        for (size_t k = 0; k < m; k++) pAp += p[k] * Ap[k];
        const double alpha = ry / pAp;
        for (size_t k = 0; k < m; k++) {
            x[k] += alpha * p[k];
            r[k] -= alpha * Ap[k];
            ry_new += r[k] * dinv[k] * r[k];
        }
        const double beta = ry_new / ry;
        ry = ry_new;
        for (size_t k = 0; k < m; k++) p[k] = dinv[k] * r[k] + beta * p[k];
    }
}

static int self_check(const double *x, const unsigned char *f, const float *A, double *m, double *t, double *y,
                      double *c, double *x2, double *pp, double *Ap) {
    restrict_free(x, f, m, t, y);
    for (size_t k = 0; k < (size_t)nc * nc; k++) c[k] = sin(0.37 * (double)k);
    prolong_free(c, f, t, x2);
    double lhs = 0.0, rhs = 0.0, scale = 0.0;
    for (size_t k = 0; k < (size_t)nc * nc; k++) lhs += y[k] * c[k];
    for (size_t k = 0; k < (size_t)n * n; k++) {
        rhs += x[k] * x2[k];
        scale += fabs(x[k] * x2[k]);
    }
    if (fabs(lhs - rhs) > 1e-12 * scale) {
        fprintf(stderr, "restriction and prolongation not adjoint: %.17g against %.17g\n", lhs, rhs);
        return 1;
    }
    matvec(A, c, pp, Ap);
    for (int I = 0; I < nc; I++)
        for (int J = 0; J < nc; J++) {
            double s = 0.0;
            for (int u = 0; u < S; u++)
                for (int v = 0; v < S; v++)
                    s += A[((size_t)I * nc + J) * S * S + u * S + v] * c[(size_t)((I + u - H + nc) % nc) * nc + (J + v - H + nc) % nc];
            if (fabs(s - Ap[(size_t)I * nc + J]) > 1e-12 * (fabs(s) + 1.0)) {
                fprintf(stderr, "stencil product wrong at (%d, %d)\n", I, J);
                return 1;
            }
        }
    return 0;
}

int main(int argc, char **argv) {
    int its = 3, reps = 3;
    n = 2048;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--n") && i + 1 < argc) n = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--its") && i + 1 < argc) its = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--reps") && i + 1 < argc) reps = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: %s [--n N] [--its K] [--reps R]\n", argv[0]);
            return 2;
        }
    }
    if (n < 8 * C || n % C || its < 1 || reps < 1) {
        fprintf(stderr, "need N >= 32 a multiple of 4, K >= 1, R >= 1\n");
        return 2;
    }
    nc = n / C;
    np_ = nc + 2 * H;
    const size_t fine = (size_t)n * n, coarse = (size_t)nc * nc;
    double *x = fftw_alloc_real(fine), *x2 = fftw_alloc_real(fine);
    fftw_complex *X = fftw_alloc_complex((size_t)n * (n / 2 + 1));
    double *t = malloc(sizeof(double) * (size_t)n * nc), *m = malloc(sizeof(double) * (size_t)(n + 2 * C));
    unsigned char *f = malloc(fine);
    float *A = malloc(sizeof(float) * coarse * S * S);
    double *dinv = malloc(sizeof(double) * coarse), *b = malloc(sizeof(double) * coarse), *cx = malloc(sizeof(double) * coarse),
           *r = malloc(sizeof(double) * coarse), *p = malloc(sizeof(double) * coarse), *Ap = malloc(sizeof(double) * coarse),
           *pp = malloc(sizeof(double) * (size_t)np_ * np_);
    if (!x || !x2 || !X || !t || !m || !f || !A || !dinv || !b || !cx || !r || !p || !Ap || !pp) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    srand(1);
    for (size_t k = 0; k < fine; k++) {
        x[k] = rand() / (double)RAND_MAX;
        f[k] = (rand() % 20) != 0; /* 5 % of the points held, as at the thin sheets' low loads */
    }
    for (size_t k = 0; k < coarse * S * S; k++)
        A[k] = (k % (S * S) == (S * S) / 2) ? 10.0f : -0.1f * (float)(rand() / (double)RAND_MAX);
    for (size_t k = 0; k < coarse; k++) dinv[k] = 0.1;
    if (self_check(x, f, A, m, t, b, cx, x2, pp, Ap)) return 1;

    fftw_plan fwd = fftw_plan_dft_r2c_2d(n, n, x2, X, FFTW_MEASURE), bwd = fftw_plan_dft_c2r_2d(n, n, X, x2, FFTW_MEASURE);
    printf("coarse solve at %d^2 (coarse %d^2, 7x7 float stencil, %d Jacobi-CG iterations), one thread\n", n, nc, its);
    for (int rep = 0; rep < reps; rep++) {
        const int k = 10;
        double t0 = now();
        for (int i = 0; i < k; i++) {
            fftw_execute(fwd);
            fftw_execute(bwd);
        }
        const double t_pair = (now() - t0) / k;
        t0 = now();
        for (int i = 0; i < k; i++) restrict_free(x, f, m, t, b);
        const double t_restrict = (now() - t0) / k;
        t0 = now();
        for (int i = 0; i < k; i++) jacobi_cg(A, dinv, b, cx, r, p, pp, Ap, its);
        const double t_cg = (now() - t0) / k;
        t0 = now();
        for (int i = 0; i < k; i++) prolong_free(cx, f, t, x2);
        const double t_prolong = (now() - t0) / k;
        const double solve = t_restrict + t_cg + t_prolong;
        printf("pair %.3e s  restrict %.3e s  Jacobi-CG %.3e s  prolong %.3e s  solve %.3e s = %.2f pairs\n", t_pair,
               t_restrict, t_cg, t_prolong, solve, solve / t_pair);
    }
    fftw_destroy_plan(fwd);
    fftw_destroy_plan(bwd);
    fftw_free(x);
    fftw_free(x2);
    fftw_free(X);
    free(t);
    free(m);
    free(f);
    free(A);
    free(dinv);
    free(b);
    free(cx);
    free(r);
    free(p);
    free(Ap);
    free(pp);
    return 0;
}
