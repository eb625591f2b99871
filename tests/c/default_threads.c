/* The default thread count as a process sees it: default_threads <expected>.  Run by ctest under
 * `taskset -c 0` (one CPU in the affinity mask, OMP_NUM_THREADS unset: expect 1) and with
 * OMP_NUM_THREADS=3 (the user's choice wins: expect 3). */
#include <gfmd.h>
#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv) {
    if (argc != 2) return 2;
    gfmd_sim *s = NULL;
    int32_t threads = -1;
    if (gfmd_sim_create_ex(16, 16, 16.0, 16.0, 0, GFMD_PLANNER_ESTIMATE, &s) != GFMD_OK ||
        gfmd_get_threads(s, &threads) != GFMD_OK)
        return 1;
    gfmd_sim_destroy(&s);
    printf("default threads: %d (expected %s)\n", (int)threads, argv[1]);
    return threads == atoi(argv[1]) ? 0 : 1;
}
