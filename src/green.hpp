// Green's functions of the elastic bodies: G(q) = 2 f(q w) / (q E*).
#ifndef GFMD_SRC_GREEN_HPP
#define GFMD_SRC_GREEN_HPP

#include <cstdint>

namespace gfmd {

// 1/f(t) for a kind of body (GFMD_GREEN_*), t = q w > 0, nu used by the bonded layer only.
// Finite and >= 0 for every finite t > 0; the mode stiffness is q E* / 2 * inverse_factor.
double green_inverse_factor(int32_t kind, double t, double nu);

// f(t) itself; may be +inf where 1/f underflows (only for t < ~1e-103).
double green_factor(int32_t kind, double t, double nu);

}  // namespace gfmd

#endif
