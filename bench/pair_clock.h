/* The timing programs' yardstick: one bare out-of-place r2c + c2r FFT pair, as the library's
 * step does it, timed by seconds_each (bench_clock.h).  Not part of the library. */
#ifndef GFMD_BENCH_PAIR_CLOCK_H
#define GFMD_BENCH_PAIR_CLOCK_H

#include <fftw3.h>

#include "bench_clock.h"

typedef struct {
    fftw_plan r2c, c2r;
    double *in, *out;
    fftw_complex *spec;
} bare_pair;

static inline void bare_pair_run(void *ctx) {
    const bare_pair *p = (const bare_pair *)ctx;
    fftw_execute_dft_r2c(p->r2c, p->in, p->spec);
    fftw_execute_dft_c2r(p->c2r, p->spec, p->out);
}

/* seconds per bare pair */
static inline double pair_seconds(fftw_plan r2c, fftw_plan c2r, double *in, fftw_complex *spec, double *out) {
    bare_pair p = {r2c, c2r, in, out, spec};
    return seconds_each(bare_pair_run, &p);
}

#endif
