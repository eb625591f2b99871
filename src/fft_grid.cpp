#include "fft_grid.hpp"

#include <algorithm>
#include <climits>
#include <mutex>
#include <new>
#include <string>

#include "error.hpp"
#include "gfmd.h"

namespace gfmd {

namespace {
// FFTW's planner, plan destruction, thread setup and wisdom are not thread-safe: serialize them
// library-wide.
std::mutex &planner_mutex() {
    static std::mutex m;
    return m;
}

// Below this many points one thread transforms faster than two (measured on 2 cores).
constexpr int64_t kMinPointsForThreads = 128 * 128;

// FFTW's threads, initialized once before any plan or wisdom (wisdom exported with threads only
// imports into a process whose threads are initialized).  Call with the planner mutex held.
bool threads_ready() {
    static const bool ready = [] {
        if (fftw_init_threads() == 0) return false;
        install_fftw_callback();
        return true;
    }();
    return ready;
}

// Wisdom set aside while an ESTIMATE plan is made, and given back after.  FFTW plans from wisdom of
// an equal or more rigorous planner when it has some, so an ESTIMATE plan made after a MEASURE plan
// of the same size would be the measured one, chosen by timings: other bits in another process.
// Without the wisdom it is FFTW's deterministic estimate, the same in every process.
class WisdomAside {
public:
    explicit WisdomAside(bool active) : saved_(active ? fftw_export_wisdom_to_string() : nullptr) {
        if (active && saved_ == nullptr) throw std::bad_alloc();
        if (active) fftw_forget_wisdom();
    }
    WisdomAside(const WisdomAside &) = delete;
    WisdomAside &operator=(const WisdomAside &) = delete;
    ~WisdomAside() {
        if (saved_ == nullptr) return;
        fftw_forget_wisdom();  // the estimate's own entries: later ESTIMATE plans make them afresh
        fftw_import_wisdom_from_string(saved_);
        fftw_free(saved_);
    }

private:
    char *saved_;
};
}  // namespace

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

FftGrid::FftGrid(int64_t nx, int64_t ny, double lx, double ly, int threads, int32_t planner)
    : nx_((validate_grid(nx, ny, lx, ly), nx)), ny_(ny), lx_(lx), ly_(ly),
      pool_(std::make_unique<ThreadPool>(resolve_threads(threads))),
      planner_((validate_planner(planner), planner)), rows_per_block_(std::max<int64_t>(1, kBlock / (nx / 2 + 1))) {
    if (nx > INT_MAX || ny > INT_MAX) fail(GFMD_ERR_INVALID_ARG, "grid dimension exceeds FFTW's int range");
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
        make_plans(*pool, planner, r2c, c2r);
    } catch (...) {
        if (!pool_) pool_ = std::move(pool);  // the same pool: give it back
        throw;
    }
    pool_ = std::move(pool);
    planner_ = planner;
    std::lock_guard<std::mutex> lock(planner_mutex());
    fftw_destroy_plan(r2c_);
    fftw_destroy_plan(c2r_);
    r2c_ = r2c;
    c2r_ = c2r;
}

FftGrid::~FftGrid() {
    std::lock_guard<std::mutex> lock(planner_mutex());
    fftw_destroy_plan(r2c_);
    fftw_destroy_plan(c2r_);
}

void FftGrid::forward(const double *in, std::complex<double> *out) const {
    // FFTW's new-array execute takes a non-const input; r2c does not modify it.
    PoolScope scope(pool_.get());
    fftw_execute_dft_r2c(r2c_, const_cast<double *>(in), reinterpret_cast<fftw_complex *>(out));
}

void FftGrid::backward(std::complex<double> *in, double *out) const {
    PoolScope scope(pool_.get());
    fftw_execute_dft_c2r(c2r_, reinterpret_cast<fftw_complex *>(in), out);
}

}  // namespace gfmd
