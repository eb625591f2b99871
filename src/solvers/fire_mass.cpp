#include "fire_mass.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include "../kernels.hpp"

namespace gfmd {

namespace {
// The mass floor is the stiffness at kMassSpacing times the wave vector of the contact points'
// mean spacing (1 was best of 0.25 ... 4, docs/performance.md).
constexpr double kMassSpacing = 1.0;
}  // namespace

FireMass::FireMass(const FireMass &o)
    : Solver(o), control_(o.control_), held_(o.held_.size()), floor_(o.floor_), mass_dt_(o.mass_dt_), bucket_(o.bucket_) {}

// The mass floor of mass-weighted FIRE.  A body pressed onto a substrate at contact fraction phi
// is held at points about sqrt(1/phi) cells apart; modes longer than that spacing are pinned by the
// contacts and do not relax on their own (soft) elastic time scale.  Their masses are therefore
// raised to the stiffness k_c at the contact spacing, the largest 1/G(q) over the fraction phi of
// modes with the smallest |q| (|q|^2 <= 4 pi phi / cell).  The floor depends only on the bucket
// floor(log2(contacts)), so it is a function of the state (a checkpoint resumes bit for bit).
void FireMass::update_mass_floor(const StepContext &c) {
    const FftGrid &grid = c.grid;
    const RealBuffer &stiff = c.body.stiffness;
    const int64_t contacts = c.forces.contacts;
    const int bucket = contact_octave(contacts);
    if (bucket == bucket_) return;
    const double qc2 = contact_spacing_q2(grid, kMassSpacing, std::ldexp(1.0, bucket));
    const double kc = stiffest_mode_within(grid, c.body, qc2);
    const int64_t nxh = grid.nxh();
    floor_ = std::min(std::max(kc, c.body.k_min), c.body.k_max);
    // omega^2 = k(q)/m(q) <= 1 for the elastic modes.  The adhesive law's stiffness is local: a
    // single point's acceleration per unit force is the real-space diagonal of M^-1, the mean of
    // 1/m(q) over all modes (translation invariance), so it adds k_adh <1/m>.
    const double floor = floor_;
    const double inv_m = grid.sum_mode_rows<1>([&](int64_t r0, int64_t r1, double *acc) {
        double t = 0.0;
        for (int64_t r = r0; r < r1; ++r)
            for (int64_t kx = 0; kx < nxh; ++kx)
                t += grid.weight(kx) / std::max(stiff[static_cast<std::size_t>(r * nxh + kx)], floor);
        acc[0] += t;
    })[0] / static_cast<double>(grid.real_size());
    mass_dt_ = kDtFactor / std::sqrt(1.0 + c.params.adhesive_stiffness() * inv_m);
    bucket_ = bucket;
}

void FireMass::advance(StepContext &c) {
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
    const bool uphill = control_.control(c.forces.power, kFireDtMax);  // the step as a fraction of mass_dt_
    const double dt = std::min(control_.dt, kFireDtMax) * mass_dt_;

    // a = M^-1 F_projected, one more r2c/c2r pair, computed in place of F (evaluate_forces()
    // recomputes F after the step); |a|^2 by Parseval in the same pass.  Points held by the wall
    // (in contact, pushed into it) are marked first: their acceleration is masked after the
    // preconditioning, so that only the free points move, with the preconditioner restricted to
    // them (a principal block of M^-1, still positive definite).  Without the mask the wall's
    // held points are lifted by their neighbours' preconditioned pull and clamped back every
    // step: the run bounces and never converges (measured; see docs/performance.md).
    double *z = c.fields.z.data(), *v = c.fields.v.data(), *a = c.fields.f.data();
    const double *h = c.fields.h.data();
    unsigned char *held = held_.data();
    grid.for_points([&](int64_t i0, int64_t i1) { kernels::use().mark_held(z + i0, h + i0, a + i0, held + i0, i1 - i0); });
    grid.forward(a, c.fields.work.data());
    const int64_t nxh = grid.nxh();
    const double inv_n = 1.0 / static_cast<double>(grid.real_size()), floor = floor_;
    std::complex<double> *work = c.fields.work.data();
    const double *stiff = c.body.stiffness.data();
    const auto a2 = grid.sum_mode_rows<1>([&](int64_t y0, int64_t y1, double *acc) {
        for (int64_t r = y0; r < y1; ++r) {  // local mode rows
            std::complex<double> *row = work + r * nxh;
            const double *krow = stiff + r * nxh;
            for (int64_t kx = 0; kx < nxh; ++kx) {
                row[kx] *= inv_n / std::max(krow[kx], floor);
                acc[0] += grid.weight(kx) * std::norm(row[kx]);
            }
        }
    });
    grid.backward(c.fields.work.data(), a);
    const double a_norm = std::sqrt(a2[0] * static_cast<double>(grid.real_size()));

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
