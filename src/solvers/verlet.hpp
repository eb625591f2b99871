// The seed paper's damped Verlet dynamics (Sec. 2.2): no adaptive state.
#ifndef GFMD_SRC_SOLVERS_VERLET_HPP
#define GFMD_SRC_SOLVERS_VERLET_HPP

#include "solver.hpp"

namespace gfmd {

class Verlet final : public Solver {
public:
    void restart(const Dynamics &) override {}
    void advance(StepContext &c) override;
    std::unique_ptr<Solver> clone() const override { return std::make_unique<Verlet>(*this); }
    std::vector<double> state() const override { return {}; }
    void set_state(const std::vector<double> &) override {}  // nothing to restore (format 1 files carry FIRE's)
};

}  // namespace gfmd

#endif
