/* A measurement, not part of the library: what one multigrid V(2,2)-cycle (--nu) for a thin sheet's
 * stencil block on the free points would cost beside a bare r2c + c2r FFT pair, done as a C
 * implementation would (bench/two_level_prototype.py --stencil 0 --stencil-mg 2 counts the cycles;
 * docs/performance.md, *What was tried*, a real-space stencil for the sheet between its contacts):
 *   fine grid    the fixed 13-point biharmonic stencil L^2 on the free points (the held points, a
 *                pseudo-random fraction --phi of the grid, held at zero), damped Jacobi;
 *   coarse grids Galerkin operators P^T A P (bilinear P), 25 float coefficients a point, found by
 *                probing with 64 colours of coarse unit vectors (prolong, apply, restrict), down
 *                to 16^2 (the probing is the simple way, not the fast one: its time is printed as
 *                an upper bound of the assembly);
 *   the cycle    two Jacobi sweeps, the residual restricted, the cycle on the next grid, its
 *                correction prolonged, two Jacobi sweeps; 40 Jacobi sweeps on the coarsest grid.
 * It prints the time of the pair, of the Galerkin assembly (once per held set) and of a cycle, both
 * in pairs, and the residual's reduction per cycle from a random right-hand side over 8 cycles.
 * It fails (exit 1) unless every coarse operator equals P^T A P on a test vector (to its float
 * coefficients' rounding) and the cycle reduces the residual: colours that collide across the
 * periodic boundary (tried: 5 colours on sides of powers of 2) gave wrong coarse operators and a
 * cycle that diverged on some grids.
 *
 *   stencil_vcycle_timing [--n N] [--phi F] [--reps R] [--nu S]
 *                         (defaults 2048, 0.05, 3, 2; N a power of 2 >= 32; S sweeps: a V(S,S)-cycle)
 *
 * The passes are built for the baseline and for AVX2 + FMA (target_clones on x86-64). */
#include <fftw3.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_clock.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define CLONES __attribute__((target_clones("default", "arch=x86-64-v3")))
#else
#define CLONES
#endif

enum { MAXL = 20, NC = 25 }; /* levels; coarse stencil 5 x 5 */
typedef struct {
    int m;                      /* side */
    float *c;                   /* coarse levels: NC coefficients a point, entry (dy + 2) * 5 + dx + 2 */
    double *x, *b, *r, *t, *dinv; /* solution, right-hand side, residual, scratch, damped 1/diagonal */
} level;
static level lv[MAXL];
static int nl;
static unsigned char *held; /* fine grid: 1 where the wall holds the point */
static int nu = 2;          /* Jacobi sweeps before and after the coarse correction (--nu) */

static inline int wrap(int i, int m) { return i & (m - 1); } /* m a power of 2 */

/* y = A x on level l (A: masked L^2 on the fine grid, the 25-point operator on coarse ones); with
 * b and dinv given, y = x + dinv (b - A x) instead: a Jacobi sweep in the same pass.  Rows in
 * order, the interior of each row in a loop without branches (it vectorizes), its two ends
 * wrapped. */
CLONES static void apply_fine(int m, const double *x, double *y, const double *b, const double *dinv) {
    for (int i = 0; i < m; i++) {
        const double *rm2 = x + (size_t)wrap(i - 2, m) * m, *rm1 = x + (size_t)wrap(i - 1, m) * m,
                     *r0 = x + (size_t)i * m, *rp1 = x + (size_t)wrap(i + 1, m) * m,
                     *rp2 = x + (size_t)wrap(i + 2, m) * m;
        const unsigned char *h = held + (size_t)i * m;
        double *yr = y + (size_t)i * m;
        const double *br = b ? b + (size_t)i * m : NULL, *dr = b ? dinv + (size_t)i * m : NULL;
        for (int j = 0; j < m; j++) {
            if (j == 2) j = (m > 4) ? m - 2 : j; /* the interior below */
            const int jm2 = wrap(j - 2, m), jm1 = wrap(j - 1, m), jp1 = wrap(j + 1, m), jp2 = wrap(j + 2, m);
            const double s = 20 * r0[j] - 8 * (r0[jm1] + r0[jp1] + rm1[j] + rp1[j]) + r0[jm2] + r0[jp2] + rm2[j] +
                             rp2[j] + 2 * (rm1[jm1] + rm1[jp1] + rp1[jm1] + rp1[jp1]);
            const double a = h[j] ? 0.0 : s;
            yr[j] = b ? r0[j] + dr[j] * (br[j] - a) : a;
        }
        if (b) {
            for (int j = 2; j < m - 2; j++) {
                const double s = 20 * r0[j] - 8 * (r0[j - 1] + r0[j + 1] + rm1[j] + rp1[j]) + r0[j - 2] + r0[j + 2] +
                                 rm2[j] + rp2[j] + 2 * (rm1[j - 1] + rm1[j + 1] + rp1[j - 1] + rp1[j + 1]);
                yr[j] = r0[j] + dr[j] * (br[j] - (h[j] ? 0.0 : s));
            }
        } else {
            for (int j = 2; j < m - 2; j++) {
                const double s = 20 * r0[j] - 8 * (r0[j - 1] + r0[j + 1] + rm1[j] + rp1[j]) + r0[j - 2] + r0[j + 2] +
                                 rm2[j] + rp2[j] + 2 * (rm1[j - 1] + rm1[j + 1] + rp1[j - 1] + rp1[j + 1]);
                yr[j] = h[j] ? 0.0 : s;
            }
        }
    }
}

/* the coarse operator: coefficient k of point p at c[k * m^2 + p] (25 planes, so that the row loop
 * vectorizes), entry k = (dy + 2) * 5 + dx + 2 */
CLONES static void apply_coarse(int m, const float *c, const double *x, double *y, const double *b,
                                const double *dinv) {
    const size_t mm = (size_t)m * m;
    for (int i = 0; i < m; i++) {
        double *yr = y + (size_t)i * m;
        for (int j = 0; j < m; j++) yr[j] = 0.0;
        for (int a = -2; a <= 2; a++) {
            const double *row = x + (size_t)wrap(i + a, m) * m;
            for (int e = -2; e <= 2; e++) {
                const float *ck = c + (size_t)((a + 2) * 5 + e + 2) * mm + (size_t)i * m;
                yr[0] += ck[0] * row[wrap(e, m)];
                yr[1] += ck[1] * row[wrap(1 + e, m)];
                for (int j = 2; j < m - 2; j++) yr[j] += (double)ck[j] * row[j + e];
                yr[m - 2] += ck[m - 2] * row[wrap(m - 2 + e, m)];
                yr[m - 1] += ck[m - 1] * row[wrap(m - 1 + e, m)];
            }
        }
        if (b) {
            const double *xr = x + (size_t)i * m, *br = b + (size_t)i * m, *dr = dinv + (size_t)i * m;
            for (int j = 0; j < m; j++) yr[j] = xr[j] + dr[j] * (br[j] - yr[j]);
        }
    }
}

static void apply(int l, const double *x, double *y) {
    if (l == 0) apply_fine(lv[l].m, x, y, NULL, NULL);
    else apply_coarse(lv[l].m, lv[l].c, x, y, NULL, NULL);
}

/* coarse (side m/2) <- P^T fine (side m): bilinear weights 1, 1/2, 1/4 */
CLONES static void restrict_to(int l, const double *f, double *c) {
    const int m = lv[l].m, mc = m / 2;
    for (int I = 0; I < mc; I++)
        for (int J = 0; J < mc; J++) {
            double s = 0.0;
            for (int a = -1; a <= 1; a++)
                for (int e = -1; e <= 1; e++) {
                    const double wgt = (a ? 0.5 : 1.0) * (e ? 0.5 : 1.0);
                    s += wgt * f[(size_t)wrap(2 * I + a, m) * m + wrap(2 * J + e, m)];
                }
            c[(size_t)I * mc + J] = s;
        }
}

/* fine (side m) += P coarse; on the fine grid the held points stay zero */
CLONES static void prolong_add(int l, const double *c, double *f) {
    const int m = lv[l].m, mc = m / 2;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < m; j++) {
            const size_t p = (size_t)i * m + j;
            if (l == 0 && held[p]) continue;
            const int I0 = i / 2, J0 = j / 2, I1 = (i % 2) ? wrap(I0 + 1, mc) : I0, J1 = (j % 2) ? wrap(J0 + 1, mc) : J0;
            const double *r0 = c + (size_t)I0 * mc, *r1 = c + (size_t)I1 * mc;
            f[p] += 0.25 * (r0[J0] + r0[J1] + r1[J0] + r1[J1]);
        }
}

/* x <- x + D^-1 (b - A x) (D^-1 damped), `sweeps` times, each one pass into t, then swapped */
static void jacobi(int l, int sweeps) {
    for (int s = 0; s < sweeps; s++) {
        if (l == 0) apply_fine(lv[l].m, lv[l].x, lv[l].t, lv[l].b, lv[l].dinv);
        else apply_coarse(lv[l].m, lv[l].c, lv[l].x, lv[l].t, lv[l].b, lv[l].dinv);
        double *x = lv[l].x;
        lv[l].x = lv[l].t;
        lv[l].t = x;
    }
}

/* dinv <- 4 / (3 lambda) D^-1 on level l, given D^-1 in dinv: lambda 1.25 times lambda_max(D^-1 A)
 * by 40 power iterations, which approach it from below (a margin, so that the sweeps stay stable) */
static void damp(int l) {
    const size_t mm = (size_t)lv[l].m * lv[l].m;
    double *v = lv[l].r, *av = lv[l].t, lam = 1.0;
    for (size_t p = 0; p < mm; p++) v[p] = (lv[l].dinv[p] > 0) ? 1.0 + 0.5 * sin((double)p) : 0.0;
    for (int it = 0; it < 40; it++) {
        apply(l, v, av);
        double n2 = 0.0;
        for (size_t p = 0; p < mm; p++) {
            av[p] *= lv[l].dinv[p];
            n2 += av[p] * av[p];
        }
        lam = sqrt(n2);
        if (!(lam > 0)) return;
        for (size_t p = 0; p < mm; p++) v[p] = av[p] / lam;
    }
    for (size_t p = 0; p < mm; p++) lv[l].dinv[p] *= 4.0 / (3.0 * 1.25 * lam);
}

/* the first sweep from x = 0: x = D^-1 b, no operator to apply (the same bits as a sweep) */
CLONES static void first_sweep(int l) {
    const size_t mm = (size_t)lv[l].m * lv[l].m;
    for (size_t p = 0; p < mm; p++) lv[l].x[p] = lv[l].dinv[p] * lv[l].b[p];
}

static void cycle(int l) {
    const size_t mm = (size_t)lv[l].m * lv[l].m;
    first_sweep(l);
    if (l == nl - 1) {
        jacobi(l, 39);
        return;
    }
    jacobi(l, nu - 1);
    apply(l, lv[l].x, lv[l].t);
    for (size_t p = 0; p < mm; p++) lv[l].r[p] = lv[l].b[p] - lv[l].t[p];
    restrict_to(l, lv[l].r, lv[l + 1].b);
    cycle(l + 1);
    prolong_add(l, lv[l + 1].x, lv[l].x);
    jacobi(l, nu);
}

/* level l+1's coefficients by probing: for each of the 64 colours (I mod 8, J mod 8: the sides are
 * powers of 2, and points of a colour are 8 apart, more than the 5 x 5 stencil spans) the coarse
 * vector e of ones at that colour's points, A_c e = P^T A P e; the entry of coarse point K for the
 * coloured point within its 5 x 5 neighbourhood (if one is) is (A_c e)[K] */
static void galerkin(int l) {
    const int m = lv[l].m, mc = m / 2;
    const size_t mmc = (size_t)mc * mc, mm = (size_t)m * m;
    double *e = lv[l + 1].t, *pe = lv[l].r, *ape = lv[l].t, *out = lv[l + 1].r;
    float *c = lv[l + 1].c;
    const int period = mc < 8 ? mc : 8;
    for (int cy = 0; cy < period; cy++)
        for (int cx = 0; cx < period; cx++) {
            for (int I = 0; I < mc; I++)
                for (int J = 0; J < mc; J++) e[(size_t)I * mc + J] = (I % period == cy && J % period == cx) ? 1.0 : 0.0;
            memset(pe, 0, mm * sizeof(double));
            prolong_add(l, e, pe);
            apply(l, pe, ape);
            restrict_to(l, ape, out);
            for (int I = 0; I < mc; I++)
                for (int J = 0; J < mc; J++) {
                    /* the coloured coarse point in K's neighbourhood: offset d in -2..2 with (K + d) % 5 == colour */
                    const int a = ((cy - I) % period + period + period / 2) % period - period / 2,
                              b = ((cx - J) % period + period + period / 2) % period - period / 2;
                    if (a >= -2 && a <= 2 && b >= -2 && b <= 2)
                        c[(size_t)((a + 2) * 5 + b + 2) * mmc + (size_t)I * mc + J] = (float)out[(size_t)I * mc + J];
                }
        }
    for (size_t p = 0; p < mmc; p++) {
        const double d = c[12 * mmc + p];
        lv[l + 1].dinv[p] = d > 0 ? 1.0 / d : 0.0;
    }
    damp(l + 1);
}

int main(int argc, char **argv) {
    int n = 2048, reps = 3;
    double phi = 0.05;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--n") && i + 1 < argc) n = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--phi") && i + 1 < argc) phi = atof(argv[++i]);
        else if (!strcmp(argv[i], "--reps") && i + 1 < argc) reps = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--nu") && i + 1 < argc) nu = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: %s [--n N] [--phi F] [--reps R] [--nu S]\n", argv[0]);
            return 2;
        }
    }
    if (n < 32 || (n & (n - 1)) || !(phi >= 0.0 && phi < 1.0) || reps < 1 || nu < 1 || nu > 8) {
        fprintf(stderr, "stencil_vcycle_timing: N a power of 2 >= 32, 0 <= F < 1, R >= 1, 1 <= S <= 8\n");
        return 2;
    }
    for (int m = n; m >= 16; m /= 2) {
        if (nl == MAXL) break;
        const size_t mm = (size_t)m * m;
        level *L = &lv[nl++];
        L->m = m;
        L->x = fftw_alloc_real(mm);
        L->b = fftw_alloc_real(mm);
        L->r = fftw_alloc_real(mm);
        L->t = fftw_alloc_real(mm);
        L->dinv = fftw_alloc_real(mm);
        L->c = (m < n) ? malloc(mm * NC * sizeof(float)) : NULL;
        if (!L->x || !L->b || !L->r || !L->t || !L->dinv || (m < n && !L->c)) {
            fprintf(stderr, "stencil_vcycle_timing: out of memory\n");
            return 1;
        }
    }
    const size_t N = (size_t)n * n;
    held = malloc(N);
    double *fx = fftw_alloc_real(N), *fy = fftw_alloc_real(N);
    fftw_complex *fc = fftw_alloc_complex((size_t)n * (n / 2 + 1));
    if (!held || !fx || !fy || !fc) {
        fprintf(stderr, "stencil_vcycle_timing: out of memory\n");
        return 1;
    }
    uint64_t s = 88172645463325252ull; /* xorshift64 */
    for (size_t p = 0; p < N; p++) {
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        held[p] = (double)(s >> 11) * 0x1.0p-53 < phi;
        lv[0].dinv[p] = held[p] ? 0.0 : 1.0 / 20.0;
        fx[p] = (double)(s >> 11) * 0x1.0p-53;
    }
    fftw_plan r2c = fftw_plan_dft_r2c_2d(n, n, fx, fc, FFTW_MEASURE);
    fftw_plan c2r = fftw_plan_dft_c2r_2d(n, n, fc, fy, FFTW_MEASURE);
    /* the operators, timed */
    double t0 = now();
    damp(0);
    for (int l = 0; l + 1 < nl; l++) galerkin(l);
    const double t_assembly = now() - t0;
    /* the check of the assembly: A_c x = P^T A P x on every coarse grid for a pseudo-random x, to
     * the float coefficients' rounding (1e-5 of |A_c x|: 25 terms of relative error 6e-8) */
    for (int l = 0; l + 1 < nl; l++) {
        const int mc = lv[l + 1].m;
        const size_t mmc = (size_t)mc * mc, mm = (size_t)lv[l].m * lv[l].m;
        double *xc = lv[l + 1].x, *yc = lv[l + 1].b, *zc = lv[l + 1].r, *pf = lv[l].x, *apf = lv[l].b;
        for (size_t p = 0; p < mmc; p++) xc[p] = sin(0.37 * (double)p) + 0.3;
        apply(l + 1, xc, yc);
        memset(pf, 0, mm * sizeof(double));
        prolong_add(l, xc, pf);
        apply(l, pf, apf);
        restrict_to(l, apf, zc);
        double e2 = 0.0, y2 = 0.0;
        for (size_t p = 0; p < mmc; p++) {
            e2 += (yc[p] - zc[p]) * (yc[p] - zc[p]);
            y2 += yc[p] * yc[p];
        }
        if (!(sqrt(e2) <= 1e-5 * sqrt(y2))) {
            fprintf(stderr, "stencil_vcycle_timing: grid %d's operator is not P^T A P (%g relative)\n", l + 1,
                    sqrt(e2 / y2));
            return 1;
        }
    }
    /* the check: the residual of A x = b (b random on the free points) over 8 cycles used as a
     * stationary iteration x += V(b - A x) */
    double *x = fftw_alloc_real(N), *res = fftw_alloc_real(N), *bb = fftw_alloc_real(N);
    for (size_t p = 0; p < N; p++) {
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        bb[p] = held[p] ? 0.0 : (double)(s >> 11) * 0x1.0p-53 - 0.5;
        x[p] = 0.0;
    }
    double r0 = 0.0, rk = 0.0;
    for (int k = 0; k <= 8; k++) {
        apply(0, x, res);
        double r2 = 0.0;
        for (size_t p = 0; p < N; p++) {
            res[p] = bb[p] - res[p];
            r2 += res[p] * res[p];
        }
        if (k == 0) r0 = sqrt(r2);
        rk = sqrt(r2);
        if (k == 8) break;
        memcpy(lv[0].b, res, N * sizeof(double));
        cycle(0);
        for (size_t p = 0; p < N; p++) x[p] += lv[0].x[p];
    }
    const double rate = pow(rk / r0, 1.0 / 8.0);
    printf("n = %d, held fraction %.3f, %d grids, one thread: residual reduced %.3f a V(%d,%d)-cycle over 8\n", n, phi,
           nl, rate, nu, nu);
    if (!(rate < 1.0)) {
        fprintf(stderr, "stencil_vcycle_timing: the cycle does not converge (%g a cycle)\n", rate);
        return 1; /* the operating system frees the rest */
    }
    memcpy(lv[0].b, bb, N * sizeof(double));
    for (int rep = 0; rep < reps; rep++) {
        int k = 0;
        t0 = now();
        do {
            fftw_execute_dft_r2c(r2c, fx, fc); /* out of place, as the library's step */
            fftw_execute_dft_c2r(c2r, fc, fy);
            k++;
        } while (now() - t0 < 0.5);
        const double t_pair = (now() - t0) / k;
        k = 0;
        t0 = now();
        do {
            cycle(0);
            k++;
        } while (now() - t0 < 0.5);
        const double t_cycle = (now() - t0) / k;
        printf("pair %.3e s  V-cycle %.3e s = %.2f pairs  Galerkin assembly %.3e s = %.2f pairs\n", t_pair, t_cycle,
               t_cycle / t_pair, t_assembly, t_assembly / t_pair);
    }
    fftw_destroy_plan(r2c);
    fftw_destroy_plan(c2r);
    for (int l = 0; l < nl; l++) {
        fftw_free(lv[l].x);
        fftw_free(lv[l].b);
        fftw_free(lv[l].r);
        fftw_free(lv[l].t);
        fftw_free(lv[l].dinv);
        free(lv[l].c);
    }
    fftw_free(x);
    fftw_free(res);
    fftw_free(bb);
    fftw_free(fx);
    fftw_free(fy);
    fftw_free(fc);
    free(held);
    fftw_cleanup();
    return 0;
}
