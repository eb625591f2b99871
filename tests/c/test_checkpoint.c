/* Checkpoint and restart: N steps, save, load, M steps equals N + M steps bit for bit; damaged
 * files (truncated, corrupted, another version, not a checkpoint, missing) are refused with their
 * own status and a message, never a crash. */
#include <math.h>
#include <signal.h>
#include <sys/resource.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "gfmd.h"
#include "test_support.h"

enum { NX = 40, NY = 24 };
static const char *PATH = "test_checkpoint.gfmd";

static gfmd_sim *make(int32_t solver) {
    gfmd_sim *s = ts_create(NX, NY, 40.0, 24.0);
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 12.0, 3.0, 1.0, 21, GFMD_DIST_UNIFORM));
    TS_OK(s, gfmd_set_poisson(s, 0.3));
    TS_OK(s, gfmd_set_green(s, GFMD_GREEN_LAYER_BONDED, 2.0));
    TS_OK(s, gfmd_set_adhesion(s, 0.002, 0.5));
    TS_OK(s, gfmd_set_solver(s, solver));
    TS_OK(s, gfmd_set_pressure(s, 0.03));
    return s;
}

static void fields(const gfmd_sim *s, double *z, double *p) {
    TS_OK(s, gfmd_get_surface(s, z));
    TS_OK(s, gfmd_get_pressure(s, p));
}

static void restart_is_bit_exact(void **state) {
    (void)state;
    /* GFMD_SOLVER_APPROACH_THEN_FIRE saved inside its approach (37 of 100 mass-weighted steps) and resumed
     * past its switch to FIRE (37 + 80 > 100) */
    const int32_t solvers[] = {GFMD_SOLVER_VERLET, GFMD_SOLVER_FIRE, GFMD_SOLVER_MASS_WEIGHTED_FIRE, GFMD_SOLVER_APPROACH_THEN_FIRE};
    for (size_t k = 0; k < sizeof solvers / sizeof solvers[0]; ++k) {
        gfmd_sim *a = make(solvers[k]), *b = NULL;
        double za[NX * NY], pa[NX * NY], zb[NX * NY], pb[NX * NY];
        TS_OK(a, gfmd_step(a, 37));
        TS_OK(a, gfmd_sim_save(a, PATH));
        char msg[256] = "x";
        assert_int_equal(gfmd_sim_load(PATH, &b, msg, sizeof msg), GFMD_OK);
        assert_string_equal(msg, "");
        int32_t solver_b = -1;
        TS_OK(b, gfmd_get_solver(b, &solver_b));
        assert_int_equal(solver_b, solvers[k]);
        TS_OK(a, gfmd_step(a, 80));
        TS_OK(b, gfmd_step(b, 80));
        fields(a, za, pa);
        fields(b, zb, pb);
        assert_memory_equal(za, zb, sizeof za);
        assert_memory_equal(pa, pb, sizeof pa);
        double ea, ua, eb, ub;
        TS_OK(a, gfmd_get_energies(a, &ea, &ua));
        TS_OK(b, gfmd_get_energies(b, &eb, &ub));
        assert_true(ea == eb && ua == ub);
        gfmd_sim_destroy(&a);
        gfmd_sim_destroy(&b);
    }
    remove(PATH);
}

/* a and b have bit-identical surfaces; destroys both and removes PATH. */
static void same_surfaces_then_destroy(gfmd_sim *a, gfmd_sim *b) {
    double za[NX * NY], zb[NX * NY];
    TS_OK(a, gfmd_get_surface(a, za));
    TS_OK(b, gfmd_get_surface(b, zb));
    assert_memory_equal(za, zb, sizeof za);
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
    remove(PATH);
}

/* Loads PATH and checks that the handle runs `solver`. */
static gfmd_sim *load_running(int32_t solver) {
    gfmd_sim *b = NULL;
    char msg[256] = "";
    if (gfmd_sim_load(PATH, &b, msg, sizeof msg) != GFMD_OK) fail_msg("%s", msg);
    int32_t active = -1;
    TS_OK(b, gfmd_get_solver(b, &active));
    assert_int_equal(active, solver);
    return b;
}

/* Loads PATH (saved from a), checks that it runs `solver`, continues both `steps` steps and
 * compares the surfaces bit for bit; destroys a. */
static void expect_resumed(gfmd_sim *a, int32_t solver, int64_t steps) {
    gfmd_sim *b = load_running(solver);
    TS_OK(a, gfmd_step(a, steps));
    TS_OK(b, gfmd_step(b, steps));
    same_surfaces_then_destroy(a, b);
}

/* GFMD_SOLVER_AUTO's choice survives a restart: it is the choice made when the load was set (CG
 * here: a fluid layer without adhesion), not what the loaded, relaxed state would suggest (a
 * regression: the loaded file was refused, "invalid FIRE state"). */
static void auto_choice_survives_restart(void **state) {
    (void)state;
    gfmd_sim *a = ts_create(NX, NY, 40.0, 24.0);
    TS_OK(a, gfmd_generate_selfaffine(a, 0.8, 20.0, 4.0, 0.1, 5, GFMD_DIST_UNIFORM));
    TS_OK(a, gfmd_set_green(a, GFMD_GREEN_LAYER_FLUID, 4.0));
    TS_OK(a, gfmd_set_pressure(a, 0.02));
    int32_t active = -1;
    TS_OK(a, gfmd_get_solver(a, &active));
    assert_int_equal(active, GFMD_SOLVER_CG);
    TS_OK(a, gfmd_step(a, 40));
    TS_OK(a, gfmd_sim_save(a, PATH));
    expect_resumed(a, GFMD_SOLVER_CG, 10);
    /* an adhesive thin sheet at a low load (w = 0.25, f(q_min w) = 1e5, q_max w = 1.1, Persson's
     * A/A0 = 0.05): AUTO takes mass-weighted FIRE (thinner than q_max w < 4; the approach then FIRE
     * needs q_max w >= 4 and f(q_min w) >= 2e4 together, which a grid 40 points wide cannot
     * hold); its frequency estimates per contact bucket, made during the 60 steps, resume with it */
    a = ts_create(NX, NY, 40.0, 24.0);
    TS_OK(a, gfmd_generate_selfaffine(a, 0.8, 20.0, 4.0, 0.1, 5, GFMD_DIST_UNIFORM));
    TS_OK(a, gfmd_set_green(a, GFMD_GREEN_LAYER_FLUID, 0.25));
    TS_OK(a, gfmd_set_adhesion(a, 1e-4, 0.5));
    TS_OK(a, gfmd_set_pressure(a, 1e-5));
    TS_OK(a, gfmd_get_solver(a, &active));
    assert_int_equal(active, GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    TS_OK(a, gfmd_step(a, 60));
    TS_OK(a, gfmd_sim_save(a, PATH));
    expect_resumed(a, GFMD_SOLVER_MASS_WEIGHTED_FIRE, 90);
}

static long file_size(const char *path) {
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fclose(f);
    return n;
}

/* A bonded layer under pressure relaxed by CG (non-adhesive: CG refuses adhesion). */
static gfmd_sim *make_cg_body(void) {
    gfmd_sim *a = ts_create(NX, NY, 40.0, 24.0);
    TS_OK(a, gfmd_generate_selfaffine(a, 0.8, 12.0, 3.0, 1.0, 21, GFMD_DIST_UNIFORM));
    TS_OK(a, gfmd_set_poisson(a, 0.3));
    TS_OK(a, gfmd_set_green(a, GFMD_GREEN_LAYER_BONDED, 2.0));
    TS_OK(a, gfmd_set_solver(a, GFMD_SOLVER_CG));
    TS_OK(a, gfmd_set_pressure(a, 0.03));
    return a;
}

/* CG keeps its contact pressure as grid-sized state: a non-adhesive body (CG refuses adhesion) */
static void cg_restart_is_bit_exact(void **state) {
    (void)state;
    gfmd_sim *a = make_cg_body();
    TS_OK(a, gfmd_step(a, 7));
    TS_OK(a, gfmd_sim_save(a, PATH));
    /* one field more than FIRE's file: the pressure (and its row hashes); 8 numbers of state instead of 3 */
    assert_int_equal(file_size(PATH), 8 + 8 + 32 + 10 * 8 + 4 * 4 + 8 + 4 + 4 + 8 * 8 + 4 + 12 + 4 * 8 * NX * NY + 4 * 8 * NY + 8);
    expect_resumed(a, GFMD_SOLVER_CG, 9);
}


static void rewrite(const char *path, long keep, long flip_at, const unsigned char *patch, size_t patch_len,
                    long patch_at) {
    FILE *f = fopen(path, "rb");
    long n = file_size(path);
    unsigned char *buf = malloc((size_t)n);
    assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    if (flip_at >= 0) buf[flip_at] ^= 0x10;
    if (patch) memcpy(buf + patch_at, patch, patch_len);
    f = fopen("damaged.gfmd", "wb");
    fwrite(buf, 1, (size_t)(keep >= 0 ? keep : n), f);
    fclose(f);
    free(buf);
}

/* damaged.gfmd refused with `expected`, the handle left NULL, a message given (containing `says`
 * unless that is NULL) */
static void expect_refused_saying(int32_t expected, const char *what, const char *says) {
    gfmd_sim *s = (gfmd_sim *)&s;
    char msg[512] = "";
    int32_t st = gfmd_sim_load("damaged.gfmd", &s, msg, sizeof msg);
    if (st != expected) fail_msg("%s: got %s (%s)", what, gfmd_status_string(st), msg);
    assert_null(s);
    assert_true(strlen(msg) > 0);
    if (says && !strstr(msg, says)) fail_msg("%s: the message does not say '%s': %s", what, says, msg);
    print_message("%s: %s: %s\n", what, gfmd_status_string(st), msg);
}

static void expect_refused(int32_t expected, const char *what) { expect_refused_saying(expected, what, NULL); }

static void damaged_files_are_refused(void **state) {
    (void)state;
    gfmd_sim *a = make(GFMD_SOLVER_FIRE);
    TS_OK(a, gfmd_step(a, 10));
    TS_OK(a, gfmd_sim_save(a, PATH));
    gfmd_sim_destroy(&a);
    const long n = file_size(PATH);
    /* format 7: magic, version + flags, grid, 10 f64 + 4 i32 parameters, threads + planner, the
     * solver state (count + FIRE's 3 numbers), the count of solver fields (0), the count of
     * plastic fields (0) and the plastic volume, three fields, a hash per row of each field, the
     * hash of header and row hashes */
    assert_int_equal(n, 8 + 8 + 32 + 10 * 8 + 4 * 4 + 8 + 4 + 4 + 3 * 8 + 4 + 12 + 3 * 8 * NX * NY + 3 * 8 * NY + 8);

    const long cuts[] = {0, 5, 12, 100, n / 2, n - 1};
    for (int i = 0; i < 6; ++i) {
        rewrite(PATH, cuts[i], -1, NULL, 0, 0);
        expect_refused(GFMD_ERR_FORMAT, "truncated");
    }
    const long flips[] = {20, 60, 200, n / 2, n - 3};
    for (int i = 0; i < 5; ++i) {
        rewrite(PATH, -1, flips[i], NULL, 0, 0);
        expect_refused(GFMD_ERR_FORMAT, "corrupted");
    }
    const unsigned char v8[4] = {8, 0, 0, 0};
    rewrite(PATH, -1, -1, v8, 4, 8);
    expect_refused(GFMD_ERR_VERSION, "another version");
    const unsigned char junk[8] = {'P', 'K', 3, 4, 0, 0, 0, 0};
    rewrite(PATH, -1, -1, junk, 8, 0);
    expect_refused(GFMD_ERR_FORMAT, "not a checkpoint");

    gfmd_sim *s = NULL;
    char msg[64];
    assert_int_equal(gfmd_sim_load("no/such/file.gfmd", &s, msg, sizeof msg), GFMD_ERR_IO);
    assert_int_equal(gfmd_sim_load(NULL, &s, msg, sizeof msg), GFMD_ERR_NULL);
    assert_int_equal(gfmd_sim_load(PATH, NULL, msg, sizeof msg), GFMD_ERR_NULL);
    assert_int_equal(gfmd_sim_load(PATH, &s, NULL, 0), GFMD_OK); /* the message buffer is optional */
    assert_int_equal(gfmd_sim_save(s, "no/such/dir/x.gfmd"), GFMD_ERR_IO);
    assert_int_equal(gfmd_sim_save(s, NULL), GFMD_ERR_NULL);
    assert_int_equal(gfmd_sim_save(NULL, PATH), GFMD_ERR_NULL);
    gfmd_sim_destroy(&s);
    remove(PATH);
    remove("damaged.gfmd");
}

/* Layout of a format-3 file (see src/checkpoint.cpp): offsets of the flags, grid, the control
 * parameters format 3 added, the solver state; format 2 lacks the 12 bytes of the control. */
enum { OFF_VERSION = 8, OFF_FLAGS = 12, OFF_NX = 16, OFF_CONTROL = 120, CONTROL_BYTES = 12, OFF_COUNT = 140,
       OFF_STATE = 144, OFF_FIELDS = 172 };

static uint64_t fnv(uint64_t h, const unsigned char *b, long n);
static void put_le(uint64_t x, unsigned char *b);

/* A file of the current format 6 without plasticity as the format-5 file it extends: the hardness
 * (8 bytes after mean_z, +infinity) and the plastic count and volume (12 bytes after the count of
 * solver fields, zero) taken out and the final hash formed again.  The byte-level tests below
 * work on format 5's layout; test_plasticity checks format 6's own fields. */
enum { OFF_HARDNESS6 = 132 };
static void as_format5(unsigned char *buf, long *n) {
    assert_int_equal(buf[8], 6);
    double hardness = 0.0;
    memcpy(&hardness, buf + OFF_HARDNESS6, 8);
    assert_true(isinf(hardness));
    memmove(buf + OFF_HARDNESS6, buf + OFF_HARDNESS6 + 8, (size_t)(*n - OFF_HARDNESS6 - 8));
    *n -= 8;
    uint32_t count = 0, m = 1;
    memcpy(&count, buf + 144, 4); /* format 5's count of solver state numbers */
    const long k_at = 148 + 8L * count, plastic_at = k_at + 4;
    memcpy(&m, buf + plastic_at, 4);
    assert_int_equal(m, 0);
    memmove(buf + plastic_at, buf + plastic_at + 12, (size_t)(*n - plastic_at - 12));
    *n -= 12;
    buf[8] = 5;
    uint32_t k = 0;
    memcpy(&k, buf + k_at, 4);
    const long fields_at = k_at + 4, table = *n - 8 - 8L * (3 + k) * NY;
    put_le(fnv(fnv(0xcbf29ce484222325ULL, buf, fields_at), buf + table, *n - 8 - table), buf + *n - 8);
}

/* A file of the current format 7 with periodic boundaries as the format-6 file it extends: the
 * boundary (4 bytes after the hardness, GFMD_BOUNDARY_PERIODIC) taken out; as_format5 then forms
 * the hash again.  test_free_boundary and restart_process check format 7's free boundaries. */
enum { OFF_BOUNDARY7 = 140 };
static void as_format6(unsigned char *buf, long *n) {
    int32_t boundary = -1;
    memcpy(&boundary, buf + OFF_BOUNDARY7, 4);
    assert_int_equal(boundary, GFMD_BOUNDARY_PERIODIC);
    memmove(buf + OFF_BOUNDARY7, buf + OFF_BOUNDARY7 + 4, (size_t)(*n - OFF_BOUNDARY7 - 4));
    *n -= 4;
    buf[8] = 6;
}

static unsigned char *read_all(const char *path, long *n) {
    *n = file_size(path);
    unsigned char *buf = malloc((size_t)*n);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fread(buf, 1, (size_t)*n, f), (size_t)*n);
    fclose(f);
    if (buf[8] == 7) as_format6(buf, n);
    if (buf[8] == 6) as_format5(buf, n);
    return buf;
}

static void write_raw(const char *path, const unsigned char *buf, long n) {
    FILE *f = fopen(path, "wb");
    assert_int_equal(fwrite(buf, 1, (size_t)n, f), (size_t)n);
    fclose(f);
}

/* FNV-1a 64 of n bytes, continuing from h. */
static uint64_t fnv(uint64_t h, const unsigned char *b, long n) {
    for (long i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ULL;
    return h;
}

static void put_le(uint64_t x, unsigned char *b) {
    for (int k = 0; k < 8; ++k) b[k] = (unsigned char)(x >> (8 * k));
}

/* Write buf[0..n) to path with a fresh FNV-1a hash in its last 8 bytes (little-endian), as a
 * forger or an older library would. */
static void write_rehashed(const char *path, unsigned char *buf, long n) {
    put_le(fnv(0xcbf29ce484222325ULL, buf, n - 8), buf + n - 8);
    write_raw(path, buf, n);
}

/* The same for format 5: buf[0..n) with k fields of an nx x ny grid, its row hashes recomputed and
 * then the hash of the header and the row hashes, as a forger would. */
static void write_rehashed5_grid(const char *path, unsigned char *buf, long n, int k, long nx, long ny) {
    const long table = n - 8 - 8L * k * ny, fields_at = table - 8L * k * nx * ny;
    for (long row = 0; row < k * ny; ++row)
        put_le(fnv(0xcbf29ce484222325ULL, buf + fields_at + row * 8L * nx, 8L * nx), buf + table + 8 * row);
    put_le(fnv(fnv(0xcbf29ce484222325ULL, buf, fields_at), buf + table, n - 8 - table), buf + n - 8);
    write_raw(path, buf, n);
}

static void write_rehashed5(const char *path, unsigned char *buf, long n, int k) {
    write_rehashed5_grid(path, buf, n, k, NX, NY);
}

/* The bytes of a fresh checkpoint of the FIRE body (n of them). */
static unsigned char *saved_fire_file(long *n) {
    gfmd_sim *a = make(GFMD_SOLVER_FIRE);
    TS_OK(a, gfmd_sim_save(a, PATH));
    gfmd_sim_destroy(&a);
    return read_all(PATH, n);
}

/* Format 5's two hashes: a field byte changed under an intact table and final hash is caught by
 * its row's hash (each rank checks its own rows); a table entry changed under an intact final
 * hash by the final hash; the same change with both recomputed (as the test's own writer does)
 * loads, so the test's hashing is the library's. */
static void row_hashes_are_checked(void **state) {
    (void)state;
    long n = 0;
    unsigned char *buf = saved_fire_file(&n);
    const long z_byte = OFF_FIELDS + 4 + 8L * NX * NY + 8L * NX * 5; /* the lowest byte of z at (0, 5) (format 5: +4) */
    buf[z_byte] ^= 1;
    write_raw("damaged.gfmd", buf, n);
    expect_refused(GFMD_ERR_FORMAT, "a field byte under its row hash");
    buf[z_byte] ^= 1;
    const long table_byte = n - 8 - 3L * 8 * NY + 8L * (NY + 5);
    buf[table_byte] ^= 1;
    write_raw("damaged.gfmd", buf, n);
    expect_refused(GFMD_ERR_FORMAT, "a row hash under the final hash");
    buf[table_byte] ^= 1;
    buf[z_byte] ^= 1;
    write_rehashed5("damaged.gfmd", buf, n, 3);
    gfmd_sim *s = NULL;
    char msg[256] = "";
    if (gfmd_sim_load("damaged.gfmd", &s, msg, sizeof msg) != GFMD_OK) fail_msg("rehashed file refused: %s", msg);
    gfmd_sim_destroy(&s);
    free(buf);
    remove("damaged.gfmd");
    remove(PATH);
}

/* Files of the earlier formats made from a format-6 one load and resume the run bit for bit: format 5 (no plastic fields),
 * format 4 (no row hashes), format 3 (no count of solver fields: none), format 2 (no control parameters: pressure control) and format 1 (also FIRE's dt, alpha as f64
 * and its count as i64 in place of the solver state). */
static void older_formats_resume(void **state) {
    (void)state;
    for (int version = 1; version <= 6; ++version)
        for (int32_t solver = GFMD_SOLVER_VERLET; solver <= GFMD_SOLVER_MASS_WEIGHTED_FIRE; ++solver) {
            gfmd_sim *a = make(solver), *b = NULL;
            TS_OK(a, gfmd_step(a, 37));
            TS_OK(a, gfmd_sim_save(a, PATH));
            long n4 = 0;
            unsigned char *v4 = NULL;
            if (version == 6) { /* format 7 without its boundary, its hashes formed again */
                n4 = file_size(PATH);
                v4 = malloc((size_t)n4);
                FILE *f = fopen(PATH, "rb");
                assert_non_null(f);
                assert_int_equal(fread(v4, 1, (size_t)n4, f), (size_t)n4);
                fclose(f);
                as_format6(v4, &n4);
            } else {
                v4 = read_all(PATH, &n4); /* format 5 (read_all: format 7 without its boundary and plastic fields) */
            }
            if (version <= 4) {
                /* format 4: format 5 without the active solver (4 bytes at OFF_COUNT) and the row
                 * hashes (3 fields here), one hash over all before it */
                memmove(v4 + OFF_COUNT, v4 + OFF_COUNT + 4, (size_t)(n4 - OFF_COUNT - 4));
                n4 -= 4 + 3 * 8 * NY;
                v4[OFF_VERSION] = 4;
            }
            unsigned char *old = v4;
            long n_old = n4;
            if (version <= 3) { /* format 3: without the count of solver fields (FIRE, Verlet: 3 or 0 numbers of state) */
                const long k_at = OFF_STATE + 8 * (long)old[OFF_COUNT];
                assert_int_equal(old[k_at], 0);
                unsigned char *v3 = malloc((size_t)(n_old - 4));
                memcpy(v3, old, (size_t)k_at);
                memcpy(v3 + k_at, old + k_at + 4, (size_t)(n_old - k_at - 4));
                v3[OFF_VERSION] = 3;
                free(old);
                old = v3;
                n_old -= 4;
            }
            if (version <= 2) { /* format 2: without the control parameters */
                const long n2 = n_old - CONTROL_BYTES;
                unsigned char *v2 = malloc((size_t)n2);
                memcpy(v2, old, OFF_CONTROL);
                memcpy(v2 + OFF_CONTROL, old + OFF_CONTROL + CONTROL_BYTES, (size_t)(n_old - OFF_CONTROL - CONTROL_BYTES));
                v2[OFF_VERSION] = 2;
                free(old);
                old = v2;
                n_old = n2;
                if (version == 1) { /* the solver state as FIRE's fixed triple */
                    const long count_at = OFF_COUNT - CONTROL_BYTES, state_at = OFF_STATE - CONTROL_BYTES;
                    const uint32_t count = old[count_at];
                    double st[3] = {0.0, 0.0, 0.0};
                    /* FIRE's control comes first (mass-weighted FIRE: its frequency estimates after it,
                     * which format 1 cannot hold) -- little-endian machine (x86_64) */
                    if (count >= 3) memcpy(st, old + state_at, sizeof st);
                    n_old = n2 - 4 - 8 * (long)count + 24;
                    unsigned char *v1 = malloc((size_t)n_old);
                    memcpy(v1, old, (size_t)count_at);
                    v1[OFF_VERSION] = 1;
                    const int64_t positive = (int64_t)st[2];
                    memcpy(v1 + count_at, st, 16);
                    memcpy(v1 + count_at + 16, &positive, 8);
                    memcpy(v1 + count_at + 24, old + state_at + 8 * count, (size_t)(n2 - state_at - 8 * (long)count));
                    free(old);
                    old = v1;
                }
            }
            if (version == 6)
                write_rehashed5("older.gfmd", old, n_old, 3); /* formats 5 and 6 hash alike */
            else if (version == 5)
                write_raw("older.gfmd", old, n_old); /* rehashed by read_all */
            else
                write_rehashed("older.gfmd", old, n_old);
            char msg[256] = "";
            const int32_t st_load = gfmd_sim_load("older.gfmd", &b, msg, sizeof msg);
            if (st_load != GFMD_OK) fail_msg("format %d: %s", version, msg);
            if (version == 1 && solver == GFMD_SOLVER_MASS_WEIGHTED_FIRE) {
                /* without its frequency estimates b would estimate again from its held set of now,
                 * a used those of when each bucket was first entered: both start the dynamics anew */
                TS_OK(a, gfmd_restart_solver(a));
                TS_OK(b, gfmd_restart_solver(b));
            }
            TS_OK(a, gfmd_step(a, 50));
            TS_OK(b, gfmd_step(b, 50));
            double za[NX * NY], pa[NX * NY], zb[NX * NY], pb[NX * NY];
            fields(a, za, pa);
            fields(b, zb, pb);
            assert_memory_equal(za, zb, sizeof za);
            free(old);
            gfmd_sim_destroy(&a);
            gfmd_sim_destroy(&b);
        }
    remove("older.gfmd");
    remove(PATH);
}

/* Saves a to PATH and returns the file's bytes (*n of them), its solver state asserted to hold
 * `count` numbers, *value the one at `index`. */
static unsigned char *saved_with_state(gfmd_sim *a, uint32_t count, int index, long *n, double *value) {
    TS_OK(a, gfmd_sim_save(a, PATH));
    unsigned char *buf = read_all(PATH, n);
    uint32_t k = 0;
    memcpy(&k, buf + OFF_STATE, 4);
    assert_int_equal(k, count);
    memcpy(value, buf + OFF_STATE + 4 + 8L * index, 8);
    return buf;
}

/* Saves a (its solver state of `count` numbers checked, the number at `probe` equal to
 * `expect`), drops `drop` numbers from the state after its first `keep` as an older library's
 * file would not have them, rehashes the file (`fields` grid fields) and loads it. */
static gfmd_sim *saved_without(gfmd_sim *a, uint32_t count, int probe, double expect, int keep, int drop, int fields) {
    long n = 0;
    double x = -1.0;
    unsigned char *buf = saved_with_state(a, count, probe, &n, &x);
    assert_true(x == expect);
    const long cut = OFF_STATE + 4 + 8L * keep, bytes = 8L * drop;
    memmove(buf + cut, buf + cut + bytes, (size_t)(n - cut - bytes));
    n -= bytes;
    const uint32_t k = count - (uint32_t)drop;
    memcpy(buf + OFF_STATE, &k, 4);
    write_rehashed5(PATH, buf, n, fields);
    free(buf);
    gfmd_sim *b = NULL;
    char msg[256] = "";
    if (gfmd_sim_load(PATH, &b, msg, sizeof msg) != GFMD_OK) fail_msg("%s", msg);
    return b;
}

/* A CG file of this format written before the pressure CG kept its iteration count (7 numbers of
 * state instead of 8; the count schedules the convergence test, every third iteration since the
 * restart) still loads, with the count 0, and resumes the same iterates: saved at a count that is
 * a multiple of three, the schedule is the same too, so relax stops at the same step. */
static void cg_state_without_count_resumes(void **state) {
    (void)state;
    gfmd_sim *a = make_cg_body();
    TS_OK(a, gfmd_step(a, 6));
    /* 8 numbers, the count last (6); dropped: 7; fields h, z, v and the pressure */
    gfmd_sim *b = saved_without(a, 8, 7, 6.0, 7, 1, 4);
    int64_t sa = 0, sb = 0;
    TS_OK(a, gfmd_relax(a, 1e-9, 100000, &sa));
    TS_OK(b, gfmd_relax(b, 1e-9, 100000, &sb));
    assert_int_equal(sa, sb);
    same_surfaces_then_destroy(a, b);
}

/* Polonsky-Keer's restart when every pressure clears: an iteration whose update leaves no point
 * carrying pressure and none joining restarts from the uniform load (pk.cpp).  No relaxation of
 * the tests reaches it (the update keeps the sum of the pressures but for rounding); a file does:
 * a CG checkpoint whose pressure field is zero -- valid by the format, every value >= 0 -- is
 * resumed with u = G p = 0 and the approach 0, so every point has a gap >= 0 (the substrate's
 * highest point at 0) and none joins.  The resumed run must reach the original run's equilibrium
 * (without the restart the load would be scaled by 1/0 and the call diverge). */
static void pk_restarts_when_every_pressure_clears(void **state) {
    (void)state;
    gfmd_sim *a = make_cg_body();
    TS_OK(a, gfmd_step(a, 7));
    TS_OK(a, gfmd_sim_save(a, PATH));
    TS_OK(a, gfmd_relax(a, 1e-10, 100000, NULL));
    double area_a, gap_a;
    TS_OK(a, gfmd_get_contact_area(a, &area_a));
    TS_OK(a, gfmd_get_mean_gap(a, &gap_a));
    long n = 0;
    unsigned char *buf = read_all(PATH, &n);
    const int k = 4; /* h, z, v and the CG's pressure, the last */
    const long pressure_at = n - 8 - 8L * k * NY - 8L * NX * NY;
    double p = -1.0;
    int carrying = 0;
    for (long i = 0; i < NX * NY; ++i) {
        memcpy(&p, buf + pressure_at + 8 * i, 8);
        carrying += p > 0.0;
    }
    assert_true(carrying > 0); /* the field found is a contact pressure (the run is in contact) */
    memset(buf + pressure_at, 0, 8 * (size_t)(NX * NY));
    write_rehashed5(PATH, buf, n, k);
    free(buf);
    gfmd_sim *b = NULL;
    char msg[256] = "";
    if (gfmd_sim_load(PATH, &b, msg, sizeof msg) != GFMD_OK) fail_msg("zero pressure field: %s", msg);
    int64_t steps_b = 0;
    TS_OK(b, gfmd_relax(b, 1e-10, 100000, &steps_b));
    double area_b, gap_b;
    TS_OK(b, gfmd_get_contact_area(b, &area_b));
    TS_OK(b, gfmd_get_mean_gap(b, &gap_b));
    print_message("resumed from a cleared pressure: %lld iterations, A/A0 %.8f (original %.8f), gap %.12g (%.12g)\n",
                  (long long)steps_b, area_b, area_a, gap_b, gap_a);
    /* both at 1e-10 of the pressure scale, the problem convex: the same contact points, the gap
     * to 1e-8 (as the surface CG's resumed runs below) */
    assert_true(area_b == area_a && ts_rel(gap_b, gap_a) < 1e-8);
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
    remove(PATH);
}

/* The surface CG's flag in a file (the second number of CG's state): 0 conjugate, 1 fresh (the
 * next direction the preconditioned force), 2 fresh with the next direction the force itself (a
 * projected step that failed its energy check was undone; src/solvers/cg.cpp).  The library rarely
 * saves a 2 (no case of the tests reaches an undone step), so the file is written by hand: each of
 * the three values loads and relaxes to the equilibrium of the original run, 2 takes another
 * first step than 1 (the value is read, not dropped), and any other value is refused. */
static void surface_cg_flag_values(void **state) {
    (void)state;
    gfmd_sim *a = ts_create(NX, NY, 40.0, 24.0);
    TS_OK(a, gfmd_generate_selfaffine(a, 0.8, 12.0, 3.0, 1.0, 21, GFMD_DIST_UNIFORM));
    TS_OK(a, gfmd_set_green(a, GFMD_GREEN_LAYER_FLUID, 1.0)); /* preconditioned surface CG */
    TS_OK(a, gfmd_set_solver(a, GFMD_SOLVER_CG));
    TS_OK(a, gfmd_set_pressure(a, 0.003));
    TS_OK(a, gfmd_step(a, 3));
    long n = 0;
    double saved = -1.0;
    unsigned char *buf = saved_with_state(a, 8, 1, &n, &saved);
    const long flag_at = OFF_STATE + 4 + 8;
    assert_true(saved == 0.0 || saved == 1.0);
    int64_t steps_a = 0;
    TS_OK(a, gfmd_relax(a, 1e-10, 100000, &steps_a));
    double area_a, gap_a;
    TS_OK(a, gfmd_get_contact_area(a, &area_a));
    TS_OK(a, gfmd_get_mean_gap(a, &gap_a));
    double first[3][NX * NY];
    for (int v = 0; v < 3; ++v) {
        const double flag = (double)v;
        memcpy(buf + flag_at, &flag, 8);
        write_rehashed5(PATH, buf, n, 4);
        gfmd_sim *b = NULL;
        char msg[256] = "";
        if (gfmd_sim_load(PATH, &b, msg, sizeof msg) != GFMD_OK) fail_msg("flag %d: %s", v, msg);
        TS_OK(b, gfmd_step(b, 1));
        TS_OK(b, gfmd_get_surface(b, first[v]));
        int64_t steps_b = 0;
        TS_OK(b, gfmd_relax(b, 1e-10, 100000, &steps_b));
        double area_b, gap_b;
        TS_OK(b, gfmd_get_contact_area(b, &area_b));
        TS_OK(b, gfmd_get_mean_gap(b, &gap_b));
        print_message("flag %d: %lld + 1 iterations (the original %lld), A/A0 %.8f, gap %.12g\n", v,
                      (long long)steps_b, (long long)steps_a, area_b, gap_b);
        /* both at 1e-10 of the pressure scale: the same contact points, the gap to 1e-8 */
        assert_true(area_b == area_a && ts_rel(gap_b, gap_a) < 1e-8);
        if (flag == saved) assert_int_equal(steps_b + 1, steps_a); /* the file as saved: the original run */
        gfmd_sim_destroy(&b);
    }
    assert_memory_not_equal(first[1], first[2], sizeof first[1]);
    const double bad[] = {3.0, -1.0, 0.5, NAN};
    for (size_t j = 0; j < sizeof bad / sizeof bad[0]; ++j) {
        memcpy(buf + flag_at, &bad[j], 8);
        write_rehashed5("damaged.gfmd", buf, n, 4);
        expect_refused(GFMD_ERR_FORMAT, "surface CG flag out of range");
    }
    free(buf);
    gfmd_sim_destroy(&a);
    remove(PATH);
    remove("damaged.gfmd");
}

/* The Newton solver's state is its trust region's radius in units of rho (used with adhesion; one
 * number, >= 0.3).  A file of a library before the trust region holds none: it loads, with the
 * radius of a restart, and relaxes to the tolerance; a radius below the floor, negative, NaN or
 * infinite is refused (gfmd.h: a checkpoint that is not one the library wrote).  64^2 (the solver
 * takes square power-of-2 grids), restart_process's adhesive sheet, 2 steps: the radius grew to 4. */
static void newton_radius_values(void **state) {
    (void)state;
    enum { M = 64 };
    gfmd_sim *a = ts_create(M, M, (double)M, (double)M);
    TS_OK(a, gfmd_generate_selfaffine(a, 0.8, 16.0, 4.0, 0.1, 9, GFMD_DIST_UNIFORM));
    TS_OK(a, gfmd_set_green(a, GFMD_GREEN_LAYER_FLUID, 0.35));
    TS_OK(a, gfmd_set_adhesion(a, 1e-4, 0.5));
    TS_OK(a, gfmd_set_pressure(a, 2e-5));
    TS_OK(a, gfmd_set_solver(a, GFMD_SOLVER_NEWTON));
    TS_OK(a, gfmd_step(a, 2));
    long n = 0;
    double radius = -1.0;
    unsigned char *buf = saved_with_state(a, 1, 0, &n, &radius);
    print_message("radius after 2 steps: %g rho\n", radius);
    assert_true(radius > 1.0); /* it grew: the state is not the restart's */
    const double bad[] = {0.2, -1.0, NAN, INFINITY};
    for (size_t j = 0; j < sizeof bad / sizeof bad[0]; ++j) {
        memcpy(buf + OFF_STATE + 4, &bad[j], 8);
        write_rehashed5_grid("damaged.gfmd", buf, n, 3, M, M);
        expect_refused(GFMD_ERR_FORMAT, "Newton radius out of range");
    }
    /* without the number, as an older library wrote it */
    const long cut = OFF_STATE + 4;
    memmove(buf + cut, buf + cut + 8, (size_t)(n - cut - 8));
    const uint32_t none = 0;
    memcpy(buf + OFF_STATE, &none, 4);
    write_rehashed5_grid(PATH, buf, n - 8, 3, M, M);
    gfmd_sim *b = load_running(GFMD_SOLVER_NEWTON);
    TS_OK(b, gfmd_relax(b, 1e-9, 10000, NULL));
    free(buf);
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
    remove(PATH);
    remove("damaged.gfmd");
}

/* A GFMD_SOLVER_APPROACH_THEN_FIRE file written before mass-weighted FIRE kept its frequency estimates per
 * contact bucket (7 numbers of state: the approach's count, the mass-weighted control's 3 and
 * FIRE's 3, instead of 1 + 51 + 3) still loads and resumes bit for bit: the approach keeps the
 * step it had then and never reads the estimates.  Saved inside the approach (37 of its 100
 * steps) and resumed past its switch to FIRE. */
static void mass_fire_state_without_estimates_resumes(void **state) {
    (void)state;
    gfmd_sim *a = make(GFMD_SOLVER_APPROACH_THEN_FIRE);
    TS_OK(a, gfmd_step(a, 37));
    /* 1 + 51 + 3 numbers, the approach's count first (37); the 48 estimates after the
     * mass-weighted control dropped; fields h, z and v */
    gfmd_sim *b = saved_without(a, 1 + 51 + 3, 0, 37.0, 1 + 3, 48, 3);
    TS_OK(a, gfmd_step(a, 80));
    TS_OK(b, gfmd_step(b, 80));
    same_surfaces_then_destroy(a, b);
}

/* Files with a valid checksum that are still wrong: unknown flags, and a small file whose header
 * claims a huge grid (refused from its length, before anything is allocated: the message says so). */
static void forged_headers_are_refused(void **state) {
    (void)state;
    long n = 0;
    unsigned char *buf = saved_fire_file(&n);
    buf[OFF_FLAGS] = 1;
    write_rehashed5("damaged.gfmd", buf, n, 3);
    expect_refused(GFMD_ERR_FORMAT, "unknown flags");
    buf[OFF_FLAGS] = 0;
    const int64_t big = 4096;
    memcpy(buf + OFF_NX, &big, 8);
    memcpy(buf + OFF_NX + 8, &big, 8);
    memmove(buf + OFF_FIELDS + 4, buf + n - 8, 8); /* a 184-byte file: format 5's header and a hash only */
    write_rehashed("damaged.gfmd", buf, OFF_FIELDS + 4 + 8);
    gfmd_sim *s = NULL;
    char msg[256] = "";
    assert_int_equal(gfmd_sim_load("damaged.gfmd", &s, msg, sizeof msg), GFMD_ERR_FORMAT);
    assert_null(s);
    assert_non_null(strstr(msg, "implies"));
    /* the message buffer is always terminated, even when the path is missing */
    char small[8] = {'x', 'x', 'x', 'x', 'x', 'x', 'x', 'x'};
    assert_int_equal(gfmd_sim_load(NULL, &s, small, sizeof small), GFMD_ERR_NULL);
    assert_true(memchr(small, '\0', sizeof small) != NULL);
    memset(small, 'x', sizeof small);
    assert_int_equal(gfmd_sim_load("damaged.gfmd", NULL, small, sizeof small), GFMD_ERR_NULL);
    assert_true(memchr(small, '\0', sizeof small) != NULL);
    free(buf);
    remove("damaged.gfmd");
    remove(PATH);
}

/* The combination the setters refuse (GFMD_ERR_STATE: adhesion, the CG and displacement control)
 * cannot come in through a file either: a checkpoint of the adhesive CG under pressure control,
 * its control patched to displacement control (at the surface's own mean, which the loader
 * adopts) and rehashed, is refused with GFMD_ERR_FORMAT -- with the CG set, and with AUTO set and
 * the CG recorded as its choice.  The same patch on the same file without adhesion (gamma0 = 0)
 * loads: the refusal is the combination's, not the patch's. */
enum { OFF_GAMMA0 = 84, OFF_SOLVER = 116, OFF_MEAN_Z = 124, OFF_ACTIVE = 140 };

static void forged_cg_with_adhesion_under_displacement_is_refused(void **state) {
    (void)state;
    gfmd_sim *a = make(GFMD_SOLVER_CG); /* bonded, adhesive, pressure control: the adhesive CG */
    TS_OK(a, gfmd_step(a, 5));
    double z[NX * NY], mean = 0.0;
    TS_OK(a, gfmd_get_surface(a, z));
    for (int i = 0; i < NX * NY; ++i) mean += z[i];
    mean /= NX * NY;
    TS_OK(a, gfmd_sim_save(a, PATH));
    gfmd_sim_destroy(&a);
    long n = 0;
    unsigned char *buf = read_all(PATH, &n);
    uint32_t count = 0;
    memcpy(&count, buf + OFF_STATE, 4);
    const long fields_at = OFF_STATE + 4 + 8L * count + 4;
    const int k = (int)((n - 8 - fields_at) / (8L * NX * NY + 8L * NY)); /* h, z, v and the CG's own */
    assert_int_equal(fields_at + k * (8L * NX * NY + 8L * NY) + 8, n);
    const int32_t displacement = 1, auto_solver = GFMD_SOLVER_AUTO, cg = GFMD_SOLVER_CG;
    int32_t active = -1;
    memcpy(&active, buf + OFF_ACTIVE, 4);
    assert_int_equal(active, cg);
    memcpy(buf + OFF_CONTROL, &displacement, 4);
    memcpy(buf + OFF_MEAN_Z, &mean, 8);
    write_rehashed5("damaged.gfmd", buf, n, k);
    expect_refused_saying(GFMD_ERR_FORMAT, "CG with adhesion under displacement control", "adhesion under pressure control only");
    memcpy(buf + OFF_SOLVER, &auto_solver, 4);
    write_rehashed5("damaged.gfmd", buf, n, k);
    expect_refused_saying(GFMD_ERR_FORMAT, "AUTO's CG with adhesion under displacement control",
                          "adhesion under pressure control only");

    const double none = 0.0;
    memcpy(buf + OFF_SOLVER, &cg, 4);
    memcpy(buf + OFF_GAMMA0, &none, 8);
    write_rehashed5("damaged.gfmd", buf, n, k);
    gfmd_sim *b = NULL;
    char msg[256] = "";
    if (gfmd_sim_load("damaged.gfmd", &b, msg, sizeof msg) != GFMD_OK) fail_msg("without adhesion: %s", msg);
    int32_t solver = -1;
    TS_OK(b, gfmd_get_solver(b, &solver));
    assert_int_equal(solver, cg);
    TS_OK(b, gfmd_step(b, 3)); /* it steps */
    gfmd_sim_destroy(&b);
    free(buf);
    remove("damaged.gfmd");
    remove(PATH);
}

/* A save that fails half-way (the file size limit reached while writing the fields) reports
 * GFMD_ERR_IO and leaves neither the checkpoint nor its temporary file behind. */
static void failed_save_leaves_nothing(void **state) {
    (void)state;
    gfmd_sim *a = make(GFMD_SOLVER_FIRE);
    remove(PATH);
    struct rlimit old;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN); /* a write beyond the limit fails with EFBIG */
    struct rlimit small = old;
    small.rlim_cur = 4096; /* the header fits, the fields (3 x 7680 bytes) do not */
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
    const int32_t st = gfmd_sim_save(a, PATH);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
    signal(SIGXFSZ, old_handler);
    assert_int_equal(st, GFMD_ERR_IO);
    char tmp[256];
    snprintf(tmp, sizeof tmp, "%s.tmp", PATH);
    FILE *f = fopen(tmp, "rb");
    assert_null(f);
    f = fopen(PATH, "rb");
    assert_null(f);
    TS_OK(a, gfmd_sim_save(a, PATH)); /* the handle still saves once the limit is gone */
    remove(PATH);
    gfmd_sim_destroy(&a);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(restart_is_bit_exact),
        cmocka_unit_test(damaged_files_are_refused),
        cmocka_unit_test(older_formats_resume),
        cmocka_unit_test(row_hashes_are_checked),
        cmocka_unit_test(auto_choice_survives_restart),
        cmocka_unit_test(cg_restart_is_bit_exact),
        cmocka_unit_test(cg_state_without_count_resumes),
        cmocka_unit_test(pk_restarts_when_every_pressure_clears),
        cmocka_unit_test(surface_cg_flag_values),
        cmocka_unit_test(mass_fire_state_without_estimates_resumes),
        cmocka_unit_test(newton_radius_values),
        cmocka_unit_test(forged_headers_are_refused),
        cmocka_unit_test(forged_cg_with_adhesion_under_displacement_is_refused),
        cmocka_unit_test(failed_save_leaves_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
