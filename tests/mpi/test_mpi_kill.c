/* A rank killed in the middle of a collective checkpoint write leaves the previous checkpoint
 * intact.  Two modes, run by kill_checkpoint.cmake:
 *   test_mpi_kill write PATH   (mpiexec, 2 ranks): saves PATH and copies its bytes to PATH.good,
 *     steps on, and saves PATH again while a thread of the last rank kills its own process
 *     (SIGKILL) as soon as the temporary file PATH.tmp holds data: the job dies mid-write;
 *   test_mpi_kill check PATH   (one process): PATH equals PATH.good byte for byte and loads. */
#include <gfmd_mpi.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static char tmp_path[4096];

static void *kill_when_written(void *arg) {
    (void)arg;
    const struct timespec pause = {0, 20000}; /* 20 us */
    for (;;) {
        struct stat st;
        if (stat(tmp_path, &st) == 0 && st.st_size > 0) kill(getpid(), SIGKILL);
        nanosleep(&pause, NULL);
    }
    return NULL;
}

static long copy_file(const char *from, const char *to) {
    FILE *in = fopen(from, "rb"), *out = fopen(to, "wb");
    long n = 0;
    int c;
    if (!in || !out) return -1;
    while ((c = fgetc(in)) != EOF) {
        fputc(c, out);
        ++n;
    }
    fclose(in);
    fclose(out);
    return n;
}

static int write_mode(const char *path) {
    MPI_Init(NULL, NULL);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    gfmd_sim *s = NULL;
    char good[4096];
    snprintf(good, sizeof good, "%s.good", path);
    snprintf(tmp_path, sizeof tmp_path, "%s.tmp", path);
    if (gfmd_sim_create_mpi(MPI_COMM_WORLD, 512, 512, 512.0, 512.0, GFMD_PLANNER_ESTIMATE, &s) != GFMD_OK ||
        gfmd_generate_selfaffine(s, 0.8, 128.0, 4.0, 1.0, 3, GFMD_DIST_UNIFORM) != GFMD_OK ||
        gfmd_set_pressure(s, 0.02) != GFMD_OK || gfmd_step(s, 10) != GFMD_OK || gfmd_sim_save(s, path) != GFMD_OK) {
        fprintf(stderr, "the first checkpoint failed\n");
        MPI_Abort(MPI_COMM_WORLD, 3);
    }
    if (rank == 0 && copy_file(path, good) <= 0) MPI_Abort(MPI_COMM_WORLD, 3);
    remove(tmp_path);
    if (gfmd_step(s, 10) != GFMD_OK) MPI_Abort(MPI_COMM_WORLD, 3);
    MPI_Barrier(MPI_COMM_WORLD);
    pthread_t watcher;
    if (rank == size - 1) pthread_create(&watcher, NULL, kill_when_written, NULL);
    gfmd_sim_save(s, path); /* the last rank dies in here */
    fprintf(stderr, "rank %d: the second save returned: the kill came too late\n", rank);
    MPI_Finalize();
    return 4;
}

static int check_mode(const char *path) {
    char good[4096];
    snprintf(good, sizeof good, "%s.good", path);
    FILE *a = fopen(path, "rb"), *b = fopen(good, "rb");
    if (!a || !b) {
        fprintf(stderr, "missing %s or %s\n", path, good);
        return 1;
    }
    long n = 0;
    int ca, cb;
    do {
        ca = fgetc(a);
        cb = fgetc(b);
        if (ca != cb) {
            fprintf(stderr, "%s differs from the checkpoint written before the kill at byte %ld\n", path, n);
            return 1;
        }
        ++n;
    } while (ca != EOF);
    fclose(a);
    fclose(b);
    gfmd_sim *s = NULL;
    char msg[256] = "";
    if (gfmd_sim_load(path, &s, msg, sizeof msg) != GFMD_OK) {
        fprintf(stderr, "the surviving checkpoint does not load: %s\n", msg);
        return 1;
    }
    gfmd_sim_destroy(&s);
    printf("the checkpoint before the kill survived intact (%ld bytes) and loads\n", n - 1);
    return 0;
}

int main(int argc, char **argv) {
    if (argc != 3) return 2;
    if (strcmp(argv[1], "write") == 0) return write_mode(argv[2]);
    if (strcmp(argv[1], "check") == 0) {
        MPI_Init(NULL, NULL);
        const int rc = check_mode(argv[2]);
        MPI_Finalize();
        return rc;
    }
    return 2;
}
