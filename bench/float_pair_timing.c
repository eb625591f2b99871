/* A measurement, not part of the library: what an FFT pair in single precision would cost beside
 * the library's double pair, for the offset form of single precision that docs/performance.md
 * (*What was tried*, single precision) weighs: the elastic stress of a continuing load as
 * K z_ref (double, once per load) + K dz, with dz = z - z_ref rounded to float and K dz transformed
 * in float (bench/float_offset_prototype.py measures its error).  Timed, alternating, one thread,
 * FFTW_MEASURE plans of the library's layout (out-of-place r2c into the half spectrum, c2r back):
 *   double  the r2c + c2r pair on doubles, as the library's step does it;
 *   float   the same pair with fftwf on floats;
 *   convert the pass the offset form adds in front of the float pair: dz = (float)(z - z_ref)
 *           (reads 16 bytes a point, writes 4), and the one behind it, K z_ref + (double)K dz
 *           (reads 12, writes 8), together.
 * It prints, per repetition, each time and the float pair, and the pair with both passes, in
 * double pairs.  The passes are built for the baseline and for AVX2 + FMA (target_clones on x86-64),
 * as the library's are.  Before timing it checks both pairs (exit 1 if not): a random field transformed
 * forth and back comes back to 1e-12 (double) and 1e-6 (float) of its rms.
 *
 *   float_pair_timing [--n N] [--reps R]   (defaults 2048 and 3; N >= 8 and even) */
#include <fftw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pair_clock.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define CLONES __attribute__((target_clones("default", "arch=x86-64-v3")))
#else
#define CLONES
#endif

/* rms of (back / n^2 - x) over rms of x */
static double round_trip_error_d(fftw_plan r2c, fftw_plan c2r, double *x, fftw_complex *c, double *back, size_t m) {
    fftw_execute_dft_r2c(r2c, x, c);
    fftw_execute_dft_c2r(c2r, c, back);
    double e = 0.0, s = 0.0;
    for (size_t i = 0; i < m; i++) {
        const double d = back[i] / (double)m - x[i];
        e += d * d;
        s += x[i] * x[i];
    }
    return sqrt(e / s);
}

static double round_trip_error_f(fftwf_plan r2c, fftwf_plan c2r, float *x, fftwf_complex *c, float *back, size_t m) {
    fftwf_execute_dft_r2c(r2c, x, c);
    fftwf_execute_dft_c2r(c2r, c, back);
    double e = 0.0, s = 0.0;
    for (size_t i = 0; i < m; i++) {
        const double d = (double)back[i] / (double)m - (double)x[i];
        e += d * d;
        s += (double)x[i] * (double)x[i];
    }
    return sqrt(e / s);
}

/* the offset form's two passes: dz = (float)(z - zref) before the float pair, and
 * f = kzref + (double)kdz after it */
CLONES static void convert(const double *z, const double *zref, float *dz, const double *kzref, const float *kdz, double *f,
                    size_t m) {
    for (size_t i = 0; i < m; i++) dz[i] = (float)(z[i] - zref[i]);
    for (size_t i = 0; i < m; i++) f[i] = kzref[i] + (double)kdz[i];
}

/* the parts timed beside the double pair: the float pair, and the two passes around it */
typedef struct {
    fftwf_plan r2c, c2r;
    float *dz, *kdz;
    fftwf_complex *spec;
    const double *z, *zref, *kzref;
    double *f;
    size_t m;
} float_parts;

static void float_pair_run(void *ctx) {
    const float_parts *p = (const float_parts *)ctx;
    fftwf_execute_dft_r2c(p->r2c, p->dz, p->spec);
    fftwf_execute_dft_c2r(p->c2r, p->spec, p->kdz);
}

static void convert_run(void *ctx) {
    const float_parts *p = (const float_parts *)ctx;
    convert(p->z, p->zref, p->dz, p->kzref, p->kdz, p->f, p->m);
}

int main(int argc, char **argv) {
    int n = 2048, reps = 3;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--n") && i + 1 < argc) n = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--reps") && i + 1 < argc) reps = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: %s [--n N] [--reps R]\n", argv[0]);
            return 2;
        }
    }
    if (n < 8 || n % 2 || reps < 1) {
        fprintf(stderr, "float_pair_timing: N must be even and >= 8, R >= 1\n");
        return 2;
    }
    const size_t m = (size_t)n * (size_t)n, mc = (size_t)n * (size_t)(n / 2 + 1);
    double *z = fftw_alloc_real(m), *zref = fftw_alloc_real(m), *kzref = fftw_alloc_real(m), *f = fftw_alloc_real(m),
           *back = fftw_alloc_real(m);
    fftw_complex *c = fftw_alloc_complex(mc);
    float *dz = fftwf_alloc_real(m), *kdz = fftwf_alloc_real(m);
    fftwf_complex *cf = fftwf_alloc_complex(mc);
    if (!z || !zref || !kzref || !f || !back || !c || !dz || !kdz || !cf) {
        fprintf(stderr, "float_pair_timing: out of memory\n");
        return 1;
    }
    fftw_plan r2c = fftw_plan_dft_r2c_2d(n, n, z, c, FFTW_MEASURE);
    fftw_plan c2r = fftw_plan_dft_c2r_2d(n, n, c, back, FFTW_MEASURE);
    fftwf_plan r2cf = fftwf_plan_dft_r2c_2d(n, n, dz, cf, FFTW_MEASURE);
    fftwf_plan c2rf = fftwf_plan_dft_c2r_2d(n, n, cf, kdz, FFTW_MEASURE);
    if (!r2c || !c2r || !r2cf || !c2rf) {
        fprintf(stderr, "float_pair_timing: FFTW planning failed\n");
        return 1;
    }
    srand(1);
    for (size_t i = 0; i < m; i++) {
        zref[i] = 20.0 * rand() / (double)RAND_MAX;
        z[i] = zref[i] + 0.1 * (rand() / (double)RAND_MAX - 0.5);
        dz[i] = (float)(z[i] - zref[i]);
        kzref[i] = 0.0;
    }
    const double ed = round_trip_error_d(r2c, c2r, z, c, back, m);
    const double ef = round_trip_error_f(r2cf, c2rf, dz, cf, kdz, m);
    printf("n = %d, one thread, FFTW_MEASURE; round trip: double %.1e, float %.1e of the rms\n", n, ed, ef);
    if (!(ed < 1e-12) || !(ef < 1e-6)) {
        fprintf(stderr, "float_pair_timing: a round trip is off (double %g, float %g)\n", ed, ef);
        return 1;
    }
    for (int rep = 0; rep < reps; rep++) {
        /* each part repeated for at least half a second, the three alternating */
        float_parts parts = {r2cf, c2rf, dz, kdz, cf, z, zref, kzref, f, m};
        const double t[3] = {pair_seconds(r2c, c2r, z, c, back), seconds_each(float_pair_run, &parts),
                             seconds_each(convert_run, &parts)};
        printf("double pair %.3e s  float pair %.3e s  convert %.3e s  float %.2f pairs, with convert %.2f pairs\n",
               t[0], t[1], t[2], t[1] / t[0], (t[1] + t[2]) / t[0]);
    }
    fftw_destroy_plan(r2c);
    fftw_destroy_plan(c2r);
    fftwf_destroy_plan(r2cf);
    fftwf_destroy_plan(c2rf);
    fftw_free(z);
    fftw_free(zref);
    fftw_free(kzref);
    fftw_free(f);
    fftw_free(back);
    fftw_free(c);
    fftwf_free(dz);
    fftwf_free(kdz);
    fftwf_free(cf);
    return 0;
}
