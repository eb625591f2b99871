/* Adhesion.  With gamma0 > 0 the contact area at a given load grows, the relaxed state is
 * a minimum of the total energy U_el - U_ad + sigma0 A <z> (no small admissible perturbation
 * lowers it), the library's energies equal the test's own evaluation of their definitions, and
 * the substrate's stress still balances the load. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "gfmd.h"
#include "test_support.h"

enum { N = 64 };
static const double L = 64.0, SIGMA0 = 0.02, GAMMA0 = 0.01, RHO = 0.5;

typedef struct {
    int32_t kind;
    double width;
    const double *h;
} body;

/* Total energy of the surface z, evaluated by the test from the model's definitions. */
static double total_energy(const body *b, const double *z, double *u_el, double *u_ad) {
    double ad = 0.0, zbar = 0.0;
    for (int i = 0; i < N * N; ++i) {
        ad += exp(-(z[i] - b->h[i]) / RHO);
        zbar += z[i];
    }
    *u_ad = GAMMA0 * ad * L * L / (N * N);
    *u_el = ts_elastic_energy(N, N, L, L, b->kind, b->width, 0.0, 1.0, z);
    return *u_el - *u_ad + SIGMA0 * L * L * zbar / (N * N);
}

static void check_body(int32_t kind, double width, int32_t solver) {
    gfmd_sim *s = ts_create(N, N, L, L);
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 1.0, 77, GFMD_DIST_UNIFORM));
    if (kind != GFMD_GREEN_HALFSPACE) TS_OK(s, gfmd_set_green(s, kind, width));
    TS_OK(s, gfmd_set_solver(s, solver));
    TS_OK(s, gfmd_set_pressure(s, SIGMA0));
    int64_t steps = 0;
    double a_plain = 0.0, a_adh = 0.0;
    TS_OK(s, gfmd_relax(s, 1e-9, 200000, &steps));
    TS_OK(s, gfmd_get_contact_area(s, &a_plain));
    TS_OK(s, gfmd_set_adhesion(s, GAMMA0, RHO));
    TS_OK(s, gfmd_relax(s, 1e-9, 200000, &steps));
    TS_OK(s, gfmd_get_contact_area(s, &a_adh));
    print_message("solver %d kind %d: A/A0 %.4f without adhesion, %.4f with\n", solver, kind, a_plain, a_adh);
    assert_true(a_adh > a_plain);

    double *h = ts_alloc(N * N), *z = ts_alloc(N * N), *zp = ts_alloc(N * N), *p = ts_alloc(N * N);
    TS_OK(s, gfmd_get_heights(s, h));
    TS_OK(s, gfmd_get_surface(s, z));
    TS_OK(s, gfmd_get_pressure(s, p));
    body b = {kind, width, h};
    double lib_el = 0, lib_ad = 0, el = 0, ad = 0;
    TS_OK(s, gfmd_get_energies(s, &lib_el, &lib_ad));
    const double e0 = total_energy(&b, z, &el, &ad);
    /* same definitions, different code: agreement to rounding */
    assert_true(ts_rel(lib_el, el) < 1e-10);
    assert_true(ts_rel(lib_ad, ad) < 1e-10);
    assert_true(lib_ad > 0.0);

    /* Force balance with the adhesive pull included in the substrate's stress. */
    double psum = 0.0;
    for (int i = 0; i < N * N; ++i) psum += p[i];
    assert_true(ts_rel(psum / (N * N), SIGMA0) < 1e-6);

    /* Perturbations of size eps = 1e-3 (gap scale ~1): the second-order rise, >= k_min eps^2 per
     * point (~1e-7 of the energy), dominates the first-order term left by the residual 1e-9 by
     * orders of magnitude, so a true minimum gives a strictly positive change.  Admissible means
     * z + dz >= h: points in contact may only be lifted. */
    const double eps = 1e-3;
    srand(12345);
    for (int trial = 0; trial < 24; ++trial) {
        for (int iy = 0; iy < N; ++iy)
            for (int ix = 0; ix < N; ++ix) {
                int i = ix + N * iy;
                double dz;
                if (trial < 16)
                    dz = eps * (2.0 * rand() / (double)RAND_MAX - 1.0);        /* random field */
                else if (trial < 20)
                    dz = eps * cos(2.0 * M_PI * (trial - 15) * (ix + iy) / N); /* smooth modes */
                else
                    dz = (trial % 2 ? eps : -eps);                            /* rigid shifts */
                zp[i] = fmax(z[i] + dz, h[i]);
            }
        double e = total_energy(&b, zp, &el, &ad);
        assert_true(e > e0);
    }
    free(h);
    free(z);
    free(zp);
    free(p);
    gfmd_sim_destroy(&s);
}

/* solver and FIRE from the same start, both to a residual of 1e-10: the contact set to a point,
 * U_el and U_ad to 1e-7 */
static void same_equilibrium_as_fire(int32_t solver, int32_t kind, double width) {
    double area[2], el[2], ad[2];
    int64_t steps[2];
    const int32_t solvers[2] = {GFMD_SOLVER_FIRE, solver};
    for (int k = 0; k < 2; ++k) {
        gfmd_sim *s = ts_create(N, N, L, L);
        TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 1.0, 77, GFMD_DIST_UNIFORM));
        TS_OK(s, gfmd_set_poisson(s, 0.3));
        if (kind != GFMD_GREEN_HALFSPACE) TS_OK(s, gfmd_set_green(s, kind, width));
        TS_OK(s, gfmd_set_adhesion(s, GAMMA0, RHO));
        TS_OK(s, gfmd_set_solver(s, solvers[k]));
        int32_t active = -1;
        TS_OK(s, gfmd_get_solver(s, &active));
        assert_int_equal(active, solvers[k]);
        TS_OK(s, gfmd_set_pressure(s, SIGMA0));
        TS_OK(s, gfmd_relax(s, 1e-10, 400000, &steps[k]));
        TS_OK(s, gfmd_get_contact_area(s, &area[k]));
        TS_OK(s, gfmd_get_energies(s, &el[k], &ad[k]));
        gfmd_sim_destroy(&s);
    }
    print_message("solver %d, kind %d, w = %g: FIRE %lld steps, the other %lld; A/A0 %.6f / %.6f, U_el %.10g / %.10g, "
                  "U_ad %.10g / %.10g\n",
                  solver, kind, width, (long long)steps[0], (long long)steps[1], area[0], area[1], el[0], el[1], ad[0],
                  ad[1]);
    assert_true(fabs(area[0] - area[1]) * N * N <= 1.0);
    assert_true(ts_rel(el[0], el[1]) < 1e-7);
    assert_true(ts_rel(ad[0], ad[1]) < 1e-7);
}

static void adhesion_halfspace(void **state) {
    (void)state;
    check_body(GFMD_GREEN_HALFSPACE, 0.0, GFMD_SOLVER_FIRE);
}

static void adhesion_layer(void **state) {
    (void)state;
    check_body(GFMD_GREEN_LAYER_FLUID, 8.0, GFMD_SOLVER_FIRE);
}

/* The same checks for FIRE with mass weighting, down to a thin sheet (W = 0.25). */
static void adhesion_mass_weighted(void **state) {
    (void)state;
    check_body(GFMD_GREEN_HALFSPACE, 0.0, GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    check_body(GFMD_GREEN_LAYER_FLUID, 8.0, GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    check_body(GFMD_GREEN_LAYER_FLUID, 1.0, GFMD_SOLVER_MASS_WEIGHTED_FIRE);
}

/* And for the approach then FIRE (the default's choice on adhesive thin sheets). */
static void adhesion_approach_then_fire(void **state) {
    (void)state;
    check_body(GFMD_GREEN_LAYER_FLUID, 1.0, GFMD_SOLVER_APPROACH_THEN_FIRE);
}

/* And for the CG, which takes adhesion under pressure control (the surface CG, its line search
 * along the adhesive energy, its steps checked against it): the energy-minimum checks above on the
 * half-space, a thick layer and a thin one (W = 0.25), and the same equilibrium as FIRE from the
 * same start on every body -- the contact set to a point and the energies to 1e-7 (both relaxed
 * to a residual of 1e-10 of the stress scale, which bounds their distance from the same minimum
 * far below that). */
static void adhesion_cg(void **state) {
    (void)state;
    check_body(GFMD_GREEN_HALFSPACE, 0.0, GFMD_SOLVER_CG);
    check_body(GFMD_GREEN_LAYER_FLUID, 8.0, GFMD_SOLVER_CG);
    check_body(GFMD_GREEN_LAYER_FLUID, 1.0, GFMD_SOLVER_CG);
    const struct {
        int32_t kind;
        double width;
    } bodies[] = {{GFMD_GREEN_HALFSPACE, 0.0},
                  {GFMD_GREEN_LAYER_BONDED, 4.0},
                  {GFMD_GREEN_LAYER_FLUID, 1.0},
                  {GFMD_GREEN_LAYER_FLUID, 4.0},
                  {GFMD_GREEN_LAYER_FLUID, 16.0}};
    for (size_t w = 0; w < sizeof bodies / sizeof bodies[0]; ++w)
        same_equilibrium_as_fire(GFMD_SOLVER_CG, bodies[w].kind, bodies[w].width);
}

/* Every iteration of the adhesive CG (or step of the Newton method) lowers the energy U_el - U_ad +
 * sigma0 A <z> (its steps are checked against it): iterated one gfmd_step at a time from flat to
 * convergence, the energy evaluated through the public getters after each. */
static void descends(int32_t solver, const double *widths, size_t count) {
    for (size_t w = 0; w < count; ++w) {
        gfmd_sim *s = ts_create(N, N, L, L);
        TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 1.0, 77, GFMD_DIST_UNIFORM));
        if (widths[w] > 0.0) TS_OK(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, widths[w]));
        TS_OK(s, gfmd_set_adhesion(s, GAMMA0, RHO));
        TS_OK(s, gfmd_set_solver(s, solver));
        TS_OK(s, gfmd_set_pressure(s, SIGMA0));
        double last = HUGE_VAL, residual = 1.0;
        int k = 0, rises = 0;
        for (; k < 2000 && residual > 1e-10; ++k) {
            double el = 0.0, ad = 0.0, zbar = 0.0;
            TS_OK(s, gfmd_get_energies(s, &el, &ad));
            TS_OK(s, gfmd_get_mean_displacement(s, &zbar));
            const double e = el - ad + SIGMA0 * L * L * zbar;
            /* rounding: the energies are sums over 4096 points and modes, about 1e-13 of their size */
            if (e > last + 1e-11 * (fabs(el) + ad + SIGMA0 * L * L * fabs(zbar))) ++rises;
            last = e;
            TS_OK(s, gfmd_step(s, 1));
            TS_OK(s, gfmd_get_residual(s, &residual));
        }
        print_message("solver %d, w = %g: %d iterations to a residual of %.1e, the energy rose %d times\n", solver,
                      widths[w], k, residual, rises);
        assert_true(residual <= 1e-10);
        assert_int_equal(rises, 0);
        gfmd_sim_destroy(&s);
    }
}

/* on a half-space, a thick and a thin layer */
static void adhesion_cg_descends(void **state) {
    (void)state;
    const double widths[] = {0.0, 8.0, 1.0};
    descends(GFMD_SOLVER_CG, widths, 3);
}

/* The Newton method with adhesion (GFMD_SOLVER_NEWTON, its CG in a trust region on the non-convex
 * energy): the energy-minimum checks on thin sheets (W = w/lambda_s = 0.25, 0.125) and a thicker
 * layer (W = 1, where its stencil no longer stands for the layer: slower, not wrong); every step
 * lowers the energy (here the trust region alone keeps it so: these sheets passed with the line
 * search removed; test_newton's adhesive_descends is the sheet where that fails); and from the same start it ends where FIRE ends, as the CG does above (the
 * contact set to a point, the energies to 1e-7). */
static void adhesion_newton(void **state) {
    (void)state;
    const double widths[] = {1.0, 0.5, 4.0};
    /* under valgrind the first sheet's checks only (the same code; FIRE's comparison runs natively
     * and under the sanitizers) */
    const size_t count = ts_valgrind() ? 1 : 3;
    for (size_t w = 0; w < count; ++w) check_body(GFMD_GREEN_LAYER_FLUID, widths[w], GFMD_SOLVER_NEWTON);
    if (ts_valgrind()) return;
    descends(GFMD_SOLVER_NEWTON, widths, 2);
    for (size_t w = 0; w < 3; ++w) same_equilibrium_as_fire(GFMD_SOLVER_NEWTON, GFMD_GREEN_LAYER_FLUID, widths[w]);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(adhesion_halfspace),
        cmocka_unit_test(adhesion_layer),
        cmocka_unit_test(adhesion_mass_weighted),
        cmocka_unit_test(adhesion_approach_then_fire),
        cmocka_unit_test(adhesion_cg),
        cmocka_unit_test(adhesion_cg_descends),
        cmocka_unit_test(adhesion_newton),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
