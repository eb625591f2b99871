// The distributed grid's own state (libgfmd_mpi only: the serial library never includes mpi.h).
#ifndef GFMD_SRC_MPI_MPI_STATE_HPP
#define GFMD_SRC_MPI_MPI_STATE_HPP

#include <fftw3-mpi.h>
#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "../buffer.hpp"

namespace gfmd {

// What a grid is distributed over: the caller's communicator (the grid duplicates it).
struct Distribution {
    MPI_Comm comm;
};

// Throws GFMD_ERR_MPI with the MPI library's message if rc is not MPI_SUCCESS.
void check_mpi(int rc, const char *what);

// The status and message of the lowest rank of comm whose status is not 0 (on every rank), or 0.
// Collective; never throws.
int32_t agree_on(MPI_Comm comm, int32_t status, std::string &message) noexcept;

// This rank's slab of an nx x ny grid on comm: rows [y0, y0 + local_ny) (local_ny may be 0).
void local_slab(MPI_Comm comm, int64_t nx, int64_t ny, int64_t &local_ny, int64_t &y0);
// GFMD_ERR_NOMEM on every rank if any rank's slab of a handle does not fit.  Collective.
void check_slab_memory(const Distribution &dist, int64_t nx, int64_t ny);

// True if every rank of comm passed the same fingerprint.  Collective.
bool same_everywhere(MPI_Comm comm, uint64_t fingerprint) noexcept;
// True between MPI_Init and MPI_Finalize.
bool mpi_usable() noexcept;

struct MpiState {
    MpiState() = default;
    MpiState(const MpiState &) = delete;
    MpiState &operator=(const MpiState &) = delete;
    ~MpiState();  // collective: frees the plans and the duplicated communicator
    void destroy_plans();

    Distribution dist{MPI_COMM_NULL};  // the grid's own communicator (dist.comm, duplicated)
    // FFTW-MPI plans in the transposed layout (kx columns of ny modes per rank), and the exact
    // transposes between it and the library's layout (ky rows of nxh modes, the real rows' slab).
    fftw_plan r2c = nullptr, c2r = nullptr, to_rows = nullptr, to_columns = nullptr;
    RealBuffer padded;      // the real slab with rows padded to 2 (nx/2 + 1), as FFTW-MPI wants it
    ComplexBuffer columns;  // the spectrum in the transposed layout
    std::vector<int> rows_of, first_row_of;  // every rank's slab (for the gathers)
};

}  // namespace gfmd

#endif
