/* The serial library (libgfmd, no MPI in this process) loads a checkpoint written on 4 ranks by
 * test_mpi_checkpoint, continues it and compares with the observables of the MPI run's own
 * continuation: within 1e-12 relative (the two FFT algorithms differ by about an ulp per pair;
 * 20 steps of a CG run do not amplify that beyond 1e-13, measured). */
#include <gfmd.h>
#include <math.h>
#include <stdio.h>

int main(int argc, char **argv) {
    if (argc != 3) return 2;
    gfmd_sim *s = NULL;
    char msg[256] = "";
    if (gfmd_sim_load(argv[1], &s, msg, sizeof msg) != GFMD_OK) {
        fprintf(stderr, "load %s: %s\n", argv[1], msg);
        return 1;
    }
    FILE *f = fopen(argv[2], "r");
    int steps = 0;
    double ref[4];
    if (f == NULL || fscanf(f, "%d %lg %lg %lg %lg", &steps, &ref[0], &ref[1], &ref[2], &ref[3]) != 5) return 1;
    fclose(f);
    double got[4];
    int32_t solver = -1;
    if (gfmd_get_solver(s, &solver) != GFMD_OK || solver != GFMD_SOLVER_CG || gfmd_step(s, steps) != GFMD_OK ||
        gfmd_get_contact_area(s, &got[0]) != GFMD_OK || gfmd_get_mean_gap(s, &got[1]) != GFMD_OK ||
        gfmd_get_energies(s, &got[2], &got[3]) != GFMD_OK) {
        fprintf(stderr, "continuing the loaded run failed\n");
        return 1;
    }
    int bad = 0;
    for (int i = 0; i < 4; ++i) {
        const double d = fabs(got[i] - ref[i]) / fmax(fabs(ref[i]), 1e-300);
        printf("observable %d: serial %.17g, MPI %.17g, relative difference %.2e\n", i, got[i], ref[i], d);
        if (d > 1e-12 && !(ref[i] == 0.0 && got[i] == 0.0)) bad = 1;
    }
    gfmd_sim_destroy(&s);
    return bad;
}
