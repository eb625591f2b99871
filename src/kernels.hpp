// The element-wise passes of a step (the force completion, the stiffness in Fourier space, the FIRE
// updates).  On x86-64 with GCC they are compiled twice, for the baseline (SSE2, namespace
// kernels_base) and for x86-64-v3 (AVX2, kernels_v3); kernels::use() is the table of the build the
// CPU runs, chosen once per process (the environment variable GFMD_KERNELS=baseline forces the
// baseline).  The passes are memory- and instruction-bound (docs/decisions.md).
//
// Both builds give the same bits: kernels.cpp is compiled without floating-point contraction (no
// FMA), and every sum is formed in kLanes fixed lanes (lane l takes the points l, l + kLanes, ... of
// a block, in order; the lanes are then added in order) with GCC's vector extension, whatever the
// vector width.  The sums so do not depend on the CPU, as they do not depend on the threads;
// test_kernels compares both builds on every tail length, and trajectory_bits_baseline runs the
// recorded trajectories with the baseline forced.
#ifndef GFMD_SRC_KERNELS_HPP
#define GFMD_SRC_KERNELS_HPP

#include <complex>
#include <cstdint>

namespace gfmd {
namespace kernels {

constexpr int kLanes = 8;

// The real-space force completion of points [0, n): f <- f - sigma0 - adh_coef exp(-(z-h) inv_rho)
// (the exponential only if adh_coef > 0), and adds to acc[0..5]: the adhesive weight sum of
// exp(-(z-h) inv_rho), |F|^2, F.v, |v|^2, |F inv_ref|^2 and the points in contact (z <= h), where
// F is f projected on the wall (in contact only pulling away counts).
struct Completion {
    const double *z, *h, *v;
    double sigma0, adh_coef, inv_rho, inv_ref;
};
// free_stress_sums: the stress f - adh_coef exp(-(z-h) inv_rho) (the exponential only if adh_coef
// > 0) of the free points (z > h) of [0, n) added to acc[0], their count to acc[1] (the mean
// pressure under displacement control, evaluate_forces()).
// FIRE 2.0's update of points [0, n) with the wall (Fire::advance()).
struct FireUpdate {
    double dt, keep, mix, back;
    bool uphill;
};
// Mass-weighted FIRE's update from the preconditioned acceleration a (MassWeightedFire::advance()).
struct MassUpdate {
    double dt, keep, mix_dt, back;
};

// What each build provides.  apply_stiffness: the elastic stress in Fourier space of mode rows
// [r0, r1) of width nxh, row *= -k inv_n, returning the energy sum of k |Z|^2 over the full plane
// (column 0 and a Nyquist column, weight w_last, once; the others twice, their k re^2 and k im^2
// summed in kLanes lanes per row), per row, the rows in order; mode_energy: the same sum without
// the scaling (the surface CG's t.K.t).  mark_held: marks the points the wall holds (in contact,
// pushed into it) and projects the force on the wall.  The surface CG's passes (SurfaceCg, cg.cpp),
// a point being held where z <= h and f <= 0: cg_mask, zp = f where free, 0 where held;
// precondition_modes, the preconditioner's Fourier rows *= inv_n / max(k, floor), returning the sum
// of |scaled mode|^2 over the full plane summed as apply_stiffness's (also mass-weighted FIRE's
// M^-1, with |a|^2); cg_restrict, zp = 0 where held and acc[0] += f.zp; cg_direction, t = s + b t
// where free, 0 where held, and acc[0] += f.t (with inv_rho > 0 also acc[1..3] += cg_adhesive_line's
// three sums at alpha = 0); cg_move, z += alpha t stopped at the wall
// (to_wall: z = h where t < 0) and acc[0] += the points stopped, the z it started from written to
// save unless save is null (the checked step's undo); cg_adhesive_line, with g = z - h + alpha t
// and w = exp(-g inv_rho) where g > 0, 1 at the wall: acc[0] += sum of w t, acc[1] += sum of w t^2
// where g > 0, acc[2] += sum of w (the adhesive surface CG's line search); cg_step_sums, acc[0..1] += the sums of
// z - z0 and f (z - z0), and if adhesive acc[2] += the sum of exp(-(z - h) inv_rho) (the checked
// step's energy change).
// Polonsky & Keer's passes (PolonskyKeer, pk.cpp), a point being in the contact set where p > 0,
// its gap g = (u + a) - h: pk_direction, t = g + beta t in the set, 0 elsewhere; pk_sums, acc[0..3]
// += the sums over the set of r, t, r t and g t; pk_update, p = max(p - tau t, 0) in the set, -tau g
// where a point outside it penetrates (g < 0), 0 elsewhere, and acc[0..1] += the sum of the new p
// and the points that joined; pk_scale, p *= scale; pk_approach, acc[0..1] += the sum of h - u over
// the set and its points; pk_gap, acc[0] += the sum of g^2 over the set and, unless z is null, z = h
// in the set and max(h, u + a) elsewhere; pk_scale_modes, the Fourier rows *= inv_n / k (0 where
// k = 0): the compliance.
#define GFMD_KERNEL_DECLARATIONS                                                                               \
    void complete_forces(const kernels::Completion &in, double *f, int64_t n, double *acc);                   \
    void free_stress_sums(const double *z, const double *h, const double *f, double adh_coef, double inv_rho,  \
                          int64_t n, double *acc);                                                             \
    double apply_stiffness(std::complex<double> *work, const double *stiff, int64_t r0, int64_t r1, int64_t nxh, \
                           double inv_n, double w_last);                                                       \
    double mode_energy(const std::complex<double> *work, const double *stiff, int64_t r0, int64_t r1,          \
                       int64_t nxh, double w_last);                                                            \
    void fire_update(const kernels::FireUpdate &u, double *z, double *v, const double *h, const double *f,      \
                     int64_t n);                                                                               \
    void mark_held(const double *z, const double *h, double *f, unsigned char *held, int64_t n);              \
    void mass_update(const kernels::MassUpdate &u, double *z, double *v, const double *h, const double *a,     \
                     const unsigned char *held, int64_t n);                                                    \
    void cg_mask(const double *z, const double *h, const double *f, double *zp, int64_t n);                   \
    double precondition_modes(std::complex<double> *work, const double *stiff, int64_t r0, int64_t r1,          \
                              int64_t nxh, double inv_n, double floor, double w_last);                         \
    void cg_restrict(const double *z, const double *h, const double *f, double *zp, int64_t n, double *acc);  \
    void cg_direction(const double *z, const double *h, const double *f, const double *s, double *t, double b, \
                      double inv_rho, int64_t n, double *acc);                                                 \
    void cg_move(double *z, const double *h, const double *t, double alpha, bool to_wall, int64_t n, double *acc, \
                 double *save);                                                                             \
    void cg_adhesive_line(const double *z, const double *h, const double *t, double alpha, double inv_rho,     \
                          int64_t n, double *acc);                                                             \
    void cg_step_sums(const double *z, const double *z0, const double *f, const double *h, double inv_rho,     \
                      bool adhesive, int64_t n, double *acc);                                                  \
    void pk_direction(const double *p, const double *u, const double *h, double *t, double a, double beta,     \
                      int64_t n);                                                                              \
    void pk_sums(const double *p, const double *r, const double *t, const double *u, const double *h, double a, \
                 int64_t n, double *acc);                                                                      \
    void pk_update(double *p, const double *u, const double *h, const double *t, double a, double tau,         \
                   int64_t n, double *acc);                                                                    \
    void pk_scale(double *p, double scale, int64_t n);                                                         \
    void pk_approach(const double *p, const double *u, const double *h, int64_t n, double *acc);               \
    void pk_gap(const double *p, const double *u, const double *h, double *z, double a, int64_t n, double *acc); \
    void pk_scale_modes(std::complex<double> *work, const double *stiff, int64_t r0, int64_t r1, int64_t nxh,  \
                        double inv_n);

}  // namespace kernels

namespace kernels_base {
GFMD_KERNEL_DECLARATIONS
}
namespace kernels_v3 {
GFMD_KERNEL_DECLARATIONS
}

namespace kernels {

// X(ns, name) for every pass of the declarations above.
#define GFMD_KERNEL_NAMES(X, ns)                                                                            \
    X(ns, complete_forces) X(ns, free_stress_sums) X(ns, apply_stiffness) X(ns, mode_energy) X(ns, fire_update)  \
    X(ns, mark_held) X(ns, mass_update)                                                                       \
    X(ns, cg_mask) X(ns, precondition_modes) X(ns, cg_restrict) X(ns, cg_direction) X(ns, cg_move)                \
    X(ns, cg_adhesive_line) X(ns, cg_step_sums)                \
    X(ns, pk_direction) X(ns, pk_sums) X(ns, pk_update) X(ns, pk_scale) X(ns, pk_approach) X(ns, pk_gap)       \
    X(ns, pk_scale_modes)
#define GFMD_KERNEL_FIELD(ns, f) decltype(&ns::f) f;
#define GFMD_KERNEL_ENTRY(ns, f) ns::f,
// One build's passes, called as use().complete_forces(...).
struct Table {
    GFMD_KERNEL_NAMES(GFMD_KERNEL_FIELD, kernels_base)
    const char *name;  // "baseline" or "x86-64-v3"
};
// The table of namespace ns (kernels_base, kernels_v3).
#define GFMD_KERNEL_TABLE(ns, label) \
    ::gfmd::kernels::Table { GFMD_KERNEL_NAMES(GFMD_KERNEL_ENTRY, ::gfmd::ns) label }

// The build the CPU runs (kernels_dispatch.cpp).
const Table &use();

}  // namespace kernels
}  // namespace gfmd

#endif
