/* A user's MPI program: a thin layer relaxed on the ranks of MPI_COMM_WORLD. */
#include <gfmd_mpi.h>
#include <stdio.h>

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    gfmd_sim *s = NULL;
    int32_t st = gfmd_sim_create_mpi(MPI_COMM_WORLD, 64, 64, 64.0, 64.0, GFMD_PLANNER_ESTIMATE, &s);
    if (st == GFMD_OK) st = gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 4.0);
    if (st == GFMD_OK) st = gfmd_generate_selfaffine(s, 0.8, 32.0, 4.0, 0.1, 1, GFMD_DIST_UNIFORM);
    if (st == GFMD_OK) st = gfmd_set_pressure(s, 0.02);
    if (st == GFMD_OK) st = gfmd_relax(s, 0.0, 100000, NULL);
    double area = 0.0;
    if (st == GFMD_OK) st = gfmd_get_contact_area(s, &area);
    if (rank == 0) printf("consumer on %d ranks: %s, A/A0 = %.4f\n", size, gfmd_status_string(st), area);
    gfmd_sim_destroy(&s);
    MPI_Finalize();
    return (st == GFMD_OK && area > 0.0 && area < 1.0) ? 0 : 1;
}
