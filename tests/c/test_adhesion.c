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
    TS_OK(s, gfmd_set_solver(s, solver));
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 1.0, 77, GFMD_DIST_UNIFORM));
    if (kind != GFMD_GREEN_HALFSPACE) TS_OK(s, gfmd_set_green(s, kind, width));
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
    check_body(GFMD_GREEN_HALFSPACE, 0.0, GFMD_SOLVER_FIRE_MASS);
    check_body(GFMD_GREEN_LAYER_FLUID, 8.0, GFMD_SOLVER_FIRE_MASS);
    check_body(GFMD_GREEN_LAYER_FLUID, 1.0, GFMD_SOLVER_FIRE_MASS);
}

/* And for the approach then FIRE (the default's choice on adhesive thin sheets). */
static void adhesion_approach_then_fire(void **state) {
    (void)state;
    check_body(GFMD_GREEN_LAYER_FLUID, 1.0, GFMD_SOLVER_MASS_FIRE);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(adhesion_halfspace),
        cmocka_unit_test(adhesion_layer),
        cmocka_unit_test(adhesion_mass_weighted),
        cmocka_unit_test(adhesion_approach_then_fire),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
