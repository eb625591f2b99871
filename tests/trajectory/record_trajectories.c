/* Records, for every solver and three bodies, the trajectory a fixed setup follows: one relax from
 * a fresh state, then 50 more steps.  Prints one line per (solver, body, stage): steps, A/A0,
 * mean gap, U_el, U_ad (all as exact hexadecimal doubles) and an FNV-1a hash of the surface z.
 * The ctest compares this output with tests/trajectory/reference.txt, recorded with the library
 * before the core was restructured: any change in the arithmetic of forces, solvers, observables or
 * the order of sums shows as a changed line.
 *
 * Deterministic plans: one thread and the ESTIMATE planner chosen before the first plan
 * (gfmd_sim_create_ex), so that no timing-dependent FFTW_MEASURE plan enters the arithmetic.
 *   record_trajectories [output-file]   (stdout without an argument)
 * Re-record (only after a change meant to alter the arithmetic, said so in its commit):
 *   build/tests/record_trajectories tests/trajectory/reference.txt */
#include <gfmd.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>

static uint64_t fnv1a(const double *z, int64_t n) {
    const unsigned char *b = (const unsigned char *)z;
    uint64_t h = 0xcbf29ce484222325ULL;
    for (int64_t i = 0; i < n * (int64_t)sizeof(double); ++i) h = (h ^ b[i]) * 0x100000001b3ULL;
    return h;
}

static int check(gfmd_sim *s, int32_t st, const char *what) {
    if (st == GFMD_OK) return 0;
    char msg[256] = "";
    if (s) gfmd_last_error(s, msg, sizeof msg);
    fprintf(stderr, "record_trajectories: %s: %s: %s\n", what, gfmd_status_string(st), msg);
    return 1;
}

static int record(FILE *out, gfmd_sim *s, const char *solver, const char *body, const char *stage,
                  int64_t steps, double *z, int64_t n) {
    double area = 0.0, gap = 0.0, uel = 0.0, uad = 0.0;
    if (check(s, gfmd_get_contact_area(s, &area), "area") || check(s, gfmd_get_mean_gap(s, &gap), "gap") ||
        check(s, gfmd_get_energies(s, &uel, &uad), "energies") || check(s, gfmd_get_surface(s, z), "surface"))
        return 1;
    fprintf(out, "%s %s %s steps=%" PRId64 " area=%a gap=%a uel=%a uad=%a z=%016" PRIx64 "\n", solver, body,
            stage, steps, area, gap, uel, uad, fnv1a(z, n));
    return 0;
}

int main(int argc, char **argv) {
    FILE *out = (argc > 1) ? fopen(argv[1], "w") : stdout;
    if (out == NULL) return 2;
    const int64_t nx = 64, ny = 48; /* non-square: the layout matters */
    const int32_t solvers[4] = {GFMD_SOLVER_VERLET, GFMD_SOLVER_FIRE, GFMD_SOLVER_MASS_WEIGHTED_FIRE, GFMD_SOLVER_APPROACH_THEN_FIRE};
    const char *solver_names[4] = {"verlet", "fire", "fire_mass", "mass_fire"};
    const char *body_names[3] = {"halfspace", "fluid_w4", "bonded_w8_adhesive"};
    double *z = malloc(sizeof(double) * (size_t)(nx * ny));
    int bad = (z == NULL);
    for (int si = 0; si < 4 && !bad; ++si) {
        for (int b = 0; b < 3 && !bad; ++b) {
            gfmd_sim *s = NULL;
            bad |= check(NULL, gfmd_sim_create_ex(nx, ny, (double)nx, (double)ny, 1, GFMD_PLANNER_ESTIMATE, &s), "create");
            if (bad) break;
            bad |= check(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 0.5, 7, GFMD_DIST_UNIFORM), "surface");
            if (b == 1) bad |= check(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 4.0), "fluid layer");
            if (b == 2) {
                bad |= check(s, gfmd_set_poisson(s, 0.3), "poisson");
                bad |= check(s, gfmd_set_green(s, GFMD_GREEN_LAYER_BONDED, 8.0), "bonded layer");
                bad |= check(s, gfmd_set_adhesion(s, 2e-3, 0.5), "adhesion");
            }
            bad |= check(s, gfmd_set_pressure(s, 0.03), "pressure");
            bad |= check(s, gfmd_set_solver(s, solvers[si]), "solver");
            int64_t steps = 0;
            bad |= check(s, gfmd_relax(s, 0.0, 20000, &steps), "relax");
            bad |= record(out, s, solver_names[si], body_names[b], "relax", steps, z, nx * ny);
            bad |= check(s, gfmd_step(s, 50), "step");
            bad |= record(out, s, solver_names[si], body_names[b], "step50", 50, z, nx * ny);
            gfmd_sim_destroy(&s);
        }
    }
    free(z);
    if (out != stdout) fclose(out);
    return bad ? 1 : 0;
}
