/* Restart in a new process, the way a user's job script does it.
 *   restart_process save <dir>    create (default planner), switch to GFMD_PLANNER_ESTIMATE, surface,
 *                                 30 steps, save <dir>/run.gfmd, export wisdom <dir>/wisdom, 50 more
 *                                 steps, write z to <dir>/z_straight.bin
 *   restart_process resume <dir>  (a fresh process) import the wisdom before any handle exists,
 *                                 load, 50 steps, write z to <dir>/z_resumed.bin
 * The ctest (resume.cmake) runs both and compares the two files byte for byte: the promise that a
 * checkpoint resumes bit for bit with GFMD_PLANNER_ESTIMATE, and that exported wisdom imports in a
 * fresh process.  The library's default solver on this small half-space is CG (asserted below), so
 * its contact pressure, grid-sized state in the file, is what the resumed run continues from.
 * Then the same for an adhesive thin sheet at a low load, where the default is mass-weighted FIRE
 * (asserted; q_max w = 1.1 < 4): saved after 60 steps, with the frequency estimates of the contact
 * buckets entered so far in its state, resumed for 80 more (<dir>/sheet.gfmd, sheet_straight.bin,
 * sheet_resumed.bin); and the Newton solver on a square thin sheet (newton.gfmd, newton_*.bin), and
 * on the same sheet with adhesion, where its trust region's radius is state that the file must
 * keep (newton_adhesive.gfmd, newton_adhesive_*.bin; it fails with the radius left out: checked).
 * And a plastic run (a hardness the rough contact reaches: FIRE, the load step's substrate and the
 * yielding points in the file): saved after 40 steps with points yielding, resumed for 60 more;
 * its surface and its flattened heights (plastic_*.bin).  And an adhesive contact with free
 * boundaries (the default's CG on the padded cell, its pressure in the file): saved after 12
 * steps, resumed for 15 more, its boundary asserted on both sides (free_*.bin). */
#include <gfmd.h>
#include <stdio.h>
#include <string.h>

enum { NX = 64, NY = 48 };

static int ok(gfmd_sim *s, int32_t st, const char *what) {
    if (st == GFMD_OK) return 1;
    char msg[256] = "";
    if (s) gfmd_last_error(s, msg, sizeof msg);
    fprintf(stderr, "restart_process: %s: %s %s\n", what, gfmd_status_string(st), msg);
    return 0;
}

/* the surface of an NX x ny grid (ny <= NX) into dir/name */
static int write_z_of(gfmd_sim *s, int64_t ny, const char *dir, const char *name) {
    static double z[NX * NX];
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    int good = f && ok(s, gfmd_get_surface(s, z), "surface") && fwrite(z, sizeof z[0] * (size_t)(NX * ny), 1, f) == 1;
    if (f) fclose(f);
    return good;
}

static int write_z(gfmd_sim *s, const char *dir, const char *name) { return write_z_of(s, NY, dir, name); }

static int solver_is(const gfmd_sim *s, int32_t expected) {
    int32_t solver = -1;
    if (gfmd_get_solver(s, &solver) != GFMD_OK || solver != expected) {
        fprintf(stderr, "restart_process: the default solver is %d, not %d\n", (int)solver, (int)expected);
        return 0;
    }
    return 1;
}

static int is_cg(const gfmd_sim *s) { return solver_is(s, GFMD_SOLVER_CG); }

/* A thin sheet on a fluid foundation, saved after `before` steps and resumed for `after` more
 * (<dir>/NAME.gfmd, NAME_straight.bin, NAME_resumed.bin), its solver asserted on both sides. */
typedef struct {
    const char *name;
    int64_t ny;
    double width, gamma0, pressure;
    int32_t set, expected; /* the solver set (-1: the default) and the one that must step */
    int64_t before, after;
} sheet_run;

static int sheet(const sheet_run *c, const char *dir, int resume) {
    char path[1024], straight[256], resumed[256];
    snprintf(path, sizeof path, "%s/%s.gfmd", dir, c->name);
    snprintf(straight, sizeof straight, "%s_straight.bin", c->name);
    snprintf(resumed, sizeof resumed, "%s_resumed.bin", c->name);
    gfmd_sim *s = NULL;
    int good;
    if (!resume) {
        good = ok(NULL, gfmd_sim_create_ex(NX, c->ny, NX, (double)c->ny, 1, GFMD_PLANNER_ESTIMATE, &s), "create sheet") &&
               ok(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 0.1, 9, GFMD_DIST_UNIFORM), "sheet surface") &&
               ok(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, c->width), "sheet body") &&
               (c->gamma0 == 0.0 || ok(s, gfmd_set_adhesion(s, c->gamma0, 0.5), "sheet adhesion")) &&
               ok(s, gfmd_set_pressure(s, c->pressure), "sheet pressure") &&
               (c->set < 0 || ok(s, gfmd_set_solver(s, c->set), "sheet solver")) && solver_is(s, c->expected) &&
               ok(s, gfmd_step(s, c->before), "sheet steps") && ok(s, gfmd_sim_save(s, path), "save sheet") &&
               ok(s, gfmd_step(s, c->after), "sheet steps") && write_z_of(s, c->ny, dir, straight);
    } else {
        char msg[256] = "";
        const int32_t st = gfmd_sim_load(path, &s, msg, sizeof msg);
        if (st != GFMD_OK) fprintf(stderr, "restart_process: load sheet: %s\n", msg);
        good = st == GFMD_OK && solver_is(s, c->expected) && ok(s, gfmd_step(s, c->after), "sheet steps") &&
               write_z_of(s, c->ny, dir, resumed);
    }
    gfmd_sim_destroy(&s);
    return good;
}

/* The adhesive thin sheet: w = 0.25 (f(q_min w) = 2e5), Persson's A/A0 0.05, the default's
 * mass-weighted FIRE; and the Newton solver on a square grid without adhesion (w = 0.35, its cycle
 * rebuilt from the loaded surface: 2 steps, then 3) and with it (its radius from the file: 2 steps,
 * then 4; the radius grows to 4 rho in the first 2 and the third step reaches it). */
static const sheet_run SHEETS[3] = {
    {"sheet", NY, 0.25, 1e-4, 1e-5, -1, GFMD_SOLVER_MASS_WEIGHTED_FIRE, 60, 80},
    {"newton", NX, 0.35, 0.0, 2e-5, GFMD_SOLVER_NEWTON, GFMD_SOLVER_NEWTON, 2, 3},
    {"newton_adhesive", NX, 0.35, 1e-4, 2e-5, GFMD_SOLVER_NEWTON, GFMD_SOLVER_NEWTON, 2, 4},
};

static int sheets(const char *dir, int resume) {
    return sheet(&SHEETS[0], dir, resume) && sheet(&SHEETS[1], dir, resume) && sheet(&SHEETS[2], dir, resume);
}

/* the plastic run: z and then the (flattened) heights into dir/name */
static int write_plastic(gfmd_sim *s, const char *dir, const char *name) {
    static double h[NX * NY];
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (!write_z(s, dir, name) || !ok(s, gfmd_get_heights(s, h), "heights")) return 0;
    FILE *f = fopen(path, "ab");
    const int good = f && fwrite(h, sizeof h, 1, f) == 1;
    if (f) fclose(f);
    return good;
}

static int plastic(const char *dir, int resume) {
    char path[1024];
    snprintf(path, sizeof path, "%s/plastic.gfmd", dir);
    gfmd_sim *s = NULL;
    int good;
    if (!resume) {
        double area = 0.0;
        good = ok(NULL, gfmd_sim_create_ex(NX, NY, NX, NY, 1, GFMD_PLANNER_ESTIMATE, &s), "create plastic") &&
               ok(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 1.0, 9, GFMD_DIST_UNIFORM), "plastic surface") &&
               ok(s, gfmd_set_hardness(s, 0.3), "hardness") && ok(s, gfmd_set_pressure(s, 0.05), "plastic load") &&
               solver_is(s, GFMD_SOLVER_FIRE) && ok(s, gfmd_step(s, 40), "plastic steps") &&
               ok(s, gfmd_get_plasticity(s, &area, NULL), "plasticity") && ok(s, gfmd_sim_save(s, path), "save plastic") &&
               ok(s, gfmd_step(s, 60), "plastic steps") && write_plastic(s, dir, "plastic_straight.bin");
        if (good && !(area > 0.0)) {
            fprintf(stderr, "restart_process: no point yields in the plastic run\n");
            good = 0;
        }
    } else {
        char msg[256] = "";
        const int32_t st = gfmd_sim_load(path, &s, msg, sizeof msg);
        if (st != GFMD_OK) fprintf(stderr, "restart_process: load plastic: %s\n", msg);
        good = st == GFMD_OK && solver_is(s, GFMD_SOLVER_FIRE) && ok(s, gfmd_step(s, 60), "plastic steps") &&
               write_plastic(s, dir, "plastic_resumed.bin");
    }
    gfmd_sim_destroy(&s);
    return good;
}

static int free_boundary(const char *dir, int resume) {
    char path[1024];
    snprintf(path, sizeof path, "%s/free.gfmd", dir);
    gfmd_sim *s = NULL;
    int32_t boundary = -1;
    int good;
    if (!resume) {
        good = ok(NULL, gfmd_sim_create_ex(NX, NY, NX, NY, 1, GFMD_PLANNER_ESTIMATE, &s), "create free") &&
               ok(s, gfmd_set_boundary(s, GFMD_BOUNDARY_FREE), "free boundary") &&
               ok(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 1.0, 9, GFMD_DIST_UNIFORM), "free surface") &&
               ok(s, gfmd_set_adhesion(s, 1e-3, 0.5), "free adhesion") && ok(s, gfmd_set_pressure(s, 0.05), "free load") &&
               is_cg(s) && ok(s, gfmd_step(s, 12), "free steps") && ok(s, gfmd_sim_save(s, path), "save free") &&
               ok(s, gfmd_step(s, 15), "free steps") && write_z(s, dir, "free_straight.bin");
    } else {
        char msg[256] = "";
        const int32_t st = gfmd_sim_load(path, &s, msg, sizeof msg);
        if (st != GFMD_OK) fprintf(stderr, "restart_process: load free: %s\n", msg);
        good = st == GFMD_OK && is_cg(s) && ok(s, gfmd_step(s, 15), "free steps") &&
               write_z(s, dir, "free_resumed.bin");
    }
    if (good && (gfmd_get_boundary(s, &boundary) != GFMD_OK || boundary != GFMD_BOUNDARY_FREE)) {
        fprintf(stderr, "restart_process: the boundary is %d, not free\n", (int)boundary);
        good = 0;
    }
    gfmd_sim_destroy(&s);
    return good;
}

int main(int argc, char **argv) {
    if (argc != 3) return 2;
    const char *dir = argv[2];
    char ckpt[1024], wisdom[1024];
    snprintf(ckpt, sizeof ckpt, "%s/run.gfmd", dir);
    snprintf(wisdom, sizeof wisdom, "%s/wisdom", dir);
    gfmd_sim *s = NULL;
    if (!strcmp(argv[1], "save")) {
        int good = ok(NULL, gfmd_sim_create(NX, NY, NX, NY, &s), "create") &&
                   ok(s, gfmd_set_fft_planner(s, GFMD_PLANNER_ESTIMATE), "planner") &&
                   ok(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 1.0, 9, GFMD_DIST_UNIFORM), "surface") &&
                   ok(s, gfmd_set_pressure(s, 0.05), "pressure") && is_cg(s) && ok(s, gfmd_step(s, 30), "steps") &&
                   ok(s, gfmd_sim_save(s, ckpt), "save") && ok(s, gfmd_export_wisdom(wisdom), "export wisdom") &&
                   ok(s, gfmd_step(s, 50), "steps") && write_z(s, dir, "z_straight.bin");
        gfmd_sim_destroy(&s);
        return good && sheets(dir, 0) && plastic(dir, 0) && free_boundary(dir, 0) ? 0 : 1;
    }
    if (!strcmp(argv[1], "resume")) {
        char msg[256] = "";
        int good = ok(NULL, gfmd_import_wisdom(wisdom), "import wisdom in a fresh process");
        int32_t st = gfmd_sim_load(ckpt, &s, msg, sizeof msg);
        if (st != GFMD_OK) fprintf(stderr, "restart_process: load: %s\n", msg);
        good = good && st == GFMD_OK && is_cg(s) && ok(s, gfmd_step(s, 50), "steps") && write_z(s, dir, "z_resumed.bin");
        gfmd_sim_destroy(&s);
        return good && sheets(dir, 1) && plastic(dir, 1) && free_boundary(dir, 1) ? 0 : 1;
    }
    return 2;
}
