// The grid and its FFT plumbing: the one internal interface behind which the layout of the
// periodic nx x ny grid, its real-to-complex transforms and its threads live.  In libgfmd_mpi a
// grid may be distributed (src/mpi/: FFTW-MPI, one slab of rows per rank) without the solvers or
// the C API knowing: they loop only through the grid's local extents (for_points, sum_points, the
// mode rows), every global sum is sum_points / sum_mode_rows (exact per-row sums when distributed),
// and a check of one rank's data goes through on_all_ranks.
#ifndef GFMD_SRC_FFT_GRID_HPP
#define GFMD_SRC_FFT_GRID_HPP

#include <fftw3.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <complex>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <string>

#include "buffer.hpp"
#include "constants.hpp"
#include "error.hpp"
#include "exact_sum.hpp"
#include "parallel.hpp"

namespace gfmd {

// FFTW planner rigour for the GFMD_PLANNER_* codes; validate_planner throws GFMD_ERR_BAD_ENUM.
unsigned planner_flags(int32_t planner);
void validate_planner(int32_t planner);
// Threads 0 = the default (all the process may use); throws GFMD_ERR_INVALID_ARG out of range.
int resolve_threads(int threads);
// Throws GFMD_ERR_INVALID_ARG for sizes or lengths a grid cannot have.
void validate_grid(int64_t nx, int64_t ny, double lx, double ly);

// FFTW wisdom, process-wide (FFTW's own state), serialized with planning.  Return false on failure.
bool import_wisdom(const char *path);
bool export_wisdom(const char *path);

// A communicator to distribute a grid over (libgfmd_mpi only; defined in src/mpi/, where mpi.h is
// seen).  The serial library never makes one: its grids are all local.
struct Distribution;
struct MpiState;

class FftGrid {
public:
    // threads: threads of the loops and transforms (small grids transform on one), 0 = default;
    // planner: GFMD_PLANNER_*.  Plans once.  With a distribution (libgfmd_mpi) the grid is split
    // into slabs of rows over its ranks, and construction is collective.
    FftGrid(int64_t nx, int64_t ny, double lx, double ly, int threads, int32_t planner,
            const Distribution *dist = nullptr);
    FftGrid(const FftGrid &) = delete;
    FftGrid &operator=(const FftGrid &) = delete;
    ~FftGrid();

    int64_t nx() const { return nx_; }
    int64_t ny() const { return ny_; }
    double lx() const { return lx_; }
    double ly() const { return ly_; }
    int64_t real_size() const { return nx_ * ny_; }
    int64_t nxh() const { return nx_ / 2 + 1; }          // complex columns (Hermitian half)
    int64_t complex_size() const { return complex_size_; }  // complex points (local)
    double cell_area() const { return lx_ * ly_; }
    double area_per_point() const { return lx_ * ly_ / static_cast<double>(nx_ * ny_); }
    int threads() const { return pool_->size(); }
    int32_t planner() const { return planner_; }

    // Local extents.  Real space: the points this process owns, local_points() of them, rows of
    // nx() values from global row first_row().  Fourier space: local_mode_rows() rows of nxh()
    // modes (ky = first_mode_row() + r); a distributed grid has the same rows in both spaces.
    // Serial: everything.  complex_size() is what a complex array of the grid must hold (the
    // distributed transforms may need more than the local modes).
    int64_t local_points() const { return local_rows_ * nx_; }
    int64_t first_row() const { return first_row_; }
    int64_t local_mode_rows() const { return local_rows_; }
    int64_t first_mode_row() const { return first_row_; }
    // Distributed (libgfmd_mpi): the grid's ranks and this process's rank; serial: 1 and 0.
    bool distributed() const { return mpi_ != nullptr; }
    int ranks() const { return ranks_; }
    int rank() const { return rank_; }
    // The distribution to make another grid over the same ranks with (nullptr: serial).
    const Distribution *distribution() const;

    // body(i0, i1) over the local points [0, local_points()) in fixed blocks, threaded.
    template <class Body>
    void for_points(Body &&body) const {
        parallel_for(*pool_, local_points(), kBlock, body);
    }
    // body(r0, r1) over the local mode rows [0, local_mode_rows()) in fixed blocks, threaded.
    template <class Body>
    void for_mode_rows(Body &&body) const {
        parallel_for(*pool_, local_mode_rows(), rows_per_block_, body);
    }
    // K global sums: body(i0, i1, acc) over local points, or body(r0, r1, acc) over local mode rows,
    // adds its block's terms to acc.  Serial: fixed blocks, added in order; the result does not
    // depend on the thread count.  Distributed: one partial per global row, added exactly over all
    // ranks; the result does not depend on the ranks or threads either.
    template <int K, class Body>
    std::array<double, K> sum_points(Body &&body) const {
        if (mpi_) return row_sums<K>(nx_, body);
        return parallel_sums<K>(*pool_, local_points(), kBlock, sums_.data(), body);
    }
    template <int K, class Body>
    std::array<double, K> sum_mode_rows(Body &&body) const {
        if (mpi_) return row_sums<K>(1, body);
        return parallel_sums<K>(*pool_, local_mode_rows(), rows_per_block_, sums_.data(), body);
    }
    // The mean of a local field over the whole grid (fixed blocks: independent of the threads).
    double mean(const double *x) const {
        const auto s = sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
            double t = 0.0;
            for (int64_t i = i0; i < i1; ++i) t += x[i];
            acc[0] += t;
        });
        return s[0] / static_cast<double>(real_size());
    }
    // K global maxima: body(i0, i1, top) over local points raises top[0..K) (each starts at
    // -infinity) to its block's largest values; then over the blocks (threaded) and all ranks.  A
    // maximum is exact in any order, so the result depends on neither threads nor ranks.
    template <int K, class Body>
    std::array<double, K> max_points(Body &&body) const {
        static_assert(K >= 1 && K <= 6, "the partials' buffer holds 6 numbers a block (or row)");
        double *part = sums_.data();
        const int64_t points = local_points(), stride = mpi_ ? nx_ : kBlock;
        const int64_t nb = mpi_ ? local_rows_ : block_count(points, kBlock);
        parallel_for(*pool_, nb, mpi_ ? rows_per_block_ : 1, [&](int64_t b0, int64_t b1) {
            for (int64_t b = b0; b < b1; ++b) {
                double *top = part + K * b;
                for (int k = 0; k < K; ++k) top[k] = -std::numeric_limits<double>::infinity();
                body(b * stride, std::min((b + 1) * stride, points), top);
            }
        });
        std::array<double, K> m;
        m.fill(-std::numeric_limits<double>::infinity());
        for (int64_t b = 0; b < nb; ++b)
            for (int k = 0; k < K; ++k) m[k] = std::max(m[k], part[K * b + k]);
        reduce_max(m.data(), K);
        return m;
    }
    // The largest of the local_points() values x over all points of all ranks (-infinity on an
    // empty grid): max_points over one field.
    double max_of(const double *x) const {
        return max_points<1>([&](int64_t i0, int64_t i1, double *top) {
            for (int64_t i = i0; i < i1; ++i) top[0] = std::max(top[0], x[i]);
        })[0];
    }
    // x[i] = the largest over all processes (serial: nothing to do).  Exact in any order.
    void reduce_max(double *x, int k) const;
    // Every rank learns the first failure: status != 0 on any rank gives every rank the status
    // and message of the lowest failing rank (serial: unchanged).  Returns the agreed status.
    int32_t agree(int32_t status, std::string &message) const;
    // True if every rank passed the same fingerprint (serial: true).  Collective.
    bool same_on_all_ranks(uint64_t fingerprint) const;
    // Runs check() (validation of this rank's data, or an allocation) so that either every rank
    // goes on or every rank throws the first failure (std::bad_alloc as GFMD_ERR_NOMEM): no rank is
    // left waiting in a collective for one that threw.
    template <class Check>
    void on_all_ranks(Check &&check) const {
        int32_t status = 0;
        std::string message;
        try {
            check();
        } catch (const Error &e) {
            status = e.status();
            message = distributed() ? "rank " + std::to_string(rank_) + ": " + e.what() : e.what();
        } catch (const std::bad_alloc &) {  // an allocation of one rank's data: every rank fails
            status = GFMD_ERR_NOMEM;
            message = distributed() ? "rank " + std::to_string(rank_) + ": out of memory" : "out of memory";
        }
        status = agree(status, message);
        if (status != 0) fail(status, message);
    }
    // Every rank's rows of per-row records (row_bytes each, local_mode_rows() of them) gathered
    // into all (ny records, in global row order) on every rank.
    void gather_rows(const void *local, std::size_t row_bytes, void *all) const;
    // Rows of a spectrum to another grid's layout: local row r of this grid (width complex values
    // at rows[r * width]) becomes row dest[r] of `to` (-1: dropped), its first `width` modes; all
    // other modes of `to`'s local array out are zero.  Collective; both grids on the same ranks.
    void send_rows(const FftGrid &to, const int64_t *dest, const std::complex<double> *rows, int64_t width,
                   std::complex<double> *out) const;
    // The modes kx = 0 of every ky (ny values, all ranks), from a local complex array.
    void gather_column0(const std::complex<double> *local, std::complex<double> *all) const;

    // Wave vector components of complex index (kx, ky), kx in [0, nxh), ky in [0, ny).
    double qx(int64_t kx) const { return 2.0 * kPi * static_cast<double>(kx) / lx_; }
    double qy(int64_t ky) const {
        const int64_t k = (2 * ky > ny_) ? ky - ny_ : ky;
        return 2.0 * kPi * static_cast<double>(k) / ly_;
    }
    // Multiplicity of column kx in a full-plane sum over the Hermitian half.
    double weight(int64_t kx) const { return (kx == 0 || 2 * kx == nx_) ? 1.0 : 2.0; }
    // True on the Nyquist lines, where a mode has no partner of opposite wave vector.
    bool nyquist(int64_t kx, int64_t ky) const { return 2 * kx == nx_ || 2 * ky == ny_; }

    // Unnormalized transforms: forward Z(q) = sum_r z(r) e^{-iqr}; backward z(r) = sum_q Z(q) e^{iqr}.
    // Arrays must come from AlignedBuffer.  backward() destroys its input.
    void forward(const double *in, std::complex<double> *out) const;
    void backward(std::complex<double> *in, double *out) const;

    // New plans for another thread count (0 = default) or planner; nothing changes if planning
    // fails.
    void replan(int threads, int32_t planner);

private:
    // Distributed sums: per global row r, body(r * stride, (r + 1) * stride, acc) (stride nx for
    // points, 1 for mode rows), each partial added exactly, then one Allreduce of the K sums.
    template <int K, class Body>
    std::array<double, K> row_sums(int64_t stride, Body &body) const {
        double *part = sums_.data();
        parallel_for(*pool_, local_rows_, rows_per_block_, [&](int64_t r0, int64_t r1) {
            for (int64_t r = r0; r < r1; ++r) {
                double *acc = part + K * r;
                for (int k = 0; k < K; ++k) acc[k] = 0.0;
                body(r * stride, (r + 1) * stride, acc);
            }
        });
        ExactSum exact[K];
        for (int64_t r = 0; r < local_rows_; ++r)
            for (int k = 0; k < K; ++k) exact[k].add(part[K * r + k]);
        reduce_exact(exact, K);
        std::array<double, K> s{};
        for (int k = 0; k < K; ++k) s[k] = exact[k].value();
        return s;
    }
    void reduce_exact(ExactSum *x, int k) const;  // adds the accumulators of all ranks
    void make_plans(ThreadPool &pool, int32_t planner, fftw_plan &r2c, fftw_plan &c2r) const;
    // libgfmd_mpi (src/mpi/fft_grid_mpi.cpp): slabs, plans and buffers; the transforms.
    void distribute(const Distribution *dist);
    void replan_distributed(ThreadPool &pool, int32_t planner);
    void gather_column0_distributed(const std::complex<double> *local, std::complex<double> *all) const;
    void gather_rows_distributed(const void *local, std::size_t row_bytes, void *all) const;
    void send_rows_distributed(const FftGrid &to, const int64_t *dest, const std::complex<double> *rows, int64_t width,
                               std::complex<double> *out) const;
    void forward_distributed(const double *in, std::complex<double> *out) const;
    void backward_distributed(std::complex<double> *in, double *out) const;
    int64_t nx_, ny_;
    double lx_, ly_;
    std::unique_ptr<ThreadPool> pool_;  // the loops' and the transforms' threads
    int32_t planner_;
    int64_t rows_per_block_;
    mutable RealBuffer sums_;  // per-block partial sums of the threaded reductions (no allocation per sum)
    fftw_plan r2c_ = nullptr;
    fftw_plan c2r_ = nullptr;
    int64_t local_rows_, first_row_ = 0, complex_size_;
    int ranks_ = 1, rank_ = 0;
    std::unique_ptr<MpiState> mpi_;  // the communicator, plans and buffers of a distributed grid
};

}  // namespace gfmd

#endif
