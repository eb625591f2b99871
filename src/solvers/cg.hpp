// Constrained conjugate gradients: the elastic energy plus the load's work (with adhesion minus
// the adhesive energy) minimized under z >= h.  Without adhesion the energy is a quadratic
// function of z: under pressure control on a half-space or a bonded layer the iteration is
// Polonsky & Keer's on the contact pressure (pk.hpp); on a layer on a fluid foundation, under
// displacement control, where the load is an outcome, and with adhesion (under pressure control
// only), projected CG on the surface z itself (below; with adhesion its line search follows the
// adhesive energy).  For bodies whose modes span a modest range of stiffness (a coating, a small
// half-space) they need far fewer force evaluations than FIRE.
#ifndef GFMD_SRC_SOLVERS_CG_HPP
#define GFMD_SRC_SOLVERS_CG_HPP

#include <array>

#include "pk.hpp"
#include "solver.hpp"

namespace gfmd {

// Projected CG on z with an exact line search (with adhesion, Newton's along the direction); its
// direction lives in the velocity field.  Given a scratch buffer, preconditioned by the inverse
// stiffness (cg.cpp).
class SurfaceCg {
public:
    void restart() {
        fresh_ = true;
        steepest_ = false;
        bucket_ = -1;  // the body may have changed: its floor is recomputed
    }
    void advance(StepContext &c, RealBuffer *scratch);
    // fresh is 1, 0, or 2: fresh and the next direction the force itself (a failed step's)
    std::vector<double> state() const { return {prev_r2_, steepest_ ? 2.0 : fresh_ ? 1.0 : 0.0}; }
    void set_state(const double *s);  // two numbers

private:
    // Where the wall stopped points, the step from z0 must decrease the energy enough (cg.cpp).
    // weight: with adhesion the sum of exp(-(z - h)/rho) at alpha (the line search's last)
    template <class Move>
    void sufficient_decrease(StepContext &c, const double *z0, double alpha, double rt, Move &&move, double weight);
    // z_p = M^-1 r on the free points (0 where the wall holds z), returns r.z_p.
    double precondition(const StepContext &c, double *zp);
    // With adhesion: the step along t to the energy's minimum from the quadratic step alpha, the
    // energy's change along the unprojected path there, its rounding and the adhesive weight sum
    // there, from the line's sums at 0 (s0: cg_adhesive_line's, summed by the direction's pass).
    struct LineMinimum {
        double alpha, change, slack, weight;
    };
    LineMinimum adhesive_line_minimum(const StepContext &c, double rt, double ktn, double alpha,
                                      const std::array<double, 3> &s0) const;
    double prev_r2_ = 0.0;  // r.r, or r.M^-1 r when preconditioned, of the last iteration
    bool fresh_ = true;
    bool steepest_ = false;  // the last step failed its check: the next direction is the force
    int bucket_ = -1;        // derived: floor(log2(contacts)) that floor_ belongs to
    double floor_ = 0.0;
};

class ConjugateGradient final : public Solver {
public:
    // 16 bytes per point: the contact pressure and its displacement (the preconditioned surface CG's
    // scratch on a layer on a fluid foundation, where PK does not iterate).
    explicit ConjugateGradient(const FftGrid &grid) : pressure_(grid) {}
    void restart(const Dynamics &) override {
        surface_.restart();
        pressure_.restart();
    }
    void advance(StepContext &c) override;
    bool at_check(const Params &p) const override { return uses_surface(p) || pressure_.at_check(); }
    std::unique_ptr<Solver> clone() const override { return std::make_unique<ConjugateGradient>(*this); }
    std::vector<double> state() const override;
    void set_state(const std::vector<double> &s) override;
    std::vector<const RealBuffer *> grid_state() const override { return {&pressure_.pressure()}; }
    void set_grid_state(std::vector<RealBuffer> &&fields) override;

private:
    static bool uses_surface(const Params &p) {
        return p.control == kDisplacementControl || p.kind == GFMD_GREEN_LAYER_FLUID || p.gamma0 > 0.0;
    }
    // Preconditioned on a layer on a fluid foundation, and with adhesion on every body, under
    // pressure control (not with the mean held: the projection would fight the preconditioner's
    // long waves, as it did mass-weighted FIRE's).
    static bool preconditioned(const Params &p) {
        return p.control == kPressureControl && (p.kind == GFMD_GREEN_LAYER_FLUID || p.gamma0 > 0.0);
    }
    SurfaceCg surface_;
    PolonskyKeer pressure_;
};

}  // namespace gfmd

#endif
