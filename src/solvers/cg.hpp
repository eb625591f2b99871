// Constrained conjugate gradients on the surface z: the elastic energy plus the load's work is a
// quadratic function of z, minimized under z >= h.  For bodies whose modes are not too spread in
// stiffness (a bonded coating, a small half-space) it needs far fewer force evaluations than FIRE.
#ifndef GFMD_SRC_SOLVERS_CG_HPP
#define GFMD_SRC_SOLVERS_CG_HPP

#include "solver.hpp"

namespace gfmd {

class ConjugateGradient final : public Solver {
public:
    void restart(const Dynamics &) override { fresh_ = true; }
    void advance(StepContext &c) override;
    std::unique_ptr<Solver> clone() const override { return std::make_unique<ConjugateGradient>(*this); }
    // The previous iteration's |r|^2 and whether the next direction starts afresh; the direction
    // itself lives in the velocity field (a CG has no velocity), so checkpoints keep it.
    std::vector<double> state() const override { return {prev_r2_, fresh_ ? 1.0 : 0.0}; }
    void set_state(const std::vector<double> &s) override;

private:
    double prev_r2_ = 0.0;
    bool fresh_ = true;
};

}  // namespace gfmd

#endif
