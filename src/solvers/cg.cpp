#include "cg.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>

#include <utility>

#include "../constraint.hpp"
#include "../error.hpp"
#include "../kernels.hpp"

namespace gfmd {

namespace {
// The checked step (sufficient_decrease, below)
constexpr double kArmijo = 1e-4;
constexpr int kMaxBacktracks = 30;
// The adhesive line search (adhesive_line_minimum): at most 12 evaluations, D within 1e-3 of D(0)
// (a CG needs a near-exact line minimum for its conjugacy; the check catches the rest).
constexpr int kLineIterations = 12;
constexpr double kLineTolerance = 1e-3;
}  // namespace

void SurfaceCg::set_state(const double *s) {
    if (!(s[0] >= 0.0) || !std::isfinite(s[0]) || (s[1] != 0.0 && s[1] != 1.0 && s[1] != 2.0))
        fail(GFMD_ERR_FORMAT, "invalid CG state");
    prev_r2_ = s[0];
    fresh_ = s[1] != 0.0;
    steepest_ = s[1] == 2.0;
    bucket_ = -1;
}

// Polonsky-Keer's iteration on the pressure under pressure control on a half-space or a bonded
// layer; the surface CG on a layer on a fluid foundation, whose long waves are soft without bound
// (the pressure CG then resets its conjugacy nearly every iteration as points keep joining the
// contact set: 64^2, W = 1: 810 iterations against the surface CG's 72; a thin sheet W = 0.25 did
// not converge to 1e-8 in 80 000 iterations where the surface CG took 1 749), and under
// displacement control.
void ConjugateGradient::advance(StepContext &c) {
    if (uses_surface(c.params))
        surface_.advance(c, preconditioned(c.params) ? &pressure_.scratch() : nullptr);
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
//   s = r, or preconditioned s = M^-1 r on the free points (below),
//   t = s + beta t_old on the points free to move (beta = r.s/(r.s)_old, Fletcher-Reeves),
//   alpha = r.t / t.K.t, the exact minimizer of the quadratic energy along t,
//   z <- max(h, z + alpha t).
// The direction restarts (beta = 0) when the projection stopped a point at the wall (the free set
// shrank, the conjugacy is lost) and whenever t would not descend.  One forward transform (for
// t.K.t) per iteration beside the force evaluation's pair; preconditioned, one pair more.
void SurfaceCg::advance(StepContext &c, RealBuffer *scratch) {
    const FftGrid &grid = c.grid;
    const ForceState &fs = c.forces;
    double *__restrict z = c.fields.z.data(), *__restrict t = c.fields.v.data();
    const double *__restrict h = c.fields.h.data(), *__restrict f = c.fields.f.data();
    // after a step that failed its check (sufficient_decrease, below): once along the force itself
    const bool preconditioned = scratch != nullptr && !steepest_;
    const double *__restrict s = preconditioned ? scratch->data() : f;
    const double r2 = preconditioned ? precondition(c, scratch->data()) : fs.f_norm2;
    const double beta = (fresh_ || steepest_ || !(prev_r2_ > 0.0)) ? 0.0 : r2 / prev_r2_;
    steepest_ = false;
    // with adhesion the line search's sums at alpha = 0 in the same pass (line0)
    const bool adhesive = c.params.gamma0 > 0.0;
    const double inv_rho = adhesive ? 1.0 / c.params.rho : 0.0;
    std::array<double, 3> line0{};
    const auto direction = [&](double b) {
        const auto d = grid.sum_points<4>([&](int64_t i0, int64_t i1, double *acc) {
            kernels::use().cg_direction(z + i0, h + i0, f + i0, s + i0, t + i0, b, inv_rho, i1 - i0, acc);
        });
        line0 = {d[1], d[2], d[3]};
        return d[0];
    };
    // Under displacement control the direction must keep mean(z): t is projected onto zero mean
    // over the points free to move (the gradient of the energy within the constraint), so that
    // the step moves the mean only where the wall stops points (128^2 sheet, w = 1, tol 1e-11:
    // 2630 iterations against 3026 with the projection onto mean(z) = d left to undo t's mean).
    const bool hold_mean = c.params.control == kDisplacementControl;
    const auto mean_free = [&] {
        const auto m = grid.sum_points<2>([&](int64_t i0, int64_t i1, double *acc) {
            double st = 0.0, nf = 0.0;
#pragma omp simd reduction(+ : st, nf)
            for (int64_t i = i0; i < i1; ++i) {
                const bool held = held_by_wall(z[i], h[i], f[i]);
                st += held ? 0.0 : t[i];
                nf += held ? 0.0 : 1.0;
            }
            acc[0] += st;
            acc[1] += nf;
        });
        const double mt = m[1] > 0.0 ? m[0] / m[1] : 0.0;
        return grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
            double rt = 0.0;
#pragma omp simd reduction(+ : rt)
            for (int64_t i = i0; i < i1; ++i) {
                const bool held = held_by_wall(z[i], h[i], f[i]);
                t[i] = held ? 0.0 : t[i] - mt;
                rt += f[i] * t[i];
            }
            acc[0] += rt;
        })[0];
    };
    double rt = direction(beta);
    if (hold_mean) rt = mean_free();
    if (!(rt > 0.0) && beta != 0.0) {
        // t_old dominated and pointed uphill: start again along s (t = s exactly, since t
        // was s + beta t_old, recompute it from scratch).
        rt = direction(0.0);
        if (hold_mean) rt = mean_free();
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
        acc[0] += kernels::use().mode_energy(work, stiff, y0, y1, nxh, w_last);
    })[0];
    // dE/dalpha = -(A/N) r.t and d2E/dalpha2 = (A/N^2) tkt, so alpha = N r.t / tkt.  Without
    // elastic curvature along t (t uniform: no contact holds the body) the step ends at the wall.
    const double n = static_cast<double>(grid.real_size());
    double alpha = n * rt / tkt;
    // (with adhesion never under displacement control: t is the direction's, as line0 was summed)
    LineMinimum line{alpha, 0.0, 0.0, 0.0};
    if (adhesive && tkt > 0.0 && std::isfinite(alpha)) line = adhesive_line_minimum(c, rt, tkt / n, alpha, line0);
    alpha = line.alpha;
    const bool to_wall = !(tkt > 0.0) || !std::isfinite(alpha);
    // Under pressure control the step is checked where the wall stopped points (below): the
    // start is kept in the scratch, whose preconditioned residual the direction has consumed.
    const bool guard = scratch != nullptr && !hold_mean && !to_wall;
    // the move; a checked one saves its start in the same pass
    const auto move = [&](double a, double *save) {
        return grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
            kernels::use().cg_move(z + i0, h + i0, t + i0, a, to_wall, i1 - i0, acc, save ? save + i0 : nullptr);
        })[0];
    };
    const double hits = move(alpha, guard ? scratch->data() : nullptr);
    fresh_ = hits > 0.0;
    // With adhesion a step the wall did not stop has the energy change the line search summed (the
    // path is the one it followed): checked against it, without a pass; one it stopped, as above.
    const bool decreased = !adhesive || (hits == 0.0 && line.change <= -kArmijo * grid.area_per_point() * alpha * rt + line.slack);
    if (guard && (hits > 0.0 || !decreased)) sufficient_decrease(c, scratch->data(), alpha, rt, move, line.weight);
}

// alpha above minimizes the quadratic energy along t, but where the wall stops points the move is
// projected, and a projected step can raise the energy, far: on a thin sheet at a low load (48^2,
// w = 0.4, sigma0/(E* g) = 1e-5) t is mostly the sheet's soft long waves, alpha slammed the whole
// sheet onto the substrate (A/A0 0.0004 -> 0.999, the energy from -3.6e-6 to +3.7e-2), and the
// iteration went on climbing and falling without converging.  So such a step must decrease the
// energy E = U_el + sigma0 A mean(z) by at least 1e-4 of its first-order prediction (Armijo's
// rule along the projected path, as in Moré & Toraldo's projected searches); if not, alpha
// shrinks by the minimizer of the parabola through E(0), E'(0) and E(alpha), kept within [0.1,
// 0.5] of the last, up to kMaxBacktracks times, each one forward transform.  A step that still
// fails is undone (z from the scratch) and the next direction is the projected force itself, along
// which a small enough step always descends.  Steps the wall does not stop are exact minimizers
// and are not checked; with adhesion (adhesive_line_minimum, below) they are, against the energy
// change the line search summed along their path, and this check follows if that fails.  With
// adhesion E includes -U_ad.
namespace {
// The smallest step along t at which a point above the wall (z > h) moving down reaches it, if
// below alpha; else 0.
double first_contact(const FftGrid &grid, const double *z, const double *h, const double *t, double alpha) {
    // the smallest step as the largest of its negatives
    const double best = -grid.max_points<1>([&](int64_t i0, int64_t i1, double *top) {
        for (int64_t i = i0; i < i1; ++i)
            if (t[i] < 0.0 && z[i] > h[i]) top[0] = std::max(top[0], (z[i] - h[i]) / t[i]);
    })[0];
    return best < alpha ? best : 0.0;
}
}  // namespace

// With adhesion the energy along t is no longer quadratic: E(alpha) = E(0) - a_pt D-integral, with
// dE/dalpha = -a_pt D(alpha),
//   D(alpha) = r.t + (gamma0/rho) (S1(0) - S1(alpha)) - alpha t.K.t/N,
//   S1(alpha) = sum of w t, w = exp(-g/rho) at the gap g = z - h + alpha t (1 at the wall),
//   D'(alpha) = (gamma0/rho^2) S2(alpha) - t.K.t/N, S2 = sum of w t^2 above the wall,
// exact for the elastic and load terms along the unprojected line and for the adhesive term along
// the projected one (a point at the wall feels the pull gamma0/rho: its w stays 1).  Its zero by
// Newton's method kept inside the bracket [lo, hi] where D changes sign (bisection when a step
// would leave it, doubling until D < 0 is found), from the quadratic step: the adhesive pull only
// lengthens it; Newton's first step is taken from 0, where the same pass gives D(0) = r.t and
// D'(0).  One pass over the points each, no transform.  The move is then
// checked against the true energy (sufficient_decrease).
SurfaceCg::LineMinimum SurfaceCg::adhesive_line_minimum(const StepContext &c, double rt, double ktn,
                                                       double alpha, const std::array<double, 3> &s0) const {
    const FftGrid &grid = c.grid;
    const double *z = c.fields.z.data(), *h = c.fields.h.data(), *t = c.fields.v.data();
    const double inv_rho = 1.0 / c.params.rho, coef = c.params.gamma0 * inv_rho;
    const auto sums = [&](double a) {
        return grid.sum_points<3>([&](int64_t i0, int64_t i1, double *acc) {
            kernels::use().cg_adhesive_line(z + i0, h + i0, t + i0, a, inv_rho, i1 - i0, acc);
        });
    };
    const double d_el = rt + coef * s0[0], slope0 = coef * inv_rho * s0[1] - ktn;
    // Newton's first step from 0 where E is convex along t there (it lengthens the quadratic step)
    if (slope0 < 0.0) alpha = rt / -slope0;
    double lo = 0.0, hi = HUGE_VAL;
    for (int k = 0;; ++k) {
        const auto s = sums(alpha);
        const double d = d_el - coef * s[0] - alpha * ktn;
        if (std::fabs(d) <= kLineTolerance * rt || k + 1 == kLineIterations) {
            // E(alpha) - E(0): the elastic and load terms integrated, the adhesive one summed
            const double a_pt = grid.area_per_point();
            const double change = -a_pt * (d_el * alpha - 0.5 * alpha * alpha * ktn) -
                                  c.params.gamma0 * a_pt * (s[2] - s0[2]);
            const double size = a_pt * (std::fabs(d_el * alpha) + 0.5 * alpha * alpha * ktn) +
                                c.params.gamma0 * a_pt * (s[2] + s0[2]);
            return {alpha, change, 1e-12 * size, s[2]};
        }
        const double slope = coef * inv_rho * s[1] - ktn;
        if (d > 0.0) lo = alpha; else hi = alpha;
        double next = (slope < 0.0) ? alpha - d / slope : HUGE_VAL;
        if (!(next > lo && next < hi)) next = std::isfinite(hi) ? 0.5 * (lo + hi) : 2.0 * alpha;
        alpha = next;
    }
}

template <class Move>
void SurfaceCg::sufficient_decrease(StepContext &c, const double *z0, double alpha, double rt, Move &&move,
                                    double weight) {
    const FftGrid &grid = c.grid;
    double *__restrict z = c.fields.z.data();
    const double *__restrict f = c.fields.f.data();
    const double a_pt = grid.area_per_point(), sigma0 = c.params.sigma0;
    const double inv_n = 1.0 / static_cast<double>(grid.real_size());
    const int64_t nxh = grid.nxh();
    const double w_last = grid.weight(nxh - 1);
    const double *stiff = c.body.stiffness.data();
    // dE/dalpha at 0 along t: -(A/N) r.t
    const double slope = a_pt * rt;
    const double *__restrict h = c.fields.h.data();
    const double inv_rho = 1.0 / c.params.rho;
    const bool adhesive = c.params.gamma0 > 0.0;
    double a = alpha;
    for (int k = 0; k <= kMaxBacktracks; ++k) {
        if (k > 0) {
            grid.for_points([&](int64_t i0, int64_t i1) { std::copy(z0 + i0, z0 + i1, z + i0); });
            move(a, nullptr);
        }
        // the change of the load's work and the first-order prediction, sum (z - z0) and f.(z - z0);
        // with adhesion the adhesive weight sum of the new z
        // (at the first try the line search's last sum is that of this z: max(h, z0 + alpha t))
        const bool summed = k == 0 && adhesive;
        auto d = grid.sum_points<3>([&](int64_t i0, int64_t i1, double *acc) {
            kernels::use().cg_step_sums(z + i0, z0 + i0, f + i0, h + i0, inv_rho, adhesive && !summed, i1 - i0, acc);
        });
        if (summed) d[2] = weight;
        grid.forward(z, c.fields.work.data());
        const std::complex<double> *work = c.fields.work.data();
        const double energy = grid.sum_mode_rows<1>([&](int64_t y0, int64_t y1, double *acc) {
            acc[0] += kernels::use().mode_energy(work, stiff, y0, y1, nxh, w_last);
        })[0];
        const double u_el = 0.5 * grid.cell_area() * energy * inv_n * inv_n;
        // U_ad = -gamma0 a_pt (weight sum); ForceState::u_ad is its magnitude
        const double u_ad = c.params.gamma0 * a_pt * d[2];
        const double change = (u_el - c.forces.u_el) + sigma0 * a_pt * d[0] - (u_ad - c.forces.u_ad);
        const double predicted = -a_pt * d[1];  // < 0 along a descent path
        // rounding: the energies summed over the modes and points, about 1e-13 of their size at most
        const double slack = 1e-12 * (std::fabs(u_el) + std::fabs(c.forces.u_el) + u_ad + c.forces.u_ad);
        if (change <= kArmijo * predicted + slack) {
            c.fields.work_holds_z = true;  // the force evaluation's transform, done
            return;
        }
        // the parabola through E(0) = 0, E'(0) = -slope and E(a) = change
        const double curvature = (change + slope * a) / (a * a);
        const double ratio = curvature > 0.0 ? slope / (2.0 * curvature * a) : 0.5;
        const double shrunk = a * std::min(0.5, std::max(0.1, ratio));
        // First, the step to where the first point above the wall reaches it, if it is longer:
        // up to there nothing is projected and the energy is the quadratic that alpha minimizes,
        // so it decreases (a sheet that floats on a few contacts lands on the next, where the
        // parabola, blind to the wall, took a tenth of the step again and again: 48 x 40, w = a,
        // sigma0/(E* g) = 1e-5, 42 iterations against 6 for the unchecked projected steps).
        a = (k == 0) ? std::max(shrunk, first_contact(grid, z0, h, c.fields.v.data(), alpha)) : shrunk;
    }
    grid.for_points([&](int64_t i0, int64_t i1) { std::copy(z0 + i0, z0 + i1, z + i0); });
    steepest_ = true;
}

namespace {
// The preconditioner's floor k_c: the stiffness at the wave vector q_c = min(0.5 q_spacing, 1/w)
// (at dense contacts 1/w no lower than 0.5 q_spacing / kPcgDenseRatio), q_spacing that of the
// contact points' mean spacing.  Modes longer than the spacing are pinned by the contacts (as
// mass-weighted FIRE's mass floor, mass_weighted_fire.cpp); on a thick layer the floor stays at or below
// the wave vector 1/w where the layer turns from half-space to plate.
// Measured (gfmd_bench --loads 0.002,0.01,0.05, W = 0.0625 ... 10, 256^2-1024^2, from flat):
// 0.5 q_spacing was best of 0.125 ... 2 (0.125 took up to 20x the iterations, 1 up to 1.8x); the
// cap at 1/w cut a W = 4 layer's iterations 2-4x at 512^2 (212 -> 72, 233 -> 59) and 1024^2
// (477 -> 148) and changed the thin sheets' (W <= 1) by 0.68-1.10x (0.5/w and 2/w: worse).
constexpr double kPcgSpacing = 0.5;
constexpr double kPcgWidth = 1.0;
// Where the contacts are dense (their fraction phi >= kPcgDenseArea) the cap at 1/w stops at
// kPcgDenseRatio below 0.5 q_spacing: there the long waves are pinned by many contacts, and a floor
// far below their scale made a thick layer's CG slow at high loads (gfmd_bench --loads; 256^2,
// W = 10, sigma0 = 0.2: 230 iterations against FIRE's 176 steps; 1024^2, W = 10, sigma0 = 0.05:
// 157).  Measured from flat (H = 0.8, lambda_s = 4a, lambda_r = n a/8, W = 1 ... 40, sigma0 =
// 0.01 ... 0.5, 256^2, 512^2; 1024^2 W = 1, 4, 10 at 0.05 and 0.2) against the cap alone: 2-14x
// fewer iterations at A/A0 >= 0.1 (256^2, W = 10, 0.2: 16; 1024^2, W = 10, 0.05: 72, 0.2: 44 against
// 208), within 1.2x either way below; thin sheets (q_max w < 6, the cap inactive) unchanged.  Ratios
// 4 and 6 did as well on some rows and up to 1.7x worse on others (a W = 40 layer at low loads,
// which the phi bound now leaves to the cap); phi at the octave's middle, as the floor's.
constexpr double kPcgDenseArea = 0.05;
constexpr double kPcgDenseRatio = 5.0;
}  // namespace

// M^-1 = 1/max(k(q), k_c) applied to the projected force, then restricted to the free points (a
// principal block of an SPD operator: SPD on the free set, so PCG's theory holds while the free
// set stays).  k_c follows the contacts' count by octave b = floor(log2(contacts)), taken at the
// octave's geometric middle sqrt(2) 2^b (at its bottom 2^b the 256^2 study's sweep of W = 0.0625
// took 7327 iterations against 5541), a function of the state, so checkpoints resume bit for bit;
// where it changes, Fletcher-Reeves carries on (a rare jump).
double SurfaceCg::precondition(const StepContext &c, double *zp) {
    const FftGrid &grid = c.grid;
    const double *__restrict z = c.fields.z.data(), *__restrict h = c.fields.h.data(), *__restrict f = c.fields.f.data();
    const double *stiff = c.body.stiffness.data();
    const int64_t nxh = grid.nxh();
    const int64_t contacts = c.forces.contacts;
    const int bucket = contact_octave(contacts);
    if (bucket != bucket_) {
        const double points = std::ldexp(std::sqrt(2.0), bucket);
        double qc2 = contact_spacing_q2(grid, kPcgSpacing, points);
        const double w = c.params.width;
        // a half-space (preconditioned with adhesion only) has no thickness: the cap of w -> infinity
        double cap2 = (w > 0.0) ? kPcgWidth * kPcgWidth / (w * w) : 0.0;
        if (points >= kPcgDenseArea * static_cast<double>(grid.real_size()))
            cap2 = std::max(cap2, qc2 / (kPcgDenseRatio * kPcgDenseRatio));
        qc2 = std::min(qc2, cap2);
        const double kc = stiffest_mode_within(grid, c.body, qc2);
        floor_ = std::min(std::max(kc, c.body.k_min), c.body.k_max);
        bucket_ = bucket;
    }
    grid.for_points([&](int64_t i0, int64_t i1) { kernels::use().cg_mask(z + i0, h + i0, f + i0, zp + i0, i1 - i0); });
    grid.forward(zp, c.fields.work.data());
    std::complex<double> *work = c.fields.work.data();
    const double inv_n = 1.0 / static_cast<double>(grid.real_size()), floor = floor_;
    grid.for_mode_rows([&](int64_t y0, int64_t y1) {
        (void)kernels::use().precondition_modes(work, stiff, y0, y1, nxh, inv_n, floor, 1.0);
    });
    grid.backward(c.fields.work.data(), zp);
    return grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
        kernels::use().cg_restrict(z + i0, h + i0, f + i0, zp + i0, i1 - i0, acc);
    })[0];
}

}  // namespace gfmd
