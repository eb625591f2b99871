/**
 * @file gfmd_mpi.h
 * @brief libgfmd_mpi: the gfmd C API on a grid distributed over the ranks of an MPI communicator.
 *
 * libgfmd_mpi exports every function of gfmd.h (link it instead of libgfmd, not beside it) plus
 * the ones below.  A handle made by gfmd_sim_create_mpi() is @e distributed: its grid is split
 * into slabs of whole rows, one per rank, with FFTW's MPI transforms between them.
 *
 * @par Collective calls
 * Every gfmd_* call on a distributed handle is collective: all ranks of the communicator make it,
 * in the same order, with the same arguments (values, string contents, and which pointers are
 * NULL - checked: a difference fails on every rank with GFMD_ERR_INVALID_ARG), and all return the
 * same status and message and the same values.  A failed call changes nothing on any rank.  The
 * exceptions are gfmd_mpi_get_local_grid() and the gfmd_mpi_get_local_* field getters, which are
 * local, and gfmd_last_error(), which reads this rank's copy of the (agreed) message.
 * gfmd_sim_destroy() is collective for a distributed handle: destroy it on every rank, before
 * MPI_Finalize.  The library never initializes or finalizes MPI: the caller does, with
 * MPI_THREAD_FUNNELED or more if the handle uses more than one thread per rank.
 *
 * @par Local slabs
 * Rank r owns the global rows y0 .. y0 + local_ny - 1 (gfmd_mpi_get_local_grid()); local_ny may
 * be 0 on some ranks of a small grid.  A local field is local_ny rows of nx values, x fastest,
 * consecutive rows ld >= nx values apart: C `field[local_ny][ld]`, Fortran `field(ld, local_ny)`.
 * The whole-grid field calls of gfmd.h (gfmd_set_heights, gfmd_get_heights/gap/surface/pressure)
 * refuse a handle spread over more than one rank (GFMD_ERR_STATE).
 *
 * @par Checkpoints
 * gfmd_sim_save() on a distributed handle writes one file collectively (MPI-IO; every rank its
 * own rows, the first rank the header and the table of row hashes): the same bytes as a serial
 * handle in the same state would write.  gfmd_sim_load_mpi() reads a file of any origin on any
 * number of ranks; gfmd_sim_load() of either library reads it into a serial handle.
 *
 * @par Results
 * With GFMD_PLANNER_ESTIMATE (chosen here, at creation), the same binary and FFTW, a run gives the
 * same bits on any number of ranks and threads per rank: the transforms are FFTW-MPI's transposed
 * layout, whose bits do not depend on the ranks, planned on one thread per rank (FFTW's threaded
 * MPI plans change the last bits; the library's own loops still use the handle's threads), and
 * every global sum is formed per global row and added exactly.  MEASURE and PATIENT plans use the
 * threads for the transforms too and promise no bits (FFTW times its candidates).  They are not the serial library's bits (another FFT algorithm): results agree with
 * libgfmd to rounding (docs/mpi.md gives the measured differences).
 */
#ifndef GFMD_MPI_H
#define GFMD_MPI_H

#include <mpi.h>

#include "gfmd.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * The slab a distributed grid of nx x ny points gives this rank: rows [*y0, *y0 + *local_ny).
 * Local (no communication); the same answer gfmd_mpi_get_local_grid() gives after creation.
 * @return GFMD_OK, GFMD_ERR_NULL, GFMD_ERR_INVALID_ARG (sizes), GFMD_ERR_STATE (MPI not initialized).
 */
GFMD_API int32_t gfmd_mpi_local_size(MPI_Comm comm, int64_t nx, int64_t ny, int64_t *local_ny, int64_t *y0);

/**
 * Create a distributed handle on @p comm (duplicated: the handle's messages never mix with the
 * caller's).  Collective.  The body and parameters are gfmd_sim_create_ex()'s defaults; threads per
 * rank: the default (OMP_NUM_THREADS), gfmd_set_threads() changes it.  @p planner is fixed for
 * the plans made here; GFMD_PLANNER_ESTIMATE gives results independent of the ranks.
 * @return GFMD_OK; GFMD_ERR_NULL; GFMD_ERR_INVALID_ARG (sizes, lengths, arguments that differ
 * between ranks); GFMD_ERR_BAD_ENUM (planner); GFMD_ERR_STATE (MPI not initialized);
 * GFMD_ERR_NOMEM (a rank's slab does not fit); GFMD_ERR_MPI.  On failure *out is NULL on every rank.
 */
GFMD_API int32_t gfmd_sim_create_mpi(MPI_Comm comm, int64_t nx, int64_t ny, double lx, double ly, int32_t planner,
                                     gfmd_sim **out);

/** gfmd_sim_create_mpi() with a Fortran communicator handle (MPI_Comm_f2c), for the Fortran module. */
GFMD_API int32_t gfmd_sim_create_mpi_f(MPI_Fint comm, int64_t nx, int64_t ny, double lx, double ly,
                                       int32_t planner, gfmd_sim **out);

/**
 * Load a checkpoint (gfmd_sim_save() of a serial or distributed handle, any number of ranks, any
 * format version this library reads) into a distributed handle on @p comm.  Collective: every
 * rank reads its own rows and checks them against the file's row hashes (format 5; older formats
 * are hashed by the first rank).  Statuses as gfmd_sim_load(), the same on every rank; the
 * message of a failure goes to @p errbuf on every rank.
 */
GFMD_API int32_t gfmd_sim_load_mpi(MPI_Comm comm, const char *path, gfmd_sim **out, char *errbuf, int64_t errlen);

/** gfmd_sim_load_mpi() with a Fortran communicator handle. */
GFMD_API int32_t gfmd_sim_load_mpi_f(MPI_Fint comm, const char *path, gfmd_sim **out, char *errbuf, int64_t errlen);

/** This rank's slab: rows [*y0, *y0 + *local_ny) of the global grid.  Local.  A serial handle
 *  owns all rows (local_ny = ny, y0 = 0). */
GFMD_API int32_t gfmd_mpi_get_local_grid(const gfmd_sim *s, int64_t *local_ny, int64_t *y0);

/** Number of ranks of the handle's communicator (1 for a serial handle).  Local. */
GFMD_API int32_t gfmd_mpi_get_ranks(const gfmd_sim *s, int32_t *ranks);

/**
 * Set this rank's rows of the substrate (see gfmd_set_heights()).  Collective: a bad value on any
 * rank (NaN, infinite, |h| > 1e100, ld < nx, h NULL on a rank with rows) fails on every rank
 * and changes nothing.  @p h may be NULL on a rank without rows.
 */
GFMD_API int32_t gfmd_mpi_set_local_heights(gfmd_sim *s, const double *h, int64_t ld);

/** This rank's rows of the substrate / surface z / gap z - h / contact pressure (see
 *  gfmd_get_pressure()), into local_ny rows @p ld apart.  Local. */
GFMD_API int32_t gfmd_mpi_get_local_heights(const gfmd_sim *s, double *h, int64_t ld);
GFMD_API int32_t gfmd_mpi_get_local_surface(const gfmd_sim *s, double *z, int64_t ld);
GFMD_API int32_t gfmd_mpi_get_local_gap(const gfmd_sim *s, double *gap, int64_t ld);
GFMD_API int32_t gfmd_mpi_get_local_pressure(const gfmd_sim *s, double *p, int64_t ld);

/**
 * This rank's rows of the contact patches' labels (see gfmd_get_contact_patches(): the labels of
 * the whole grid, the same at any number of ranks), into local_ny rows @p ld apart, and their
 * number.  Collective: the contact set is gathered on every rank (1 B and 8 B of labels per point
 * of the whole grid, checked on every rank first: GFMD_ERR_NOMEM everywhere if it does not fit
 * on one).  gfmd_get_contact_patches() with labels = NULL, gfmd_get_patch_property() and
 * gfmd_get_pressure_histogram() work on a distributed handle the same way.  @p labels may be NULL
 * on a rank without rows.
 */
GFMD_API int32_t gfmd_mpi_get_local_contact_patches(const gfmd_sim *s, int32_t connectivity, int64_t *labels,
                                                    int64_t ld, int64_t *npatches);

#ifdef __cplusplus
}
#endif

#endif
