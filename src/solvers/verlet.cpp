#include "verlet.hpp"

namespace gfmd {

void Verlet::advance(StepContext &c) {
    // Damped leapfrog: v(t+dt/2) = [(1 - eta dt/2) v(t-dt/2) + dt F(t)] / (1 + eta dt/2),
    // z(t+dt) = z(t) + dt v(t+dt/2), then the hard wall z >= h with the velocity of a point that
    // hits it set to zero (seed paper, Sec. 2.2).
    const double eta = c.dynamics.eta, dt = c.dynamics.dt;
    const double c1 = 1.0 - 0.5 * eta * dt, c2 = 1.0 / (1.0 + 0.5 * eta * dt);
    double *z = c.fields.z.data(), *v = c.fields.v.data();
    const double *h = c.fields.h.data(), *f = c.fields.f.data();
    c.grid.for_points([&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) {
            double vi = (c1 * v[i] + dt * f[i]) * c2;
            double zi = z[i] + dt * vi;
            if (zi < h[i]) {
                zi = h[i];
                vi = 0.0;
            }
            v[i] = vi;
            z[i] = zi;
        }
    });
}

}  // namespace gfmd
