// Mass-weighted FIRE as an approach, then FIRE: after each restart at most kApproachSteps steps of
// mass-weighted FIRE (which nears the equilibrium of a soft body fast and then converges slowly),
// then FIRE from where it got (docs/decisions.md).
#ifndef GFMD_SRC_SOLVERS_APPROACH_THEN_FIRE_HPP
#define GFMD_SRC_SOLVERS_APPROACH_THEN_FIRE_HPP

#include "fire.hpp"
#include "mass_weighted_fire.hpp"
#include "solver.hpp"

namespace gfmd {

// The approach's length: the seed paper's study measured with 100 (gfmd_paper --approach 100).
constexpr int64_t kApproachSteps = 100;
// The approach steps as the unmasked modes allow (lambda_max = 1, MassWeightedFire), not as the masked
// dynamics does: for its 100 steps the longer step nears the equilibrium faster, uphill restarts
// notwithstanding.  Measured with the estimate (gfmd_paper, 256^2, one thread): the default's
// adhesive sheets W = 0.25 ... 0.0625 took 54 705 steps against 46 211 with this step
// (docs/decisions.md).
constexpr bool kApproachEstimates = false;

class ApproachThenFire final : public Solver {
public:
    explicit ApproachThenFire(const FftGrid &grid) : mass_(grid, kApproachEstimates) {}
    void restart(const Dynamics &d) override {
        mass_.restart(d);
        fire_.restart(d);  // FIRE starts restarted where the approach ends; the motion carries over
        taken_ = 0;
    }
    void advance(StepContext &c) override {
        if (taken_ < kApproachSteps) {
            mass_.advance(c);
            if (++taken_ == kApproachSteps) carry_over(c);
        } else {
            fire_.advance(c);
        }
    }
    std::unique_ptr<Solver> clone() const override { return std::make_unique<ApproachThenFire>(*this); }
    // {approach steps taken, mass-weighted FIRE's state, FIRE's state}
    std::vector<double> state() const override;
    void set_state(const std::vector<double> &s) override;

private:
    void carry_over(StepContext &c) const;
    MassWeightedFire mass_;
    Fire fire_;
    int64_t taken_ = 0;
};

}  // namespace gfmd

#endif
