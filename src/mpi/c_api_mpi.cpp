// The C API of gfmd_mpi.h: distributed handles (the rest of the API is c_api.cpp, shared with the
// serial library).
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "../c_api_support.hpp"
#include "../fft_grid.hpp"
#include "../fields.hpp"
#include "../fftw_planner.hpp"
#include "../patches.hpp"
#include "../simulation.hpp"
#include "gfmd_mpi.h"
#include "mpi_state.hpp"

namespace {

using gfmd::fail;
using gfmd::capi::need;
using gfmd::capi::status_of;

constexpr const char *kNoMpi = "MPI is not initialized (or already finalized): call MPI_Init first";

void need_mpi() {
    if (!gfmd::mpi_usable()) fail(GFMD_ERR_STATE, kNoMpi);
}

// The local rows of a field, from the contiguous local array `from`, into rows ld apart.
void copy_rows(const gfmd::Simulation &m, const double *from, double *to, int64_t ld) {
    const int64_t nx = m.grid().nx(), rows = m.grid().local_points() / std::max<int64_t>(nx, 1);
    for (int64_t r = 0; r < rows; ++r) std::memcpy(to + r * ld, from + r * nx, static_cast<std::size_t>(nx) * sizeof(double));
}

// A local field getter: get(contiguous local array) then the rows copied out ld apart.
template <class Get>
int32_t local_field(const gfmd_sim *s, double *out, int64_t ld, const char *name, Get &&get) noexcept {
    if (s == nullptr || !s->sim) return GFMD_ERR_NULL;
    return status_of(
        [&] {
            const gfmd::Simulation &m = *s->sim;
            if (ld < m.grid().nx())
                fail(GFMD_ERR_INVALID_ARG, "ld = " + std::to_string(ld) + " is below nx = " + std::to_string(m.grid().nx()));
            if (m.grid().local_points() == 0) return;  // a rank without rows: nothing to write
            need(out, name);
            if (ld == m.grid().nx()) return get(m, out);
            std::vector<double> local(static_cast<std::size_t>(m.grid().local_points()));
            get(m, local.data());
            copy_rows(m, local.data(), out, ld);
        },
        [s](const char *msg) { gfmd::capi::record(s, msg); });
}

}  // namespace

extern "C" {

int32_t gfmd_mpi_local_size(MPI_Comm comm, int64_t nx, int64_t ny, int64_t *local_ny, int64_t *y0) {
    if (local_ny == nullptr || y0 == nullptr) return GFMD_ERR_NULL;
    return status_of([&] {
        need_mpi();
        gfmd::validate_grid(nx, ny, 1.0, 1.0);
        gfmd::local_slab(comm, nx, ny, *local_ny, *y0);
    }, [](const char *) {});
}

int32_t gfmd_sim_create_mpi(MPI_Comm comm, int64_t nx, int64_t ny, double lx, double ly, int32_t planner,
                            gfmd_sim **out) {
    if (out == nullptr) return GFMD_ERR_NULL;
    *out = nullptr;
    if (!gfmd::mpi_usable()) return GFMD_ERR_STATE;  // no communication possible: every rank sees the same
    std::string message;
    // Checked everywhere before anything collective: the arguments are valid and agree.
    int32_t status = status_of([&] {
        gfmd::validate_grid(nx, ny, lx, ly);
        gfmd::validate_planner(planner);
    }, [&](const char *msg) { message = msg; });
    if (!gfmd::same_everywhere(comm, gfmd::capi::args(nx, ny, lx, ly, planner))) return GFMD_ERR_INVALID_ARG;
    status = gfmd::agree_on(comm, status, message);
    if (status != GFMD_OK) return status;
    std::unique_ptr<gfmd_sim> handle;
    status = status_of([&] {
        handle = std::make_unique<gfmd_sim>();
        const gfmd::Distribution dist{comm};
        gfmd::check_slab_memory(dist, nx, ny);  // collective: every rank's slab fits, or none is made
        handle->sim = std::make_unique<gfmd::Simulation>(nx, ny, lx, ly, 0, planner, &dist);
    }, [&](const char *msg) { message = msg; });
    status = gfmd::agree_on(comm, status, message);
    if (status != GFMD_OK) return status;  // a handle made on some ranks is destroyed on them
    *out = handle.release();
    return GFMD_OK;
}

int32_t gfmd_sim_create_mpi_f(MPI_Fint comm, int64_t nx, int64_t ny, double lx, double ly, int32_t planner,
                              gfmd_sim **out) {
    return gfmd_sim_create_mpi(MPI_Comm_f2c(comm), nx, ny, lx, ly, planner, out);
}

int32_t gfmd_sim_load_mpi(MPI_Comm comm, const char *path, gfmd_sim **out, char *errbuf, int64_t errlen) {
    std::string message;
    auto report = [&](const char *msg) {
        if (errbuf != nullptr && errlen > 0) std::snprintf(errbuf, static_cast<std::size_t>(errlen), "%s", msg);
    };
    report("");
    if (out != nullptr) *out = nullptr;
    if (!gfmd::mpi_usable()) {
        report(kNoMpi);
        return GFMD_ERR_STATE;
    }
    // The same path everywhere (and out and path given everywhere), before anything collective.
    if (!gfmd::same_everywhere(comm, gfmd::capi::args(path, out))) {
        report(gfmd::capi::kOtherArguments);
        return GFMD_ERR_INVALID_ARG;
    }
    std::unique_ptr<gfmd_sim> handle;
    int32_t status = status_of([&] {
        need(out, "out");
        need(path, "path");
        handle = std::make_unique<gfmd_sim>();
        const gfmd::Distribution dist{comm};
        handle->sim = gfmd::Simulation::load(path, &dist);
    }, [&](const char *msg) { message = msg; });
    status = gfmd::agree_on(comm, status, message);
    if (status != GFMD_OK) {
        report(message.c_str());
        return status;
    }
    *out = handle.release();
    return GFMD_OK;
}

int32_t gfmd_sim_load_mpi_f(MPI_Fint comm, const char *path, gfmd_sim **out, char *errbuf, int64_t errlen) {
    return gfmd_sim_load_mpi(MPI_Comm_f2c(comm), path, out, errbuf, errlen);
}

int32_t gfmd_mpi_get_local_grid(const gfmd_sim *s, int64_t *local_ny, int64_t *y0) {
    if (s == nullptr || !s->sim) return GFMD_ERR_NULL;
    if (local_ny == nullptr || y0 == nullptr) {
        gfmd::capi::record(s, "argument 'local_ny' or 'y0' is NULL");
        return GFMD_ERR_NULL;
    }
    const gfmd::FftGrid &g = s->sim->grid();
    *local_ny = g.local_mode_rows();
    *y0 = g.first_row();
    return GFMD_OK;
}

int32_t gfmd_mpi_get_ranks(const gfmd_sim *s, int32_t *ranks) {
    if (s == nullptr || !s->sim) return GFMD_ERR_NULL;
    if (ranks == nullptr) {
        gfmd::capi::record(s, "argument 'ranks' is NULL");
        return GFMD_ERR_NULL;
    }
    *ranks = s->sim->grid().ranks();
    return GFMD_OK;
}

int32_t gfmd_mpi_set_local_heights(gfmd_sim *s, const double *h, int64_t ld) {
    // Not fingerprinted: h and ld may differ between ranks (a rank without rows may pass NULL).
    return gfmd::capi::guarded(s, gfmd::capi::args(), [&](gfmd::Simulation &m) {
        const int64_t nx = m.grid().nx(), points = m.grid().local_points();
        std::vector<double> local;
        m.grid().on_all_ranks([&] {
            if (ld < nx) fail(GFMD_ERR_INVALID_ARG, "ld = " + std::to_string(ld) + " is below nx = " + std::to_string(nx));
            if (points > 0) need(h, "h");
            local.resize(static_cast<std::size_t>(points));
            for (int64_t r = 0; r < points / std::max<int64_t>(nx, 1); ++r)
                std::memcpy(local.data() + r * nx, h + r * ld, static_cast<std::size_t>(nx) * sizeof(double));
        });
        m.set_heights(local.data());
    });
}

int32_t gfmd_mpi_get_local_heights(const gfmd_sim *s, double *h, int64_t ld) {
    return local_field(s, h, ld, "h", [](const gfmd::Simulation &m, double *o) { m.heights(o); });
}
int32_t gfmd_mpi_get_local_surface(const gfmd_sim *s, double *z, int64_t ld) {
    return local_field(s, z, ld, "z", [](const gfmd::Simulation &m, double *o) { m.surface(o); });
}
int32_t gfmd_mpi_get_local_gap(const gfmd_sim *s, double *gap, int64_t ld) {
    return local_field(s, gap, ld, "gap", [](const gfmd::Simulation &m, double *o) { m.gap(o); });
}
int32_t gfmd_mpi_get_local_pressure(const gfmd_sim *s, double *p, int64_t ld) {
    return local_field(s, p, ld, "p", [](const gfmd::Simulation &m, double *o) { m.pressure(o); });
}

int32_t gfmd_mpi_get_local_contact_patches(const gfmd_sim *s, int32_t connectivity, int64_t *labels, int64_t ld,
                                           int64_t *npatches) {
    // Collective; labels and ld are this rank's (not fingerprinted: NULL on a rank without rows)
    return gfmd::capi::guarded(s, gfmd::capi::args(connectivity, npatches), [&](const gfmd::Simulation &m) {
        const gfmd::FftGrid &g = m.grid();
        const int64_t nx = g.nx(), rows = g.local_mode_rows(), y0 = g.first_row();
        g.on_all_ranks([&] {
            need(npatches, "npatches");
            gfmd::check_connectivity(connectivity);
            if (ld < nx) fail(GFMD_ERR_INVALID_ARG, "ld = " + std::to_string(ld) + " is below nx = " + std::to_string(nx));
            if (rows > 0) need(labels, "labels");
        });
        const gfmd::WholeContact w = gfmd::whole_contact(m, false);
        std::vector<int64_t> all(static_cast<std::size_t>(g.real_size()));
        const gfmd::Patches p = gfmd::label_patches(nx, g.ny(), w.in.data(), connectivity, true, all.data());
        for (int64_t r = 0; r < rows; ++r)
            std::copy(all.data() + (y0 + r) * nx, all.data() + (y0 + r + 1) * nx, labels + r * ld);
        *npatches = p.count;
    });
}

}  // extern "C"
