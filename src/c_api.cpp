// The C ABI: check arguments, call the core, turn every exception into a status plus message.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "c_api_support.hpp"
#include "error.hpp"
#include "gfmd.h"
#include "green.hpp"
#include "least_squares.hpp"
#include "patches.hpp"
#include "simulation.hpp"

namespace {

using gfmd::fail;
using gfmd::capi::args;
using gfmd::capi::copy_message;
using gfmd::capi::guarded;
using gfmd::capi::make_from_file;
using gfmd::capi::need;
using gfmd::capi::record;
using gfmd::capi::status_of;
using gfmd::capi::whole_grid;

// A relaxation as gfmd_relax() documents it: tol <= 0 is the default, max_steps > 0; run(t)
// relaxes to t and returns whether it converged; *steps_taken gets the steps it reports.
template <class Run>
void relax_call(gfmd::Simulation &m, double tol, int64_t max_steps, int64_t *steps_taken, Run &&run) {
    if (std::isnan(tol)) fail(GFMD_ERR_INVALID_ARG, "tol is NaN");
    if (max_steps <= 0) fail(GFMD_ERR_INVALID_ARG, "max_steps must be > 0, got " + std::to_string(max_steps));
    const double t = (tol > 0.0) ? tol : GFMD_DEFAULT_TOL;
    int64_t taken = 0;
    const bool ok = run(t, taken);
    if (steps_taken) *steps_taken = taken;
    if (!ok) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "not converged after %lld steps: residual %.3e > tol %.3e",
                      static_cast<long long>(taken), m.forces().residual, t);
        fail(GFMD_ERR_NOT_CONVERGED, buf);
    }
}

// The contact patches of a handle's configuration, labels of the whole grid into `labels`.
gfmd::Patches handle_patches(const gfmd::WholeContact &w, const gfmd::Simulation &m, int32_t connectivity,
                             int64_t *labels) {
    return gfmd::label_patches(m.nx(), m.ny(), w.in.data(), connectivity, !m.free(), labels);
}

}  // namespace

extern "C" {

const char *gfmd_version(void) { return GFMD_VERSION_STRING; }

const char *gfmd_status_string(int32_t status) {
    switch (status) {
#define GFMD_X_CASE(name, value, text) \
    case value:                        \
        return text;
        GFMD_STATUS_LIST(GFMD_X_CASE)
#undef GFMD_X_CASE
        default:
            return "unknown status";
    }
}

int32_t gfmd_last_error(const gfmd_sim *s, char *buf, int64_t len) {
    if (buf != nullptr && len > 0) buf[0] = '\0';  // terminated on every path that can write
    if (buf != nullptr && len > 0 && s == nullptr) return GFMD_ERR_NULL;
    return copy_message(s != nullptr ? s->last_error : std::string(), buf, len);
}

int32_t gfmd_last_error_length(const gfmd_sim *s, int64_t *needed) {
    if (s == nullptr || needed == nullptr) return GFMD_ERR_NULL;
    *needed = static_cast<int64_t>(s->last_error.size()) + 1;
    return GFMD_OK;
}

int32_t gfmd_sim_create(int64_t nx, int64_t ny, double lx, double ly, gfmd_sim **out) {
    return gfmd_sim_create_ex(nx, ny, lx, ly, 0, GFMD_PLANNER_MEASURE, out);
}

int32_t gfmd_sim_create_ex(int64_t nx, int64_t ny, double lx, double ly, int32_t nthreads, int32_t planner,
                           gfmd_sim **out) {
    if (out == nullptr) return GFMD_ERR_NULL;
    *out = nullptr;
    return status_of([&] {
        auto handle = std::make_unique<gfmd_sim>();
        handle->sim = std::make_unique<gfmd::Simulation>(nx, ny, lx, ly, nthreads, planner);
        *out = handle.release();
    });
}

int32_t gfmd_sim_clone(const gfmd_sim *s, gfmd_sim **out) {
    if (out == nullptr) {
        if (s != nullptr) record(s, "argument 'out' is NULL");
        return GFMD_ERR_NULL;
    }
    *out = nullptr;
    return guarded(s, args(out), [&](const gfmd::Simulation &m) {
        auto handle = std::make_unique<gfmd_sim>();
        handle->sim = m.clone();
        *out = handle.release();
    });
}

void gfmd_sim_destroy(gfmd_sim **sim) {
    if (sim == nullptr || *sim == nullptr) return;
    delete *sim;
    *sim = nullptr;
}

int32_t gfmd_sim_save(const gfmd_sim *s, const char *path) {
    return guarded(s, args(path), [&](const gfmd::Simulation &m) {
        need(path, "path");
        m.save(path);
    });
}

int32_t gfmd_sim_load(const char *path, gfmd_sim **out, char *errbuf, int64_t errlen) {
    return make_from_file(path, out, errbuf, errlen, [](const char *p) {
        auto handle = std::make_unique<gfmd_sim>();
        handle->sim = gfmd::Simulation::load(p);
        return handle;
    });
}

int32_t gfmd_get_grid(const gfmd_sim *s, int64_t *nx, int64_t *ny, double *lx, double *ly) {
    return guarded(s, args(nx, ny, lx, ly), [&](const gfmd::Simulation &m) {
        if (nx) *nx = m.nx();
        if (ny) *ny = m.ny();
        if (lx) *lx = m.lx();
        if (ly) *ly = m.ly();
    });
}

int32_t gfmd_set_boundary(gfmd_sim *s, int32_t boundary) {
    std::unique_ptr<gfmd::Simulation> replaced;  // freed after guarded() is done with the handle
    return guarded(s, args(boundary), [&](gfmd::Simulation &m) {
        if (boundary != GFMD_BOUNDARY_PERIODIC && boundary != GFMD_BOUNDARY_FREE)
            fail(GFMD_ERR_BAD_ENUM, "unknown boundary " + std::to_string(boundary));
        if (boundary == (m.free() ? GFMD_BOUNDARY_FREE : GFMD_BOUNDARY_PERIODIC)) return;
        replaced = m.with_boundary(boundary);
        std::swap(replaced, s->sim);
    });
}

int32_t gfmd_get_boundary(const gfmd_sim *s, int32_t *boundary) {
    return guarded(s, args(boundary), [&](const gfmd::Simulation &m) {
        need(boundary, "boundary");
        *boundary = m.free() ? GFMD_BOUNDARY_FREE : GFMD_BOUNDARY_PERIODIC;
    });
}

int32_t gfmd_set_modulus(gfmd_sim *s, double e_star) {
    return guarded(s, args(e_star), [&](gfmd::Simulation &m) { m.set_modulus(e_star); });
}

int32_t gfmd_set_green(gfmd_sim *s, int32_t kind, double width) {
    return guarded(s, args(kind, width), [&](gfmd::Simulation &m) { m.set_green(kind, width); });
}

int32_t gfmd_set_poisson(gfmd_sim *s, double nu) {
    return guarded(s, args(nu), [&](gfmd::Simulation &m) { m.set_poisson(nu); });
}

int32_t gfmd_green_factor(int32_t kind, double t, double nu, double *f) {
    if (f == nullptr) return GFMD_ERR_NULL;
    return status_of([&] {
        gfmd::validate_green_kind(kind);
        if (!std::isfinite(t) || t <= 0.0) fail(GFMD_ERR_INVALID_ARG, "t must be finite and > 0");
        if (kind == GFMD_GREEN_LAYER_BONDED) gfmd::validate_poisson(nu);
        const double v = gfmd::green_factor(kind, t, nu);
        if (!(v > 0.0) || !std::isfinite(v)) fail(GFMD_ERR_RANGE, "f(t) over- or underflows");  // fuzz finding
        *f = v;
    });
}

int32_t gfmd_set_heights(gfmd_sim *s, const double *h) {
    return guarded(s, args(h), [&](gfmd::Simulation &m) {
        need(h, "h");
        whole_grid(m, "gfmd_mpi_set_local_heights");
        m.set_heights(h);
    });
}

int32_t gfmd_get_heights(const gfmd_sim *s, double *h) {
    return guarded(s, args(h), [&](const gfmd::Simulation &m) {
        need(h, "h");
        whole_grid(m, "gfmd_mpi_get_local_heights");
        m.heights(h);
    });
}

int32_t gfmd_generate_selfaffine(gfmd_sim *s, double hurst, double lambda_r, double lambda_s, double rms_gradient,
                                 uint64_t seed, int32_t distribution) {
    return guarded(s, args(hurst, lambda_r, lambda_s, rms_gradient, seed, distribution), [&](gfmd::Simulation &m) {
        m.generate_selfaffine(gfmd::SelfAffineParams{hurst, lambda_r, lambda_s, rms_gradient, seed, distribution});
    });
}

int32_t gfmd_set_pressure(gfmd_sim *s, double sigma0) {
    return guarded(s, args(sigma0), [&](gfmd::Simulation &m) { m.set_pressure(sigma0); });
}

int32_t gfmd_set_mean_displacement(gfmd_sim *s, double d) {
    return guarded(s, args(d), [&](gfmd::Simulation &m) { m.set_mean_displacement(d); });
}

int32_t gfmd_get_mean_displacement(const gfmd_sim *s, double *d) {
    return guarded(s, args(d), [&](const gfmd::Simulation &m) {
        need(d, "d");
        *d = m.mean_displacement();
    });
}

int32_t gfmd_get_mean_pressure(const gfmd_sim *s, double *p) {
    return guarded(s, args(p), [&](const gfmd::Simulation &m) {
        need(p, "p");
        *p = m.mean_pressure();
    });
}

int32_t gfmd_set_adhesion(gfmd_sim *s, double gamma0, double rho) {
    return guarded(s, args(gamma0, rho), [&](gfmd::Simulation &m) { m.set_adhesion(gamma0, rho); });
}

int32_t gfmd_set_timestep(gfmd_sim *s, double dt) {
    return guarded(s, args(dt), [&](gfmd::Simulation &m) { m.set_timestep(dt); });
}

int32_t gfmd_set_damping(gfmd_sim *s, double eta) {
    return guarded(s, args(eta), [&](gfmd::Simulation &m) { m.set_damping(eta); });
}

int32_t gfmd_set_solver(gfmd_sim *s, int32_t solver) {
    return guarded(s, args(solver), [&](gfmd::Simulation &m) { m.set_solver(solver); });
}

int32_t gfmd_set_threads(gfmd_sim *s, int32_t nthreads) {
    return guarded(s, args(nthreads), [&](gfmd::Simulation &m) { m.set_threads(nthreads); });
}

int32_t gfmd_get_solver(const gfmd_sim *s, int32_t *solver) {
    return guarded(s, args(solver), [&](const gfmd::Simulation &m) {
        need(solver, "solver");
        *solver = m.active_solver();
    });
}

int32_t gfmd_get_threads(const gfmd_sim *s, int32_t *nthreads) {
    return guarded(s, args(nthreads), [&](const gfmd::Simulation &m) {
        need(nthreads, "nthreads");
        *nthreads = m.grid().threads();
    });
}

int32_t gfmd_set_fft_planner(gfmd_sim *s, int32_t planner) {
    return guarded(s, args(planner), [&](gfmd::Simulation &m) { m.set_planner(planner); });
}

int32_t gfmd_import_wisdom(const char *path) {
    if (path == nullptr) return GFMD_ERR_NULL;
    return gfmd::import_wisdom(path) ? GFMD_OK : GFMD_ERR_IO;
}

int32_t gfmd_export_wisdom(const char *path) {
    if (path == nullptr) return GFMD_ERR_NULL;
    return gfmd::export_wisdom(path) ? GFMD_OK : GFMD_ERR_IO;
}

int32_t gfmd_get_dynamics(const gfmd_sim *s, double *dt, double *eta) {
    return guarded(s, args(dt, eta), [&](const gfmd::Simulation &m) {
        if (dt) *dt = m.dynamics().dt;
        if (eta) *eta = m.dynamics().eta;
    });
}

int32_t gfmd_step(gfmd_sim *s, int64_t nsteps) {
    return guarded(s, args(nsteps), [&](gfmd::Simulation &m) {
        if (nsteps < 0) fail(GFMD_ERR_INVALID_ARG, "nsteps must be >= 0, got " + std::to_string(nsteps));
        m.step(nsteps);
    });
}

int32_t gfmd_restart_solver(gfmd_sim *s) {
    return guarded(s, [&](gfmd::Simulation &m) { m.restart_solver(); });
}

int32_t gfmd_relax_multilevel(gfmd_sim *s, double tol, int64_t max_steps, int32_t levels, int64_t *steps_taken,
                              int64_t *coarse_steps) {
    return guarded(s, args(tol, max_steps, levels, steps_taken, coarse_steps), [&](gfmd::Simulation &m) {
        relax_call(m, tol, max_steps, steps_taken, [&](double t, int64_t &taken) {
            int64_t below = 0;
            const bool ok = m.relax_multilevel(t, max_steps, levels, taken, below);
            if (coarse_steps) *coarse_steps = below;
            return ok;
        });
    });
}

int32_t gfmd_relax(gfmd_sim *s, double tol, int64_t max_steps, int64_t *steps_taken) {
    return guarded(s, args(tol, max_steps, steps_taken), [&](gfmd::Simulation &m) {
        relax_call(m, tol, max_steps, steps_taken,
                   [&](double t, int64_t &taken) { return m.relax(t, max_steps, taken); });
    });
}

int32_t gfmd_get_residual(const gfmd_sim *s, double *residual) {
    return guarded(s, args(residual), [&](const gfmd::Simulation &m) {
        need(residual, "residual");
        *residual = m.forces().residual;
    });
}

int32_t gfmd_reset(gfmd_sim *s) {
    return guarded(s, [&](gfmd::Simulation &m) { m.reset(); });
}

int32_t gfmd_get_contact_area(const gfmd_sim *s, double *rel_area) {
    return guarded(s, args(rel_area), [&](const gfmd::Simulation &m) {
        need(rel_area, "rel_area");
        *rel_area = m.contact_area();
    });
}

int32_t gfmd_get_mean_gap(const gfmd_sim *s, double *mean_gap) {
    return guarded(s, args(mean_gap), [&](const gfmd::Simulation &m) {
        need(mean_gap, "mean_gap");
        *mean_gap = m.mean_gap();
    });
}

int32_t gfmd_get_energies(const gfmd_sim *s, double *elastic, double *adhesive) {
    return guarded(s, args(elastic, adhesive), [&](const gfmd::Simulation &m) {
        need(elastic, "elastic");
        need(adhesive, "adhesive");
        *elastic = m.elastic_energy();
        *adhesive = m.adhesive_energy();
    });
}

int32_t gfmd_get_gap(const gfmd_sim *s, double *gap) {
    return guarded(s, args(gap), [&](const gfmd::Simulation &m) {
        need(gap, "gap");
        whole_grid(m, "gfmd_mpi_get_local_gap");
        m.gap(gap);
    });
}

int32_t gfmd_get_surface(const gfmd_sim *s, double *z) {
    return guarded(s, args(z), [&](const gfmd::Simulation &m) {
        need(z, "z");
        whole_grid(m, "gfmd_mpi_get_local_surface");
        m.surface(z);
    });
}

int32_t gfmd_get_pressure(const gfmd_sim *s, double *p) {
    return guarded(s, args(p), [&](const gfmd::Simulation &m) {
        need(p, "p");
        whole_grid(m, "gfmd_mpi_get_local_pressure");
        m.pressure(p);
    });
}

int32_t gfmd_set_hardness(gfmd_sim *s, double hardness) {
    return guarded(s, args(hardness), [&](gfmd::Simulation &m) { m.set_hardness(hardness); });
}

int32_t gfmd_get_hardness(const gfmd_sim *s, double *hardness) {
    return guarded(s, args(hardness), [&](const gfmd::Simulation &m) {
        need(hardness, "hardness");
        *hardness = m.hardness();
    });
}

int32_t gfmd_get_plasticity(const gfmd_sim *s, double *plastic_area, double *plastic_volume) {
    return guarded(s, args(plastic_area, plastic_volume), [&](const gfmd::Simulation &m) {
        if (plastic_area != nullptr) *plastic_area = m.plastic_area();
        if (plastic_volume != nullptr) *plastic_volume = m.plastic_volume();
    });
}

int32_t gfmd_label_patches(int64_t nx, int64_t ny, const int32_t *mask, int32_t connectivity, int32_t periodic,
                           int64_t *labels, int64_t *npatches) {
    if (mask == nullptr || labels == nullptr || npatches == nullptr) return GFMD_ERR_NULL;
    return status_of([&] {
        if (nx < 1 || ny < 1 || nx > INT64_MAX / ny)
            fail(GFMD_ERR_INVALID_ARG, "nx and ny must be >= 1 (and their product an int64_t)");
        gfmd::check_connectivity(connectivity);
        const auto n = static_cast<std::size_t>(nx * ny);
        std::vector<unsigned char> in(n);
        for (std::size_t i = 0; i < n; ++i) in[i] = mask[i] != 0 ? 1 : 0;
        *npatches = gfmd::label_patches(nx, ny, in.data(), connectivity, periodic != 0, labels).count;
    });
}

int32_t gfmd_get_contact_patches(const gfmd_sim *s, int32_t connectivity, int64_t *labels, int64_t *npatches) {
    return guarded(s, args(connectivity, labels, npatches), [&](const gfmd::Simulation &m) {
        need(npatches, "npatches");
        gfmd::check_connectivity(connectivity);
        if (labels != nullptr) whole_grid(m, "labels = NULL (count only) or gfmd_mpi_get_local_contact_patches");
        const gfmd::WholeContact w = gfmd::whole_contact(m, false);
        // labels written only once the call cannot fail
        std::vector<int64_t> out(static_cast<std::size_t>(m.points()));
        const gfmd::Patches p = handle_patches(w, m, connectivity, out.data());
        if (labels != nullptr) std::copy(out.begin(), out.end(), labels);
        *npatches = p.count;
    });
}

int32_t gfmd_get_patch_property(const gfmd_sim *s, int32_t connectivity, int32_t property, int64_t capacity,
                                double *values, int64_t *npatches) {
    return guarded(s, args(connectivity, property, capacity, values, npatches), [&](const gfmd::Simulation &m) {
        need(npatches, "npatches");
        if (capacity < 0) fail(GFMD_ERR_INVALID_ARG, "capacity must be >= 0, got " + std::to_string(capacity));
        if (capacity > 0) need(values, "values");
        gfmd::check_connectivity(connectivity);
        if (property < GFMD_PATCH_POINTS || property > GFMD_PATCH_LOAD)
            fail(GFMD_ERR_BAD_ENUM, "unknown patch property " + std::to_string(property));
        const gfmd::WholeContact w = gfmd::whole_contact(m, property == GFMD_PATCH_LOAD);
        std::vector<int64_t> labels(static_cast<std::size_t>(m.points()));
        const gfmd::Patches p = handle_patches(w, m, connectivity, labels.data());
        const std::vector<double> v = gfmd::patch_values(p, property, m.nx(), m.ny(), m.lx(), m.ly(), labels.data(),
                                                         w.pressure.data());
        const std::size_t written = std::min(v.size(), static_cast<std::size_t>(capacity));
        std::copy(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(written), values);
        *npatches = p.count;
        if (p.count > capacity)
            fail(GFMD_ERR_TRUNCATED, std::to_string(p.count) + " patches, room for " + std::to_string(capacity));
    });
}

int32_t gfmd_get_pressure_histogram(const gfmd_sim *s, int64_t nbins, double *range, double *fraction,
                                    double *mean) {
    return guarded(s, args(nbins, range, fraction, mean), [&](const gfmd::Simulation &m) {
        need(range, "range");
        need(fraction, "fraction");
        need(mean, "mean");
        if (nbins < 1) fail(GFMD_ERR_INVALID_ARG, "nbins must be >= 1, got " + std::to_string(nbins));
        const gfmd::WholeContact w = gfmd::whole_contact(m, true);
        std::vector<double> fr(static_cast<std::size_t>(nbins)), me(static_cast<std::size_t>(nbins));
        double lo = range[0], hi = range[1];
        gfmd::pressure_histogram(m.points(), w.in.data(), w.pressure.data(), nbins, lo, hi, fr.data(),
                                 me.data());
        std::copy(fr.begin(), fr.end(), fraction);
        std::copy(me.begin(), me.end(), mean);
        range[0] = lo;
        range[1] = hi;
    });
}

int32_t gfmd_persson_pressure_distribution(const gfmd_sim *s, double sigma0, int64_t n, const double *p,
                                           double *density) {
    return guarded(s, args(sigma0, n, p, density), [&](const gfmd::Simulation &m) {
        if (n < 0) fail(GFMD_ERR_INVALID_ARG, "n must be >= 0, got " + std::to_string(n));
        if (n > 0) {
            need(p, "p");
            need(density, "density");
        }
        for (int64_t i = 0; i < n; ++i)
            if (!std::isfinite(p[i])) fail(GFMD_ERR_INVALID_ARG, "p[" + std::to_string(i) + "] is not finite");
        const double v = m.persson_variance();
        (void)m.persson_contact_area(sigma0);  // checks sigma0
        for (int64_t i = 0; i < n; ++i) density[i] = gfmd::persson_pressure_density(v, sigma0, p[i]);
    });
}

int32_t gfmd_persson_variance(const gfmd_sim *s, double *variance) {
    return guarded(s, args(variance), [&](const gfmd::Simulation &m) {
        need(variance, "variance");
        *variance = m.persson_variance();
    });
}

int32_t gfmd_persson_contact_area(const gfmd_sim *s, double sigma0, double *rel_area) {
    return guarded(s, args(sigma0, rel_area), [&](const gfmd::Simulation &m) {
        need(rel_area, "rel_area");
        *rel_area = m.persson_contact_area(sigma0);
    });
}

int32_t gfmd_persson_load(const gfmd_sim *s, double rel_area, double *sigma0) {
    return guarded(s, args(rel_area, sigma0), [&](const gfmd::Simulation &m) {
        need(sigma0, "sigma0");
        *sigma0 = m.persson_load(rel_area);
    });
}

int32_t gfmd_least_squares(int64_t m, int64_t n, const double *a, const double *b, double *x, double *rss) {
    if (a == nullptr || b == nullptr || x == nullptr) return GFMD_ERR_NULL;
    return status_of([&] {
        const double r = gfmd::least_squares(m, n, a, b, x);
        if (rss != nullptr) *rss = r;
    });
}

}  // extern "C"
