// The forces and energies of a configuration: the one FFT pair of every step.
#ifndef GFMD_SRC_FORCES_HPP
#define GFMD_SRC_FORCES_HPP

#include <cmath>
#include <cstdint>

#include "fft_grid.hpp"
#include "fields.hpp"
#include "green.hpp"
#include "params.hpp"

namespace gfmd {

// What one force evaluation knows of the configuration z: energies, the residual of the
// constrained problem, the sums the FIRE solvers steer by (over the projected force F, which is
// zero where the wall holds the body: power F.v, |F|^2, |v|^2), and the points in contact.
struct ForceState {
    double u_el = 0.0, u_ad = 0.0, residual = 0.0;
    double power = 0.0, f_norm2 = 0.0, v_norm2 = 0.0;
    int64_t contacts = 0;  // points with zero gap
    double mean_pressure = 0.0;  // sigma0, or under displacement control the pressure that balances
    bool finite() const { return std::isfinite(u_el) && std::isfinite(u_ad) && std::isfinite(residual); }
};

constexpr double kDisplacementStressFloor = 1e-8;  // see evaluate_forces()

// The stress the residual is relative to: |sigma0| + gamma0/rho (+ a floor under displacement
// control), E* where that is zero.
double residual_scale(const Params &p, double sigma0);

// Writes the force per area on z into fields.f (fields.work is scratch) and returns the sums.
// Under displacement control the uniform pressure is not given but the Lagrange multiplier of
// mean(z) = mean_z: the mean over the points out of contact of the elastic and adhesive stress
// (then the net force on them has zero mean, and vanishes at equilibrium).
ForceState evaluate_forces(const FftGrid &grid, const Params &p, const Body &body, Fields &fields);

}  // namespace gfmd

#endif
