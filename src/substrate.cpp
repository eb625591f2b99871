#include "substrate.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "error.hpp"
#include "rng.hpp"

namespace gfmd {

namespace {

constexpr double kTwoPi = 2.0 * kPi;  // the same double as 2 pi's literal: power-of-two scaling is exact

// Spectrum of a self-affine surface with roll-off (Persson et al., J. Phys.: Condens. Matter 17,
// R1 (2005); the seed paper's Sec. 2.3): flat below q_r, power law q^-2(1+H) up to q_s, zero above.
double spectrum(double q, double q_r, double q_s, double hurst) {
    if (q > q_s * (1.0 + 1e-12)) return 0.0;
    if (q < q_r) return 1.0;
    return std::pow(q / q_r, -2.0 * (1.0 + hurst));
}

}  // namespace

void validate_selfaffine(const FftGrid &grid, const SelfAffineParams &p) {
    if (!std::isfinite(p.hurst) || p.hurst < 0.0 || p.hurst > 1.0)
        fail(GFMD_ERR_INVALID_ARG, "hurst must be finite and in [0, 1], got " + std::to_string(p.hurst));
    if (!std::isfinite(p.rms_gradient) || p.rms_gradient <= 0.0)
        fail(GFMD_ERR_INVALID_ARG, "rms_gradient must be finite and > 0, got " + std::to_string(p.rms_gradient));
    if (!std::isfinite(p.lambda_s) || !std::isfinite(p.lambda_r) || p.lambda_s <= 0.0)
        fail(GFMD_ERR_INVALID_ARG, "lambda_r and lambda_s must be finite and > 0");
    if (p.lambda_r < p.lambda_s)
        fail(GFMD_ERR_INVALID_ARG, "lambda_r must be >= lambda_s");
    const double spacing = std::max(grid.lx() / static_cast<double>(grid.nx()), grid.ly() / static_cast<double>(grid.ny()));
    if (p.lambda_s < 2.0 * spacing * (1.0 - 1e-12))
        fail(GFMD_ERR_INVALID_ARG, "lambda_s = " + std::to_string(p.lambda_s) +
                                       " is below two grid spacings (" + std::to_string(2.0 * spacing) + ")");
    if (p.rms_gradient * std::max(grid.lx(), grid.ly()) > 1e100)
        fail(GFMD_ERR_INVALID_ARG, "rms_gradient times the cell length exceeds 1e100");
    if (p.distribution != GFMD_DIST_UNIFORM && p.distribution != GFMD_DIST_GAUSSIAN)
        fail(GFMD_ERR_BAD_ENUM, "unknown distribution " + std::to_string(p.distribution));
    if (p.lambda_s > std::max(grid.lx(), grid.ly()) * (1.0 + 1e-12))
        fail(GFMD_ERR_INVALID_ARG, "lambda_s exceeds the cell: no Fourier mode has q <= q_s");
}

void generate_selfaffine(const FftGrid &grid, const SelfAffineParams &p, std::complex<double> *work, double *h) {
    validate_selfaffine(grid, p);
    const double q_r = kTwoPi / p.lambda_r, q_s = kTwoPi / p.lambda_s;
    const int64_t nxh = grid.nxh(), ny = grid.ny(), rows = grid.local_mode_rows(), y0 = grid.first_mode_row();
    Rng rng(p.seed);
    // Two numbers of unit total second moment per mode: uniform on [-sqrt(3/2), sqrt(3/2)] has
    // variance 1/2, as has a Gaussian of sigma sqrt(1/2).  Every mode draws two numbers, in a fixed
    // order (ky rows, kx fastest), so the phases of a seed do not depend on H, lambda_r or
    // lambda_s, and a distributed grid's rows are one stretch of the same stream.
    const double uniform_half_width = std::sqrt(1.5);
    for (int64_t d = 0; d < 2 * nxh * y0; ++d) rng.next();
    for (int64_t r = 0; r < rows; ++r) {
        const int64_t ky = y0 + r;
        for (int64_t kx = 0; kx < nxh; ++kx) {
            double re = 0.0, im = 0.0;
            if (p.distribution == GFMD_DIST_UNIFORM) {
                re = uniform_half_width * (2.0 * rng.uniform() - 1.0);
                im = uniform_half_width * (2.0 * rng.uniform() - 1.0);
            } else {  // Box-Muller
                const double rad = std::sqrt(-std::log(rng.uniform_open0()));
                const double phi = kTwoPi * rng.uniform();
                re = rad * std::cos(phi);
                im = rad * std::sin(phi);
            }
            const double qx = grid.qx(kx), qy = grid.qy(ky);
            const double q2 = qx * qx + qy * qy;
            double amp = 0.0;
            if ((kx != 0 || ky != 0) && !grid.nyquist(kx, ky)) amp = std::sqrt(spectrum(std::sqrt(q2), q_r, q_s, p.hurst));
            work[r * nxh + kx] = std::complex<double>(amp * re, amp * im);
        }
    }
    // Real result: on the column kx = 0 the modes ky and ny - ky must be complex conjugates.
    std::vector<std::complex<double>> column(static_cast<std::size_t>(ny));
    grid.gather_column0(work, column.data());
    for (int64_t r = 0; r < rows; ++r) {
        const int64_t ky = y0 + r;
        if (ky > ny / 2) work[r * nxh] = std::conj(column[static_cast<std::size_t>(ny - ky)]);
    }
    // <|grad h|^2>: term by term in the serial library's order (its surfaces stay the bits they
    // were); a distributed grid sums exactly per row.
    const auto gradient_terms = [&](int64_t r0, int64_t r1, double *acc) {
        for (int64_t r = r0; r < r1; ++r)
            for (int64_t kx = 0; kx < nxh; ++kx) {
                const double qx = grid.qx(kx), qy = grid.qy(y0 + r);
                acc[0] += grid.weight(kx) * (qx * qx + qy * qy) * std::norm(work[r * nxh + kx]);
            }
    };
    double grad2 = 0.0;
    if (grid.distributed()) grad2 = grid.sum_mode_rows<1>(gradient_terms)[0];
    else gradient_terms(0, rows, &grad2);
    if (!(grad2 > 0.0)) fail(GFMD_ERR_INVALID_ARG, "no Fourier mode of the grid lies in (0, q_s]");
    // Coefficients are the normalized ones (h(r) = sum_q h(q) e^{iqr}), so <|grad h|^2> = grad2.
    const double scale = p.rms_gradient / std::sqrt(grad2);
    for (int64_t c = 0; c < rows * nxh; ++c) work[c] *= scale;
    grid.backward(work, h);
    const int64_t n = grid.local_points();
    const double hmax = grid.max_of(h);  // every rank: the same
    for (int64_t i = 0; i < n; ++i) h[i] -= hmax;
}

}  // namespace gfmd
