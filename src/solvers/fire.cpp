#include "fire.hpp"

#include <algorithm>
#include <cmath>

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
    // |v + dt F|^2 follows from the sums of the last force evaluation.
    double vn2 = 0.0;
    if (!uphill) vn2 = fs.v_norm2 + 2.0 * dt * fs.power + dt * dt * fs.f_norm2;
    const double mix = (fs.f_norm2 > 0.0) ? control_.alpha * std::sqrt(std::max(vn2, 0.0) / fs.f_norm2) : 0.0;
    const double keep = 1.0 - control_.alpha;
    // Uphill: step back half a step (FIRE 2.0), then restart from rest.
    const double back = uphill ? 0.5 * dt : 0.0;
    double *__restrict z = c.fields.z.data(), *__restrict v = c.fields.v.data();
    const double *__restrict h = c.fields.h.data(), *__restrict f = c.fields.f.data();
    c.grid.for_points([&](int64_t i0, int64_t i1) {
        // Branch-free (selects), so that scattered contact points cost no mispredictions and
        // the loop vectorizes.
#pragma omp simd
        for (int64_t i = i0; i < i1; ++i) {
            const double zo = z[i], vo = v[i], hi = h[i], fo = f[i];
            const double fi = (zo <= hi) ? std::max(fo, 0.0) : fo;
            double vi = uphill ? 0.0 : vo;
            vi += dt * fi;
            vi = keep * vi + mix * fi;
            const double zn = zo - back * vo + dt * vi;
            const bool hit = zn < hi;  // the wall stops a point that reaches it
            v[i] = hit ? 0.0 : vi;
            z[i] = hit ? hi : zn;
        }
    });
}

}  // namespace gfmd
