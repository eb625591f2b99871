// FIRE 2.0 on the real-space field with unit mass per area (Bitzek et al., PRL 97, 170201 (2006);
// Guenole et al., Comput. Mater. Sci. 175, 109584 (2020)): GFMD_SOLVER_FIRE.
#ifndef GFMD_SRC_SOLVERS_FIRE_HPP
#define GFMD_SRC_SOLVERS_FIRE_HPP

#include "fire_control.hpp"
#include "solver.hpp"

namespace gfmd {

class Fire final : public Solver {
public:
    void restart(const Dynamics &d) override { control_.restart(kFireDtStart * d.dt / kDtFactor); }
    // The time step the next advance() starts from (after restart(), FIRE's first)
    double step() const { return control_.dt; }
    void advance(StepContext &c) override;
    std::unique_ptr<Solver> clone() const override { return std::make_unique<Fire>(*this); }
    std::vector<double> state() const override { return control_.state(); }
    void set_state(const std::vector<double> &s) override { control_.set_state(s); }

private:
    FireControl control_;
};

}  // namespace gfmd

#endif
