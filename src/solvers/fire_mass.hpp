// FIRE with mass weighting: each Fourier mode's inertia from its stiffness, floored at the
// stiffness of the contact spacing (docs/model.md, docs/performance.md).
#ifndef GFMD_SRC_SOLVERS_FIRE_MASS_HPP
#define GFMD_SRC_SOLVERS_FIRE_MASS_HPP

#include "fire_control.hpp"
#include "solver.hpp"

namespace gfmd {

class FireMass final : public Solver {
public:
    // One byte per point: the mask of the points the wall holds.
    explicit FireMass(const FftGrid &grid) : held_(static_cast<std::size_t>(grid.local_points())) {}
    FireMass(const FireMass &o);
    void restart(const Dynamics &) override {
        control_.restart(kFireDtStart);  // a fraction of its own time step, mass_dt_
        bucket_ = -1;
    }
    void advance(StepContext &c) override;
    std::unique_ptr<Solver> clone() const override { return std::make_unique<FireMass>(*this); }
    // The floor is a function of the configuration (its contact count), not state: recomputed.
    std::vector<double> state() const override { return control_.state(); }
    void set_state(const std::vector<double> &s) override {
        control_.set_state(s);
        bucket_ = -1;
    }

private:
    void update_mass_floor(const StepContext &c);
    FireControl control_;
    ByteBuffer held_;  // 1 where the wall holds the body (scratch of one step)
    // Masses m(q) = max(k(q), floor_), chosen for the contact-count bucket bucket_
    // (floor(log2(contacts)), -1 = not chosen yet); the time step they allow.
    double floor_ = 0.0, mass_dt_ = 0.0;
    int bucket_ = -1;
};

}  // namespace gfmd

#endif
