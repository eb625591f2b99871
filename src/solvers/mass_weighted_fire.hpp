// FIRE with mass weighting: each Fourier mode's inertia from its stiffness, floored at the
// stiffness of the contact spacing (docs/model.md, docs/decisions.md).
#ifndef GFMD_SRC_SOLVERS_MASS_WEIGHTED_FIRE_HPP
#define GFMD_SRC_SOLVERS_MASS_WEIGHTED_FIRE_HPP

#include <algorithm>
#include <array>

#include "fire_control.hpp"
#include "solver.hpp"

namespace gfmd {

class MassWeightedFire final : public Solver {
public:
    // One byte per point: the mask of the points the wall holds.  estimate = false: the step of the
    // unmasked modes (lambda_max = 1), as GFMD_SOLVER_APPROACH_THEN_FIRE's approach takes it (approach_then_fire.hpp).
    // Under displacement control one grid-sized field and a byte per point more (hold_mean()),
    // written only then: a buffer costs memory once written (buffer.hpp).
    explicit MassWeightedFire(const FftGrid &grid, bool estimate = true)
        : held_(static_cast<std::size_t>(grid.local_points())),
          mean_response_(static_cast<std::size_t>(grid.local_points())),
          response_held_(static_cast<std::size_t>(grid.local_points())), estimate_(estimate) {}
    MassWeightedFire(const MassWeightedFire &o);
    void restart(const Dynamics &) override {
        control_.restart(kFireDtStart);  // a fraction of its own time step, mass_dt_
        bucket_ = -1;
        lambda_.fill(0.0);
        response_valid_ = false;  // the body may have changed
    }
    void advance(StepContext &c) override;
    std::unique_ptr<Solver> clone() const override { return std::make_unique<MassWeightedFire>(*this); }
    // FIRE's control, then the highest frequency^2 found for each contact-count bucket since the
    // last restart (0: none yet).  The floor is a function of the configuration (its contact
    // count): recomputed.  A state of FIRE's control alone (3 numbers, checkpoints of version
    // 0.1.0 before the estimate) leaves the estimates to be made again.
    std::vector<double> state() const override;
    void set_state(const std::vector<double> &s) override;
    // The time step advance() takes, in the masked dynamics' own (dimensionless) time: from the
    // control and the masses the step set, so after a step the one it took (neither changes until
    // the next).
    double step() const { return std::min(control_.dt, kMassDtMax) * mass_dt_; }
    // contact counts below 2^48 (a grid of 2^48 points needs petabytes); within the checkpoint
    // format's 64 numbers of solver state also after GFMD_SOLVER_APPROACH_THEN_FIRE's 4 of its own
    static constexpr std::size_t kBuckets = 48;

private:
    void update_mass_floor(const StepContext &c);
    double masked_lambda(StepContext &c);
    double hold_mean(StepContext &c, double *a);
    FireControl control_;
    ByteBuffer held_;  // 1 where the wall holds the body (scratch of one step)
    // Under displacement control: P M^-1 P 1, kept while the held set (response_held_, a copy of
    // held_ when it was computed) and the floor (response_floor_) stay the same: it is a function
    // of them, so a kept one has the bits a new one would have.
    RealBuffer mean_response_;
    ByteBuffer response_held_;
    double response_floor_ = 0.0;
    bool response_valid_ = false;
    // Masses m(q) = max(k(q), floor_), chosen for the contact-count bucket bucket_
    // (floor(log2(contacts)), -1 = not chosen yet); the time step they allow.
    double floor_ = 0.0, mass_dt_ = 0.0, inv_m_ = 0.0;
    int bucket_ = -1;
    bool estimate_ = true;
    std::array<double, kBuckets> lambda_{};  // per bucket: lambda_max of P M^-1 P K P (0: not yet)
};

}  // namespace gfmd

#endif
