#include "mass_weighted_fire.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>

#include "../kernels.hpp"

namespace gfmd {

namespace {
// The mass floor is the stiffness at kMassSpacing times the wave vector of the contact points'
// mean spacing (1 was best of 0.25 ... 4, docs/decisions.md).
constexpr double kMassSpacing = 1.0;

// Power iterations for the highest frequency of the masked dynamics (10: within 5-15 % of the
// converged value on the study's thin sheets, 256^2, against 30; it is approached from below, and
// FIRE's uphill test catches the rest).
constexpr int kLambdaIterations = 10;

// x <- P op(x) in place: op the Fourier rows' scaling scale_rows(r0, r1) on the work array, P
// zeroes the points `held` marks (the masked operators of masked_lambda and hold_mean).
template <class ScaleRows>
void apply_masked(const FftGrid &grid, double *x, std::complex<double> *work, const unsigned char *held,
                  ScaleRows scale_rows) {
    grid.forward(x, work);
    grid.for_mode_rows(scale_rows);
    grid.backward(work, x);
    grid.for_points([&](int64_t i0, int64_t i1) {
#pragma omp simd
        for (int64_t i = i0; i < i1; ++i) x[i] = held[i] ? 0.0 : x[i];  // branch-free: scattered contacts
    });
}
}  // namespace

MassWeightedFire::MassWeightedFire(const MassWeightedFire &o)
    : Solver(o), control_(o.control_), held_(o.held_.size()), mean_response_(o.mean_response_.size()),
      response_held_(o.response_held_.size()), floor_(o.floor_), mass_dt_(o.mass_dt_),
      inv_m_(o.inv_m_), bucket_(o.bucket_), estimate_(o.estimate_), lambda_(o.lambda_) {}

std::vector<double> MassWeightedFire::state() const {
    std::vector<double> s = control_.state();
    s.insert(s.end(), lambda_.begin(), lambda_.end());
    return s;
}

void MassWeightedFire::set_state(const std::vector<double> &s) {
    const std::size_t nc = control_.state().size();
    if (s.size() != nc && s.size() != nc + kBuckets) fail(GFMD_ERR_FORMAT, "invalid state of mass-weighted FIRE");
    std::array<double, kBuckets> lambda{};
    for (std::size_t b = 0; b + nc < s.size(); ++b) {
        const double l = s[nc + b];
        if (!(l == 0.0 || (l >= 1.0 && std::isfinite(l)))) fail(GFMD_ERR_FORMAT, "invalid state of mass-weighted FIRE");
        lambda[b] = l;
    }
    control_.set_state(std::vector<double>(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(nc)));
    lambda_ = lambda;
    bucket_ = -1;
    response_valid_ = false;
}

// The mass floor of mass-weighted FIRE.  A body pressed onto a substrate at contact fraction phi
// is held at points about sqrt(1/phi) cells apart; modes longer than that spacing are pinned by the
// contacts and do not relax on their own (soft) elastic time scale.  Their masses are therefore
// raised to the stiffness k_c at the contact spacing, the largest 1/G(q) over the fraction phi of
// modes with the smallest |q| (|q|^2 <= 4 pi phi / cell).  The floor depends only on the bucket
// floor(log2(contacts)), so it is a function of the state (a checkpoint resumes bit for bit).
void MassWeightedFire::update_mass_floor(const StepContext &c) {
    const FftGrid &grid = c.grid;
    const RealBuffer &stiff = c.body.stiffness;
    const int64_t contacts = c.forces.contacts;
    const int bucket = contact_octave(contacts);
    if (bucket == bucket_) return;
    const double qc2 = contact_spacing_q2(grid, kMassSpacing, std::ldexp(1.0, bucket));
    const double kc = stiffest_mode_within(grid, c.body, qc2);
    const int64_t nxh = grid.nxh();
    floor_ = std::min(std::max(kc, c.body.k_min), c.body.k_max);
    // The adhesive law's stiffness is local: a single point's acceleration per unit force is the
    // real-space diagonal of M^-1, the mean of 1/m(q) over all modes (translation invariance), so
    // it adds k_adh <1/m> to the elastic frequencies^2 (masked_lambda).
    const double floor = floor_;
    const double inv_m = grid.sum_mode_rows<1>([&](int64_t r0, int64_t r1, double *acc) {
        double t = 0.0;
        for (int64_t r = r0; r < r1; ++r)
            for (int64_t kx = 0; kx < nxh; ++kx)
                t += grid.weight(kx) / std::max(stiff[static_cast<std::size_t>(r * nxh + kx)], floor);
        acc[0] += t;
    })[0] / static_cast<double>(grid.real_size());
    inv_m_ = inv_m;
    bucket_ = bucket;
}

// The highest frequency^2 of the masked dynamics, lambda_max of P M^-1 P K P (P zeroes the points
// held_ marks): by power iteration from a fixed pseudo-random field of the global point index, in
// the force field f (the caller evaluates the forces again).  Without the mask every elastic mode
// has k(q)/m(q) <= 1; with it, measured, lambda_max grows as the contacts thin out (a thin sheet
// W = 0.088 at 256^2: 1.5, 3.1, 9.4, 29, 80, 121 at 2^15 ... 2^10 contacts): the principal block
// of M^-1 exceeds the inverse of M's block (Schur), and the modes coupled through the held points
// are stiff.  With the step set for lambda = 1 FIRE went uphill every ~10 steps there (1485
// restarts in 15 780 steps), its step halved each time.
double MassWeightedFire::masked_lambda(StepContext &c) {
    const FftGrid &grid = c.grid;
    const int64_t nxh = grid.nxh(), first = grid.first_row() * grid.nx();
    const double inv_n = 1.0 / static_cast<double>(grid.real_size()), floor = floor_;
    const double *stiff = c.body.stiffness.data();
    const unsigned char *held = held_.data();
    double *x = c.fields.f.data();
    std::complex<double> *work = c.fields.work.data();
    grid.for_points([&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) {  // splitmix64 of the global index: the same on any ranks
            uint64_t r = static_cast<uint64_t>(first + i) + 0x9E3779B97F4A7C15ull;
            r = (r ^ (r >> 30)) * 0xBF58476D1CE4E5B9ull;
            r = (r ^ (r >> 27)) * 0x94D049BB133111EBull;
            r ^= r >> 31;
            x[i] = held[i] ? 0.0 : static_cast<double>(r >> 11) * 0x1.0p-53 - 0.5;
        }
    });
    // x <- P op(x), op K (by k(q)) or M^-1 (the surface CG's preconditioner, the same inverse masses)
    const auto apply = [&](auto scale_rows) { apply_masked(grid, x, work, held, scale_rows); };
    const auto norm2 = [&] {
        return grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
            double t = 0.0;
            for (int64_t i = i0; i < i1; ++i) t += x[i] * x[i];
            acc[0] += t;
        })[0];
    };
    double x2 = norm2(), lambda = 0.0;
    for (int it = 0; it < kLambdaIterations && x2 > 0.0; ++it) {
        apply([&](int64_t r0, int64_t r1) {  // K
            for (int64_t k = r0 * nxh; k < r1 * nxh; ++k) work[k] *= stiff[k] * inv_n;
        });
        apply([&](int64_t r0, int64_t r1) {
            (void)kernels::use().precondition_modes(work, stiff, r0, r1, nxh, inv_n, floor, 1.0);
        });
        const double y2 = norm2();
        lambda = std::sqrt(y2 / x2);
        if (!(y2 > 0.0)) break;
        const double s = 1.0 / std::sqrt(y2);
        grid.for_points([&](int64_t i0, int64_t i1) {
            for (int64_t i = i0; i < i1; ++i) x[i] *= s;
        });
        x2 = 1.0;
    }
    return lambda;
}

// Under displacement control mean(z) is held: a step must move the free points without moving
// their mean.  The acceleration and the velocity are both projected in the metric of the masked
// preconditioner B = P M^-1 P (P: the free points) onto the free points' zero sum: a = B F - la B 1
// with la = sum(B F) / sum(B 1), and v - lv B 1 with lv = sum(v) / sum(B 1) (sums over the free
// points).  B 1, the free points' response to a uniform pull, is one FFT pair more per step.  The
// acceleration alone (in this metric, in the plain one, or the uniform mode of M^-1 F zeroed) was
// not enough: FIRE's velocity carries a mean into the step whenever the held set changes, which
// the projection after the step then takes out of every point; on thin sheets the run stalled far
// from equilibrium (docs/decisions.md).  At
// equilibrium a = 0 on the free points, so F = la there, and la = 0: the mean pressure makes the
// free points' forces sum to zero (evaluate_forces).  Returns |a| (a in place of B F).
double MassWeightedFire::hold_mean(StepContext &c, double *a) {
    const FftGrid &grid = c.grid;
    const unsigned char *held = held_.data();
    double *b = mean_response_.data(), *v = c.fields.v.data();
    // B 1 again only where the held set or the floor changed since it was computed (over all
    // ranks): near the equilibrium most steps keep both, and the FFT pair is a third of a step.
    unsigned char *kept = response_held_.data();
    const bool same = response_valid_ && response_floor_ == floor_ &&
                      grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
                          double changed = 0.0;
#pragma omp simd reduction(+ : changed)
                          for (int64_t i = i0; i < i1; ++i) changed += (held[i] != kept[i]) ? 1.0 : 0.0;
                          acc[0] += changed;
                      })[0] == 0.0;
    if (!same) {
        grid.for_points([&](int64_t i0, int64_t i1) {
#pragma omp simd
            for (int64_t i = i0; i < i1; ++i) {
                b[i] = held[i] ? 0.0 : 1.0;
                kept[i] = held[i];
            }
        });
        std::complex<double> *work = c.fields.work.data();
        const double *stiff = c.body.stiffness.data();
        const int64_t nxh = grid.nxh();
        const double inv_n = 1.0 / static_cast<double>(grid.real_size()), floor = floor_;
        apply_masked(grid, b, work, held, [&](int64_t r0, int64_t r1) {
            (void)kernels::use().precondition_modes(work, stiff, r0, r1, nxh, inv_n, floor, 1.0);
        });
        response_floor_ = floor_;
        response_valid_ = true;
    }
    const auto sums = grid.sum_points<3>([&](int64_t i0, int64_t i1, double *acc) {
        double sa = 0.0, sb = 0.0, sv = 0.0;
#pragma omp simd reduction(+ : sa, sb, sv)
        for (int64_t i = i0; i < i1; ++i) {
            sa += held[i] ? 0.0 : a[i];
            sb += b[i];  // zero where held (apply_masked)
            sv += held[i] ? 0.0 : v[i];
        }
        acc[0] += sa;
        acc[1] += sb;
        acc[2] += sv;
    });
    // sum(B 1) = 1^T B 1 > 0 when any point is free (B is positive definite on the free points)
    const double la = (sums[1] > 0.0) ? sums[0] / sums[1] : 0.0, lv = (sums[1] > 0.0) ? sums[2] / sums[1] : 0.0;
    const auto a2 = grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
        double t = 0.0;
#pragma omp simd reduction(+ : t)
        for (int64_t i = i0; i < i1; ++i) {
            const double ai = held[i] ? 0.0 : a[i] - la * b[i];
            a[i] = ai;
            v[i] -= lv * b[i];
            t += ai * ai;
        }
        acc[0] += t;
    });
    return std::sqrt(a2[0]);
}

void MassWeightedFire::advance(StepContext &c) {
    // FIRE with mass weighting (after Zhou, Moseler & Mueser, PRB 99, 144103 (2019)): each Fourier
    // mode has the inertia m(q) = max(k(q), k_c), so every mode stiffer than the contact spacing's
    // k_c oscillates with the same frequency.  The wall stays a real-space constraint, treated so
    // that it cannot feed the mass metric: (1) the force is projected before it is preconditioned,
    // so the wall's reaction never enters M^-1; (2) the points the wall holds are masked after it
    // (below); (3) the masses are bounded below by k_c, so M^-1 is bounded and the pinned long
    // modes are not accelerated beyond what the contacts let them move; (4) a point that hits the
    // wall stops, and FIRE's power test uses the true derivative of the energy, F.v, so any energy
    // a clamp puts in is caught as an uphill step.
    update_mass_floor(c);
    const FftGrid &grid = c.grid;
    const bool uphill = control_.control(c.forces.power, kMassDtMax);  // the step as a fraction of mass_dt_

    // a = M^-1 F_projected, one more r2c/c2r pair, computed in place of F (evaluate_forces()
    // recomputes F after the step); |a|^2 by Parseval in the same pass.  Points held by the wall
    // (in contact, pushed into it) are marked first: their acceleration is masked after the
    // preconditioning, so that only the free points move, with the preconditioner restricted to
    // them (a principal block of M^-1, still positive definite).  Without the mask the wall's
    // held points are lifted by their neighbours' preconditioned pull and clamped back every
    // step: the run bounces and never converges (measured; see docs/decisions.md).
    double *z = c.fields.z.data(), *v = c.fields.v.data(), *a = c.fields.f.data();
    const double *h = c.fields.h.data();
    unsigned char *held = held_.data();
    const auto mark = [&] {
        grid.for_points([&](int64_t i0, int64_t i1) { kernels::use().mark_held(z + i0, h + i0, a + i0, held + i0, i1 - i0); });
    };
    mark();
    // The step: omega_max dt = kDtFactor for the masked dynamics, estimated once per contact bucket
    // from its first held set (at least 1: the unmasked elastic modes); the estimate works in the
    // force field, which is then evaluated again (same z: the same bits) -- an FFT pair per bucket
    // instead of 16 bytes per point.
    double &lambda = lambda_[std::min(static_cast<std::size_t>(bucket_), kBuckets - 1)];
    if (lambda == 0.0 && !estimate_) lambda = 1.0;
    if (lambda == 0.0) {
        lambda = std::max(1.0, masked_lambda(c));
        (void)evaluate_forces(grid, c.params, c.body, c.fields);
        mark();
    }
    mass_dt_ = kDtFactor / std::sqrt(lambda + c.params.adhesive_stiffness() * inv_m_);
    const double dt = step();
    grid.forward(a, c.fields.work.data());
    const int64_t nxh = grid.nxh();
    const double inv_n = 1.0 / static_cast<double>(grid.real_size()), floor = floor_;
    std::complex<double> *work = c.fields.work.data();
    const double *stiff = c.body.stiffness.data();
    // M^-1 (masked_lambda's, the surface CG's preconditioner) with |a|^2 summed in the same pass
    const double w_last = grid.weight(nxh - 1);
    const auto a2 = grid.sum_mode_rows<1>([&](int64_t y0, int64_t y1, double *acc) {
        acc[0] += kernels::use().precondition_modes(work, stiff, y0, y1, nxh, inv_n, floor, w_last);
    });
    grid.backward(c.fields.work.data(), a);
    const double a_norm = (c.params.control == kDisplacementControl)
                              ? hold_mean(c, a)
                              : std::sqrt(a2[0] * static_cast<double>(grid.real_size()));

    // FIRE 1.0 order (Bitzek et al. 2006): mix v towards a with the current |v| (|a| before the
    // mask: steering slightly weaker than FIRE's), then a semi-implicit Euler step; uphill: step
    // back half a step and restart from rest.
    const double mix = (a_norm > 0.0 && !uphill) ? control_.alpha * std::sqrt(c.forces.v_norm2) / a_norm : 0.0;
    const double keep = uphill ? 0.0 : 1.0 - control_.alpha;
    const double back = uphill ? 0.5 * dt : 0.0;
    const kernels::MassUpdate u{dt, keep, mix + dt, back};
    grid.for_points([&](int64_t i0, int64_t i1) {
        kernels::use().mass_update(u, z + i0, v + i0, h + i0, a + i0, held + i0, i1 - i0);
    });
}

}  // namespace gfmd
