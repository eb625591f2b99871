#include "mass_fire.hpp"

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
    const std::size_t nm = mass_.state().size(), nf = fire_.state().size();
    if (s.size() != 1 + nm + nf || !valid_count(s[0]) || s[0] > static_cast<double>(kApproachSteps))
        fail(GFMD_ERR_FORMAT, "invalid state of mass-weighted FIRE then FIRE");
    const std::vector<double> m(s.begin() + 1, s.begin() + 1 + static_cast<std::ptrdiff_t>(nm)),
        f(s.begin() + 1 + static_cast<std::ptrdiff_t>(nm), s.end());
    // both parts are FIRE controls: checked on scratch ones first, so that a refused state leaves
    // the solver as it was
    FireControl check;
    check.set_state(m);
    check.set_state(f);
    mass_.set_state(m);
    fire_.set_state(f);
    taken_ = static_cast<int64_t>(s[0]);
}

}  // namespace gfmd
