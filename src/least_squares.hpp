// Linear least squares (LAPACKE_dgels): min ||A x - b|| for a column-major m x n A of full rank.
#ifndef GFMD_SRC_LEAST_SQUARES_HPP
#define GFMD_SRC_LEAST_SQUARES_HPP

#include <cstdint>

namespace gfmd {

// Writes x (n values) only on success; returns the residual sum of squares.  Throws gfmd::Error.
double least_squares(int64_t m, int64_t n, const double *a, const double *b, double *x);

}  // namespace gfmd

#endif
