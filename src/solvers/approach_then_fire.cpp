#include "approach_then_fire.hpp"

#include <algorithm>

#include "../error.hpp"

namespace gfmd {

// The approach's velocity is per unit of the masked dynamics' own time, which has no units; FIRE's
// is per unit of the body's time (its step a fraction of 1/omega_max).  Carried over as it was, the
// velocity FIRE started from depended on the units of lengths and stresses (a relaxation in SI
// units and the same one in units of a and E* parted after the approach).  It is converted so that
// it carries each point as far per step as in the approach's last (v dt the same; FIRE's first
// step then adds its own force and mixing): times the approach's last step over FIRE's first
// (FIRE was restarted with the approach, so its step is still its first).
void ApproachThenFire::carry_over(StepContext &c) const {
    const double scale = mass_.step() / fire_.step();
    double *v = c.fields.v.data();
    c.grid.for_points([&](int64_t i0, int64_t i1) {
#pragma omp simd
        for (int64_t i = i0; i < i1; ++i) v[i] *= scale;
    });
}

std::vector<double> ApproachThenFire::state() const {
    std::vector<double> s{static_cast<double>(taken_)};
    const std::vector<double> m = mass_.state(), f = fire_.state();
    s.insert(s.end(), m.begin(), m.end());
    s.insert(s.end(), f.begin(), f.end());
    return s;
}

void ApproachThenFire::set_state(const std::vector<double> &s) {
    // the mass-weighted part with or without its frequency estimates (MassWeightedFire::set_state)
    const std::size_t nf = fire_.state().size(), nm = s.size() - std::min(s.size(), 1 + nf);
    const std::size_t nc = FireControl().state().size();
    if ((nm != nc && nm != nc + MassWeightedFire::kBuckets) || !valid_count(s[0]) || s[0] > static_cast<double>(kApproachSteps))
        fail(GFMD_ERR_FORMAT, "invalid state of mass-weighted FIRE then FIRE");
    // FIRE's state is checked on a copy first (cheap; a copy of mass_ would copy its grid-sized
    // mask), so that a refused state leaves the solver as it was
    Fire fire = fire_;
    fire.set_state(std::vector<double>(s.begin() + 1 + static_cast<std::ptrdiff_t>(nm), s.end()));
    mass_.set_state(std::vector<double>(s.begin() + 1, s.begin() + 1 + static_cast<std::ptrdiff_t>(nm)));
    fire_ = fire;
    taken_ = static_cast<int64_t>(s[0]);
}

}  // namespace gfmd
