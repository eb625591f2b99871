// gfmd::kernels: the element-wise passes of the build the CPU runs (kernels.hpp).
#include <cstdlib>
#include <cstring>

#include "kernels.hpp"

namespace gfmd {
namespace kernels {

namespace {

struct Table {
    decltype(&kernels_base::complete_forces) complete_forces;
    decltype(&kernels_base::apply_stiffness) apply_stiffness;
    decltype(&kernels_base::fire_update) fire_update;
    decltype(&kernels_base::mark_held) mark_held;
    decltype(&kernels_base::mass_update) mass_update;
    decltype(&kernels_base::cg_mask) cg_mask;
    decltype(&kernels_base::cg_scale_modes) cg_scale_modes;
    decltype(&kernels_base::cg_restrict) cg_restrict;
    decltype(&kernels_base::cg_direction) cg_direction;
    decltype(&kernels_base::cg_move) cg_move;
    const char *name;
};

Table choose() {
#define GFMD_KERNEL_TABLE(ns, name)                                                                          \
    Table {                                                                                                  \
        ns::complete_forces, ns::apply_stiffness, ns::fire_update, ns::mark_held, ns::mass_update, ns::cg_mask, \
            ns::cg_scale_modes, ns::cg_restrict, ns::cg_direction, ns::cg_move, name                         \
    }
    const Table base = GFMD_KERNEL_TABLE(kernels_base, "baseline");
#ifdef GFMD_KERNELS_V3
    const char *forced = std::getenv("GFMD_KERNELS");
    if (forced != nullptr && std::strcmp(forced, "baseline") == 0) return base;
    __builtin_cpu_init();
    if (__builtin_cpu_supports("x86-64-v3"))
        return GFMD_KERNEL_TABLE(kernels_v3, "x86-64-v3");
#endif
    return base;
}

// Chosen once per process, on first use (thread-safe static initialization).
const Table &table() {
    static const Table t = choose();
    return t;
}

}  // namespace

void complete_forces(const Completion &in, double *f, int64_t n, double *acc) {
    table().complete_forces(in, f, n, acc);
}
double apply_stiffness(std::complex<double> *work, const double *stiff, int64_t r0, int64_t r1, int64_t nxh,
                       double inv_n, double w_last) {
    return table().apply_stiffness(work, stiff, r0, r1, nxh, inv_n, w_last);
}
void fire_update(const FireUpdate &u, double *z, double *v, const double *h, const double *f, int64_t n) {
    table().fire_update(u, z, v, h, f, n);
}
void mark_held(const double *z, const double *h, double *f, unsigned char *held, int64_t n) {
    table().mark_held(z, h, f, held, n);
}
void mass_update(const MassUpdate &u, double *z, double *v, const double *h, const double *a,
                 const unsigned char *held, int64_t n) {
    table().mass_update(u, z, v, h, a, held, n);
}
void cg_mask(const double *z, const double *h, const double *f, double *zp, int64_t n) {
    table().cg_mask(z, h, f, zp, n);
}
void cg_scale_modes(std::complex<double> *work, const double *stiff, int64_t r0, int64_t r1, int64_t nxh,
                    double inv_n, double floor) {
    table().cg_scale_modes(work, stiff, r0, r1, nxh, inv_n, floor);
}
void cg_restrict(const double *z, const double *h, const double *f, double *zp, int64_t n, double *acc) {
    table().cg_restrict(z, h, f, zp, n, acc);
}
void cg_direction(const double *z, const double *h, const double *f, const double *s, double *t, double b,
                  int64_t n, double *acc) {
    table().cg_direction(z, h, f, s, t, b, n, acc);
}
void cg_move(double *z, const double *h, const double *t, double alpha, bool to_wall, int64_t n, double *acc) {
    table().cg_move(z, h, t, alpha, to_wall, n, acc);
}
const char *name() { return table().name; }

}  // namespace kernels
}  // namespace gfmd
