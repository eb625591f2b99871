#include "observables.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <complex>
#include <string>

#include "error.hpp"
#include "green.hpp"

namespace gfmd {

double contact_area(const FftGrid &grid, const ForceState &forces) {
    return static_cast<double>(forces.contacts) / static_cast<double>(grid.real_size());
}

double mean_gap(const FftGrid &grid, const Fields &fields) {
    const double *z = fields.z.data(), *h = fields.h.data();
    const auto s = grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
        double t = 0.0;
        for (int64_t i = i0; i < i1; ++i) t += z[i] - h[i];
        acc[0] += t;
    });
    return s[0] / static_cast<double>(grid.real_size());
}

void gap(const Fields &fields, double *out) {
    for (std::size_t i = 0; i < fields.z.size(); ++i) out[i] = fields.z[i] - fields.h[i];
}

void pressure(const Params &p, const Fields &fields, double *out) {
    const double adh_coef = (p.gamma0 > 0.0) ? p.gamma0 / p.rho : 0.0;
    for (std::size_t i = 0; i < fields.z.size(); ++i) {
        const double g = fields.z[i] - fields.h[i];
        const double pull = (adh_coef > 0.0) ? adh_coef * std::exp(-g / p.rho) : 0.0;
        const double contact = (g <= 0.0) ? std::max(-fields.f[i], 0.0) : 0.0;
        out[i] = contact - pull;
    }
}

double persson_variance(const FftGrid &grid, const Body &body, const Fields &fields, const double *h) {
    // In full contact the surface follows the substrate, so the stress modes are sigma(q) =
    // h(q)/G(q) with h(q) the normalized Fourier coefficients; their variance (q != 0, full plane,
    // Parseval) is the width of Persson's pressure distribution at full magnification.
    // h's transform in the solvers' scratch, free between computations (this runs between calls,
    // when the default chooses a solver or a caller asks): a buffer of its own was a transient
    // 8 B/pt on top of the fields (the half-space's peak at 2048^2: 68.4 B/pt against 60.4), and
    // an allocation, with its NOMEM, in a setter.
    assert(!fields.work_holds_z);
    std::complex<double> *hq = fields.work.data();
    grid.forward(h != nullptr ? h : fields.h.data(), hq);
    const int64_t nxh = grid.nxh();
    const double inv_n = 1.0 / static_cast<double>(grid.real_size());
    const double v = grid.sum_mode_rows<1>([&](int64_t r0, int64_t r1, double *acc) {
        double t = 0.0;
        for (int64_t r = r0; r < r1; ++r)
            for (int64_t kx = 0; kx < nxh; ++kx) {
                const std::size_t c = static_cast<std::size_t>(r * nxh + kx);
                const double s = body.stiffness[c] * (std::abs(hq[c]) * inv_n);  // scaled first: no overflow
                t += grid.weight(kx) * s * s;
            }
        acc[0] += t;
    })[0];
    if (!std::isfinite(v)) fail(GFMD_ERR_RANGE, "the full-contact pressure variance overflows double precision");
    return v;
}

double substrate_shortest_wave(const FftGrid &grid, const Fields &fields, const double *h) {
    // A self-affine substrate's roll-off q_s (0.9996-1.0 q_s for H = 0.3-1, lambda_s = 2-8 a,
    // 128^2-2048^2), the grid's corner for one rough down to the grid spacing (a measured
    // topography's noise).  Bisection on the tail's share over h's transform.
    assert(!fields.work_holds_z);
    std::complex<double> *hq = fields.work.data();
    grid.forward(h != nullptr ? h : fields.h.data(), hq);
    const int64_t nxh = grid.nxh();
    const double inv_n = 1.0 / static_cast<double>(grid.real_size());
    const auto slope_above = [&](double qt) {  // the slope variance at |q| > qt
        return grid.sum_mode_rows<1>([&](int64_t r0, int64_t r1, double *acc) {
            double t = 0.0;
            for (int64_t r = r0; r < r1; ++r) {
                const double qy = grid.qy(grid.first_mode_row() + r);
                for (int64_t kx = 0; kx < nxh; ++kx) {
                    const double qx = grid.qx(kx), q2 = qx * qx + qy * qy;
                    const double a = std::abs(hq[static_cast<std::size_t>(r * nxh + kx)]) * inv_n;  // scaled first
                    t += (q2 > qt * qt) ? grid.weight(kx) * q2 * a * a : 0.0;
                }
            }
            acc[0] += t;
        })[0];
    };
    double lo = 0.0, hi = shortest_wave_q(grid);
    const double total = slope_above(0.0);  // all of it (q = 0 carries no slope)
    if (!(total > 0.0) || !std::isfinite(total)) return hi;
    while (hi - lo > 1e-4 * shortest_wave_q(grid)) {
        const double mid = 0.5 * (lo + hi);
        (slope_above(mid) <= 1e-4 * total ? hi : lo) = mid;
    }
    return hi;
}

double persson_contact_area(double variance, double sigma0) {
    if (variance > 0.0) return std::erf(sigma0 / std::sqrt(2.0 * variance));
    return (sigma0 > 0.0) ? 1.0 : 0.0;  // flat substrate: full contact under any load
}

double persson_load(double variance, double area) {
    // erf(10) is 1 to double precision and 1 - area >= 2^-53, so x < 10 (erfc(6) = 2e-17 already).
    // Below 1/2 the test is erf(x) < area; above, the same test as erfc(x) > 1 - area (exact by
    // Sterbenz there), which keeps the digits erf loses near 1.
    const bool upper = area > 0.5;
    const double rest = 1.0 - area;
    double lo = 0.0, hi = 10.0;
    for (;;) {
        const double mid = 0.5 * (lo + hi);
        if (!(mid > lo && mid < hi)) break;  // the bracket is two neighbouring doubles
        if (upper ? std::erfc(mid) > rest : std::erf(mid) < area)
            lo = mid;
        else
            hi = mid;
    }
    const double scale = std::isfinite(2.0 * variance) ? std::sqrt(2.0 * variance) : std::sqrt(2.0) * std::sqrt(variance);
    return 0.5 * (lo + hi) * scale;
}

}  // namespace gfmd
