/* gfmd MPI benchmark: a distributed handle (libgfmd_mpi) against the threaded serial handle of the
 * same library, in the same run, on the same body:
 *   mpirun -np P ./gfmd_bench_mpi [--sizes 1024,2048,4096] [--steps 10] [--planner estimate|measure]
 * Body: a layer of width w = 4 (W = 1) on a fluid foundation, self-affine substrate (H = 0.8,
 * lambda_s = 4, lambda_r = n/8, rms gradient 0.1), sigma0 = 0.004 E*, FIRE; the steps timed are
 * the first ones from the flat start (the cost of a step does not depend on the contact).  Per size it prints:
 *   pair     the bare FFTW-MPI r2c + c2r pair in the library's layout (transposed, padded rows)
 *            on the P ranks, one thread each (median of the repetitions);
 *   step     a FIRE step of the distributed handle (median; the slowest rank);
 *   B/pt     peak resident bytes per local point on the busiest rank (VmHWM minus the resident
 *            set before the handle was made, so the MPI runtime is not counted);
 *   serial   a FIRE step of a serial handle with P threads (rank 0 alone, the others waiting),
 *            and its bytes per point.
 * Timings on a shared 2-core machine are noisy: compare within a run. */
#include <fftw3-mpi.h>
#include <gfmd_mpi.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_clock.h"

static int cmp(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *t, int n) {
    qsort(t, (size_t)n, sizeof *t, cmp);
    return t[n / 2];
}

/* The bare pair of FFTW-MPI transforms in the library's layout. */
static double mpi_pair_seconds(int n, unsigned flags, int reps) {
    ptrdiff_t rows, y0, cols, kx0;
    const ptrdiff_t nn[2] = {n, n}, spectrum[2] = {n, n / 2 + 1};
    const ptrdiff_t alloc = fftw_mpi_local_size_many_transposed(2, spectrum, 1, FFTW_MPI_DEFAULT_BLOCK,
                                                                FFTW_MPI_DEFAULT_BLOCK, MPI_COMM_WORLD, &rows, &y0, &cols, &kx0);
    double *r = fftw_alloc_real(2 * (size_t)alloc);
    fftw_complex *c = fftw_alloc_complex((size_t)alloc);
    fftw_plan f = fftw_mpi_plan_many_dft_r2c(2, nn, 1, FFTW_MPI_DEFAULT_BLOCK, FFTW_MPI_DEFAULT_BLOCK, r, c, MPI_COMM_WORLD,
                                             flags | FFTW_MPI_TRANSPOSED_OUT);
    fftw_plan b = fftw_mpi_plan_many_dft_c2r(2, nn, 1, FFTW_MPI_DEFAULT_BLOCK, FFTW_MPI_DEFAULT_BLOCK, c, r, MPI_COMM_WORLD,
                                             flags | FFTW_MPI_TRANSPOSED_IN);
    for (ptrdiff_t i = 0; i < 2 * alloc; ++i) r[i] = sin(0.001 * (double)i);
    double *t = malloc(sizeof(double) * (size_t)reps);
    for (int k = -1; k < reps; ++k) {
        MPI_Barrier(MPI_COMM_WORLD);
        const double t0 = now();
        fftw_execute(f);
        fftw_execute(b);
        double dt = now() - t0;
        MPI_Allreduce(MPI_IN_PLACE, &dt, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
        if (k >= 0) t[k] = dt;
    }
    const double m = median(t, reps);
    free(t);
    fftw_destroy_plan(f);
    fftw_destroy_plan(b);
    fftw_free(r);
    fftw_free(c);
    return m;
}

static int build(gfmd_sim *s, int n) {
    int32_t st = gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 4.0);
    if (st == GFMD_OK) st = gfmd_generate_selfaffine(s, 0.8, n / 8.0, 4.0, 0.1, 1, GFMD_DIST_UNIFORM);
    if (st == GFMD_OK) st = gfmd_set_solver(s, GFMD_SOLVER_FIRE);
    if (st == GFMD_OK) st = gfmd_set_pressure(s, 0.004);
    if (st == GFMD_OK) st = gfmd_step(s, 2); /* warm-up */
    return st;
}

/* Median step time over `steps` single steps (the slowest rank of comm). */
static double step_seconds(gfmd_sim *s, int steps, MPI_Comm comm) {
    double *t = malloc(sizeof(double) * (size_t)steps);
    for (int k = 0; k < steps; ++k) {
        if (comm != MPI_COMM_NULL) MPI_Barrier(comm);
        const double t0 = now();
        gfmd_step(s, 1);
        double dt = now() - t0;
        if (comm != MPI_COMM_NULL) MPI_Allreduce(MPI_IN_PLACE, &dt, 1, MPI_DOUBLE, MPI_MAX, comm);
        t[k] = dt;
    }
    const double m = median(t, steps);
    free(t);
    return m;
}

int main(int argc, char **argv) {
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    int64_t unused_rows = 0, unused_y0 = 0;  /* the library sets up FFTW (threads, then MPI) first */
    gfmd_mpi_local_size(MPI_COMM_WORLD, 8, 8, &unused_rows, &unused_y0);
    fftw_mpi_init();
    char sizes[256] = "1024,2048,4096";
    int steps = 10;
    int32_t planner = GFMD_PLANNER_ESTIMATE;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--sizes") && i + 1 < argc) snprintf(sizes, sizeof sizes, "%s", argv[++i]);
        else if (!strcmp(argv[i], "--steps") && i + 1 < argc) steps = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--planner") && i + 1 < argc)
            planner = strcmp(argv[++i], "measure") ? GFMD_PLANNER_ESTIMATE : GFMD_PLANNER_MEASURE;
        else {
            if (rank == 0) fprintf(stderr, "usage: gfmd_bench_mpi [--sizes n1,n2,..] [--steps k] [--planner estimate|measure]\n");
            MPI_Finalize();
            return 2;
        }
    }
    if (steps < 1) steps = 1;
    const unsigned flags = planner == GFMD_PLANNER_MEASURE ? FFTW_MEASURE : FFTW_ESTIMATE;
    if (rank == 0) {
        printf("gfmd %s MPI benchmark: %d ranks (one thread each) vs a serial handle with %d threads; planner %s\n",
               gfmd_version(), ranks, ranks, planner == GFMD_PLANNER_MEASURE ? "MEASURE" : "ESTIMATE");
        printf("fluid layer W = 1, FIRE; medians of %d steps; B/pt = peak bytes per local point\n", steps);
        printf("%6s %5s | %9s %9s %6s %7s | %9s %7s\n", "n", "ranks", "pair ms", "step ms", "/pair", "B/pt", "serial ms",
               "B/pt");
    }
    int failed = 0;
    for (char *tok = strtok(sizes, ","); tok; tok = strtok(NULL, ",")) {
        const int n = atoi(tok);
        if (n < 8) continue;
        const double pair = mpi_pair_seconds(n, flags, steps);

        reset_peak();
        const double base = read_status_kb("VmRSS:");
        gfmd_sim *s = NULL;
        int32_t st = gfmd_sim_create_mpi(MPI_COMM_WORLD, n, n, n, n, planner, &s);
        if (st == GFMD_OK) st = gfmd_set_threads(s, 1);
        if (st == GFMD_OK) st = build(s, n);
        double step = 0.0;
        if (st == GFMD_OK) step = step_seconds(s, steps, MPI_COMM_WORLD);
        int64_t rows = 0, y0 = 0;
        if (s) gfmd_mpi_get_local_grid(s, &rows, &y0);
        double bpt = (read_status_kb("VmHWM:") - base) * 1024.0 / (double)(rows > 0 ? rows * n : 1);
        MPI_Allreduce(MPI_IN_PLACE, &bpt, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
        gfmd_sim_destroy(&s);
        failed |= st != GFMD_OK;

        double serial = 0.0, serial_bpt = 0.0;
        if (rank == 0) {
            reset_peak();
            const double sbase = read_status_kb("VmRSS:");
            gfmd_sim *t = NULL;
            int32_t ts = gfmd_sim_create_ex(n, n, n, n, ranks, planner, &t);
            if (ts == GFMD_OK) ts = build(t, n);
            if (ts == GFMD_OK) serial = step_seconds(t, steps, MPI_COMM_NULL);
            serial_bpt = (read_status_kb("VmHWM:") - sbase) * 1024.0 / ((double)n * n);
            gfmd_sim_destroy(&t);
            failed |= ts != GFMD_OK;
            printf("%6d %5d | %9.2f %9.2f %6.2f %7.1f | %9.2f %7.1f\n", n, ranks, 1e3 * pair, 1e3 * step, step / pair, bpt,
                   1e3 * serial, serial_bpt);
            fflush(stdout);
        }
        MPI_Barrier(MPI_COMM_WORLD);
    }
    MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
    return failed;
}
