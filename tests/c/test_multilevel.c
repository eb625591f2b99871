/* gfmd_relax_multilevel: a start made on coarser grids must end where a flat start ends (same
 * convergence test, same contact set, A/A0 and gap within 1e-6 relative), on a half-space, a thin
 * sheet on a fluid foundation, a bonded layer, with adhesion and under displacement control; runs
 * repeat bit for bit and agree across thread counts; bad levels change nothing. */
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

enum { N = 64 };

typedef struct {
    int32_t kind;
    double width, sigma0, gamma0;
    int displacement; /* prescribe the mean of z instead of the pressure */
} body;

static gfmd_sim *make(const body *b, int threads) {
    gfmd_sim *s = NULL;
    assert_int_equal(gfmd_sim_create_ex(N, N, N, N, threads, GFMD_PLANNER_ESTIMATE, &s), GFMD_OK);
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 1.0, 7, GFMD_DIST_UNIFORM));
    TS_OK(s, gfmd_set_poisson(s, 0.3));
    if (b->kind != GFMD_GREEN_HALFSPACE) TS_OK(s, gfmd_set_green(s, b->kind, b->width));
    if (b->gamma0 > 0.0) TS_OK(s, gfmd_set_adhesion(s, b->gamma0, 0.5));
    TS_OK(s, gfmd_set_pressure(s, b->sigma0));
    if (b->displacement) TS_OK(s, gfmd_set_mean_displacement(s, -2.0)); /* the highest peak is at 0 */
    return s;
}

static void state_of(const gfmd_sim *s, double out[3]) {
    TS_OK(s, gfmd_get_contact_area(s, &out[0]));
    TS_OK(s, gfmd_get_mean_gap(s, &out[1]));
    TS_OK(s, gfmd_get_residual(s, &out[2]));
}

static void agrees_with_flat_start(void **state) {
    (void)state;
    const body bodies[] = {
        {GFMD_GREEN_HALFSPACE, 0.0, 0.05, 0.0, 0},
        {GFMD_GREEN_LAYER_FLUID, 1.0, 2e-4, 0.0, 0}, /* thin sheet W = 0.25 at low load */
        {GFMD_GREEN_LAYER_BONDED, 8.0, 0.05, 0.0, 0},
        {GFMD_GREEN_LAYER_FLUID, 4.0, 0.02, 2e-3, 0}, /* adhesive layer W = 1 */
        {GFMD_GREEN_HALFSPACE, 0.0, 0.0, 0.0, 1},     /* displacement control */
    };
    /* relaxed to 1e-10, far below the default: both ends are the same minimum to ~1e-10, so the
     * contact sets agree exactly (the problems are not degenerate at these loads) */
    const double tol = 1e-10;
    for (size_t k = 0; k < sizeof bodies / sizeof bodies[0]; ++k) {
        gfmd_sim *flat = make(&bodies[k], 1), *ml = make(&bodies[k], 1);
        int64_t steps_flat = 0, steps_ml = 0, coarse = 0;
        TS_OK(flat, gfmd_relax(flat, tol, 2000000, &steps_flat));
        TS_OK(ml, gfmd_relax_multilevel(ml, tol, 2000000, 3, &steps_ml, &coarse));
        double a[3], b[3];
        state_of(flat, a);
        state_of(ml, b);
        print_message("body %zu: flat %lld steps, multilevel %lld + %lld coarse; A/A0 %.8f %.8f, gap %.10f %.10f\n", k,
                      (long long)steps_flat, (long long)steps_ml, (long long)coarse, a[0], b[0], a[1], b[1]);
        assert_true(coarse > 0);
        assert_true(b[2] <= tol); /* the same convergence test */
        assert_true(a[0] == b[0]); /* the same number of points in contact */
        assert_true(ts_rel(a[1], b[1]) < 1e-6);
        double *ga = ts_alloc(N * N), *gb = ts_alloc(N * N);
        TS_OK(flat, gfmd_get_gap(flat, ga));
        TS_OK(ml, gfmd_get_gap(ml, gb));
        for (int i = 0; i < N * N; ++i) assert_true((ga[i] == 0.0) == (gb[i] == 0.0)); /* the same contact set */
        free(ga);
        free(gb);
        gfmd_sim_destroy(&flat);
        gfmd_sim_destroy(&ml);
    }
}

static void deterministic(void **state) {
    (void)state;
    const body b = {GFMD_GREEN_LAYER_FLUID, 1.0, 2e-4, 0.0, 0};
    double z[3][N * N], r[3][3];
    for (int k = 0; k < 3; ++k) { /* two runs on one thread, one on two */
        gfmd_sim *s = make(&b, k < 2 ? 1 : 2);
        TS_OK(s, gfmd_relax_multilevel(s, 1e-9, 2000000, 3, NULL, NULL));
        TS_OK(s, gfmd_get_surface(s, z[k]));
        state_of(s, r[k]);
        gfmd_sim_destroy(&s);
    }
    assert_memory_equal(z[0], z[1], sizeof z[0]);
    /* FFTW may round differently on two threads: the equilibria agree to the tolerance's level */
    assert_true(fabs(r[0][0] - r[2][0]) <= 2.0 / (N * N));
    assert_true(ts_rel(r[0][1], r[2][1]) < 1e-7);
}

static void bad_levels_change_nothing(void **state) {
    (void)state;
    const body b = {GFMD_GREEN_HALFSPACE, 0.0, 0.05, 0.0, 0};
    gfmd_sim *s = make(&b, 1);
    TS_OK(s, gfmd_step(s, 5));
    double before[N * N], after[N * N];
    TS_OK(s, gfmd_get_surface(s, before));
    const int32_t levels[] = {0, -1, 5, 40, 1000};
    for (size_t k = 0; k < sizeof levels / sizeof levels[0]; ++k) {
        assert_int_equal(gfmd_relax_multilevel(s, 0.0, 1000, levels[k], NULL, NULL), GFMD_ERR_INVALID_ARG);
        TS_OK(s, gfmd_get_surface(s, after));
        assert_memory_equal(before, after, sizeof before);
    }
    assert_int_equal(gfmd_relax_multilevel(s, NAN, 1000, 2, NULL, NULL), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_relax_multilevel(s, 0.0, 0, 2, NULL, NULL), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_relax_multilevel(NULL, 0.0, 10, 2, NULL, NULL), GFMD_ERR_NULL);
    TS_OK(s, gfmd_get_surface(s, after));
    assert_memory_equal(before, after, sizeof before);
    /* a grid that does not halve: 48 = 3 x 16, so 5 levels (48/16 = 3 points) are refused */
    gfmd_sim *odd = ts_create(48, 40, 48.0, 40.0);
    assert_int_equal(gfmd_relax_multilevel(odd, 0.0, 10, 5, NULL, NULL), GFMD_ERR_INVALID_ARG);
    char msg[256] = "";
    gfmd_last_error(odd, msg, sizeof msg);
    assert_non_null(strstr(msg, "divisible"));
    /* 4 levels of 48 x 40 leave 6 x 5 points: below 8 a side */
    assert_int_equal(gfmd_relax_multilevel(odd, 0.0, 10, 4, NULL, NULL), GFMD_ERR_INVALID_ARG);
    TS_OK(odd, gfmd_relax_multilevel(odd, 0.0, 100000, 2, NULL, NULL)); /* 24 x 20: fine */
    gfmd_sim_destroy(&odd);
    /* levels = 1 is gfmd_relax: the same steps and bits */
    gfmd_sim *a = make(&b, 1), *c = make(&b, 1);
    int64_t sa = 0, sc = 0, coarse = -1;
    TS_OK(a, gfmd_relax(a, 0.0, 100000, &sa));
    TS_OK(c, gfmd_relax_multilevel(c, 0.0, 100000, 1, &sc, &coarse));
    assert_int_equal(sa, sc);
    assert_int_equal(coarse, 0);
    TS_OK(a, gfmd_get_surface(a, before));
    TS_OK(c, gfmd_get_surface(c, after));
    assert_memory_equal(before, after, sizeof before);
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&c);
    /* on any grid: 64 x 6, whose sides are below 8 points (no coarse grid; it was refused) */
    a = ts_create(64, 6, 64.0, 6.0);
    c = ts_create(64, 6, 64.0, 6.0);
    double thin_a[64 * 6], thin_c[64 * 6];
    for (int k = 0; k < 2; ++k) {
        gfmd_sim *t = k == 0 ? a : c;
        TS_OK(t, gfmd_generate_selfaffine(t, 0.8, 6.0, 3.0, 1.0, 5, GFMD_DIST_UNIFORM));
        TS_OK(t, gfmd_set_pressure(t, 0.05));
    }
    TS_OK(a, gfmd_relax(a, 0.0, 100000, &sa));
    TS_OK(c, gfmd_relax_multilevel(c, 0.0, 100000, 1, &sc, &coarse));
    assert_true(sa > 0 && sa == sc && coarse == 0);
    TS_OK(a, gfmd_get_surface(a, thin_a));
    TS_OK(c, gfmd_get_surface(c, thin_c));
    assert_memory_equal(thin_a, thin_c, sizeof thin_a);
    assert_int_equal(gfmd_relax_multilevel(c, 0.0, 100000, 2, NULL, NULL), GFMD_ERR_INVALID_ARG); /* 32 x 3 */
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&c);
    gfmd_sim_destroy(&s);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(agrees_with_flat_start),
        cmocka_unit_test(deterministic),
        cmocka_unit_test(bad_levels_change_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
