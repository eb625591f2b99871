/* Independent reference solver for the tests: the constrained conjugate-gradient method of
 * Polonsky & Keer, Wear 231, 206 (1999), on the same periodic grid and Green's function.
 * It iterates on the contact pressure, where GFMD moves the surface: a second algorithm. */
#ifndef GFMD_CG_REFERENCE_H
#define GFMD_CG_REFERENCE_H

#include <stdint.h>

typedef struct {
    double rel_area;   /* fraction of points with p > 0 */
    double mean_gap;   /* <gap> */
    double elastic;    /* (1/2) integral of p (u - <u>) dA */
    int64_t iterations;
    int converged;
} cg_result;

/* Solve for the pressure p >= 0 (mean sigma0) and the gap >= 0 with p * gap = 0.
 * p_out and gap_out (nx*ny, may be NULL) receive the fields. */
cg_result cg_solve(int64_t nx, int64_t ny, double lx, double ly, const double *h, int32_t kind, double width,
                   double nu, double e_star, double sigma0, double tol, int64_t max_iter, double *p_out,
                   double *gap_out);

#endif
