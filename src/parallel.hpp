// The library's own loops over the grid, on the handle's thread pool.  Sums are formed per fixed
// block of indices and then added in block order, so a result never depends on the number of
// threads or on which thread ran which block: runs are reproducible bit for bit.
#ifndef GFMD_SRC_PARALLEL_HPP
#define GFMD_SRC_PARALLEL_HPP

#include <array>
#include <cstdint>

#include "thread_pool.hpp"

namespace gfmd {

// Indices per block: large enough to amortize the hand-out, small enough to balance two cores
// (and a core shared with another process).
constexpr int64_t kBlock = 16384;

inline int64_t block_count(int64_t n, int64_t block) { return (n + block - 1) / block; }

// body(begin, end) over [0, n) in blocks.
template <class Body>
void parallel_for(ThreadPool &pool, int64_t n, int64_t block, Body &&body) {
    pool.run(block_count(n, block), [&](int64_t b) { body(b * block, (b + 1) * block < n ? (b + 1) * block : n); });
}

// K sums: body(begin, end, double acc[K]) adds its block's contributions to acc.  `scratch` holds
// K * block_count(n, block) doubles, allocated once by the caller (no allocation per call).
template <int K, class Body>
std::array<double, K> parallel_sums(ThreadPool &pool, int64_t n, int64_t block, double *scratch, Body &&body) {
    const int64_t nb = block_count(n, block);
    pool.run(nb, [&](int64_t b) {
        double *acc = scratch + K * b;
        for (int k = 0; k < K; ++k) acc[k] = 0.0;
        body(b * block, (b + 1) * block < n ? (b + 1) * block : n, acc);
    });
    std::array<double, K> total{};
    for (int64_t b = 0; b < nb; ++b)
        for (int k = 0; k < K; ++k) total[k] += scratch[K * b + k];
    return total;
}

}  // namespace gfmd

#endif
