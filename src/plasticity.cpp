#include "plasticity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gfmd {

Plasticity::Plasticity(const FftGrid &grid, const RealBuffer &h)
    : substrate(static_cast<std::size_t>(grid.local_points())), yielding(static_cast<std::size_t>(grid.local_points()), 0) {
    std::copy(h.data(), h.data() + h.size(), substrate.data());
}

Plasticity::Plasticity(const Plasticity &o)
    : substrate(o.substrate.size()), yielding(o.yielding), committed_volume(o.committed_volume),
      yielding_points(o.yielding_points) {
    std::copy(o.substrate.data(), o.substrate.data() + o.substrate.size(), substrate.data());
}

void settle(const FftGrid &grid, const Plasticity &pl, Fields &fields) {
    double *h = fields.h.data();
    const double *z = fields.z.data(), *hs = pl.substrate.data();
    grid.for_points([&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) h[i] = std::min(hs[i], z[i]);
    });
}

void yield(const FftGrid &grid, const Params &p, Plasticity &pl, Fields &fields, ForceState &fs) {
    const double hard = p.hardness;
    double *f = fields.f.data();
    const double *z = fields.z.data(), *h = fields.h.data(), *hs = pl.substrate.data(), *v = fields.v.data();
    unsigned char *y = pl.yielding.data();
    // below the substrate of the step's start, or on it and pressed beyond H
    const auto counted = grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
        double n = 0.0;
        for (int64_t i = i0; i < i1; ++i) {
            y[i] = (z[i] < hs[i] || (z[i] <= h[i] && f[i] < -hard)) ? 1 : 0;
            n += y[i];
        }
        acc[0] += n;
    });
    pl.yielding_points = static_cast<int64_t>(counted[0]);
    if (pl.yielding_points == 0) return;  // the elastic numbers stand, bit for bit
    if (p.control == kDisplacementControl) {
        // the multiplier of mean(z) = d over every point free to move, the yielding ones with
        // their pressure H: their mean force is then zero too
        const double old = fs.mean_pressure;
        const auto m = grid.sum_points<2>([&](int64_t i0, int64_t i1, double *acc) {
            for (int64_t i = i0; i < i1; ++i) {
                if (!(y[i] != 0 || z[i] > h[i])) continue;
                acc[0] += f[i] + old + (y[i] != 0 ? hard : 0.0);
                acc[1] += 1.0;
            }
        });
        const double sigma0 = m[1] > 0.0 ? m[0] / m[1] : old;
        grid.for_points([&](int64_t i0, int64_t i1) {
            for (int64_t i = i0; i < i1; ++i) f[i] += old - sigma0;
        });
        fs.mean_pressure = sigma0;
    }
    const double inv_ref = 1.0 / residual_scale(p, fs.mean_pressure);
    const auto sums = grid.sum_points<4>([&](int64_t i0, int64_t i1, double *acc) {
        for (int64_t i = i0; i < i1; ++i) {
            const double r = y[i] != 0 ? f[i] + hard : (z[i] <= h[i] ? std::max(f[i], 0.0) : f[i]);
            const double rs = r * inv_ref;
            acc[0] += r * r;
            acc[1] += r * v[i];
            acc[2] += v[i] * v[i];
            acc[3] += rs * rs;
        }
    });
    fs.f_norm2 = sums[0];
    fs.power = sums[1];
    fs.v_norm2 = sums[2];
    fs.residual = std::sqrt(sums[3] / static_cast<double>(grid.real_size()));
}

void release(const FftGrid &grid, const Params &p, const Plasticity &pl, Fields &fields) {
    if (pl.yielding_points == 0) return;
    double *f = fields.f.data(), *h = fields.h.data();
    const unsigned char *y = pl.yielding.data();
    const double hard = p.hardness, below = -std::numeric_limits<double>::infinity();
    grid.for_points([&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i)
            if (y[i] != 0) {
                f[i] += hard;
                h[i] = below;
            }
    });
}

void commit(const FftGrid &grid, Plasticity &pl, const Fields &fields) {
    pl.committed_volume = plastic_volume(grid, pl, fields);
    std::copy(fields.h.data(), fields.h.data() + fields.h.size(), pl.substrate.data());
}

double plastic_volume(const FftGrid &grid, const Plasticity &pl, const Fields &fields) {
    const double *h = fields.h.data(), *hs = pl.substrate.data();
    const auto s = grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
        double t = 0.0;
        for (int64_t i = i0; i < i1; ++i) t += hs[i] - h[i];
        acc[0] += t;
    });
    return pl.committed_volume + s[0] * grid.area_per_point();
}

}  // namespace gfmd
