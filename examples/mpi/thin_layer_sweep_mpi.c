/* The seed paper's thin-layer load sweep on several MPI ranks (libgfmd_mpi):
 *   mpirun -np 2 ./thin_layer_sweep_mpi [n]      (grid n x n, default 256)
 * A self-affine substrate (H = 0.8, lambda_s = 4a, lambda_r = L/8, rms gradient 1, E* = 1), layers
 * of width w = W lambda_s on a fluid foundation, the load stepped up from one equilibrium to the
 * next.  Each rank holds a slab of rows; every call below is made by all ranks with the same
 * arguments, and rank 0 prints.  The same program as examples/fortran/thin_layer_sweep.f90, and
 * as thin_layer_sweep_mpi.f90 in Fortran. */
#include <gfmd_mpi.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Stop every rank with the library's message (the same on all ranks). */
static void check(const gfmd_sim *s, int32_t st, const char *what, int rank) {
    if (st == GFMD_OK) return;
    char msg[256] = "";
    if (s) gfmd_last_error(s, msg, sizeof msg);
    if (rank == 0) fprintf(stderr, "%s: %s: %s\n", what, gfmd_status_string(st), msg);
    MPI_Abort(MPI_COMM_WORLD, 1);
}

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    const int64_t n = (argc > 1) ? atoll(argv[1]) : 256;
    const double l = (double)n, lambda_s = 4.0, widths[3] = {4.0, 1.0, 0.5};
    const int nloads = 8;

    gfmd_sim *s = NULL;
    /* ESTIMATE: the same bits on any number of ranks (gfmd_mpi.h). */
    check(s, gfmd_sim_create_mpi(MPI_COMM_WORLD, n, n, l, l, GFMD_PLANNER_ESTIMATE, &s), "create", rank);
    int64_t local_ny = 0, y0 = 0;
    check(s, gfmd_mpi_get_local_grid(s, &local_ny, &y0), "local grid", rank);
    printf("rank %d of %d: rows %lld .. %lld\n", rank, ranks, (long long)y0, (long long)(y0 + local_ny - 1));
    fflush(stdout);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) printf("gfmd %s thin-layer sweep on %lld x %lld, %d ranks\n", gfmd_version(), (long long)n, (long long)n, ranks);
    for (int iw = 0; iw < 3; ++iw) {
        check(s, gfmd_generate_selfaffine(s, 0.8, l / 8.0, lambda_s, 1.0, 2016, GFMD_DIST_UNIFORM), "substrate", rank);
        check(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, widths[iw] * lambda_s), "body", rank);
        if (rank == 0) {
            printf("\nlayer on a fluid foundation, W = %.2f\n", widths[iw]);
            printf("%4s%12s%10s%10s%14s%7s\n", "W", "sigma0/E*g", "A/A0", "mean gap", "U_el", "steps");
        }
        for (int k = 0; k < nloads; ++k) {
            const double sigma0 = 1e-3 * pow(100.0, (double)k / (nloads - 1));
            int64_t steps = 0;
            double area = 0.0, gap = 0.0, u_el = 0.0, u_ad = 0.0;
            check(s, gfmd_set_pressure(s, sigma0), "load", rank);
            check(s, gfmd_relax(s, 0.0, 1000000, &steps), "relax", rank);
            check(s, gfmd_get_contact_area(s, &area), "A/A0", rank);
            check(s, gfmd_get_mean_gap(s, &gap), "gap", rank);
            check(s, gfmd_get_energies(s, &u_el, &u_ad), "energies", rank);
            if (rank == 0)
                printf("%4.2f%12.4e%10.5f%10.5f%14.5e%7lld\n", widths[iw], sigma0, area, gap, u_el, (long long)steps);
        }
    }
    gfmd_sim_destroy(&s); /* collective: on every rank, before MPI_Finalize */
    MPI_Finalize();
    return 0;
}
