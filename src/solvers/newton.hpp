// The active-set Newton method for a thin sheet: without adhesion the energy is quadratic in z,
// so between changes of the contact set one Newton step solves the problem.  Each step (one
// "step" of gfmd_step()/gfmd_relax()):
//   the held set   the points at the wall that the force presses onto it (z <= h, F <= 0);
//   the direction  d from CG on H_FF d = F_F (H the energy's Hessian: the stiffness K, with
//                  adhesion plus the adhesive law's curvature -(gamma0/rho^2) exp(-(z-h)/rho), F the
//                  force, on the free points; d = 0 on the held ones) from d = 0 to a tenth of its
//                  right-hand side's norm, at most 500 iterations, preconditioned by one V-cycle of
//                  the stencil's block (stencil_mg.hpp) scaled by c0, the stencil's least-squares
//                  fit to k(q); without adhesion stopped where the curvature is not positive (then
//                  the first direction if it came first); with adhesion, whose curvature is
//                  negative and whose law changes on the scale rho, kept within a trust region
//                  max |d| <= R on the free points (Steihaug's CG: stopped at its edge, and at
//                  non-positive curvature stepped along that direction to the edge), R = rho after a
//                  restart, doubled after a full step to the edge, after a shortened step the step
//                  taken, never below 0.3 rho (R is the solver's state);
//   the move       z <- max(h, z + alpha d), alpha = 1, 1/2, ... until the energy falls by 1e-4 of
//                  its first-order prediction (Armijo's rule along the projected path); without
//                  adhesion a step that no point of the wall stopped is taken without a test: the
//                  CG's iterate lowers the quadratic energy, and no other term changes.  Each test
//                  one forward transform (the energy's change by Parseval, the adhesive law's part
//                  summed point by point), each CG iteration one FFT pair and one cycle (about
//                  1.3-1.9 pairs at 2048^2).
// Why this method, and its measurements: docs/decisions.md, "The active-set Newton method".
// Takes a layer on a fluid foundation under pressure control on a serial square grid of square
// cells whose side is a power of 2 >= 32 (newton_refusal()); its velocity stays zero.
#ifndef GFMD_SRC_SOLVERS_NEWTON_HPP
#define GFMD_SRC_SOLVERS_NEWTON_HPP

#include "solver.hpp"
#include "stencil_mg.hpp"

namespace gfmd {

// Why the Newton method cannot run the body p on the grid (an empty string if it can); its grid's
// part alone.
const char *newton_refusal(const FftGrid &grid, const Params &p);
const char *newton_grid_refusal(const FftGrid &grid);

class ActiveSetNewton final : public Solver {
public:
    // Bytes per point it adds to a handle: its four fields, the held set and the cycle's levels.
    static double bytes_per_point();
    // Throws std::bad_alloc.  The grid must be one newton_refusal() takes.
    explicit ActiveSetNewton(int64_t side);
    void restart(const Dynamics &) override;
    void advance(StepContext &c) override;
    std::unique_ptr<Solver> clone() const override { return std::make_unique<ActiveSetNewton>(side_); }
    // The adaptive state: the trust region's radius in units of rho (used with adhesion only);
    // the rest is derived (the cycle's operators of its held set, c0 of the body: made again
    // after a restart or a load).
    std::vector<double> state() const override { return {radius_}; }
    void set_state(const std::vector<double> &s) override;

private:
    int64_t side_;
    double c0_ = 0.0;  // the stencil's scale for the body (0: not yet computed since the restart)
    double radius_ = 1.0;  // the trust region's radius / rho (kTrustStart after a restart)
    RealBuffer r_, p_, s_;  // the CG's residual, direction and preconditioned residual (or K p)
    RealBuffer e_;          // with adhesion exp(-(z - h)/rho) on the free points of the step's z
    ByteBuffer held_;
    std::vector<double> block_top_;  // the trust region's limit per block of points (to_edge)
    StencilMultigrid mg_;
};

}  // namespace gfmd

#endif
