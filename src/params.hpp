// Every user parameter of a simulation, as one plain value: copied, compared and serialized as
// a unit.  The grid's size, threads and FFT planner belong to the grid (fft_grid.hpp).
#ifndef GFMD_SRC_PARAMS_HPP
#define GFMD_SRC_PARAMS_HPP

#include <cstdint>
#include <cstring>
#include <limits>

#include "gfmd.h"

namespace gfmd {

// X(type, name, default): the one list of parameters, in checkpoint order.
#define GFMD_PARAMS_LIST(X)                                                                    \
    X(double, e_star, 1.0)                    /* contact modulus E* */                         \
    X(int32_t, kind, GFMD_GREEN_HALFSPACE)    /* body: GFMD_GREEN_* */                         \
    X(double, width, 0.0)                     /* layer width w (0 for the half-space) */       \
    X(double, nu, std::numeric_limits<double>::quiet_NaN()) /* Poisson's ratio, NaN = unset */ \
    X(double, sigma0, 0.0)                    /* external pressure */                          \
    X(double, gamma0, 0.0)                    /* adhesion: surface energy, 0 = none */         \
    X(double, rho, 1.0)                       /* adhesion: range */                            \
    X(double, dt_user, 0.0)                   /* time step, 0 = automatic */                   \
    X(double, eta_user, 0.0)                  /* damping, 0 = automatic */                     \
    X(int32_t, solver, GFMD_SOLVER_FIRE)      /* GFMD_SOLVER_* */

struct Params {
#define GFMD_PARAM_MEMBER(type, name, value) type name = value;
    GFMD_PARAMS_LIST(GFMD_PARAM_MEMBER)
#undef GFMD_PARAM_MEMBER

    // Adhesive stiffness gamma0/rho^2: the stiffest point of the adhesive law (0 without adhesion).
    double adhesive_stiffness() const { return (gamma0 > 0.0) ? gamma0 / (rho * rho) : 0.0; }
};

// Bitwise equality of every parameter (an unset nu equals an unset nu).
inline bool same(const Params &a, const Params &b) {
    bool eq = true;
#define GFMD_PARAM_SAME(type, name, value) eq = eq && std::memcmp(&a.name, &b.name, sizeof(type)) == 0;
    GFMD_PARAMS_LIST(GFMD_PARAM_SAME)
#undef GFMD_PARAM_SAME
    return eq;
}

}  // namespace gfmd

#endif
