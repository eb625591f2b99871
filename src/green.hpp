// Green's functions of the elastic bodies: G(q) = 2 f(q w) / (q E*).
#ifndef GFMD_SRC_GREEN_HPP
#define GFMD_SRC_GREEN_HPP

#include <cstdint>

#include "buffer.hpp"
#include "fft_grid.hpp"

namespace gfmd {

// Throw GFMD_ERR_BAD_ENUM / GFMD_ERR_INVALID_ARG for a kind or Poisson's ratio no body can have.
void validate_green_kind(int32_t kind);
void validate_poisson(double nu);

// The elastic body on a grid: the stiffness 1/G(q) = q E* / (2 f(q w)) of every mode of the local
// Hermitian half-spectrum (0 for q = 0, whose force balance the load sets), and its extremes over
// the modes with a stiffness.  make_body throws GFMD_ERR_RANGE if a stiffness overflows.
struct Body {
    RealBuffer stiffness;
    double k_min = 0.0, k_max = 0.0;
    // Free boundaries only: the uniform mode's compliance K(0) of the padded cell (below), 0 otherwise
    double compliance0 = 0.0;
};
Body make_body(const FftGrid &grid, int32_t kind, double width, double e_star, double nu);

// The half-space with free boundaries on the zero-padded cell `grid` (twice the region each way):
// the stiffness 1/K(q) of the free-space Boussinesq response to a uniform pressure on one grid
// cell (Love's rectangle, exact for piecewise-constant pressure), its periodic images cut at half
// the padded cell.  Any pressure inside the region then sees exactly the free-space response: the
// region is at most half the padded cell from any of its points, so no image reaches it.  K(q) > 0
// for every q (checked: GFMD_ERR_INTERNAL otherwise); the uniform mode keeps stiffness 0, so that
// the load on the padded cell moves the body as a whole, and its K(0) is kept in compliance0.
// Distributed grids are refused by the caller.
Body make_free_body(const FftGrid &grid, double e_star);

// The displacement, at offset (x, y) from a grid cell's centre, of unit pressure on that cell of
// sides ax x ay, on a half-space of contact modulus e_star: (1 / (pi E*)) times the integral of 1/r
// over the cell.
double boussinesq_cell(double x, double y, double ax, double ay, double e_star);

// |q| of the grid's corner mode (the shortest wave, pi sqrt(2)/a on a square grid of spacing a).
double shortest_wave_q(const FftGrid &grid);

// How much softer the body's softest mode is than a half-space's shortest wave on this grid,
// k_hs(q_max) / k_min: 0.7 n for an n x n half-space, bounded on a bonded layer whatever the grid,
// huge on a layer on a fluid foundation.  What the constrained CG's iteration count follows.
double long_wave_softness(const FftGrid &grid, const Body &body, double e_star);

// How much softer the body's softest mode is than a half-space at the same (smallest) wave
// vector, k_hs(q_min) / k_min: f(q_min w) on a layer, 1 on a half-space.
double longest_wave_softness(const FftGrid &grid, const Body &body, double e_star);

// The largest mode stiffness k(q) over the wave vectors |q|^2 <= q2 (over all ranks): the floor
// of the solvers that weigh the modes by their stiffness, at the contact spacing.
double stiffest_mode_within(const FftGrid &grid, const Body &body, double q2);

// The octave floor(log2(contacts)) of a contact count (0 without contact): the solvers' floors
// follow it, so they are a function of the state (checkpoints resume bit for bit).
int contact_octave(int64_t contacts);

// |q|^2 = spacing^2 4 pi phi / cell at the mean spacing of `points` contacts (phi = points / N):
// the wave vector below which the contacts pin the modes, times `spacing`.
double contact_spacing_q2(const FftGrid &grid, double spacing, double points);

// 1/f(t) for a kind of body (GFMD_GREEN_*), t = q w > 0, nu used by the bonded layer only.
// Finite and >= 0 for every finite t > 0; the mode stiffness is q E* / 2 * inverse_factor.
double green_inverse_factor(int32_t kind, double t, double nu);

// f(t) itself; may be +inf where 1/f underflows (only for t < ~1e-103).
double green_factor(int32_t kind, double t, double nu);

}  // namespace gfmd

#endif
