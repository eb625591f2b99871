// The C API of measured topographies (gfmd_topo_*, src/topography.hpp).  A call that fails leaves
// the topography as it was: the changing calls work on a copy and swap it in at the end.
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "c_api_support.hpp"
#include "gfmd.h"
#include "topography.hpp"
#include "x3p.hpp"

struct gfmd_topo {
    gfmd::Topography topo;
    mutable std::string last_error;
};

namespace {

using gfmd::capi::need;
using gfmd::capi::status_of;

template <class F>
int32_t on_topo(const gfmd_topo *t, F &&f) noexcept {
    if (t == nullptr) return GFMD_ERR_NULL;
    return status_of([&] { f(); }, [&](const char *msg) {
        try {
            t->last_error = msg;
        } catch (...) {
            t->last_error.clear();
        }
    });
}

// a changing call: f gets a copy, which replaces the topography only if f succeeds
template <class F>
int32_t changing(gfmd_topo *t, F &&f) noexcept {
    return on_topo(t, [&] {
        gfmd::Topography copy = t->topo;
        f(copy);
        t->topo = std::move(copy);
    });
}

}  // namespace

extern "C" {

int32_t gfmd_topo_read(const char *path, int32_t format, double unit, gfmd_topo **out, char *errbuf, int64_t errlen) {
    return gfmd::capi::make_from_file(path, out, errbuf, errlen, [&](const char *p) {
        auto handle = std::make_unique<gfmd_topo>();
        handle->topo = gfmd::read_topography(p, format, unit);
        return handle;
    });
}

int32_t gfmd_topo_from_heights(int64_t nx, int64_t ny, double lx, double ly, const double *h, gfmd_topo **out) {
    if (out == nullptr || h == nullptr) return GFMD_ERR_NULL;
    *out = nullptr;
    return status_of([&] {
        auto handle = std::make_unique<gfmd_topo>();
        handle->topo = gfmd::topography_from_heights(nx, ny, lx, ly, h);
        *out = handle.release();
    });
}

void gfmd_topo_destroy(gfmd_topo **t) {
    if (t == nullptr) return;
    delete *t;
    *t = nullptr;
}

int32_t gfmd_topo_last_error(const gfmd_topo *t, char *buf, int64_t len) {
    if (buf != nullptr && len > 0) buf[0] = '\0';
    if (buf != nullptr && len > 0 && t == nullptr) return GFMD_ERR_NULL;
    return gfmd::capi::copy_message(t != nullptr ? t->last_error : std::string(), buf, len);
}

int32_t gfmd_topo_get_grid(const gfmd_topo *t, int64_t *nx, int64_t *ny, double *lx, double *ly) {
    return on_topo(t, [&] {
        if (nx) *nx = t->topo.nx;
        if (ny) *ny = t->topo.ny;
        if (lx) *lx = t->topo.lx;
        if (ly) *ly = t->topo.ly;
    });
}

int32_t gfmd_topo_get_info(const gfmd_topo *t, int32_t *format, int32_t *has_units, int64_t *missing) {
    return on_topo(t, [&] {
        if (format) *format = t->topo.format;
        if (has_units) *has_units = t->topo.has_units ? 1 : 0;
        if (missing) *missing = t->topo.missing();
    });
}

int32_t gfmd_topo_set_physical_size(gfmd_topo *t, double lx, double ly) {
    return changing(t, [&](gfmd::Topography &c) {
        if (!(std::isfinite(lx) && lx > 0.0 && std::isfinite(ly) && ly > 0.0))
            gfmd::fail(GFMD_ERR_INVALID_ARG, "lx and ly must be finite and > 0");
        c.lx = lx;
        c.ly = ly;
    });
}

int32_t gfmd_topo_get_heights(const gfmd_topo *t, double *h) {
    return on_topo(t, [&] {
        need(h, "h");
        std::memcpy(h, t->topo.h.data(), t->topo.h.size() * sizeof(double));
    });
}

int32_t gfmd_topo_fill_missing(gfmd_topo *t, int32_t method) {
    return changing(t, [&](gfmd::Topography &c) { gfmd::fill_missing(c, method); });
}

int32_t gfmd_topo_detrend(gfmd_topo *t, int32_t mode) {
    return changing(t, [&](gfmd::Topography &c) { gfmd::detrend(c, mode); });
}

int32_t gfmd_topo_resample(gfmd_topo *t, int64_t nx, int64_t ny) {
    return changing(t, [&](gfmd::Topography &c) { gfmd::resample(c, nx, ny); });
}

int32_t gfmd_topo_psd(const gfmd_topo *t, int32_t window, int64_t nbins, double *q, double *c, int64_t *count) {
    return on_topo(t, [&] {
        need(q, "q");
        need(c, "c");
        const gfmd::RadialPsd p = gfmd::radial_psd(t->topo, window, nbins);
        std::copy(p.q.begin(), p.q.end(), q);
        std::copy(p.c.begin(), p.c.end(), c);
        if (count) std::copy(p.count.begin(), p.count.end(), count);
    });
}

int32_t gfmd_topo_profile_psd(const gfmd_topo *t, int32_t window, int64_t capacity, double *q, double *c, int64_t *n) {
    return on_topo(t, [&] {
        need(n, "n");
        if (capacity < 0) gfmd::fail(GFMD_ERR_INVALID_ARG, "capacity must be >= 0");
        if (capacity > 0) {
            need(q, "q");
            need(c, "c");
        }
        const gfmd::RadialPsd p = gfmd::profile_psd(t->topo, window);
        const auto m = static_cast<int64_t>(p.q.size());
        const auto k = static_cast<std::size_t>(m < capacity ? m : capacity);
        std::copy(p.q.begin(), p.q.begin() + static_cast<std::ptrdiff_t>(k), q);
        std::copy(p.c.begin(), p.c.begin() + static_cast<std::ptrdiff_t>(k), c);
        *n = m;
        if (m > capacity)
            gfmd::fail(GFMD_ERR_TRUNCATED, "the profiles' PSD has " + std::to_string(m) + " values, room for " +
                                               std::to_string(capacity));
    });
}

int32_t gfmd_topo_moments(const gfmd_topo *t, int32_t window, double *rms_height, double *rms_slope,
                          double *rms_curvature) {
    return on_topo(t, [&] {
        const gfmd::SpectralMoments m = gfmd::spectral_moments(t->topo, window);
        if (rms_height) *rms_height = m.rms_height;
        if (rms_slope) *rms_slope = m.rms_slope;
        if (rms_curvature) *rms_curvature = m.rms_curvature;
    });
}

int32_t gfmd_topo_persson_contact_area(const gfmd_topo *t, int32_t window, int32_t kind, double width, double nu,
                                       double e_star, double sigma0, double *rel_area, double *variance) {
    return on_topo(t, [&] {
        need(rel_area, "rel_area");
        if (!(std::isfinite(sigma0) && sigma0 >= 0.0)) gfmd::fail(GFMD_ERR_INVALID_ARG, "sigma0 must be finite and >= 0");
        const double v = gfmd::topography_persson_variance(t->topo, window, kind, width, nu, e_star);
        *rel_area = v > 0.0 ? std::erf(sigma0 / std::sqrt(2.0 * v)) : (sigma0 > 0.0 ? 1.0 : 0.0);
        if (variance) *variance = v;
    });
}

int32_t gfmd_topo_format_supported(int32_t format) {
    if (format == GFMD_TOPO_X3P) return gfmd::x3p_supported() ? 1 : 0;
    return (format >= GFMD_TOPO_AUTO && format <= GFMD_TOPO_NPY) ? 1 : 0;
}

int32_t gfmd_topo_persson_mean_gap(const gfmd_topo *t, int32_t window, int32_t kind, double width, double nu,
                                   double e_star, double sigma0, double gamma, double *mean_gap) {
    return on_topo(t, [&] {
        need(mean_gap, "mean_gap");
        *mean_gap = gfmd::topography_persson_mean_gap(t->topo, window, kind, width, nu, e_star, sigma0,
                                                      gamma < 0.0 ? 0.45 : gamma);
    });
}

}  // extern "C"
