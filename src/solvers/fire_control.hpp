// FIRE's adaptive step and velocity mixing (Bitzek et al., PRL 97, 170201 (2006); Guenole et al.,
// Comput. Mater. Sci. 175, 109584 (2020)), shared by both FIRE solvers.
#ifndef GFMD_SRC_SOLVERS_FIRE_CONTROL_HPP
#define GFMD_SRC_SOLVERS_FIRE_CONTROL_HPP

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "../error.hpp"
#include "solver.hpp"

namespace gfmd {

// The time step grows by kFireInc after kFireDelay downhill steps up to its maximum and is halved
// on an uphill step; the velocity mixing starts at kFireAlpha0 and decays by kFireAlphaDec.
// Plain FIRE's maximum is kFireDtMax times the time step 1/omega_max (semi-implicit Euler is
// stable up to 2/omega_max).  Measured (the study's sweeps, 10 loads, 512^2 and 1024^2, FIRE
// throughout, the ceiling set from outside in a build made for it): 1.3-1.4 took 6-10 % fewer
// steps than 1 on the half-space, W = 10 and W = 0.125, with and without adhesion (1024^2, steps
// at 1, 1.3, 1.4: half-space 2425, 2271, 2236; W = 10 3057, 2817, 2867; W = 0.125 11 620, 10 775,
// 10 427), while 1.6 went uphill so often that the half-space took more (512^2: 2144 against
// 2035) and 1.8 up to 7x more: 1.3 keeps a margin below that edge.  Mass-weighted FIRE keeps 1
// (its step, set by an estimate of its masked dynamics, gained nothing at 1.3 on W = 0.125).
constexpr double kFireDtMax = 1.3;
constexpr double kMassDtMax = 1.0;
constexpr double kFireDtStart = 0.5;
constexpr double kFireInc = 1.1, kFireDec = 0.5;
constexpr double kFireAlpha0 = 0.1, kFireAlphaDec = 0.99;
constexpr int64_t kFireDelay = 5;

struct FireControl {
    double dt = 0.0, alpha = 0.0;
    int64_t positive = 0;  // downhill steps in a row

    void restart(double dt_start) {
        dt = dt_start;
        alpha = kFireAlpha0;
        positive = 0;
    }
    // From the power F.v of the last force evaluation: downhill -> after kFireDelay such steps grow
    // the step (up to dt_max) and decay the mixing; uphill -> halve the step and reset the mixing.
    // Returns true if uphill.
    bool control(double power, double dt_max) {
        if (power > 0.0) {
            if (++positive > kFireDelay) {
                dt = std::min(dt * kFireInc, dt_max);
                alpha *= kFireAlphaDec;
            }
            return false;
        }
        positive = 0;
        dt *= kFireDec;
        alpha = kFireAlpha0;
        return true;
    }
    std::vector<double> state() const { return {dt, alpha, static_cast<double>(positive)}; }
    void set_state(const std::vector<double> &s) {
        // positive is an exact integer below 2^53 in a double
        if (s.size() != 3 || !(s[0] >= 0.0) || !std::isfinite(s[0]) || !(s[1] >= 0.0) || !std::isfinite(s[1]) ||
            !valid_count(s[2]))
            fail(GFMD_ERR_FORMAT, "invalid FIRE state");
        dt = s[0];
        alpha = s[1];
        positive = static_cast<int64_t>(s[2]);
    }
};

}  // namespace gfmd

#endif
