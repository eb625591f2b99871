// Mass-weighted FIRE as an approach, then FIRE: after each restart at most kApproachSteps steps of
// mass-weighted FIRE (which nears the equilibrium of a soft body fast and then converges slowly),
// then FIRE from where it got (docs/performance.md, "A thin sheet's first load").
#ifndef GFMD_SRC_SOLVERS_MASS_FIRE_HPP
#define GFMD_SRC_SOLVERS_MASS_FIRE_HPP

#include "fire.hpp"
#include "fire_mass.hpp"
#include "solver.hpp"

namespace gfmd {

// The approach's length: the seed paper's study measured with 100 (gfmd_paper --approach 100).
constexpr int64_t kApproachSteps = 100;

class MassThenFire final : public Solver {
public:
    explicit MassThenFire(const FftGrid &grid) : mass_(grid) {}
    void restart(const Dynamics &d) override {
        mass_.restart(d);
        fire_.restart(d);  // FIRE starts restarted where the approach ends; v carries over
        taken_ = 0;
    }
    void advance(StepContext &c) override {
        if (taken_ < kApproachSteps) {
            mass_.advance(c);
            ++taken_;
        } else {
            fire_.advance(c);
        }
    }
    std::unique_ptr<Solver> clone() const override { return std::make_unique<MassThenFire>(*this); }
    // {approach steps taken, mass-weighted FIRE's state, FIRE's state}
    std::vector<double> state() const override;
    void set_state(const std::vector<double> &s) override;

private:
    FireMass mass_;
    Fire fire_;
    int64_t taken_ = 0;
};

}  // namespace gfmd

#endif
