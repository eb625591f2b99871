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
    const char *name;
};

Table choose() {
    const Table base{kernels_base::complete_forces, kernels_base::apply_stiffness, kernels_base::fire_update,
                     kernels_base::mark_held,       kernels_base::mass_update,     "baseline"};
#ifdef GFMD_KERNELS_V3
    const char *forced = std::getenv("GFMD_KERNELS");
    if (forced != nullptr && std::strcmp(forced, "baseline") == 0) return base;
    __builtin_cpu_init();
    if (__builtin_cpu_supports("x86-64-v3"))
        return Table{kernels_v3::complete_forces, kernels_v3::apply_stiffness, kernels_v3::fire_update,
                     kernels_v3::mark_held,       kernels_v3::mass_update,     "x86-64-v3"};
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
const char *name() { return table().name; }

}  // namespace kernels
}  // namespace gfmd
