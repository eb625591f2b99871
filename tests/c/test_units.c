/* The units are the user's: the same body, load and solver in other units of length and stress
 * relax along the same trajectory.  The model has no constant of its own with a unit (the time
 * step and the masses follow from the stiffness, the tolerance is relative, the adhesive law's
 * range is the user's rho), so a change of units that multiplies every length by 2^-23 and every
 * stress by 2^37 -- E* about 1.4e11 Pa on a cell of micrometres, as a user of SI units would give
 * them -- scales every sum, product and quotient of the relaxation by a power of two, exactly:
 * the steps and the dimensionless results (A/A0, gap/a, U/(E* a^3), the mean pressure over E*)
 * must be the same bits, on every solver, under pressure and displacement control, with and
 * without adhesion.  A constant with a unit in the code shows as a difference: the approach of
 * GFMD_SOLVER_APPROACH_THEN_FIRE handed FIRE its velocity in the masked dynamics' units (the half-space
 * below took 261 steps in units of a and E*, 270 in these), and the projection of displacement
 * control stopped its root search at an absolute 1e-15 (1e-9 of the lengths in these units; the
 * CG's gap then differed in the last bit).  In units that are not powers of two (E* = 2e11,
 * a = 0.15625 um) the roundings differ, and the runs agree to the tolerance: each to a residual
 * of 1e-10, the results within 1e-9 of each other (measured within 6e-12) and A/A0 within two
 * points of the grid. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "gfmd.h"
#include "test_support.h"

enum { NX = 32, NY = 24 };
enum { HALFSPACE, THIN_SHEET, STICKY_COATING, N_BODIES };
enum { N_OUT = 7 };

/* steps, A/A0, gap/a, U_el/(E* a^3), U_ad/(E* a^3), mean pressure/E*, mean position error/a.
 * Returns the status of gfmd_set_solver (a solver may refuse a body: then in every unit). */
static int32_t relax_in_units(double e_star, double a, int body, int displacement, int32_t solver, double out[N_OUT]) {
    gfmd_sim *s = NULL;
    TS_OK(NULL, gfmd_sim_create_ex(NX, NY, NX * a, NY * a, 1, GFMD_PLANNER_ESTIMATE, &s));
    TS_OK(s, gfmd_set_modulus(s, e_star));
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, NY * a / 2.0, 4.0 * a, 1.0, 11, GFMD_DIST_UNIFORM));
    if (body == THIN_SHEET) TS_OK(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 0.4 * a));
    if (body == STICKY_COATING) {
        TS_OK(s, gfmd_set_poisson(s, 0.3));
        TS_OK(s, gfmd_set_green(s, GFMD_GREEN_LAYER_BONDED, 8.0 * a));
        TS_OK(s, gfmd_set_adhesion(s, 5e-4 * e_star * a, a));
    }
    double top = -INFINITY;
    double *h = ts_alloc(NX * NY);
    TS_OK(s, gfmd_get_heights(s, h));
    for (int i = 0; i < NX * NY; ++i) top = fmax(top, h[i]);
    free(h);
    const double mean_z = top - 3.0 * a;
    if (displacement)
        TS_OK(s, gfmd_set_mean_displacement(s, mean_z));
    else
        TS_OK(s, gfmd_set_pressure(s, (body == THIN_SHEET ? 5e-4 : 1e-2) * e_star));
    const int32_t st = gfmd_set_solver(s, solver);
    if (st == GFMD_OK) {
        int64_t steps = 0;
        TS_OK(s, gfmd_relax(s, 1e-10, 100000, &steps));
        double area, gap, u_el, u_ad, p, d;
        TS_OK(s, gfmd_get_contact_area(s, &area));
        TS_OK(s, gfmd_get_mean_gap(s, &gap));
        TS_OK(s, gfmd_get_energies(s, &u_el, &u_ad));
        TS_OK(s, gfmd_get_mean_pressure(s, &p));
        TS_OK(s, gfmd_get_mean_displacement(s, &d));
        const double a3 = e_star * a * a * a;
        const double o[N_OUT] = {(double)steps, area, gap / a, u_el / a3, u_ad / a3, p / e_star,
                                 displacement ? (d - mean_z) / a : 0.0};
        memcpy(out, o, sizeof o);
    }
    gfmd_sim_destroy(&s);
    return st;
}

static void units_do_not_matter(void **state) {
    (void)state;
    const int32_t solvers[] = {GFMD_SOLVER_AUTO, GFMD_SOLVER_FIRE, GFMD_SOLVER_MASS_WEIGHTED_FIRE, GFMD_SOLVER_APPROACH_THEN_FIRE,
                               GFMD_SOLVER_CG, GFMD_SOLVER_VERLET};
    const int n_solvers = (int)(sizeof solvers / sizeof solvers[0]);
    int compared = 0;
    for (int body = 0; body < N_BODIES; ++body) {
        for (int displacement = 0; displacement < 2; ++displacement) {
            for (int k = 0; k < n_solvers; ++k) {
                /* the damped dynamics once (it takes thousands of steps on the layers), and not
                 * under valgrind, which runs it in test_continuation and test_hertz */
                if (solvers[k] == GFMD_SOLVER_VERLET && (body != HALFSPACE || displacement || ts_valgrind())) continue;
                double ref[N_OUT] = {0}, pow2[N_OUT] = {0}, si[N_OUT] = {0};
                const int32_t st = relax_in_units(1.0, 1.0, body, displacement, solvers[k], ref);
                assert_int_equal(relax_in_units(0x1p37, 0x1p-23, body, displacement, solvers[k], pow2), st);
                if (st != GFMD_OK) continue; /* refused alike in every unit (the CG, adhesion, displacement) */
                if (memcmp(ref, pow2, sizeof ref) != 0)
                    fail_msg("body %d, displacement %d, solver %d: steps %g/%g, A/A0 %.17g/%.17g, gap %.17g/%.17g",
                             body, displacement, (int)solvers[k], ref[0], pow2[0], ref[1], pow2[1], ref[2], pow2[2]);
                assert_true(fabs(ref[6]) <= 1e-12); /* the mean held */
                ++compared;
                /* under valgrind the units that are not powers of two are left out: the same code */
                if (ts_valgrind()) continue;
                assert_int_equal(relax_in_units(2e11, 1.5625e-7, body, displacement, solvers[k], si), st);
                assert_true(fabs(si[1] - ref[1]) * NX * NY <= 2.0);
                for (int j = 2; j < 6; ++j) assert_true(fabs(si[j] - ref[j]) <= 1e-9 * fmax(fabs(ref[j]), 1e-300));
                assert_true(fabs(si[6]) <= 1e-12);
            }
        }
    }
    /* 31 combinations (30 under valgrind, without the damped dynamics), less the one the CG
     * refuses (adhesion under displacement control) */
    assert_int_equal(compared, ts_valgrind() ? 29 : 30);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(units_do_not_matter),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
