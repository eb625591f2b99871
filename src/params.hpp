// Every user parameter of a simulation, as one plain value: copied, compared and serialized as
// a unit.  The grid's size, threads and FFT planner belong to the grid (fft_grid.hpp).
#ifndef GFMD_SRC_PARAMS_HPP
#define GFMD_SRC_PARAMS_HPP

#include <cstdint>
#include <cstring>
#include <limits>

#include "gfmd.h"

namespace gfmd {

// The load: a pressure sigma0 (the body's mean position follows), or the mean position of the
// body's surface, mean(z) = mean_z (the mean pressure follows: displacement control).
constexpr int32_t kPressureControl = 0, kDisplacementControl = 1;

// X(type, name, default, since): the one list of parameters, in checkpoint order; `since` is the
// checkpoint format version that first holds the parameter (older files leave the default).
#define GFMD_PARAMS_LIST(X)                                                                       \
    X(double, e_star, 1.0, 1)                    /* contact modulus E* */                         \
    X(int32_t, kind, GFMD_GREEN_HALFSPACE, 1)    /* body: GFMD_GREEN_* */                         \
    X(double, width, 0.0, 1)                     /* layer width w (0 for the half-space) */       \
    X(double, nu, std::numeric_limits<double>::quiet_NaN(), 1) /* Poisson's ratio, NaN = unset */ \
    X(double, sigma0, 0.0, 1)                    /* external pressure (pressure control) */       \
    X(double, gamma0, 0.0, 1)                    /* adhesion: surface energy, 0 = none */         \
    X(double, rho, 1.0, 1)                       /* adhesion: range */                            \
    X(double, dt_user, 0.0, 1)                   /* time step, 0 = automatic */                   \
    X(double, eta_user, 0.0, 1)                  /* damping, 0 = automatic */                     \
    X(int32_t, solver, GFMD_SOLVER_AUTO, 1)      /* GFMD_SOLVER_* */                              \
    X(int32_t, control, kPressureControl, 3)     /* what the load prescribes */                   \
    X(double, mean_z, 0.0, 3)                    /* displacement control: the mean of z */        \
    X(double, hardness, std::numeric_limits<double>::infinity(), 6) /* plasticity: H, inf = none */ \
    X(int32_t, boundary, GFMD_BOUNDARY_PERIODIC, 7) /* GFMD_BOUNDARY_* */

struct Params {
#define GFMD_PARAM_MEMBER(type, name, value, since) type name = value;
    GFMD_PARAMS_LIST(GFMD_PARAM_MEMBER)
#undef GFMD_PARAM_MEMBER

    // Adhesive stiffness gamma0/rho^2: the stiffest point of the adhesive law (0 without adhesion).
    double adhesive_stiffness() const { return (gamma0 > 0.0) ? gamma0 / (rho * rho) : 0.0; }
};

// Bitwise equality of every parameter (an unset nu equals an unset nu).
inline bool same(const Params &a, const Params &b) {
    bool eq = true;
#define GFMD_PARAM_SAME(type, name, value, since) eq = eq && std::memcmp(&a.name, &b.name, sizeof(type)) == 0;
    GFMD_PARAMS_LIST(GFMD_PARAM_SAME)
#undef GFMD_PARAM_SAME
    return eq;
}

}  // namespace gfmd

#endif
