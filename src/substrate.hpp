// Self-affine random substrates.
#ifndef GFMD_SRC_SUBSTRATE_HPP
#define GFMD_SRC_SUBSTRATE_HPP

#include <complex>
#include <cstdint>

#include "fft_grid.hpp"

namespace gfmd {

struct SelfAffineParams {
    double hurst;
    double lambda_r;
    double lambda_s;
    double rms_gradient;
    uint64_t seed;
    int32_t distribution;
};

// Throws gfmd::Error for invalid parameters (checked before anything is written).
void validate_selfaffine(const FftGrid &grid, const SelfAffineParams &p);

// Writes the heights into h (real_size values); work is a complex scratch of complex_size values.
void generate_selfaffine(const FftGrid &grid, const SelfAffineParams &p, std::complex<double> *work, double *h);

}  // namespace gfmd

#endif
