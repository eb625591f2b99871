/* Checkpoints of distributed handles, under mpiexec with P ranks:
 *  - a run on all P ranks is saved (one file, MPI-IO) and continued; the file loads on 1 .. P
 *    ranks and on a serial handle, and each continues: the distributed ones with the original's
 *    bits (ESTIMATE, rank-independent), the serial one within 1e-12 (another FFT algorithm);
 *  - a file saved by a serial handle loads on P ranks with the same fields, bit for bit;
 *  - the same state as format 4 (no row hashes, one sequential hash: the older files) loads on P
 *    ranks with the same bits;
 *  - a byte changed in the last rank's rows is refused on every rank with one status;
 *  - for the serial library's own check (read_checkpoint, another process without MPI), the file
 *    and the observables of the continued run are left as mpi_checkpoint_<P>.gfmd / .txt.
 * Two bodies: mass-weighted FIRE on a fluid layer (solver state: numbers) and CG on a bonded
 * layer (solver state: the pressure field). */
#include <gfmd_mpi.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpi_check.h"

static int size = 1;
enum { NX = 36, NY = 28, kContinue = 20 };

typedef struct {
    double obs[4];
    double z[NX * NY];
} Run;

static void observe(gfmd_sim *s, MPI_Comm comm, Run *r) {
    OK(gfmd_get_contact_area(s, &r->obs[0]));
    OK(gfmd_get_mean_gap(s, &r->obs[1]));
    OK(gfmd_get_energies(s, &r->obs[2], &r->obs[3]));
    int ranks = 1;
    if (comm != MPI_COMM_NULL) MPI_Comm_size(comm, &ranks);
    int64_t rows = NY, y0 = 0;
    OK(gfmd_mpi_get_local_grid(s, &rows, &y0));
    double *mine = malloc(sizeof(double) * (size_t)(rows * NX + 1));
    OK(gfmd_mpi_get_local_surface(s, mine, NX));
    if (comm == MPI_COMM_NULL) {
        memcpy(r->z, mine, sizeof r->z);
    } else {
        int count = (int)(rows * NX), first = (int)(y0 * NX), counts[16], firsts[16];
        MPI_Gather(&count, 1, MPI_INT, counts, 1, MPI_INT, 0, comm);
        MPI_Gather(&first, 1, MPI_INT, firsts, 1, MPI_INT, 0, comm);
        MPI_Gatherv(mine, count, MPI_DOUBLE, r->z, counts, firsts, MPI_DOUBLE, 0, comm);
    }
    free(mine);
}

static void build(gfmd_sim *s, int body) {
    if (body == 0) {
        OK(gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 2.0));
        OK(gfmd_set_solver(s, GFMD_SOLVER_MASS_WEIGHTED_FIRE));
    } else {
        OK(gfmd_set_poisson(s, 0.3));
        OK(gfmd_set_green(s, GFMD_GREEN_LAYER_BONDED, 6.0));
        OK(gfmd_set_solver(s, GFMD_SOLVER_CG));
    }
    OK(gfmd_generate_selfaffine(s, 0.7, 18.0, 4.0, 0.1, 11, GFMD_DIST_UNIFORM));
    OK(gfmd_set_pressure(s, 0.02));
}

static unsigned char *read_all(const char *path, long *n) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    *n = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *b = malloc((size_t)*n);
    if (fread(b, 1, (size_t)*n, f) != (size_t)*n) *n = -1;
    fclose(f);
    return b;
}

static void write_all(const char *path, const unsigned char *b, long n) {
    FILE *f = fopen(path, "wb");
    fwrite(b, 1, (size_t)n, f);
    fclose(f);
}

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    if (size > 16) size = 16;
    MPI_Comm comms[16];
    for (int k = 0; k < size; ++k) MPI_Comm_split(MPI_COMM_WORLD, rank <= k ? 0 : MPI_UNDEFINED, rank, &comms[k]);
    char path[64], text[64], v4path[64];
    snprintf(path, sizeof path, "mpi_checkpoint_%d.gfmd", size);
    snprintf(text, sizeof text, "mpi_checkpoint_%d.txt", size);
    snprintf(v4path, sizeof v4path, "mpi_checkpoint_%d_v4.gfmd", size);

    for (int body = 0; body < 2; ++body) {
        Run original, loaded, serial;
        gfmd_sim *s = NULL;
        OK(gfmd_sim_create_mpi(MPI_COMM_WORLD, NX, NY, NX, NY, GFMD_PLANNER_ESTIMATE, &s));
        build(s, body);
        OK(gfmd_step(s, 30));
        OK(gfmd_sim_save(s, path));
        OK(gfmd_step(s, kContinue));
        observe(s, MPI_COMM_WORLD, &original);
        gfmd_sim_destroy(&s);
        if (rank == 0 && body == 1) { /* for read_checkpoint: the continued run's observables */
            FILE *f = fopen(text, "w");
            fprintf(f, "%d %.17g %.17g %.17g %.17g\n", kContinue, original.obs[0], original.obs[1], original.obs[2],
                    original.obs[3]);
            fclose(f);
        }

        /* On 1 .. P ranks: the original's bits. */
        for (int k = 0; k < size; ++k) {
            if (comms[k] == MPI_COMM_NULL) continue;
            gfmd_sim *d = NULL;
            char msg[256] = "";
            const int32_t st = gfmd_sim_load_mpi(comms[k], path, &d, msg, sizeof msg);
            CHECK(st == GFMD_OK, "body %d: load on %d ranks: %s", body, k + 1, msg);
            if (d == NULL) continue;
            int32_t solver = -1;
            OK(gfmd_get_solver(d, &solver));
            CHECK(solver == (body == 0 ? GFMD_SOLVER_MASS_WEIGHTED_FIRE : GFMD_SOLVER_CG), "body %d: solver %d", body, solver);
            OK(gfmd_step(d, kContinue));
            observe(d, comms[k], &loaded);
            if (rank == 0)
                CHECK(memcmp(&loaded, &original, sizeof loaded) == 0,
                      "body %d: saved on %d ranks, loaded on %d: the continued run differs", body, size, k + 1);
            gfmd_sim_destroy(&d);
        }
        /* Serial handle of the same library: to rounding. */
        if (rank == 0) {
            gfmd_sim *t = NULL;
            char msg[256] = "";
            CHECK(gfmd_sim_load(path, &t, msg, sizeof msg) == GFMD_OK, "serial load: %s", msg);
            if (t != NULL) {
                OK(gfmd_step(t, kContinue));
                observe(t, MPI_COMM_NULL, &serial);
                double worst = 0.0;
                for (int i = 0; i < NX * NY; ++i) worst = fmax(worst, fabs(serial.z[i] - original.z[i]));
                CHECK(worst <= 1e-12, "body %d: serial continuation differs by %.3e", body, worst);
                printf("body %d: saved on %d ranks; continued on 1..%d ranks: same bits; serially: max |dz| %.2e\n", body,
                       size, size, worst);
                OK(gfmd_sim_save(t, "mpi_checkpoint_serial.gfmd"));
                gfmd_sim_destroy(&t);
            }
        }
        /* A serial handle's file on P ranks: the same fields. */
        MPI_Barrier(MPI_COMM_WORLD);
        gfmd_sim *d = NULL;
        OK(gfmd_sim_load_mpi(MPI_COMM_WORLD, "mpi_checkpoint_serial.gfmd", &d, NULL, 0));
        if (d != NULL) {
            observe(d, MPI_COMM_WORLD, &loaded);
            if (rank == 0)
                CHECK(memcmp(loaded.z, serial.z, sizeof loaded.z) == 0, "body %d: a serial file loaded on %d ranks has other z",
                      body, size);
            gfmd_sim_destroy(&d);
        }
    }

    /* The CG file as format 4 (strip the row hashes, one hash over all before it): same bits. */
    if (rank == 0) {
        long n = 0;
        unsigned char *b = read_all(path, &n);
        const long k = 4; /* h, z, v and CG's pressure */
        /* format 7's boundary (after the hardness, periodic) out: format 6 */
        memmove(b + 140, b + 144, (size_t)(n - 144));
        n -= 4;
        /* format 6's hardness (after mean_z), its active solver (after the planner), its plastic count
         * and volume (after the count of solver fields) out: format 4 */
        const long hardness_at = 132, active_at = 140, n4 = n - 8 - 4 - 12 - 8 * k * NY;
        memmove(b + hardness_at, b + hardness_at + 8, (size_t)(n - hardness_at - 8));
        memmove(b + active_at, b + active_at + 4, (size_t)(n - 8 - active_at - 4));
        unsigned int count = 0;
        memcpy(&count, b + 140, 4);
        const long plastic_at = 144 + 8L * count + 4;
        memmove(b + plastic_at, b + plastic_at + 12, (size_t)(n - 12 - plastic_at - 12));
        b[8] = 4;
        unsigned long long h = 0xcbf29ce484222325ULL;
        for (long i = 0; i < n4 - 8; ++i) h = (h ^ b[i]) * 0x100000001b3ULL;
        for (int i = 0; i < 8; ++i) b[n4 - 8 + i] = (unsigned char)(h >> (8 * i));
        write_all(v4path, b, n4);
        free(b);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    {
        Run a, b;
        gfmd_sim *s5 = NULL, *s4 = NULL;
        char msg[256] = "";
        OK(gfmd_sim_load_mpi(MPI_COMM_WORLD, path, &s5, NULL, 0));
        CHECK(gfmd_sim_load_mpi(MPI_COMM_WORLD, v4path, &s4, msg, sizeof msg) == GFMD_OK, "format 4: %s", msg);
        if (s5 && s4) {
            OK(gfmd_step(s5, 10));
            OK(gfmd_step(s4, 10));
            observe(s5, MPI_COMM_WORLD, &a);
            observe(s4, MPI_COMM_WORLD, &b);
            if (rank == 0) CHECK(memcmp(&a, &b, sizeof a) == 0, "format 4 and 5 of one state continue differently");
        }
        gfmd_sim_destroy(&s5);
        gfmd_sim_destroy(&s4);
    }

    /* A byte of z in the last row (the last rank's) changed: refused on every rank. */
    if (rank == 0) {
        long n = 0;
        unsigned char *b = read_all(path, &n);
        const long header = n - 8 - 4L * 8 * NY - 4L * 8 * NX * NY;
        b[header + 8L * NX * NY + 8L * NX * (NY - 1) + 3] ^= 0x20;
        write_all("mpi_checkpoint_damaged.gfmd", b, n);
        free(b);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    {
        gfmd_sim *d = NULL;
        char msg[256] = "", first[256];
        const int32_t st = gfmd_sim_load_mpi(MPI_COMM_WORLD, "mpi_checkpoint_damaged.gfmd", &d, msg, sizeof msg);
        CHECK(st == GFMD_ERR_FORMAT && d == NULL, "damaged file: status %d", st);
        memcpy(first, msg, sizeof msg);
        MPI_Bcast(first, sizeof first, MPI_CHAR, 0, MPI_COMM_WORLD);
        CHECK(strcmp(first, msg) == 0 && strlen(msg) > 0, "damaged file: message '%s' vs rank 0's '%s'", msg, first);
        if (rank == 0) printf("damaged row on the last rank: %s\n", msg);
        CHECK(gfmd_sim_load_mpi(MPI_COMM_WORLD, "no/such/file.gfmd", &d, NULL, 0) == GFMD_ERR_IO, "missing file");
    }
    if (rank == 0) {
        remove(v4path);
        remove("mpi_checkpoint_damaged.gfmd");
        remove("mpi_checkpoint_serial.gfmd");
    }
    for (int k = 0; k < size; ++k)
        if (comms[k] != MPI_COMM_NULL) MPI_Comm_free(&comms[k]);
    int all = 0;
    MPI_Allreduce(&failures, &all, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    if (rank == 0) printf("test_mpi_checkpoint on %d ranks: %s (%d failures)\n", size, all ? "FAILED" : "passed", all);
    MPI_Finalize();
    return all ? 1 : 0;
}
