// Constants shared by the core.
#ifndef GFMD_SRC_CONSTANTS_HPP
#define GFMD_SRC_CONSTANTS_HPP

#include <cstdint>

namespace gfmd {

constexpr double kPi = 3.14159265358979323846;

// Heights and lengths are limited to 1e100 in magnitude so that no sum of squares of the fields
// (energies, FFT power) can overflow.
constexpr double kMaxHeight = 1e100;
constexpr double kMinLength = 1e-100, kMaxLength = 1e100;
constexpr int64_t kMaxGridDimension = INT64_C(1) << 30;
constexpr int kMaxThreads = 4096;

}  // namespace gfmd

#endif
