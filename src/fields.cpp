#include "fields.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>

#include "error.hpp"

namespace gfmd {

namespace {

// Bytes the kernel could give this process now without swapping: MemAvailable of /proc/meminfo,
// or the physical memory where that is unknown; < 0 if neither is known.
double available_bytes() {
    if (std::FILE *f = std::fopen("/proc/meminfo", "r")) {
        char line[256];
        double kb = -1.0;
        while (std::fgets(line, sizeof line, f))
            if (std::strncmp(line, "MemAvailable:", 13) == 0) kb = std::strtod(line + 13, nullptr);
        std::fclose(f);
        if (kb > 0.0) return kb * 1024.0;
    }
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page <= 0) return -1.0;
    return static_cast<double>(pages) * static_cast<double>(page);
}

std::size_t points(const FftGrid &grid) { return static_cast<std::size_t>(grid.local_points()); }

}  // namespace

void check_memory(int64_t nx, int64_t ny, double bytes_per_point) {
    const double need = static_cast<double>(nx) * static_cast<double>(ny) * bytes_per_point;
    const double have = available_bytes();
    if ((have > 0.0 && need > have) || (have <= 0.0 && need > 1e14))
        fail(GFMD_ERR_NOMEM, "this " + std::to_string(nx) + " x " + std::to_string(ny) + " grid needs about " +
                                 std::to_string(static_cast<long long>(need / 1048576.0)) + " MiB; " +
                                 std::to_string(static_cast<long long>(have / 1048576.0)) + " MiB are available");
}

Fields::Fields(const FftGrid &grid)
    : h(points(grid)), z(points(grid)), v(points(grid)), f(points(grid)),
      work(static_cast<std::size_t>(grid.complex_size())) {}

void Fields::lift_at_rest(const FftGrid &grid) {
    double *pz = z.data(), *pv = v.data();
    const double *ph = h.data();
    grid.for_points([&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) {
            pz[i] = std::max(pz[i], ph[i]);
            pv[i] = 0.0;
        }
    });
}

void Fields::put_flat_at_rest(const FftGrid &grid) {
    const double top = grid.max_of(h.data());  // every rank: the same
    std::fill(z.data(), z.data() + z.size(), top);
    std::fill(v.data(), v.data() + v.size(), 0.0);
}

Snapshot::Snapshot(const FftGrid &grid) : z(points(grid)), v(points(grid)) {}

void Snapshot::save(const Fields &from) {
    std::copy(from.z.data(), from.z.data() + z.size(), z.data());
    std::copy(from.v.data(), from.v.data() + v.size(), v.data());
}

void Snapshot::restore(Fields &to) const {
    std::copy(z.data(), z.data() + z.size(), to.z.data());
    std::copy(v.data(), v.data() + v.size(), to.v.data());
}

}  // namespace gfmd
