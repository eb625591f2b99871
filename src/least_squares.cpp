// Linear least squares behind the C API: a thin, checked wrapper of LAPACKE_dgels (QR).
#include "least_squares.hpp"

#include <lapacke.h>

#include <climits>
#include <cmath>
#include <string>
#include <vector>

#include "error.hpp"

namespace gfmd {

double least_squares(int64_t m, int64_t n, const double *a, const double *b, double *x) {
    if (n < 1 || m < n)
        fail(GFMD_ERR_INVALID_ARG, "least squares needs m >= n >= 1, got m = " + std::to_string(m) +
                                       ", n = " + std::to_string(n));
    if (m > INT_MAX || m * n > INT_MAX)  // LAPACK's default (LP64) interface indexes with int
        fail(GFMD_ERR_INVALID_ARG, "least squares: m*n = " + std::to_string(m * n) +
                                       " is beyond LAPACK's 32-bit index range");
    const std::size_t mn = static_cast<std::size_t>(m * n), mm = static_cast<std::size_t>(m);
    for (std::size_t i = 0; i < mn; ++i)
        if (!std::isfinite(a[i])) fail(GFMD_ERR_INVALID_ARG, "least squares: A[" + std::to_string(i) + "] is not finite");
    for (std::size_t i = 0; i < mm; ++i)
        if (!std::isfinite(b[i])) fail(GFMD_ERR_INVALID_ARG, "least squares: b[" + std::to_string(i) + "] is not finite");
    std::vector<double> qr(a, a + mn), rhs(b, b + mm);  // dgels overwrites both
    const auto lm = static_cast<lapack_int>(m), ln = static_cast<lapack_int>(n);
    const lapack_int info = LAPACKE_dgels(LAPACK_COL_MAJOR, 'N', lm, ln, 1, qr.data(), lm, rhs.data(), lm);
    if (info > 0)
        fail(GFMD_ERR_INVALID_ARG, "least squares: the matrix is rank deficient (column " + std::to_string(info) +
                                       " depends on the others)");
    if (info < 0) fail(GFMD_ERR_INTERNAL, "LAPACKE_dgels rejected argument " + std::to_string(-info));
    // dgels stops only at an exactly zero pivot; a column that is a combination of the others up
    // to rounding leaves a pivot at the rounding level of the largest one: refuse that too.
    double rmax = 0.0;
    for (std::size_t j = 0; j < static_cast<std::size_t>(n); ++j) rmax = std::fmax(rmax, std::fabs(qr[j * mm + j]));
    const double cut = 64.0 * static_cast<double>(m) * 2.220446049250313e-16 * rmax;
    for (std::size_t j = 0; j < static_cast<std::size_t>(n); ++j)
        if (std::fabs(qr[j * mm + j]) <= cut)
            fail(GFMD_ERR_INVALID_ARG, "least squares: the matrix is rank deficient (column " + std::to_string(j + 1) +
                                           " depends on the others to rounding)");
    double rss = 0.0;  // rows n..m-1 of the transformed right-hand side hold the residual
    for (std::size_t i = static_cast<std::size_t>(n); i < mm; ++i) rss += rhs[i] * rhs[i];
    if (!std::isfinite(rss)) fail(GFMD_ERR_RANGE, "least squares: the residual overflows double precision");
    for (std::size_t j = 0; j < static_cast<std::size_t>(n); ++j)
        if (!std::isfinite(rhs[j])) fail(GFMD_ERR_RANGE, "least squares: the solution overflows double precision");
    for (std::size_t j = 0; j < static_cast<std::size_t>(n); ++j) x[j] = rhs[j];
    return rss;
}

}  // namespace gfmd
