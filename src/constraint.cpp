#include "constraint.hpp"

#include <algorithm>
#include <cmath>

namespace gfmd {

void project_mean(const FftGrid &grid, Fields &fields, double d) {
    double *z = fields.z.data(), *v = fields.v.data();
    const double *h = fields.h.data();
    const double n = static_cast<double>(grid.real_size());
    // mean(max(h, z + c)) >= mean(z) + c: from c = d - mean(z) the mean is at or above d, and
    // Newton's steps on the convex mean(c) approach the root from above.
    const auto m = grid.sum_points<2>([&](int64_t i0, int64_t i1, double *acc) {
        double sz = 0.0, sa = 0.0;
#pragma omp simd reduction(+ : sz, sa)
        for (int64_t i = i0; i < i1; ++i) {
            sz += z[i];
            sa += std::fabs(z[i]);
        }
        acc[0] += sz;
        acc[1] += sa;
    });
    double c = d - m[0] / n;
    // A mean below d by no more than the sum's rounding (sqrt(n) roundings of the size of |z|,
    // with a factor 4) is d: lifting the body by such a c would lift every point the wall holds
    // by 1e-14 off it -- no contact, a mean pressure of zero, every contact force suddenly
    // unbalanced -- which trapped CG on a 128^2 sheet between that state and the right one.
    if (c > 0.0 && c <= 4.0 * 2.220446049250313e-16 * std::sqrt(n) * (m[1] / n)) return;
    // The root to a few roundings of the lengths involved: d, the shift and the heights' mean size
    // (a length of the problem's own: an absolute 1 held the mean to 1e-9 of itself where lengths
    // are 1e-7, SI units on a micrometre cell, and made the trajectory depend on the units).
    const double tol = 4.0 * 2.220446049250313e-16 * (std::fabs(d) + std::fabs(c) + m[1] / n);
    for (int it = 0; it < 100; ++it) {
        const auto s = grid.sum_points<2>([&](int64_t i0, int64_t i1, double *acc) {
            double sum = 0.0, nfree = 0.0;
#pragma omp simd reduction(+ : sum, nfree)
            for (int64_t i = i0; i < i1; ++i) {
                const double y = z[i] + c;
                sum += std::max(h[i], y);
                nfree += (y > h[i]) ? 1.0 : 0.0;
            }
            acc[0] += sum;
            acc[1] += nfree;
        });
        const double excess = s[0] / n - d;
        if (excess <= tol || s[1] == 0.0) break;
        c -= excess * n / s[1];
    }
    grid.for_points([&](int64_t i0, int64_t i1) {
#pragma omp simd
        for (int64_t i = i0; i < i1; ++i) {
            const double y = z[i] + c;
            const bool wall = y <= h[i];
            z[i] = wall ? h[i] : y;
            v[i] = wall ? 0.0 : v[i];
        }
    });
}

}  // namespace gfmd
