#include "patches.hpp"

#include <algorithm>
#include <cmath>
#include <new>
#include <string>

#include "error.hpp"
#include "fields.hpp"
#include "gfmd.h"
#include "simulation.hpp"

namespace gfmd {

void check_connectivity(int32_t connectivity) {
    if (connectivity != 4 && connectivity != 8)
        fail(GFMD_ERR_INVALID_ARG, "connectivity must be 4 or 8, got " + std::to_string(connectivity));
}

namespace {
struct Visit {
    int64_t i, ux, uy;  // point, and its unwrapped coordinates
};
constexpr int kSteps[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
}  // namespace

Patches label_patches(int64_t nx, int64_t ny, const unsigned char *in, int32_t connectivity, bool periodic,
                      int64_t *labels) {
    check_connectivity(connectivity);
    const int64_t n = nx * ny;
    std::fill(labels, labels + n, int64_t{0});
    Patches out;
    std::vector<Visit> queue;
    // whether (x, y) lies on the grid after wrapping, and its index
    const auto locate = [&](int64_t x, int64_t y, int64_t &j) {
        if (periodic) {
            x = (x % nx + nx) % nx;
            y = (y % ny + ny) % ny;
        } else if (x < 0 || x >= nx || y < 0 || y >= ny) {
            return false;
        }
        j = x + nx * y;
        return true;
    };
    for (int64_t start = 0; start < n; ++start) {
        if (in[start] == 0 || labels[start] != 0) continue;
        const int64_t label = ++out.count;
        double points = 0.0, ex = 0.0, ey = 0.0, sx = 0.0, sy = 0.0;
        queue.clear();
        queue.push_back({start, start % nx, start / nx});
        labels[start] = label;
        for (std::size_t head = 0; head < queue.size(); ++head) {
            const Visit p = queue[head];
            const int64_t x = p.i % nx, y = p.i / nx;
            points += 1.0;
            sx += static_cast<double>(p.ux);
            sy += static_cast<double>(p.uy);
            for (int k = 0; k < connectivity; ++k) {
                const int64_t dx = kSteps[k][0], dy = kSteps[k][1];
                int64_t j = 0;
                const bool on_grid = locate(x + dx, y + dy, j);
                const bool member = on_grid && in[j] != 0;
                if (k < 4 && !member) (dx != 0 ? ex : ey) += 1.0;
                if (member && labels[j] == 0) {
                    labels[j] = label;
                    queue.push_back({j, p.ux + dx, p.uy + dy});
                }
            }
        }
        out.points.push_back(points);
        out.edges_x.push_back(ex);
        out.edges_y.push_back(ey);
        out.mean_x.push_back(sx / points);
        out.mean_y.push_back(sy / points);
    }
    return out;
}

std::vector<double> patch_values(const Patches &patches, int32_t property, int64_t nx, int64_t ny, double lx,
                                 double ly, const int64_t *labels, const double *pressure) {
    const double dx = lx / static_cast<double>(nx), dy = ly / static_cast<double>(ny);
    const std::size_t count = static_cast<std::size_t>(patches.count);
    std::vector<double> v(count, 0.0);
    // a mean position in [0, l): the unwrapped mean folded into the cell
    const auto fold = [](double x, double l) {
        const double r = x - l * std::floor(x / l);
        return (r >= l) ? 0.0 : r;
    };
    switch (property) {
        case GFMD_PATCH_POINTS: v = patches.points; break;
        case GFMD_PATCH_AREA:
            for (std::size_t k = 0; k < count; ++k) v[k] = patches.points[k] * dx * dy;
            break;
        case GFMD_PATCH_EDGES:
            for (std::size_t k = 0; k < count; ++k) v[k] = patches.edges_x[k] + patches.edges_y[k];
            break;
        case GFMD_PATCH_PERIMETER:
            for (std::size_t k = 0; k < count; ++k)
                v[k] = 0.25 * M_PI * (patches.edges_x[k] * dy + patches.edges_y[k] * dx);
            break;
        case GFMD_PATCH_CENTROID_X:
            for (std::size_t k = 0; k < count; ++k) v[k] = fold(patches.mean_x[k] * dx, lx);
            break;
        case GFMD_PATCH_CENTROID_Y:
            for (std::size_t k = 0; k < count; ++k) v[k] = fold(patches.mean_y[k] * dy, ly);
            break;
        case GFMD_PATCH_LOAD: {
            const int64_t n = nx * ny;
            for (int64_t i = 0; i < n; ++i)
                if (labels[i] > 0) v[static_cast<std::size_t>(labels[i] - 1)] += pressure[i];
            for (double &x : v) x *= dx * dy;
            break;
        }
        default: fail(GFMD_ERR_BAD_ENUM, "unknown patch property " + std::to_string(property));
    }
    return v;
}

void pressure_histogram(int64_t n, const unsigned char *in, const double *pressure, int64_t nbins, double &lo,
                        double &hi, double *fraction, double *mean) {
    if (nbins < 1) fail(GFMD_ERR_INVALID_ARG, "nbins must be >= 1, got " + std::to_string(nbins));
    if (lo == 0.0 && hi == 0.0) {
        bool any = false;
        for (int64_t i = 0; i < n; ++i) {
            if (in[i] == 0) continue;
            lo = any ? std::min(lo, pressure[i]) : pressure[i];
            hi = any ? std::max(hi, pressure[i]) : pressure[i];
            any = true;
        }
        if (!(hi > lo)) hi = lo + 1.0;  // no contact, or one pressure: any bin holds it
    }
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi))
        fail(GFMD_ERR_INVALID_ARG, "the range must be finite with lo < hi, got [" + std::to_string(lo) + ", " +
                                       std::to_string(hi) + "]");
    std::vector<double> count(static_cast<std::size_t>(nbins), 0.0), sum(static_cast<std::size_t>(nbins), 0.0);
    const double scale = static_cast<double>(nbins) / (hi - lo);
    for (int64_t i = 0; i < n; ++i) {
        if (in[i] == 0) continue;
        const double b = std::floor((pressure[i] - lo) * scale);
        const std::size_t k = static_cast<std::size_t>(std::clamp(b, 0.0, static_cast<double>(nbins - 1)));
        count[k] += 1.0;
        sum[k] += pressure[i];
    }
    for (std::size_t k = 0; k < count.size(); ++k) {
        fraction[k] = count[k] / static_cast<double>(n);
        mean[k] = count[k] > 0.0 ? sum[k] / count[k] : 0.0;
    }
}


WholeContact whole_contact(const Simulation &m, bool with_pressure) {
    const FftGrid &g = m.grid();
    // the user's grid (free boundaries: the region, on one rank)
    const auto n = static_cast<std::size_t>(m.points()), local = static_cast<std::size_t>(g.local_points());
    WholeContact w;
    std::vector<unsigned char> in;
    std::vector<double> p;
    g.on_all_ranks([&] {
        const double bytes = (with_pressure ? 9.0 : 1.0) + 8.0;  // with the labels the caller makes
        if (g.ranks() > 1) {
            if (8.0 * static_cast<double>(n) > 2147483647.0)
                fail(GFMD_ERR_STATE, "the contact analysis gathers the whole grid on every rank: " +
                                         std::to_string(g.nx()) + " x " + std::to_string(g.ny()) +
                                         " is beyond its 2 GB gather");
            check_memory(g.nx(), g.ny(), bytes);
        }
        try {
            w.in.resize(n);
            if (with_pressure) w.pressure.resize(n);
            if (g.ranks() > 1) {
                in.resize(local);
                if (with_pressure) p.resize(local);
            }
        } catch (const std::bad_alloc &) {
            fail(GFMD_ERR_NOMEM, "the whole grid's contact set does not fit in this rank's memory");
        }
    });
    if (g.ranks() <= 1) {
        m.contact_set(w.in.data());
        if (with_pressure) m.pressure(w.pressure.data());
        return w;
    }
    m.contact_set(in.data());
    g.gather_rows(in.data(), static_cast<std::size_t>(g.nx()), w.in.data());
    if (with_pressure) {
        m.pressure(p.data());
        g.gather_rows(p.data(), 8 * static_cast<std::size_t>(g.nx()), w.pressure.data());
    }
    return w;
}

double persson_pressure_density(double variance, double sigma0, double p) {
    if (p < 0.0) return 0.0;
    if (!(variance > 0.0)) return p == sigma0 ? HUGE_VAL : 0.0;
    const double s2 = 2.0 * variance;
    const double norm = 1.0 / std::sqrt(M_PI * s2);
    // N(p - s) - N(p + s) = N(p - s) (1 - exp(-2 p s / V)): no cancellation where both are close
    const double a = p - sigma0;
    return norm * std::exp(-a * a / s2) * -std::expm1(-2.0 * p * sigma0 / variance);
}

}  // namespace gfmd
