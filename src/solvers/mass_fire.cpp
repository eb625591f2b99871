#include "mass_fire.hpp"

#include <algorithm>

#include "../error.hpp"

namespace gfmd {

std::vector<double> MassThenFire::state() const {
    std::vector<double> s{static_cast<double>(taken_)};
    const std::vector<double> m = mass_.state(), f = fire_.state();
    s.insert(s.end(), m.begin(), m.end());
    s.insert(s.end(), f.begin(), f.end());
    return s;
}

void MassThenFire::set_state(const std::vector<double> &s) {
    // the mass-weighted part with or without its frequency estimates (FireMass::set_state)
    const std::size_t nf = fire_.state().size(), nm = s.size() - std::min(s.size(), 1 + nf);
    const std::size_t nc = FireControl().state().size();
    if ((nm != nc && nm != nc + FireMass::kBuckets) || !valid_count(s[0]) || s[0] > static_cast<double>(kApproachSteps))
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
