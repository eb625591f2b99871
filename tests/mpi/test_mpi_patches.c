/* Contact patches and the pressure histogram of a distributed handle, under mpiexec with P
 * processes: the same rough contact relaxed on communicators of 1, 2, ..., P ranks (subsets of
 * MPI_COMM_WORLD) must give the same patch count, the same labels (this rank's rows from
 * gfmd_mpi_get_local_contact_patches, gathered), the same value of every patch property and the
 * same histogram, bit for bit (the relaxation is bit-identical at any rank count: test_mpi_identity;
 * the labelling is a function of the contact set).  On each rank count the labels are those of the
 * gathered gap's zeros (gfmd_label_patches, the serial labelling), the patch areas sum to A/A0
 * and the histogram to A/A0.  A grid where a rank owns no rows (ny = 6 on 4 ranks) is included.
 * Then the gather's memory: with the last rank's address space capped just above what it uses,
 * the analysis of a 1024^2 grid fails with GFMD_ERR_NOMEM and the same message on every rank (no
 * rank left waiting in the gather), and works again once the cap is lifted. */
#include <gfmd_mpi.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "mpi_check.h"

enum { kProps = 7, kBins = 16, kMaxPatches = 4096 };

typedef struct {
    int64_t nx, ny;
} Grid;

typedef struct {
    int64_t count;
    int64_t *labels;              /* nx*ny, on the communicator's rank 0 */
    double *gap;                  /* nx*ny, idem */
    double props[kProps][kMaxPatches];
    double fraction[kBins], mean[kBins], range[2];
    double area;
} Result;

/* rows of nx values of this rank, gathered on the communicator's rank 0 in row order */
static void gather_rows(MPI_Comm comm, const void *local, int64_t rows, int64_t nx, MPI_Datatype type, size_t size,
                        void *all) {
    int n = 0, me = 0;
    MPI_Comm_size(comm, &n);
    MPI_Comm_rank(comm, &me);
    int mine = (int)(rows * nx);
    int *counts = malloc(sizeof(int) * (size_t)n), *at = malloc(sizeof(int) * (size_t)n);
    MPI_Gather(&mine, 1, MPI_INT, counts, 1, MPI_INT, 0, comm);
    if (me == 0)
        for (int r = 0, off = 0; r < n; off += counts[r], ++r) at[r] = off;
    (void)size;
    MPI_Gatherv(local, mine, type, all, counts, at, type, 0, comm);
    free(counts);
    free(at);
}

static void run(MPI_Comm comm, Grid g, Result *out) {
    gfmd_sim *s = NULL;
    OK(gfmd_sim_create_mpi(comm, g.nx, g.ny, (double)g.nx, (double)g.ny, GFMD_PLANNER_ESTIMATE, &s));
    OK(gfmd_generate_selfaffine(s, 0.8, 16.0, 3.0, 1.0, 17, GFMD_DIST_UNIFORM));
    OK(gfmd_set_pressure(s, 0.04));
    OK(gfmd_relax(s, 1e-10, 100000, NULL));
    int64_t rows = 0, y0 = 0;
    OK(gfmd_mpi_get_local_grid(s, &rows, &y0));
    int64_t *lab = malloc(sizeof(int64_t) * (size_t)(rows * g.nx + 1));
    double *gap = malloc(sizeof(double) * (size_t)(rows * g.nx + 1));
    int64_t count = 0, n = 0;
    OK(gfmd_mpi_get_local_contact_patches(s, 8, lab, g.nx, &count));
    OK(gfmd_get_contact_patches(s, 8, NULL, &n));
    CHECK(n == count, "the count of gfmd_get_contact_patches differs: %lld vs %lld", (long long)n, (long long)count);
    CHECK(count > 0 && count <= kMaxPatches, "%lld patches", (long long)count);
    OK(gfmd_mpi_get_local_gap(s, gap, g.nx));
    gather_rows(comm, lab, rows, g.nx, MPI_INT64_T, sizeof(int64_t), out->labels);
    gather_rows(comm, gap, rows, g.nx, MPI_DOUBLE, sizeof(double), out->gap);
    out->count = count;
    for (int k = 0; k < kProps; ++k) OK(gfmd_get_patch_property(s, 8, k, kMaxPatches, out->props[k], &n));
    out->range[0] = out->range[1] = 0.0;
    OK(gfmd_get_pressure_histogram(s, kBins, out->range, out->fraction, out->mean));
    OK(gfmd_get_contact_area(s, &out->area));
    free(lab);
    free(gap);
    gfmd_sim_destroy(&s);
}

static void gather_beyond_memory(int size) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    (void)size;
    if (rank == 0) printf("memory cap: skipped (the sanitizer's shadow memory needs the address space)\n");
    return;
#else
    const char *preload = getenv("LD_PRELOAD");
    if (preload && strstr(preload, "vgpreload")) return; /* valgrind: no address-space cap */
    gfmd_sim *s = NULL;
    OK(gfmd_sim_create_mpi(MPI_COMM_WORLD, 1024, 1024, 1024.0, 1024.0, GFMD_PLANNER_ESTIMATE, &s));
    OK(gfmd_set_pressure(s, 0.01));
    int64_t n = 0;
    double v = 0.0;
    OK(gfmd_get_patch_property(s, 4, GFMD_PATCH_LOAD, 1, &v, &n)); /* the flat body: one patch */
    struct rlimit old;
    getrlimit(RLIMIT_AS, &old);
    const int victim = size - 1;
    if (rank == victim) {
        struct rlimit cap = old;
        cap.rlim_cur = (rlim_t)(vm_size() + 4 * 1024 * 1024); /* the gather needs 9 MB, the labels 8 */
        CHECK(setrlimit(RLIMIT_AS, &cap) == 0, "setrlimit");
    }
    const int32_t st = gfmd_get_patch_property(s, 4, GFMD_PATCH_LOAD, 1, &v, &n);
    char msg[256] = "", first[256] = "";
    gfmd_last_error(s, msg, sizeof msg);
    if (rank == victim) setrlimit(RLIMIT_AS, &old);
    strcpy(first, msg);
    MPI_Bcast(first, sizeof first, MPI_CHAR, 0, MPI_COMM_WORLD);
    CHECK(st == GFMD_ERR_NOMEM, "capped on rank %d: status %d (%s)", victim, st, msg);
    CHECK(strcmp(msg, first) == 0, "another message than rank 0's: %s", msg);
    OK(gfmd_get_patch_property(s, 4, GFMD_PATCH_LOAD, 1, &v, &n));
    if (rank == 0) printf("memory cap on rank %d: GFMD_ERR_NOMEM on every rank: %s\n", victim, first);
    gfmd_sim_destroy(&s);
#endif
}

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    MPI_Comm *comms = malloc(sizeof(MPI_Comm) * (size_t)size);
    for (int k = 0; k < size; ++k) MPI_Comm_split(MPI_COMM_WORLD, rank <= k ? 0 : MPI_UNDEFINED, rank, &comms[k]);
    const Grid grids[] = {{48, 40}, {96, 6}};
    for (int gi = 0; gi < 2; ++gi) {
        const Grid g = grids[gi];
        const size_t n = (size_t)(g.nx * g.ny);
        Result *res = calloc((size_t)size, sizeof(Result));
        for (int k = 0; k < size; ++k) {
            res[k].labels = calloc(n, sizeof(int64_t));
            res[k].gap = calloc(n, sizeof(double));
            if (comms[k] != MPI_COMM_NULL) run(comms[k], g, &res[k]);
        }
        if (rank == 0) {
            /* on one rank: the serial labelling of the gap's zeros, areas and histogram summing to A/A0 */
            int32_t *mask = malloc(sizeof(int32_t) * n);
            int64_t *labels = malloc(sizeof(int64_t) * n), m = 0;
            for (size_t i = 0; i < n; ++i) mask[i] = res[0].gap[i] <= 0.0;
            OK(gfmd_label_patches(g.nx, g.ny, mask, 8, 1, labels, &m));
            CHECK(m == res[0].count && memcmp(labels, res[0].labels, n * sizeof(int64_t)) == 0,
                  "%lld x %lld: the labels are not those of the gap's zeros", (long long)g.nx, (long long)g.ny);
            double area = 0.0, total = 0.0;
            for (int64_t p = 0; p < res[0].count; ++p) area += res[0].props[GFMD_PATCH_AREA][p];
            for (int b = 0; b < kBins; ++b) total += res[0].fraction[b];
            CHECK(area == res[0].area * (double)n, "patch areas %.17g, A %.17g", area, res[0].area * (double)n);
            CHECK(fabs(total - res[0].area) <= 1e-14, "histogram total %.17g, A/A0 %.17g", total, res[0].area);
            for (int k = 1; k < size; ++k) {
                const Result *a = &res[0], *b = &res[k];
                int same = a->count == b->count && memcmp(a->labels, b->labels, n * sizeof(int64_t)) == 0 &&
                           memcmp(a->fraction, b->fraction, sizeof a->fraction) == 0 &&
                           memcmp(a->mean, b->mean, sizeof a->mean) == 0 && memcmp(a->range, b->range, sizeof a->range) == 0;
                for (int q = 0; q < kProps && same; ++q)
                    same = memcmp(a->props[q], b->props[q], sizeof(double) * (size_t)a->count) == 0;
                CHECK(same, "%lld x %lld: patches on %d ranks differ from 1 rank", (long long)g.nx, (long long)g.ny, k + 1);
            }
            printf("%lld x %lld: %lld patches, A/A0 %.4f; the same on 1..%d ranks\n", (long long)g.nx, (long long)g.ny,
                   (long long)res[0].count, res[0].area, size);
            free(mask);
            free(labels);
        }
        for (int k = 0; k < size; ++k) {
            free(res[k].labels);
            free(res[k].gap);
        }
        free(res);
    }
    for (int k = 0; k < size; ++k)
        if (comms[k] != MPI_COMM_NULL) MPI_Comm_free(&comms[k]);
    gather_beyond_memory(size);
    free(comms);
    int total = 0;
    MPI_Allreduce(&failures, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    if (rank == 0) printf("test_mpi_patches on %d ranks: %s\n", size, total ? "FAILED" : "passed");
    MPI_Finalize();
    return total ? 1 : 0;
}
