/* A measurement, not part of the library: what one multigrid V(2,2)-cycle (--nu) for a thin sheet's
 * stencil block on the free points would cost beside a bare r2c + c2r FFT pair, done as a C
 * implementation would (bench/two_level_prototype.py --stencil 0 --stencil-mg 2 counts the cycles;
 * docs/performance.md, *What was tried*, a real-space stencil for the sheet between its contacts):
 *   fine grid    the fixed 13-point biharmonic stencil L^2 on the free points (the held points, a
 *                pseudo-random fraction --phi of the grid, held at zero), damped Jacobi;
 *   arithmetic   single precision throughout (stencil_mg.h's mgreal; the coefficients floats);
 *   coarse grids Galerkin operators P^T A P (bilinear P), 25 float coefficients a point, found by
 *                probing with 64 colours of coarse unit vectors (prolong, apply, restrict), down
 *                to 16^2 (the probing is the simple way, not the fast one: its time is printed as
 *                an upper bound of the assembly);
 *   the cycle    two Jacobi sweeps, the residual restricted, the cycle on the next grid, its
 *                correction prolonged, two Jacobi sweeps; 40 Jacobi sweeps on the coarsest grid.
 * It prints the time of the pair, of the Galerkin assembly (once per held set) and of a cycle, both
 * in pairs, and the residual's reduction per cycle from a random right-hand side over 8 cycles;
 * then the same operators assembled directly, row by row (stencil_mg.h's mg_assemble, what
 * stencil_newton uses: it must agree with the probes), and the reduction with its l1-Jacobi
 * smoother instead of the damped one; then every 97th point flipped between held and free and the
 * rows that depend on them recomputed (mg_update: it must equal a whole assembly, bit for bit);
 * the cycle is then timed with those.
 * It fails (exit 1) unless every coarse operator equals P^T A P on a test vector (to the floats'
 * rounding), the direct rows equal the probes' and the cycle reduces the residual with either
 * smoother: colours that collide across the
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

#include "pair_clock.h"

#include "stencil_mg.h"

/* dinv <- 4 / (3 lambda) D^-1 on level l, given D^-1 in dinv: lambda 1.25 times lambda_max(D^-1 A)
 * by 40 power iterations, which approach it from below (a margin, so that the sweeps stay stable) */
static void damp(int l) {
    const size_t mm = (size_t)lv[l].m * lv[l].m;
    mgreal *v = lv[l].r, *av = lv[l].t;
    double lam = 1.0;
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
        for (size_t p = 0; p < mm; p++) v[p] = (mgreal)(av[p] / lam);
    }
    for (size_t p = 0; p < mm; p++) lv[l].dinv[p] *= (mgreal)(4.0 / (3.0 * 1.25 * lam));
}

/* level l+1's coefficients by probing: for each of the 64 colours (I mod 8, J mod 8: the sides are
 * powers of 2, and points of a colour are 8 apart, more than the 5 x 5 stencil spans) the coarse
 * vector e of ones at that colour's points, A_c e = P^T A P e; the entry of coarse point K for the
 * coloured point within its 5 x 5 neighbourhood (if one is) is (A_c e)[K] */
static void galerkin(int l) {
    const int m = lv[l].m, mc = m / 2;
    const size_t mmc = (size_t)mc * mc, mm = (size_t)m * m;
    mgreal *e = lv[l + 1].t, *pe = lv[l].r, *ape = lv[l].t, *out = lv[l + 1].r;
    float *c = lv[l + 1].c;
    const int period = mc < 8 ? mc : 8;
    for (int cy = 0; cy < period; cy++)
        for (int cx = 0; cx < period; cx++) {
            for (int I = 0; I < mc; I++)
                for (int J = 0; J < mc; J++) e[(size_t)I * mc + J] = (I % period == cy && J % period == cx) ? 1.0 : 0.0;
            memset(pe, 0, mm * sizeof(mgreal));
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

static void run_cycle(void *unused) {
    (void)unused;
    cycle(0);
}

/* the residual's reduction a cycle of A x = b over 8 cycles used as a stationary iteration
 * x += V(b - A x) from x = 0 (res: scratch) */
static double cycle_rate(const mgreal *bb, mgreal *x, mgreal *res) {
    const size_t N = (size_t)lv[0].m * lv[0].m;
    double r0 = 0.0, rk = 0.0;
    memset(x, 0, N * sizeof(mgreal));
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
        memcpy(lv[0].b, res, N * sizeof(mgreal));
        cycle(0);
        for (size_t p = 0; p < N; p++) x[p] += lv[0].x[p];
    }
    return pow(rk / r0, 1.0 / 8.0);
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
    if (mg_alloc(n)) {
        fprintf(stderr, "stencil_vcycle_timing: out of memory\n");
        return 1;
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
     * the floats' rounding (1e-5 of |A_c x|: sums of up to 900 terms of relative error 6e-8) */
    for (int l = 0; l + 1 < nl; l++) {
        const int mc = lv[l + 1].m;
        const size_t mmc = (size_t)mc * mc, mm = (size_t)lv[l].m * lv[l].m;
        mgreal *xc = lv[l + 1].x, *yc = lv[l + 1].b, *zc = lv[l + 1].r, *pf = lv[l].x, *apf = lv[l].b;
        for (size_t p = 0; p < mmc; p++) xc[p] = (mgreal)(sin(0.37 * (double)p) + 0.3);
        apply(l + 1, xc, yc);
        memset(pf, 0, mm * sizeof(mgreal));
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
    /* the check: the cycle converges, with the probed operators and damping, then with the direct
     * assembly's (the same operators, to their float rounding) and l1-Jacobi weights */
    mgreal *x = malloc(N * sizeof(mgreal)), *res = malloc(N * sizeof(mgreal)), *bb = malloc(N * sizeof(mgreal));
    for (size_t p = 0; p < N; p++) {
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        bb[p] = held[p] ? 0.0f : (mgreal)((double)(s >> 11) * 0x1.0p-53 - 0.5);
    }
    const double rate = cycle_rate(bb, x, res);
    printf("n = %d, held fraction %.3f, %d grids, one thread: residual reduced %.3f a V(%d,%d)-cycle over 8\n", n, phi,
           nl, rate, nu, nu);
    float *probed[MAXL] = {0};
    for (int l = 1; l < nl; l++) {
        const size_t bytes = (size_t)lv[l].m * lv[l].m * NC * sizeof(float);
        probed[l] = malloc(bytes);
        if (!probed[l]) {
            fprintf(stderr, "stencil_vcycle_timing: out of memory\n");
            return 1;
        }
        memcpy(probed[l], lv[l].c, bytes);
    }
    t0 = now();
    mg_assemble();
    const double t_direct = now() - t0;
    /* the direct rows against the probes: each coefficient to 1e-5 of its row's largest (both float
     * roundings of sums of up to 900 products of exact binary fractions) */
    for (int l = 1; l < nl; l++) {
        const size_t mm = (size_t)lv[l].m * lv[l].m;
        for (size_t p = 0; p < mm; p++) {
            double big = 0.0, diff = 0.0;
            for (int k = 0; k < NC; k++) {
                big = fmax(big, fabs(probed[l][(size_t)k * mm + p]));
                diff = fmax(diff, fabs(probed[l][(size_t)k * mm + p] - lv[l].c[(size_t)k * mm + p]));
            }
            if (!(diff <= 1e-5 * big)) {
                fprintf(stderr, "stencil_vcycle_timing: grid %d, point %zu: the direct row differs from the probes'\n",
                        l, p);
                return 1;
            }
        }
        free(probed[l]);
    }
    const double rate_l1 = cycle_rate(bb, x, res);
    printf("direct assembly %.3e s, l1-Jacobi: residual reduced %.3f a cycle\n", t_direct, rate_l1);
    if (!(rate < 1.0) || !(rate_l1 < 1.0)) {
        fprintf(stderr, "stencil_vcycle_timing: the cycle does not converge (%g, %g a cycle)\n", rate, rate_l1);
        return 1; /* the operating system frees the rest */
    }
    /* the update: a hundredth of the points flipped (held <-> free, every 97th), the rows that
     * depend on them recomputed (mg_update), and every level's operator and weights then equal,
     * bit for bit, to a whole assembly's for the new held set (the same rows from the same inputs) */
    unsigned char *dirty[MAXL] = {0};
    size_t *flipped = malloc((N / 97 + 1) * sizeof(size_t)), count = 0;
    float *kept_c[MAXL] = {0};
    mgreal *kept_d[MAXL] = {0};
    int bad = !flipped;
    for (int l = 0; l < nl && !bad; l++) {
        const size_t mm = (size_t)lv[l].m * lv[l].m;
        dirty[l] = calloc(mm, 1);
        kept_d[l] = malloc(mm * sizeof(mgreal));
        kept_c[l] = l ? malloc(mm * NC * sizeof(float)) : NULL;
        bad = !dirty[l] || !kept_d[l] || (l && !kept_c[l]);
    }
    if (bad) {
        fprintf(stderr, "stencil_vcycle_timing: out of memory\n");
        return 1;
    }
    for (size_t p = 0; p < N; p += 97) {
        held[p] = !held[p];
        flipped[count++] = p;
    }
    t0 = now();
    const size_t rows = mg_update(flipped, count, dirty);
    const double t_update = now() - t0;
    for (int l = 0; l < nl; l++) {
        const size_t mm = (size_t)lv[l].m * lv[l].m;
        memcpy(kept_d[l], lv[l].dinv, mm * sizeof(mgreal));
        if (l) memcpy(kept_c[l], lv[l].c, mm * NC * sizeof(float));
    }
    mg_assemble();
    for (int l = 0; l < nl; l++) {
        const size_t mm = (size_t)lv[l].m * lv[l].m;
        if (memcmp(kept_d[l], lv[l].dinv, mm * sizeof(mgreal)) ||
            (l && memcmp(kept_c[l], lv[l].c, mm * NC * sizeof(float)))) {
            fprintf(stderr, "stencil_vcycle_timing: grid %d after the update differs from a whole assembly\n", l);
            return 1;
        }
        free(dirty[l]);
        free(kept_d[l]);
        free(kept_c[l]);
    }
    free(flipped);
    printf("update after %zu points flipped: %zu rows recomputed in %.3e s, equal to a whole assembly\n", count, rows,
           t_update);
    for (size_t p = 0; p < N; p++) bb[p] = held[p] ? 0.0f : bb[p];
    memcpy(lv[0].b, bb, N * sizeof(mgreal));
    for (int rep = 0; rep < reps; rep++) {
        const double t_pair = pair_seconds(r2c, c2r, fx, fc, fy), t_cycle = seconds_each(run_cycle, NULL);
        printf("pair %.3e s  V-cycle %.3e s = %.2f pairs  Galerkin assembly %.3e s = %.2f pairs, direct %.2f pairs\n",
               t_pair, t_cycle, t_cycle / t_pair, t_assembly, t_assembly / t_pair, t_direct / t_pair);
    }
    fftw_destroy_plan(r2c);
    fftw_destroy_plan(c2r);
    mg_free();
    free(x);
    free(res);
    free(bb);
    fftw_free(fx);
    fftw_free(fy);
    fftw_free(fc);
    free(held);
    fftw_cleanup();
    return 0;
}
