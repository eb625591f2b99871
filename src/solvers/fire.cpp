#include "fire.hpp"

#include <algorithm>
#include <cmath>

#include "../kernels.hpp"

namespace gfmd {

void Fire::advance(StepContext &c) {
    // FIRE 2.0 (Guenole et al. 2020, Algorithm 2) on the real-space field, unit mass per area:
    // uphill (F.v <= 0) -> stop and shrink the step; downhill -> grow it and steer v along F.
    // The wall is handled as in the damped dynamics: forces into the substrate at points in
    // contact are taken by the wall (projected out of F) and a point that hits it stops.
    const ForceState &fs = c.forces;
    const bool uphill = control_.control(fs.power, kFireDtMax * c.dynamics.dt / kDtFactor);
    const double dt = control_.dt;
    // Mixing after the velocity update: v <- (1-a) v + a |v| F/|F|, with |v| of the updated v.
    // |v + dt F|^2 follows from the sums of the last force evaluation.  After an uphill step the
    // mixing term is left out (|v| taken as 0: the body restarts with v = (1-a) dt F, not FIRE 2.0's
    // dt F), a small extra damping the recorded trajectories keep.
    double vn2 = 0.0;
    if (!uphill) vn2 = fs.v_norm2 + 2.0 * dt * fs.power + dt * dt * fs.f_norm2;
    const double mix = (fs.f_norm2 > 0.0) ? control_.alpha * std::sqrt(std::max(vn2, 0.0) / fs.f_norm2) : 0.0;
    const double keep = 1.0 - control_.alpha;
    // Uphill: step back half a step (FIRE 2.0), then restart from rest.
    const double back = uphill ? 0.5 * dt : 0.0;
    const kernels::FireUpdate u{dt, keep, mix, back, uphill};
    double *z = c.fields.z.data(), *v = c.fields.v.data();
    const double *h = c.fields.h.data(), *f = c.fields.f.data();
    c.grid.for_points([&](int64_t i0, int64_t i1) { kernels::use().fire_update(u, z + i0, v + i0, h + i0, f + i0, i1 - i0); });
}

}  // namespace gfmd
