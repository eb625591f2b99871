/* The C side of the Python-over-MPI check (python_mpi.cmake): a layer on a fluid foundation
 * distributed over the ranks of MPI_COMM_WORLD, 60 steps, then the surface of the whole grid
 * (gathered on rank 0, x fastest) and the patch labels written to argv[1] as raw doubles and
 * int64s, with A/A0.  python/tests/mpi_surface.py does the same through the Python package. */
#include <gfmd_mpi.h>
#include <stdio.h>
#include <stdlib.h>

enum { NX = 48, NY = 40 };

static void gather(const void *local, int count, MPI_Datatype type, void *all, int size) {
    int *counts = malloc(sizeof(int) * (size_t)size), *at = malloc(sizeof(int) * (size_t)size);
    MPI_Gather(&count, 1, MPI_INT, counts, 1, MPI_INT, 0, MPI_COMM_WORLD);
    for (int r = 0, off = 0; r < size; off += counts[r], ++r) at[r] = off;
    MPI_Gatherv(local, count, type, all, counts, at, type, 0, MPI_COMM_WORLD);
    free(counts);
    free(at);
}

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    gfmd_sim *s = NULL;
    int64_t rows = 0, y0 = 0, patches = 0;
    double area = 0.0;
    int bad = argc != 2 || gfmd_sim_create_mpi(MPI_COMM_WORLD, NX, NY, NX, NY, GFMD_PLANNER_ESTIMATE, &s) != GFMD_OK ||
              gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 1.0, 7, GFMD_DIST_UNIFORM) != GFMD_OK ||
              gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 4.0) != GFMD_OK || gfmd_set_pressure(s, 0.03) != GFMD_OK ||
              gfmd_step(s, 60) != GFMD_OK || gfmd_mpi_get_local_grid(s, &rows, &y0) != GFMD_OK ||
              gfmd_get_contact_area(s, &area) != GFMD_OK;
    double *z = malloc(sizeof(double) * (size_t)(rows * NX + 1)), *all = malloc(sizeof(double) * NX * NY);
    int64_t *lab = malloc(sizeof(int64_t) * (size_t)(rows * NX + 1)), *all_lab = malloc(sizeof(int64_t) * NX * NY);
    bad = bad || gfmd_mpi_get_local_surface(s, z, NX) != GFMD_OK ||
          gfmd_mpi_get_local_contact_patches(s, 8, lab, NX, &patches) != GFMD_OK;
    gather(z, (int)(rows * NX), MPI_DOUBLE, all, size);
    gather(lab, (int)(rows * NX), MPI_INT64_T, all_lab, size);
    if (rank == 0 && !bad) {
        FILE *f = fopen(argv[1], "wb");
        bad = f == NULL || fwrite(all, sizeof(double), NX * NY, f) != NX * NY ||
              fwrite(all_lab, sizeof(int64_t), NX * NY, f) != NX * NY || fwrite(&area, sizeof area, 1, f) != 1 ||
              fwrite(&patches, sizeof patches, 1, f) != 1;
        if (f) fclose(f);
    }
    gfmd_sim_destroy(&s);
    free(z);
    free(all);
    free(lab);
    free(all_lab);
    MPI_Finalize();
    return bad;
}
