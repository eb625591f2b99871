/* GFMD_ERR_NOMEM on a distributed handle when one rank's memory does not suffice: one rank's (the
 * last of those owning the most rows) address space is capped just above what it uses (setrlimit), and then a create, a load, a solver
 * switch (the CG's 16 B/pt), new local heights and a save must each fail with GFMD_ERR_NOMEM and
 * one message on every rank -- no rank left waiting in a collective for the one that failed (a hang
 * is the ctest timeout) -- and change nothing: the solver, the observables and the next steps of
 * the handle are those of a twin; with the cap lifted each call works.  Not under the sanitizers
 * or valgrind, which need address space of their own. */
#include <gfmd_mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "mpi_check.h"

static int size = 1, victim = 0;
static struct rlimit unlimited;

/* The victim's memory squeezed: its address space capped 64 MB above what it uses, that filled
 * in 1 MB pieces (from wherever malloc takes them: fresh mappings or the reserve of its arenas)
 * until none is left, and `room` MB given back -- a call's small buffers fit, a grid-sized
 * allocation of more than `room` MB does not.  lift() gives everything back. */
static void *pieces[4096];
static int npieces = 0;

static void cap(int room) {
    if (rank != victim) return;
    struct rlimit r = unlimited;
    r.rlim_cur = (rlim_t)(vm_size() + (64LL << 20));
    CHECK(setrlimit(RLIMIT_AS, &r) == 0, "setrlimit");
    while (npieces < 4096 && (pieces[npieces] = malloc(1 << 20)) != NULL) ++npieces;
    CHECK(npieces < 4096, "the squeeze did not end");
    for (int k = 0; k < room && npieces > 0; ++k) free(pieces[--npieces]);
}

static void lift(void) {
    if (rank != victim) return;
    while (npieces > 0) free(pieces[--npieces]);
    CHECK(setrlimit(RLIMIT_AS, &unlimited) == 0, "setrlimit back");
}

/* st is GFMD_ERR_NOMEM on every rank, with rank 0's message everywhere */
static void expect_nomem(int32_t st, const char *msg, const char *what) {
    char first[512] = "";
    snprintf(first, sizeof first, "%s", msg);
    MPI_Bcast(first, sizeof first, MPI_CHAR, 0, MPI_COMM_WORLD);
    int32_t st0 = st;
    MPI_Bcast(&st0, 1, MPI_INT32_T, 0, MPI_COMM_WORLD);
    CHECK(st == st0, "%s: status %d here, %d on rank 0", what, st, st0);
    CHECK(st == GFMD_ERR_NOMEM, "%s: status %d (%s)", what, st, msg);
    CHECK(strcmp(first, msg) == 0, "%s: another message than rank 0's: %s", what, msg);
    if (rank == 0) printf("%s: GFMD_ERR_NOMEM on every rank: %s\n", what, first);
}

static void observe(gfmd_sim *s, double *x) {
    OK(gfmd_get_contact_area(s, &x[0]));
    OK(gfmd_get_energies(s, &x[1], &x[2]));
    OK(gfmd_get_residual(s, &x[3]));
}

static gfmd_sim *body(int64_t n) {
    gfmd_sim *s = NULL;
    OK(gfmd_sim_create_mpi(MPI_COMM_WORLD, n, n, (double)n, (double)n, GFMD_PLANNER_ESTIMATE, &s));
    OK(gfmd_generate_selfaffine(s, 0.8, n / 4.0, 4.0, 1.0, 5, GFMD_DIST_UNIFORM));
    OK(gfmd_set_solver(s, GFMD_SOLVER_FIRE));
    OK(gfmd_set_pressure(s, 0.02));
    OK(gfmd_step(s, 5));
    return s;
}

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    /* the victim: the last of the ranks owning the most rows of the 1024^2 grid (FFTW's blocks may
     * leave the last rank few) */
    int64_t my_rows = 0, my_y0 = 0;
    OK(gfmd_mpi_local_size(MPI_COMM_WORLD, 1024, 1024, &my_rows, &my_y0));
    long long *all_rows = malloc(sizeof(long long) * (size_t)size), mine = my_rows;
    MPI_Allgather(&mine, 1, MPI_LONG_LONG, all_rows, 1, MPI_LONG_LONG, MPI_COMM_WORLD);
    for (int r = 0; r < size; ++r)
        if (all_rows[r] >= all_rows[victim]) victim = r;
    free(all_rows);
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    if (rank == 0) printf("test_mpi_nomem: skipped under a sanitizer (its shadow memory needs the address space)\n");
    MPI_Finalize();
    return 0;
#endif
    const char *preload = getenv("LD_PRELOAD");
    if (preload && strstr(preload, "vgpreload")) {
        MPI_Finalize();
        return 0;
    }
    getrlimit(RLIMIT_AS, &unlimited);
    const char *path = "mpi_nomem.gfmd";
    char msg[512] = "";

    /* create and load: the victim's slab of a 1024^2 grid (>= 20 MB at 82 B/pt) beyond 16 MB of room */
    gfmd_sim *big = body(1024), *t = NULL;
    OK(gfmd_sim_save(big, path));
    gfmd_sim_destroy(&big);
    cap(16);
    int32_t st = gfmd_sim_create_mpi(MPI_COMM_WORLD, 1024, 1024, 1024.0, 1024.0, GFMD_PLANNER_ESTIMATE, &t);
    msg[0] = '\0';
    if (st != GFMD_OK) snprintf(msg, sizeof msg, "(create has no handle for its message)");
    lift();
    CHECK(t == NULL, "a failed create left a handle");
    expect_nomem(st, msg, "create with one rank capped");
    cap(16);
    st = gfmd_sim_load_mpi(MPI_COMM_WORLD, path, &t, msg, sizeof msg);
    lift();
    CHECK(t == NULL, "a failed load left a handle");
    expect_nomem(st, msg, "load with one rank capped");
    OK(gfmd_sim_load_mpi(MPI_COMM_WORLD, path, &t, NULL, 0));
    gfmd_sim_destroy(&t);

    /* calls on a live handle (1024^2: the CG's fields, the new heights, the save's rows are 2 MB or
     * more per rank) with 1 MB of room (a step's own buffers, its exact sums, fit): each fails
     * everywhere and changes nothing */
    gfmd_sim *a = body(1024), *b = body(1024);
    int64_t rows = 0, y0 = 0;
    OK(gfmd_mpi_get_local_grid(a, &rows, &y0));
    double *h = calloc((size_t)(rows * 1024 + 1), sizeof(double));
    for (int k = 0; k < 3; ++k) {
        cap(1);
        const char *what[] = {"the CG (16 B/pt) with one rank capped", "new local heights with one rank capped",
                              "a save with one rank capped"};
        if (k == 0) st = gfmd_set_solver(a, GFMD_SOLVER_CG);
        if (k == 1) st = gfmd_mpi_set_local_heights(a, h, 1024);
        if (k == 2) st = gfmd_sim_save(a, path);
        gfmd_last_error(a, msg, sizeof msg);
        lift();
        expect_nomem(st, msg, what[k]);
        int32_t solver = -1;
        OK(gfmd_get_solver(a, &solver));
        CHECK(solver == GFMD_SOLVER_FIRE, "%s: the solver is now %d", what[k], solver);
        double xa[4], xb[4];
        observe(a, xa);
        observe(b, xb);
        CHECK(memcmp(xa, xb, sizeof xa) == 0, "%s changed the observables: %.17g %.17g %.17g %.17g vs %.17g %.17g %.17g %.17g", what[k], xa[0], xa[1], xa[2], xa[3], xb[0], xb[1], xb[2], xb[3]);
        OK(gfmd_step(a, 3));
        OK(gfmd_step(b, 3));
        observe(a, xa);
        observe(b, xb);
        CHECK(memcmp(xa, xb, sizeof xa) == 0, "%s changed what the next steps do", what[k]);
    }
    OK(gfmd_set_solver(a, GFMD_SOLVER_CG)); /* with the cap lifted */
    OK(gfmd_sim_save(a, path));
    free(h);
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
    if (rank == 0) remove(path);
    int total = 0;
    MPI_Allreduce(&failures, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    if (rank == 0) printf("test_mpi_nomem on %d ranks: %s\n", size, total ? "FAILED" : "passed");
    MPI_Finalize();
    return total ? 1 : 0;
}
