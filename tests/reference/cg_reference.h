/* Independent reference solver for the tests and the benchmark: the constrained conjugate-gradient
 * method of Polonsky & Keer, Wear 231, 206 (1999), on the same periodic grid and Green's function
 * as the library.  It iterates on the contact pressure, where GFMD moves the surface: a second
 * algorithm.  Uses FFTW directly and, from the library, only gfmd_green_factor(). */
#ifndef GFMD_CG_REFERENCE_H
#define GFMD_CG_REFERENCE_H

#include <stddef.h>
#include <stdint.h>

/* Grid memory as the library takes it (2 MiB aligned, transparent huge pages on request where the
 * kernel has them), zeroed; free() releases it; NULL if there is none.  The reference and the
 * benchmark's bare transforms use it, so that they run on the same kind of pages as the library. */
void *cg_grid_alloc(size_t bytes);

typedef struct {
    double rel_area;   /* fraction of points with p > 0 */
    double mean_gap;   /* <gap> */
    double elastic;    /* (1/2) integral of p (u - <u>) dA */
    int64_t iterations;
    int converged;     /* the relative pressure change fell below tol */
    double seconds;    /* wall time of the iterations */
    /* With a target area: the time and iteration after which A/A0 stayed within target_band
     * (relative) of target_area until the end; -1 if it never settled. */
    double seconds_to_target;
    int64_t iterations_to_target;
} cg_result;

typedef struct {
    double tol;            /* stop when sum |p - p_old| / sum p < tol */
    int64_t max_iter;
    double max_seconds;    /* 0: no limit */
    int threads;           /* FFTW threads (1 in the tests) */
    unsigned fftw_flags;   /* FFTW_ESTIMATE in the tests */
    double target_area;    /* 0: none */
    double target_band;
} cg_options;

/* Solve for p >= 0 (mean sigma0) and gap >= 0 with p * gap = 0 for a body of the given kind
 * (GFMD_GREEN_*, width, nu) with modulus e_star.  p_out, gap_out (nx*ny) may be NULL. */
cg_result cg_solve_opts(int64_t nx, int64_t ny, double lx, double ly, const double *h, int32_t kind, double width,
                        double nu, double e_star, double sigma0, const cg_options *opt, double *p_out, double *gap_out);

/* The tests' form: one thread, FFTW_ESTIMATE, no time limit. */
cg_result cg_solve(int64_t nx, int64_t ny, double lx, double ly, const double *h, int32_t kind, double width,
                   double nu, double e_star, double sigma0, double tol, int64_t max_iter, double *p_out,
                   double *gap_out);

#endif
