// The grid and its FFT plumbing: the one internal interface behind which the layout of the
// periodic nx x ny grid and its real-to-complex transforms live.  A distributed version (FFTW MPI,
// one slab of rows per rank) replaces this class without touching the solver or the C API: the
// solver only sees local real/complex extents, wave vectors and the sum weights below.
#ifndef GFMD_SRC_FFT_GRID_HPP
#define GFMD_SRC_FFT_GRID_HPP

#include <fftw3.h>

#include <complex>
#include <cstdint>

#include "buffer.hpp"

namespace gfmd {

// FFTW planner rigour for the GFMD_PLANNER_* codes.
unsigned planner_flags(int32_t planner);

// FFTW wisdom, process-wide (FFTW's own state), serialized with planning.  Return false on failure.
bool import_wisdom(const char *path);
bool export_wisdom(const char *path);

class FftGrid {
public:
    // threads: threads of the transforms (small grids use one); planner: GFMD_PLANNER_*.
    FftGrid(int64_t nx, int64_t ny, double lx, double ly, int threads, int32_t planner);
    FftGrid(const FftGrid &) = delete;
    FftGrid &operator=(const FftGrid &) = delete;
    ~FftGrid();

    int64_t nx() const { return nx_; }
    int64_t ny() const { return ny_; }
    double lx() const { return lx_; }
    double ly() const { return ly_; }
    int64_t real_size() const { return nx_ * ny_; }
    int64_t nxh() const { return nx_ / 2 + 1; }          // complex columns (Hermitian half)
    int64_t complex_size() const { return ny_ * nxh(); }  // complex points
    double cell_area() const { return lx_ * ly_; }

    // Wave vector components of complex index (kx, ky), kx in [0, nxh), ky in [0, ny).
    double qx(int64_t kx) const { return 2.0 * 3.14159265358979323846 * static_cast<double>(kx) / lx_; }
    double qy(int64_t ky) const {
        const int64_t k = (2 * ky > ny_) ? ky - ny_ : ky;
        return 2.0 * 3.14159265358979323846 * static_cast<double>(k) / ly_;
    }
    // Multiplicity of column kx in a full-plane sum over the Hermitian half.
    double weight(int64_t kx) const { return (kx == 0 || 2 * kx == nx_) ? 1.0 : 2.0; }
    // True on the Nyquist lines, where a mode has no partner of opposite wave vector.
    bool nyquist(int64_t kx, int64_t ky) const { return 2 * kx == nx_ || 2 * ky == ny_; }

    // Unnormalized transforms: forward Z(q) = sum_r z(r) e^{-iqr}; backward z(r) = sum_q Z(q) e^{iqr}.
    // Arrays must come from AlignedBuffer.  backward() destroys its input.
    void forward(const double *in, std::complex<double> *out) const;
    void backward(std::complex<double> *in, double *out) const;

    // New plans for another thread count or planner; the old ones stay if planning fails.
    void replan(int threads, int32_t planner);

private:
    void make_plans(int threads, int32_t planner, fftw_plan &r2c, fftw_plan &c2r) const;
    int64_t nx_, ny_;
    double lx_, ly_;
    fftw_plan r2c_ = nullptr;
    fftw_plan c2r_ = nullptr;
};

}  // namespace gfmd

#endif
