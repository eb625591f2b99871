#include "fft_grid.hpp"

#include <algorithm>
#include <climits>
#include <complex>
#include <cstring>
#include <mutex>
#include <new>
#include <string>

#include "error.hpp"
#include "fftw_planner.hpp"
#include "gfmd.h"
#ifdef GFMD_MPI
#include "mpi/mpi_state.hpp"
#endif

namespace gfmd {

std::mutex &planner_mutex() {
    static std::mutex m;
    return m;
}

bool threads_ready() {
    static const bool ready = [] {
        if (fftw_init_threads() == 0) return false;
        install_fftw_callback();
        return true;
    }();
    return ready;
}


unsigned planner_flags(int32_t planner) {
    switch (planner) {
        case GFMD_PLANNER_ESTIMATE:
            return FFTW_ESTIMATE;
        case GFMD_PLANNER_PATIENT:
            return FFTW_PATIENT;
        default:
            return FFTW_MEASURE;
    }
}

void validate_planner(int32_t planner) {
    if (planner != GFMD_PLANNER_ESTIMATE && planner != GFMD_PLANNER_MEASURE && planner != GFMD_PLANNER_PATIENT)
        fail(GFMD_ERR_BAD_ENUM, "unknown FFT planner " + std::to_string(planner));
}

int resolve_threads(int threads) {
    if (threads < 0 || threads > kMaxThreads)
        fail(GFMD_ERR_INVALID_ARG, "threads must be in [0, " + std::to_string(kMaxThreads) +
                                       "] (0 = all cores), got " + std::to_string(threads));
    if (threads > 0) return threads;
    return default_threads();
}

void validate_grid(int64_t nx, int64_t ny, double lx, double ly) {
    if (nx <= 0 || ny <= 0 || nx > kMaxGridDimension || ny > kMaxGridDimension)
        fail(GFMD_ERR_INVALID_ARG, "grid sizes must be in [1, 2^30], got " + std::to_string(nx) + " x " +
                                       std::to_string(ny));
    if (!(lx >= kMinLength && lx <= kMaxLength && ly >= kMinLength && ly <= kMaxLength))  // also NaN
        fail(GFMD_ERR_INVALID_ARG, "cell lengths must be finite and within [1e-100, 1e100]");
}

bool import_wisdom(const char *path) {
    std::lock_guard<std::mutex> lock(planner_mutex());
    threads_ready();
    return fftw_import_wisdom_from_filename(path) != 0;
}

bool export_wisdom(const char *path) {
    std::lock_guard<std::mutex> lock(planner_mutex());
    return fftw_export_wisdom_to_filename(path) != 0;
}

#ifndef GFMD_MPI
// The serial library has no distributed state (src/mpi/fft_grid_mpi.cpp defines it for libgfmd_mpi).
struct MpiState {};
const Distribution *FftGrid::distribution() const { return nullptr; }
void FftGrid::reduce_exact(ExactSum *, int) const {}
void FftGrid::reduce_max(double *, int) const {}
int32_t FftGrid::agree(int32_t status, std::string &) const { return status; }
bool FftGrid::same_on_all_ranks(uint64_t) const { return true; }
void FftGrid::forward_distributed(const double *, std::complex<double> *) const {}
void FftGrid::backward_distributed(std::complex<double> *, double *) const {}
void FftGrid::distribute(const Distribution *) {}
void FftGrid::replan_distributed(ThreadPool &, int32_t) {}
void FftGrid::gather_column0_distributed(const std::complex<double> *, std::complex<double> *) const {}
void FftGrid::gather_rows_distributed(const void *, std::size_t, void *) const {}
void FftGrid::send_rows_distributed(const FftGrid &, const int64_t *, const std::complex<double> *, int64_t,
                                    std::complex<double> *) const {}
#endif

void FftGrid::gather_rows(const void *local, std::size_t row_bytes, void *all) const {
    if (!mpi_) {
        std::memcpy(all, local, row_bytes * static_cast<std::size_t>(ny_));
        return;
    }
    gather_rows_distributed(local, row_bytes, all);
}

void FftGrid::send_rows(const FftGrid &to, const int64_t *dest, const std::complex<double> *rows, int64_t width,
                        std::complex<double> *out) const {
    if (mpi_) return send_rows_distributed(to, dest, rows, width, out);
    std::fill(out, out + to.complex_size(), std::complex<double>(0.0, 0.0));
    for (int64_t r = 0; r < local_rows_; ++r)
        if (dest[r] >= 0) std::copy(rows + r * width, rows + (r + 1) * width, out + dest[r] * to.nxh());
}

void FftGrid::gather_column0(const std::complex<double> *local, std::complex<double> *all) const {
    if (!mpi_) {
        for (int64_t ky = 0; ky < ny_; ++ky) all[ky] = local[ky * nxh()];
        return;
    }
    gather_column0_distributed(local, all);
}

FftGrid::FftGrid(int64_t nx, int64_t ny, double lx, double ly, int threads, int32_t planner, const Distribution *dist)
    : nx_((validate_grid(nx, ny, lx, ly), nx)), ny_(ny), lx_(lx), ly_(ly),
      pool_(std::make_unique<ThreadPool>(resolve_threads(threads))),
      planner_((validate_planner(planner), planner)), rows_per_block_(std::max<int64_t>(1, kBlock / (nx / 2 + 1))),
      local_rows_(ny), complex_size_(ny * (nx / 2 + 1)) {
    if (nx > INT_MAX || ny > INT_MAX) fail(GFMD_ERR_INVALID_ARG, "grid dimension exceeds FFTW's int range");
    if (dist != nullptr) {
        distribute(dist);  // collective: slabs, plans and the transforms' buffers
        sums_ = RealBuffer(static_cast<std::size_t>(6 * std::max<int64_t>(local_rows_, 1)));
        return;
    }
    // Enough partial sums for the largest reduction: 6 sums per block of points or of mode rows.
    sums_ = RealBuffer(static_cast<std::size_t>(
        6 * std::max(block_count(local_points(), kBlock), block_count(local_mode_rows(), rows_per_block_))));
    make_plans(*pool_, planner_, r2c_, c2r_);
}

void FftGrid::make_plans(ThreadPool &pool, int32_t planner, fftw_plan &r2c, fftw_plan &c2r) const {
    // Planned on scratch arrays (FFTW_MEASURE overwrites them), executed later with new-array
    // execution on other fftw_malloc-aligned buffers of the same size.
    RealBuffer r(static_cast<std::size_t>(real_size()));
    ComplexBuffer c(static_cast<std::size_t>(complex_size()));
    auto *cc = reinterpret_cast<fftw_complex *>(c.data());
    const unsigned flags = planner_flags(planner);
    std::lock_guard<std::mutex> lock(planner_mutex());
    if (threads_ready()) fftw_plan_with_nthreads(real_size() >= kMinPointsForThreads ? pool.size() : 1);
    PoolScope scope(&pool);  // MEASURE executes the candidates: on the pool they will run on
    WisdomAside aside(planner == GFMD_PLANNER_ESTIMATE);
    r2c = fftw_plan_dft_r2c_2d(static_cast<int>(ny_), static_cast<int>(nx_), r.data(), cc, flags);
    c2r = fftw_plan_dft_c2r_2d(static_cast<int>(ny_), static_cast<int>(nx_), cc, r.data(), flags);
    if (r2c == nullptr || c2r == nullptr) {
        if (r2c != nullptr) fftw_destroy_plan(r2c);
        if (c2r != nullptr) fftw_destroy_plan(c2r);
        r2c = c2r = nullptr;
        throw std::bad_alloc();
    }
}

void FftGrid::replan(int threads, int32_t planner) {
    const int t = resolve_threads(threads);
    validate_planner(planner);
    auto pool = (t == pool_->size()) ? std::move(pool_) : std::make_unique<ThreadPool>(t);
    fftw_plan r2c = nullptr, c2r = nullptr;
    try {
        if (mpi_) replan_distributed(*pool, planner);
        else make_plans(*pool, planner, r2c, c2r);
    } catch (...) {
        if (!pool_) pool_ = std::move(pool);  // the same pool: give it back
        throw;
    }
    pool_ = std::move(pool);
    planner_ = planner;
    if (mpi_) return;
    std::lock_guard<std::mutex> lock(planner_mutex());
    fftw_destroy_plan(r2c_);
    fftw_destroy_plan(c2r_);
    r2c_ = r2c;
    c2r_ = c2r;
}

FftGrid::~FftGrid() {
    std::lock_guard<std::mutex> lock(planner_mutex());
    if (r2c_ != nullptr) fftw_destroy_plan(r2c_);
    if (c2r_ != nullptr) fftw_destroy_plan(c2r_);
}

void FftGrid::forward(const double *in, std::complex<double> *out) const {
    if (mpi_) return forward_distributed(in, out);
    // FFTW's new-array execute takes a non-const input; r2c does not modify it.
    PoolScope scope(pool_.get());
    fftw_execute_dft_r2c(r2c_, const_cast<double *>(in), reinterpret_cast<fftw_complex *>(out));
}

void FftGrid::backward(std::complex<double> *in, double *out) const {
    if (mpi_) return backward_distributed(in, out);
    PoolScope scope(pool_.get());
    fftw_execute_dft_c2r(c2r_, reinterpret_cast<fftw_complex *>(in), out);
}

}  // namespace gfmd
