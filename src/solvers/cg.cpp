#include "cg.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include <utility>

#include "../error.hpp"

namespace gfmd {

void SurfaceCg::set_state(const double *s) {
    if (!(s[0] >= 0.0) || !std::isfinite(s[0]) || (s[1] != 0.0 && s[1] != 1.0)) fail(GFMD_ERR_FORMAT, "invalid CG state");
    prev_r2_ = s[0];
    fresh_ = s[1] != 0.0;
}

// Polonsky-Keer's iteration on the pressure under pressure control on a half-space or a bonded
// layer; the surface CG on a layer on a fluid foundation, whose long waves are soft without bound
// (the pressure CG then resets its conjugacy nearly every iteration as points keep joining the
// contact set: 64^2, W = 1: 810 iterations against the surface CG's 72; a thin sheet W = 0.25 did
// not converge to 1e-8 in 80 000 iterations where the surface CG took 1 749), and under
// displacement control.
void ConjugateGradient::advance(StepContext &c) {
    if (uses_surface(c.params))
        surface_.advance(c);
    else
        pressure_.advance(c);
}

std::vector<double> ConjugateGradient::state() const {
    std::vector<double> s = surface_.state();
    const std::vector<double> p = pressure_.state();
    s.insert(s.end(), p.begin(), p.end());
    return s;
}

// Checks everything before changing anything: a corrupted file leaves the solver as it was.
void ConjugateGradient::set_state(const std::vector<double> &s) {
    if (s.size() != 8 && s.size() != 7) fail(GFMD_ERR_FORMAT, "invalid CG state");  // 7: without PK's count
    SurfaceCg surface = surface_;
    surface.set_state(s.data());
    pressure_.set_state(std::vector<double>(s.begin() + 2, s.end()));
    surface_ = surface;
}

void ConjugateGradient::set_grid_state(std::vector<RealBuffer> &&fields) {
    if (fields.size() != 1) fail(GFMD_ERR_FORMAT, "invalid CG grid state");
    pressure_.set_pressure(std::move(fields[0]));
}

// Projected conjugate gradients for the bound-constrained quadratic problem (the primal form of
// Polonsky & Keer's method, cf. Bugnicourt et al., Tribol. Lett. 66, 29 (2018)):
//   r = the projected force (the residual of evaluate_forces: zero where the wall holds z),
//   t = r + beta t_old on the points free to move (beta = |r|^2/|r_old|^2, Fletcher-Reeves),
//   alpha = r.t / t.K.t, the exact minimizer of the quadratic energy along t,
//   z <- max(h, z + alpha t).
// The direction restarts (beta = 0) when the projection stopped a point at the wall (the free set
// shrank, the conjugacy is lost) and whenever t would not descend.  One forward transform (for
// t.K.t) per iteration beside the force evaluation's pair.
void SurfaceCg::advance(StepContext &c) {
    const FftGrid &grid = c.grid;
    const ForceState &fs = c.forces;
    double *__restrict z = c.fields.z.data(), *__restrict t = c.fields.v.data();
    const double *__restrict h = c.fields.h.data(), *__restrict f = c.fields.f.data();
    const double r2 = fs.f_norm2;
    double beta = (fresh_ || !(prev_r2_ > 0.0)) ? 0.0 : r2 / prev_r2_;
    const auto direction = [&](double b) {
        return grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
            double rt = 0.0;
#pragma omp simd reduction(+ : rt)
            for (int64_t i = i0; i < i1; ++i) {
                const bool held = z[i] <= h[i] && f[i] <= 0.0;
                const double ti = held ? 0.0 : f[i] + b * t[i];
                t[i] = ti;
                rt += f[i] * ti;
            }
            acc[0] += rt;
        })[0];
    };
    double rt = direction(beta);
    if (!(rt > 0.0) && beta != 0.0) {
        // t_old dominated and pointed uphill: start again along the force (t = r exactly, since t
        // was r + beta t_old, recompute it from scratch).
        beta = 0.0;
        rt = direction(0.0);
    }
    prev_r2_ = r2;
    if (!(rt > 0.0)) {  // r = 0 everywhere the body may move: nothing to do
        fresh_ = true;
        return;
    }
    // t.K.t = (A/N^2) sum_q k(q) |T(q)|^2 over the full plane (the energy's second derivative).
    grid.forward(t, c.fields.work.data());
    const std::complex<double> *work = c.fields.work.data();
    const double *stiff = c.body.stiffness.data();
    const int64_t nxh = grid.nxh();
    const double w_last = grid.weight(nxh - 1);
    const double tkt = grid.sum_mode_rows<1>([&](int64_t y0, int64_t y1, double *acc) {
        for (int64_t r = y0; r < y1; ++r) {
            const std::complex<double> *row = work + r * nxh;
            const double *krow = stiff + r * nxh;
            double e = krow[0] * std::norm(row[0]);
            if (nxh > 1) e += (w_last - 2.0) * krow[nxh - 1] * std::norm(row[nxh - 1]);
            for (int64_t kx = 1; kx < nxh; ++kx) e += 2.0 * krow[kx] * std::norm(row[kx]);
            acc[0] += e;
        }
    })[0];
    // dE/dalpha = -(A/N) r.t and d2E/dalpha2 = (A/N^2) tkt, so alpha = N r.t / tkt.  Without
    // elastic curvature along t (t uniform: no contact holds the body) the step ends at the wall.
    const double n = static_cast<double>(grid.real_size());
    double alpha = n * rt / tkt;
    const bool to_wall = !(tkt > 0.0) || !std::isfinite(alpha);
    const double hits = grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
        double stopped = 0.0;
#pragma omp simd reduction(+ : stopped)
        for (int64_t i = i0; i < i1; ++i) {
            const double zn = to_wall ? (t[i] < 0.0 ? h[i] : z[i]) : z[i] + alpha * t[i];
            const bool hit = zn < h[i] || (to_wall && t[i] < 0.0);
            stopped += hit ? 1.0 : 0.0;
            z[i] = hit ? h[i] : zn;
        }
        acc[0] += stopped;
    })[0];
    fresh_ = hits > 0.0;
}

}  // namespace gfmd
