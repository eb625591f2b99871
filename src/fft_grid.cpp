#include "fft_grid.hpp"

#include <climits>
#include <mutex>
#include <new>

#include "error.hpp"

namespace gfmd {

namespace {
// FFTW's planner and plan destruction are not thread-safe: serialize them library-wide.
std::mutex &planner_mutex() {
    static std::mutex m;
    return m;
}
}  // namespace

FftGrid::FftGrid(int64_t nx, int64_t ny, double lx, double ly) : nx_(nx), ny_(ny), lx_(lx), ly_(ly) {
    if (nx > INT_MAX || ny > INT_MAX) fail(GFMD_ERR_INVALID_ARG, "grid dimension exceeds FFTW's int range");
    RealBuffer r(static_cast<std::size_t>(real_size()));
    ComplexBuffer c(static_cast<std::size_t>(complex_size()));
    auto *cc = reinterpret_cast<fftw_complex *>(c.data());
    std::lock_guard<std::mutex> lock(planner_mutex());
    // FFTW_ESTIMATE does not touch the arrays; plans are reused with new-array execution on other
    // fftw_malloc-aligned buffers of the same size.
    r2c_ = fftw_plan_dft_r2c_2d(static_cast<int>(ny), static_cast<int>(nx), r.data(), cc, FFTW_ESTIMATE);
    c2r_ = fftw_plan_dft_c2r_2d(static_cast<int>(ny), static_cast<int>(nx), cc, r.data(), FFTW_ESTIMATE);
    if (r2c_ == nullptr || c2r_ == nullptr) {
        if (r2c_ != nullptr) fftw_destroy_plan(r2c_);
        if (c2r_ != nullptr) fftw_destroy_plan(c2r_);
        throw std::bad_alloc();
    }
}

FftGrid::~FftGrid() {
    std::lock_guard<std::mutex> lock(planner_mutex());
    fftw_destroy_plan(r2c_);
    fftw_destroy_plan(c2r_);
}

void FftGrid::forward(const double *in, std::complex<double> *out) const {
    // FFTW's new-array execute takes a non-const input; r2c does not modify it.
    fftw_execute_dft_r2c(r2c_, const_cast<double *>(in), reinterpret_cast<fftw_complex *>(out));
}

void FftGrid::backward(std::complex<double> *in, double *out) const {
    fftw_execute_dft_c2r(c2r_, reinterpret_cast<fftw_complex *>(in), out);
}

}  // namespace gfmd
