#include "forces.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "kernels.hpp"

namespace gfmd {

double residual_scale(const Params &p, double sigma0) {
    double ref = std::fabs(sigma0) + ((p.gamma0 > 0.0) ? p.gamma0 / p.rho : 0.0);
    // Under displacement control the pressure is an outcome and may pass through zero (a body that
    // barely touches, or has come off): a floor of 1e-8 E* keeps the relative residual meaningful
    // where the forces are at the level of the transforms' rounding (about 1e-16 E* per unit slope).
    if (p.control == kDisplacementControl) ref += kDisplacementStressFloor * p.e_star;
    if (ref <= 0.0) ref = p.e_star;
    return ref;
}

ForceState evaluate_forces(const FftGrid &grid, const Params &p, const Body &body, Fields &fields) {
    ForceState out;
    // Elastic stress in Fourier space: sigma(q) = -u(q)/G(q); U_el = (A/2) sum_q |u(q)|^2/G(q)
    // with u(q) = Z(q)/N the normalized coefficients (seed paper, Eqs. 1-3).
    if (!fields.work_holds_z) grid.forward(fields.z.data(), fields.work.data());
    fields.work_holds_z = false;
    const int64_t nxh = grid.nxh();
    const double inv_n = 1.0 / static_cast<double>(grid.real_size());
    const double w_last = grid.weight(nxh - 1);  // 1 if the last column is the Nyquist one
    std::complex<double> *work = fields.work.data();
    const double *stiff = body.stiffness.data();
    const auto energy = grid.sum_mode_rows<1>([&](int64_t y0, int64_t y1, double *acc) {
        acc[0] += kernels::use().apply_stiffness(work, stiff, y0, y1, nxh, inv_n, w_last);
    });
    out.u_el = 0.5 * grid.cell_area() * energy[0] * inv_n * inv_n;
    grid.backward(fields.work.data(), fields.f.data());

    // Real space: external pressure, adhesion, the residual of the constrained problem, and the
    // sums FIRE needs (power F.v, |F|^2, |v|^2 of the projected force F).
    const bool adhesive = p.gamma0 > 0.0;
    const double adh_coef = adhesive ? p.gamma0 / p.rho : 0.0, inv_rho = 1.0 / p.rho;
    double *f = fields.f.data();
    const double *z = fields.z.data(), *h = fields.h.data();
    double sigma0 = p.sigma0;
    if (p.control == kDisplacementControl) {
        // the elastic and adhesive stress at point i
        const auto stress = [&](int64_t i) {
            return f[i] - (adhesive ? adh_coef * std::exp(-(z[i] - h[i]) * inv_rho) : 0.0);
        };
        // in lanes, with the completion's exponential (the C library's scalar exp per point was a
        // fifth of an adhesive step under displacement control at 1024^2)
        const auto free_sums = grid.sum_points<2>([&](int64_t i0, int64_t i1, double *acc) {
            kernels::use().free_stress_sums(z + i0, h + i0, f + i0, adh_coef, inv_rho, i1 - i0, acc);
        });
        if (free_sums[1] > 0.0) {
            sigma0 = free_sums[0] / free_sums[1];
        } else {
            // No point free (full contact, the prescribed mean at the substrate's): every pressure
            // that keeps each point pressed onto the wall balances the body.  The least of them,
            // the largest point stress, is the limit of the free points' mean as the last of them
            // closes (a mean-position sweep into full contact stays continuous), and leaves no
            // point pulling away.  The mean of all stresses (about zero: the elastic stress has
            // no mean) left half the points pulling away, a residual no step can reduce.  Rare:
            // one pass over the points.
            sigma0 = grid.max_points<1>([&](int64_t i0, int64_t i1, double *top) {
                for (int64_t i = i0; i < i1; ++i) top[0] = std::max(top[0], stress(i));
            })[0];
        }
    }
    out.mean_pressure = sigma0;
    const double inv_ref = 1.0 / residual_scale(p, sigma0);
    const auto sums = grid.sum_points<6>([&](int64_t i0, int64_t i1, double *acc) {
        const kernels::Completion in{fields.z.data() + i0, fields.h.data() + i0, fields.v.data() + i0, sigma0,
                                     adh_coef, inv_rho, inv_ref};
        kernels::use().complete_forces(in, fields.f.data() + i0, i1 - i0, acc);
    });
    out.contacts = static_cast<int64_t>(sums[5]);
    out.u_ad = p.gamma0 * grid.area_per_point() * sums[0];
    out.f_norm2 = sums[1];
    out.power = sums[2];
    out.v_norm2 = sums[3];
    out.residual = std::sqrt(sums[4] * inv_n);
    return out;
}

}  // namespace gfmd
