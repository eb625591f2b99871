// Measured topographies (gfmd_topo_*): reading the instruments' files, filling missing points,
// detrending, and the spectra (PSD) and Persson's theory from them.  A topography is a grid of
// heights on a rectangle, x fastest, in the caller's length unit; NaN marks a missing point.
#ifndef GFMD_SRC_TOPOGRAPHY_HPP
#define GFMD_SRC_TOPOGRAPHY_HPP

#include <cstdint>
#include <string>
#include <vector>

namespace gfmd {

struct Topography {
    int64_t nx = 0, ny = 0;
    double lx = 0.0, ly = 0.0;  // the rectangle, in the caller's unit
    int32_t format = 0;         // GFMD_TOPO_* the data came from
    bool has_units = false;     // the file gave lengths in physical units (converted), or not
    std::vector<double> h;      // nx * ny heights, NaN where missing
    int64_t missing() const;
};

// Reads path in the given format (GFMD_TOPO_AUTO: detected from the content), converting lengths
// to the caller's unit (its length in metres).  GFMD_ERR_IO when the file cannot be read,
// GFMD_ERR_FORMAT with what was expected and where when its content is not valid; nothing is
// allocated beyond what the file's length can hold.
Topography read_topography(const std::string &path, int32_t format, double unit);
// The same from bytes already in memory (the fuzzer's entry; read_topography reads the file and
// calls it).
Topography parse_topography(const std::string &bytes, int32_t format, double unit);
Topography topography_from_heights(int64_t nx, int64_t ny, double lx, double ly, const double *h);

void fill_missing(Topography &t, int32_t method);  // GFMD_FILL_*
void detrend(Topography &t, int32_t mode);          // GFMD_DETREND_*
// Keys' cubic convolution (a = -1/2: exact for quadratics) onto nx x ny points spanning the same
// first-to-last sample extent; the border samples continued by reflection-free clamping.
void resample(Topography &t, int64_t nx, int64_t ny);

struct RadialPsd {
    std::vector<double> q, c;
    std::vector<int64_t> count;
};
// C(q) averaged over log-spaced bins of |q| between the smallest and the largest nonzero
// wavevector of the grid: sum_k count_k C_k (2 pi)^2 / (lx ly) = the variance of h (Parseval).
RadialPsd radial_psd(const Topography &t, int32_t window, int64_t nbins);
// C1(q_x) of the profiles along x, averaged over the rows, at q_x = 2 pi k / lx, k = 0..nx/2.
RadialPsd profile_psd(const Topography &t, int32_t window);

struct SpectralMoments {
    double rms_height, rms_slope, rms_curvature;
};
SpectralMoments spectral_moments(const Topography &t, int32_t window);
// Persson's full-contact pressure variance of the topography on a body (GFMD_GREEN_*).
double topography_persson_variance(const Topography &t, int32_t window, int32_t kind, double width, double nu,
                                   double e_star);
// Persson's mean gap at sigma0 > 0 (Yang & Persson, J. Phys.: Condens. Matter 20, 215214 (2008),
// Eq. 2, with the body's stiffness: topography.cpp), gamma in [0, 1] their elastic-energy factor.
double topography_persson_mean_gap(const Topography &t, int32_t window, int32_t kind, double width, double nu,
                                   double e_star, double sigma0, double gamma);

}  // namespace gfmd

#endif
