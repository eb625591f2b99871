// gfmd::kernels::use(): the element-wise passes of the build the CPU runs (kernels.hpp).
#include <cstdlib>
#include <cstring>

#include "kernels.hpp"

namespace gfmd {
namespace kernels {

namespace {

Table choose() {
#ifdef GFMD_KERNELS_V3
    const char *forced = std::getenv("GFMD_KERNELS");
    if (forced == nullptr || std::strcmp(forced, "baseline") != 0) {
        __builtin_cpu_init();
        if (__builtin_cpu_supports("x86-64-v3")) return GFMD_KERNEL_TABLE(kernels_v3, "x86-64-v3");
    }
#endif
    return GFMD_KERNEL_TABLE(kernels_base, "baseline");
}

}  // namespace

// Chosen once per process, on first use (thread-safe static initialization).
const Table &use() {
    static const Table t = choose();
    return t;
}

}  // namespace kernels
}  // namespace gfmd
