#include "green.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "error.hpp"
#include "gfmd.h"

namespace gfmd {

namespace {

// The closed forms below are written with x = 2t.  For x < 2 they cancel (fluid denominator,
// bonded numerator at nu -> 1/2), so they are summed as power series with the leading powers
// factored out; for x >= 2 they are divided by e^x/2 so that nothing overflows up to t = 1e308.
// Once e^-x underflows to 0 (x > 745) they are 1 exactly, and are set so: x^2 e^-x would be
// inf * 0 from x = 1.3e154 on (and 2t is inf beyond DBL_MAX/2).
constexpr double kSeriesLimit = 2.0;

// (sinh x - x)/x^3 = sum_{k>=1} x^(2k-2)/(2k+1)!  ->  returns sum_{k>=1} x^(2k)/(2k+1)!
double sinh_tail(double x2) {
    double term = x2 / 6.0, sum = 0.0;
    for (int k = 1; k < 40 && term > 1e-18 * (sum + 1e-300); ++k) {
        sum += term;
        term *= x2 / ((2.0 * k + 2.0) * (2.0 * k + 3.0));
    }
    return sum;
}

// (cosh x - 1 - x^2/2)/x^4 = sum_{k>=2} x^(2k-4)/(2k)!
double cosh_tail_over_x4(double x2) {
    double term = 1.0 / 24.0, sum = 0.0;
    for (int k = 2; k < 40 && term > 1e-18 * sum; ++k) {
        sum += term;
        term *= x2 / ((2.0 * k + 1.0) * (2.0 * k + 2.0));
    }
    return sum;
}

// Layer on a fluid foundation (the seed paper, Putignano, Dapp & Müser 2016, Eq. 4):
// f(t) = (sinh 2t + 2t) / (cosh 2t - 1 - 2t^2).  Returns numerator and denominator scaled alike.
void fluid_parts(double t, double &num, double &den) {
    const double x = 2.0 * t;
    if (x < kSeriesLimit) {
        const double x2 = x * x;
        num = 2.0 + sinh_tail(x2);               // (sinh x + x)/x
        den = x * x * x * cosh_tail_over_x4(x2);  // (cosh x - 1 - x^2/2)/x
    } else if (const double e = std::exp(-x); e > 0.0) {
        num = 1.0 - e * e + 2.0 * x * e;          // (sinh x + x) 2 e^-x
        den = 1.0 + e * e - (2.0 + x * x) * e;    // (cosh x - 1 - x^2/2) 2 e^-x
    } else {
        num = 1.0;
        den = 1.0;
    }
}

// Layer bonded to a rigid foundation, kappa = 3 - 4 nu (Carbone & Mangialardi, JMPS 56, 684 (2008)):
// f_b(t) = (kappa sinh 2t - 2t) / (kappa cosh 2t + 2t^2 + (1 + kappa^2)/2).
void bonded_parts(double t, double nu, double &num, double &den) {
    const double x = 2.0 * t;
    const double kappa = 3.0 - 4.0 * nu;
    const double kappa_m1 = 2.0 - 4.0 * nu;  // exact where kappa -> 1 (incompressible)
    if (x < kSeriesLimit) {
        num = x * (kappa_m1 + kappa * sinh_tail(x * x));
        den = kappa * std::cosh(x) + 0.5 * x * x + 0.5 * (1.0 + kappa * kappa);
    } else if (const double e = std::exp(-x); e > 0.0) {
        num = kappa * (1.0 - e * e) - 2.0 * x * e;
        den = kappa * (1.0 + e * e) + (x * x + 1.0 + kappa * kappa) * e;
    } else {
        num = kappa;
        den = kappa;
    }
}

void parts(int32_t kind, double t, double nu, double &num, double &den) {
    if (kind == GFMD_GREEN_LAYER_FLUID) {
        fluid_parts(t, num, den);
    } else if (kind == GFMD_GREEN_LAYER_BONDED) {
        bonded_parts(t, nu, num, den);
    } else {
        num = 1.0;
        den = 1.0;
    }
}

}  // namespace

double green_inverse_factor(int32_t kind, double t, double nu) {
    double num = 1.0, den = 1.0;
    parts(kind, t, nu, num, den);
    return den / num;
}

double green_factor(int32_t kind, double t, double nu) {
    double num = 1.0, den = 1.0;
    parts(kind, t, nu, num, den);
    if (den == 0.0) return std::numeric_limits<double>::infinity();
    return num / den;
}

void validate_green_kind(int32_t kind) {
    if (kind != GFMD_GREEN_HALFSPACE && kind != GFMD_GREEN_LAYER_FLUID && kind != GFMD_GREEN_LAYER_BONDED)
        fail(GFMD_ERR_BAD_ENUM, "unknown Green's function kind " + std::to_string(kind));
}

void validate_poisson(double nu) {
    if (!std::isfinite(nu) || nu <= -1.0 || nu > 0.5)
        fail(GFMD_ERR_INVALID_ARG, "Poisson's ratio must be finite and in (-1, 0.5], got " + std::to_string(nu));
}

namespace {
// The integral of 1/r over [0, x] x [0, y] (signed): x asinh(y/|x|) + y asinh(x/|y|).  The
// logarithms of the textbook form, x ln(y + r) + y ln(x + r), differ from it by terms of x or y
// alone, which cancel in a rectangle's four corners; asinh has neither their cancellation for
// negative y nor their singularity on the axes.
double inverse_r_integral(double x, double y) {
    double s = 0.0;
    if (x != 0.0) s += x * std::asinh(y / std::fabs(x));
    if (y != 0.0) s += y * std::asinh(x / std::fabs(y));
    return s;
}
}  // namespace

double boussinesq_cell(double x, double y, double ax, double ay, double e_star) {
    const double x0 = x - 0.5 * ax, x1 = x + 0.5 * ax, y0 = y - 0.5 * ay, y1 = y + 0.5 * ay;
    const double s = inverse_r_integral(x1, y1) - inverse_r_integral(x0, y1) - inverse_r_integral(x1, y0) +
                     inverse_r_integral(x0, y0);
    return s / (kPi * e_star);
}

Body make_free_body(const FftGrid &grid, double e_star) {
    const int64_t nx = grid.nx(), ny = grid.ny(), nxh = grid.nxh();
    const double ax = grid.lx() / static_cast<double>(nx), ay = grid.ly() / static_cast<double>(ny);
    // The kernel in units of the spacing ax and of E* (K(x, y) = ax/E* K_1(x/ax, y/ax)): its values
    // are those of the grid's shape, whatever the lengths and the modulus; their scale is applied
    // last, where a product that leaves the doubles is the caller's range (a modulus of 1e-310
    // made the kernel itself infinite).
    const double aspect = ay / ax, scale = e_star / ax;  // stiffness = scale / K_1(q)
    if (!(aspect > 0.0) || !std::isfinite(aspect) || !(scale > 0.0) || !std::isfinite(scale))
        fail(GFMD_ERR_RANGE, "the free-boundary stiffness leaves the doubles: E* over the grid spacing, or the "
                             "spacings' ratio, is too large or too small");
    RealBuffer kernel(static_cast<std::size_t>(grid.local_points()));
    ComplexBuffer modes(static_cast<std::size_t>(grid.local_mode_rows() * nxh));
    // offsets in [-n/2, n/2): the one at -n/2 stands for both signs (only offsets below n/2 reach
    // from one point of the region to another)
    const auto offset = [](int64_t i, int64_t n) { return static_cast<double>(i < n / 2 ? i : i - n); };
    for (int64_t y = 0; y < ny; ++y)
        for (int64_t x = 0; x < nx; ++x)
            kernel[static_cast<std::size_t>(y * nx + x)] =
                boussinesq_cell(offset(x, nx), offset(y, ny) * aspect, 1.0, aspect, 1.0);
    grid.forward(kernel.data(), modes.data());
    Body b;
    b.stiffness = RealBuffer(modes.size());
    b.k_min = std::numeric_limits<double>::infinity();
    for (std::size_t c = 0; c < modes.size(); ++c) {
        const double k = modes[c].real();  // the kernel is even in x and y: K(q) is real
        if (!(k > 0.0) || !std::isfinite(k))
            fail(GFMD_ERR_RANGE, "the free-boundary compliance is not positive at one wave vector: the spacings' "
                                 "ratio is too far from 1");
        if (c == 0) {
            b.compliance0 = k / scale;
            b.stiffness[c] = 0.0;  // the uniform mode: the load on the cell moves the body as a whole
            continue;
        }
        b.stiffness[c] = scale / k;
        b.k_min = std::min(b.k_min, b.stiffness[c]);
        b.k_max = std::max(b.k_max, b.stiffness[c]);
    }
    if (!std::isfinite(b.k_max) || !(b.k_min > 0.0) || !std::isfinite(b.compliance0))
        fail(GFMD_ERR_RANGE, "the free-boundary stiffness leaves the doubles: E* is too large or too small for this "
                             "grid");
    return b;
}

Body make_body(const FftGrid &grid, int32_t kind, double width, double e_star, double nu) {
    Body b;
    b.stiffness = RealBuffer(static_cast<std::size_t>(grid.local_mode_rows() * grid.nxh()));
    const int64_t nxh = grid.nxh();
    grid.on_all_ranks([&] {  // an overflow on one rank's modes stops every rank
        for (int64_t r = 0; r < grid.local_mode_rows(); ++r) {
            const double qy = grid.qy(grid.first_mode_row() + r);
            for (int64_t kx = 0; kx < nxh; ++kx) {
                const double qx = grid.qx(kx);
                const double q = std::sqrt(qx * qx + qy * qy);
                double kq = 0.0;  // the uniform mode has no elastic stiffness: force balance sets it
                if (q > 0.0) {
                    const double g = (kind == GFMD_GREEN_HALFSPACE) ? 1.0 : green_inverse_factor(kind, q * width, nu);
                    kq = 0.5 * q * e_star * g;  // 1/G(q) = q E* / (2 f(q w)), the seed paper's Eq. 2
                    if (!std::isfinite(kq)) {
                        char t[32];
                        std::snprintf(t, sizeof t, "%.6g", q * width);
                        fail(GFMD_ERR_RANGE, std::string("the stiffness 1/G(q) overflows at q w = ") + t +
                                                 ": the layer is too thin or too stiff for this grid");
                    }
                }
                b.stiffness[static_cast<std::size_t>(r * nxh + kx)] = kq;
            }
        }
    });
    b.k_min = std::numeric_limits<double>::infinity();
    for (std::size_t c = 0; c < b.stiffness.size(); ++c) {
        if (b.stiffness[c] > 0.0) b.k_min = std::min(b.k_min, b.stiffness[c]);
        b.k_max = std::max(b.k_max, b.stiffness[c]);
    }
    double extremes[2] = {-b.k_min, b.k_max};
    grid.reduce_max(extremes, 2);
    b.k_min = -extremes[0];
    b.k_max = extremes[1];
    if (b.k_max == 0.0) {  // a single grid point, or every mode underflowed: use the cell's scale
        b.k_max = e_star * kPi / std::sqrt(grid.cell_area());
        b.k_min = b.k_max;
    }
    return b;
}

double shortest_wave_q(const FftGrid &grid) {
    const double qx = grid.qx(grid.nx() / 2), qy = grid.qy(grid.ny() / 2);
    return std::sqrt(qx * qx + qy * qy);
}

double long_wave_softness(const FftGrid &grid, const Body &body, double e_star) {
    return 0.5 * e_star * shortest_wave_q(grid) / body.k_min;
}

double longest_wave_softness(const FftGrid &grid, const Body &body, double e_star) {
    // the smallest non-zero |q|: one period along the longer side (a single row or column has none)
    const double inf = std::numeric_limits<double>::infinity();
    const double q = std::min(grid.nx() > 1 ? std::fabs(grid.qx(1)) : inf, grid.ny() > 1 ? std::fabs(grid.qy(1)) : inf);
    return std::isfinite(q) ? 0.5 * e_star * q / body.k_min : 1.0;
}

double stiffest_mode_within(const FftGrid &grid, const Body &body, double q2) {
    const int64_t nxh = grid.nxh();
    const double *stiff = body.stiffness.data();
    double kc = 0.0;
    for (int64_t r = 0; r < grid.local_mode_rows(); ++r) {
        const double qy = grid.qy(grid.first_mode_row() + r);
        for (int64_t kx = 0; kx < nxh; ++kx) {
            const double qx = grid.qx(kx);
            if (qx * qx + qy * qy <= q2) kc = std::max(kc, stiff[static_cast<std::size_t>(r * nxh + kx)]);
        }
    }
    grid.reduce_max(&kc, 1);
    return kc;
}

int contact_octave(int64_t contacts) {
    return (contacts > 0) ? static_cast<int>(std::floor(std::log2(static_cast<double>(contacts)))) : 0;
}

double contact_spacing_q2(const FftGrid &grid, double spacing, double points) {
    const double phi = points / static_cast<double>(grid.real_size());
    return spacing * spacing * 4.0 * kPi * phi / grid.area_per_point();
}

}  // namespace gfmd
