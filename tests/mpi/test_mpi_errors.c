/* libgfmd_mpi's collective error model, under mpiexec: a bad value on one rank gives the same
 * status and message on every rank and changes nothing; arguments that differ between ranks are
 * refused everywhere; whole-grid calls refuse a handle on more than one rank; bad multilevel
 * starts are refused everywhere; slabs that do not fit give GFMD_ERR_NOMEM everywhere; the local-slab
 * calls agree with gfmd_mpi_local_size(); a clone continues with the same bits. */
#include <gfmd_mpi.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpi_check.h"

static int size = 1;
enum { kNx = 24, kNy = 20 };

/* Every rank got `status` == expected, and the same message on every rank (compared on rank 0). */
static void expect_everywhere(const gfmd_sim *s, int32_t status, int32_t expected, const char *what) {
    CHECK(status == expected, "%s: status %d, expected %d", what, status, expected);
    int32_t lo = status, hi = status;
    MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_INT32_T, MPI_MIN, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_INT32_T, MPI_MAX, MPI_COMM_WORLD);
    CHECK(lo == hi, "%s: statuses differ between ranks (%d .. %d)", what, lo, hi);
    if (s == NULL || expected == GFMD_OK) return;
    char mine[512], first[512];
    OK(gfmd_last_error(s, mine, sizeof mine));
    memcpy(first, mine, sizeof mine);
    MPI_Bcast(first, sizeof first, MPI_CHAR, 0, MPI_COMM_WORLD);
    CHECK(strcmp(mine, first) == 0, "%s: message '%s' differs from rank 0's '%s'", what, mine, first);
    CHECK(strlen(mine) > 0, "%s: empty message", what);
}

/* A digest of this rank's state: local heights and surface, and the global observables. */
static void state(const gfmd_sim *s, int64_t rows, double *local_h, double *local_z, double *obs) {
    OK(gfmd_mpi_get_local_heights(s, local_h, kNx));
    OK(gfmd_mpi_get_local_surface(s, local_z, kNx));
    OK(gfmd_get_contact_area(s, &obs[0]));
    OK(gfmd_get_mean_pressure(s, &obs[1]));
    OK(gfmd_get_energies(s, &obs[2], &obs[3]));
    (void)rows;
}

static int same_state(const gfmd_sim *s, int64_t rows, const double *h0, const double *z0, const double *obs0) {
    double *h = malloc(sizeof(double) * (size_t)(rows * kNx + 1)), *z = malloc(sizeof(double) * (size_t)(rows * kNx + 1));
    double obs[4];
    state(s, rows, h, z, obs);
    const int same = memcmp(h, h0, sizeof(double) * (size_t)(rows * kNx)) == 0 &&
                     memcmp(z, z0, sizeof(double) * (size_t)(rows * kNx)) == 0 && memcmp(obs, obs0, sizeof obs) == 0;
    free(h);
    free(z);
    int all = same;
    MPI_Allreduce(MPI_IN_PLACE, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return all;
}

int main(int argc, char **argv) {
    /* Before MPI_Init: nothing can be agreed, so the calls refuse at once (and the same on every rank). */
    gfmd_sim *early = (gfmd_sim *)&early;
    const int32_t st_create = gfmd_sim_create_mpi(MPI_COMM_WORLD, kNx, kNy, kNx, kNy, GFMD_PLANNER_ESTIMATE, &early);
    const int early_null = early == NULL;
    const int32_t st_load = gfmd_sim_load_mpi(MPI_COMM_WORLD, "any.gfmd", &early, NULL, 0);
    MPI_Init(&argc, &argv);
    CHECK(st_create == GFMD_ERR_STATE && early_null, "create before MPI_Init: status %d", st_create);
    CHECK(st_load == GFMD_ERR_STATE && early == NULL, "load before MPI_Init: status %d", st_load);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    gfmd_sim *s = NULL;

    /* Creation: arguments that differ between ranks fail everywhere, with no handle anywhere. */
    int32_t st = gfmd_sim_create_mpi(MPI_COMM_WORLD, kNx + (rank == size - 1 && size > 1), kNy, kNx, kNy,
                                     GFMD_PLANNER_ESTIMATE, &s);
    expect_everywhere(NULL, st, size > 1 ? GFMD_ERR_INVALID_ARG : GFMD_OK, "create with other nx on the last rank");
    gfmd_sim_destroy(&s);
    st = gfmd_sim_create_mpi(MPI_COMM_WORLD, 0, kNy, kNx, kNy, GFMD_PLANNER_ESTIMATE, &s);
    expect_everywhere(NULL, st, GFMD_ERR_INVALID_ARG, "create with nx = 0");
    CHECK(s == NULL, "a failed create left a handle");
    st = gfmd_sim_create_mpi(MPI_COMM_WORLD, kNx, kNy, kNx, kNy, 99, &s);
    expect_everywhere(NULL, st, GFMD_ERR_BAD_ENUM, "create with an unknown planner");
    /* A grid whose slabs do not fit: 2^17 x 2^17 points, at least 2^34 / 4 points on a rank of
     * four, about 350 GB at the handle's 82 B/pt on any machine this runs on; refused everywhere
     * before anything is allocated. */
    st = gfmd_sim_create_mpi(MPI_COMM_WORLD, 1 << 17, 1 << 17, 1 << 17, 1 << 17, GFMD_PLANNER_ESTIMATE, &s);
    expect_everywhere(NULL, st, GFMD_ERR_NOMEM, "create with slabs larger than the memory");
    CHECK(s == NULL, "a create without memory left a handle");

    OK(gfmd_sim_create_mpi(MPI_COMM_WORLD, kNx, kNy, kNx, kNy, GFMD_PLANNER_ESTIMATE, &s));
    if (s == NULL) {
        MPI_Finalize();
        return 1;
    }
    int32_t ranks = 0;
    OK(gfmd_mpi_get_ranks(s, &ranks));
    CHECK(ranks == size, "gfmd_mpi_get_ranks: %d, expected %d", ranks, size);
    int64_t rows = -1, y0 = -1, rows2 = -2, y02 = -2;
    OK(gfmd_mpi_get_local_grid(s, &rows, &y0));
    OK(gfmd_mpi_local_size(MPI_COMM_WORLD, kNx, kNy, &rows2, &y02));
    CHECK(rows == rows2 && (rows == 0 || y0 == y02), "local grid %lld+%lld vs local size %lld+%lld", (long long)y0,
          (long long)rows, (long long)y02, (long long)rows2);
    int64_t total = rows;
    MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
    CHECK(total == kNy, "the slabs hold %lld rows, not %d", (long long)total, kNy);

    OK(gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 4.0));
    OK(gfmd_generate_selfaffine(s, 0.8, 12.0, 4.0, 0.1, 3, GFMD_DIST_UNIFORM));
    OK(gfmd_set_pressure(s, 0.02));
    OK(gfmd_step(s, 30));
    double *h0 = malloc(sizeof(double) * (size_t)(rows * kNx + 1)), *z0 = malloc(sizeof(double) * (size_t)(rows * kNx + 1));
    double obs0[4];
    state(s, rows, h0, z0, obs0);

    /* Local data bad on one rank only. */
    double *bad = malloc(sizeof(double) * (size_t)(rows * 2 * kNx + 1));
    for (int64_t i = 0; i < rows * 2 * kNx; ++i) bad[i] = -1.0;
    const int victim = size - 1;
    int64_t victim_rows = rows;
    MPI_Bcast(&victim_rows, 1, MPI_INT64_T, victim, MPI_COMM_WORLD);
    if (rank == victim && rows > 0) bad[kNx / 2] = NAN;
    st = gfmd_mpi_set_local_heights(s, bad, kNx);
    expect_everywhere(s, st, victim_rows > 0 ? GFMD_ERR_INVALID_ARG : GFMD_OK, "NaN height on the last rank");
    CHECK(same_state(s, rows, h0, z0, obs0), "a failed set_local_heights changed the state");
    if (rank == victim && rows > 0) bad[kNx / 2] = -1.0;
    st = gfmd_mpi_set_local_heights(s, bad, rank == 0 ? kNx - 1 : kNx);
    expect_everywhere(s, st, GFMD_ERR_INVALID_ARG, "ld < nx on rank 0");
    CHECK(same_state(s, rows, h0, z0, obs0), "a failed set_local_heights (ld) changed the state");
    st = gfmd_mpi_set_local_heights(s, (rank == 0 && rows > 0) ? NULL : bad, kNx);
    expect_everywhere(s, st, GFMD_ERR_NULL, "NULL heights on rank 0");
    CHECK(same_state(s, rows, h0, z0, obs0), "a failed set_local_heights (NULL) changed the state");

    /* Arguments that differ between ranks, or are bad everywhere. */
    st = gfmd_set_pressure(s, rank == victim ? 0.03 : 0.02);
    expect_everywhere(s, st, size > 1 ? GFMD_ERR_INVALID_ARG : GFMD_OK, "another sigma0 on the last rank");
    if (size == 1) OK(gfmd_set_pressure(s, 0.02));
    CHECK(same_state(s, rows, h0, z0, obs0), "set_pressure with other values changed the state");
    st = gfmd_set_pressure(s, -1.0);
    expect_everywhere(s, st, GFMD_ERR_INVALID_ARG, "sigma0 < 0 everywhere");
    st = gfmd_set_adhesion(s, NAN, 1.0);
    expect_everywhere(s, st, GFMD_ERR_INVALID_ARG, "gamma0 NaN everywhere");
    double e = 0.0, a = 0.0;
    st = gfmd_get_energies(s, &e, rank == victim ? NULL : &a);
    expect_everywhere(s, st, size > 1 ? GFMD_ERR_INVALID_ARG : GFMD_ERR_NULL, "NULL output on the last rank");
    CHECK(same_state(s, rows, h0, z0, obs0), "failed calls changed the state");

    /* Whole-grid calls: refused on several ranks, fine on one. */
    double *whole = malloc(sizeof(double) * kNx * kNy);
    const int32_t expect_whole = size > 1 ? GFMD_ERR_STATE : GFMD_OK;
    expect_everywhere(s, gfmd_get_heights(s, whole), expect_whole, "gfmd_get_heights");
    expect_everywhere(s, gfmd_get_surface(s, whole), expect_whole, "gfmd_get_surface");
    expect_everywhere(s, gfmd_get_gap(s, whole), expect_whole, "gfmd_get_gap");
    expect_everywhere(s, gfmd_get_pressure(s, whole), expect_whole, "gfmd_get_pressure");
    if (size > 1) expect_everywhere(s, gfmd_set_heights(s, whole), GFMD_ERR_STATE, "gfmd_set_heights");
    /* the contact's labels of the whole grid too (the count, the patches' properties and the
     * pressure histogram work on any number of ranks: test_mpi_patches) */
    int64_t *labels = malloc(sizeof(int64_t) * kNx * kNy), npatches = 0;
    expect_everywhere(s, gfmd_get_contact_patches(s, 4, labels, &npatches), expect_whole, "gfmd_get_contact_patches");
    expect_everywhere(s, gfmd_get_contact_patches(s, 4, NULL, &npatches), GFMD_OK, "gfmd_get_contact_patches, count");
    expect_everywhere(s, gfmd_mpi_get_local_contact_patches(s, 4, labels, rank == 0 ? kNx - 1 : kNx, &npatches),
                      GFMD_ERR_INVALID_ARG, "local patch labels with ld < nx on rank 0");
    expect_everywhere(s, gfmd_mpi_get_local_contact_patches(s, rank == victim ? 5 : 4, labels, kNx, &npatches),
                      GFMD_ERR_INVALID_ARG, "connectivity 5 on the last rank");
    free(labels);
    /* plasticity: refused on several ranks, taken on one (and switched off again) */
    expect_everywhere(s, gfmd_set_hardness(s, 0.5), expect_whole, "gfmd_set_hardness");
    if (size == 1) OK(gfmd_set_hardness(s, INFINITY));
    /* free boundaries: refused on a distributed handle on any number of ranks (the handle stays
     * periodic); an unknown boundary is refused as an unknown value */
    expect_everywhere(s, gfmd_set_boundary(s, GFMD_BOUNDARY_FREE), GFMD_ERR_STATE, "gfmd_set_boundary(FREE)");
    expect_everywhere(s, gfmd_set_boundary(s, 9), GFMD_ERR_BAD_ENUM, "gfmd_set_boundary(9)");
    int32_t boundary = -1;
    OK(gfmd_get_boundary(s, &boundary));
    CHECK(boundary == GFMD_BOUNDARY_PERIODIC, "the refused boundary was set");
    expect_everywhere(s, gfmd_set_boundary(s, GFMD_BOUNDARY_PERIODIC), GFMD_OK, "gfmd_set_boundary(PERIODIC)");
    int64_t steps = 0, coarse = 0;
    expect_everywhere(s, gfmd_relax_multilevel(s, 1e-6, 100, 0, &steps, &coarse), GFMD_ERR_INVALID_ARG,
                      "multilevel start with 0 levels");
    expect_everywhere(s, gfmd_relax_multilevel(s, 1e-6, 100, 4, &steps, &coarse), GFMD_ERR_INVALID_ARG,
                      "multilevel start deeper than the grid allows");
    CHECK(same_state(s, rows, h0, z0, obs0), "refused calls changed the state");
    free(whole);

    /* A clone continues with the same bits as the original. */
    gfmd_sim *c = NULL;
    OK(gfmd_sim_clone(s, &c));
    OK(gfmd_step(s, 20));
    OK(gfmd_step(c, 20));
    double ao = 0.0, ac = 0.0, eo = 0.0, ec = 0.0;
    OK(gfmd_get_contact_area(s, &ao));
    OK(gfmd_get_contact_area(c, &ac));
    OK(gfmd_get_energies(s, &eo, &a));
    OK(gfmd_get_energies(c, &ec, &a));
    CHECK(ao == ac && eo == ec, "the clone diverged: A %.17g vs %.17g, U_el %.17g vs %.17g", ao, ac, eo, ec);
    gfmd_sim_destroy(&c);

    /* A serial handle of libgfmd_mpi owns all rows. */
    gfmd_sim *serial = NULL;
    OK(gfmd_sim_create_ex(kNx, kNy, kNx, kNy, 1, GFMD_PLANNER_ESTIMATE, &serial));
    OK(gfmd_mpi_get_local_grid(serial, &rows2, &y02));
    CHECK(rows2 == kNy && y02 == 0, "a serial handle's slab is %lld+%lld", (long long)y02, (long long)rows2);
    gfmd_sim_destroy(&serial);

    free(h0);
    free(z0);
    free(bad);
    gfmd_sim_destroy(&s);
    int all = 0;
    MPI_Allreduce(&failures, &all, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    if (rank == 0) printf("test_mpi_errors on %d ranks: %s (%d failures)\n", size, all ? "FAILED" : "passed", all);
    MPI_Finalize();
    return all ? 1 : 0;
}
