/* Persson's theory (gfmd_persson_variance, gfmd_persson_contact_area, gfmd_persson_load) against
 * closed forms, and
 * the least-squares fit (gfmd_least_squares) against fits with known answers. */
#include <math.h>
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

static const double PI = 3.14159265358979323846;

static double variance(const gfmd_sim *s) {
    double v = NAN;
    TS_OK(s, gfmd_persson_variance(s, &v));
    return v;
}

/* Half-space: V = sum_q (q E* /2)^2 |h(q)|^2 = (E* /2)^2 <|grad h|^2> = (E* g/2)^2 exactly, because
 * the generator sets the spectral rms gradient g (exact to ~1e-15): 1e-12 leaves room for the
 * sums' rounding over 64^2 modes. */
static void halfspace_variance_is_gradient(void **state) {
    (void)state;
    gfmd_sim *s = ts_create_estimate(96, 64, 96.0, 64.0);
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 32.0, 4.0, 0.7, 5, GFMD_DIST_UNIFORM));
    TS_OK(s, gfmd_set_modulus(s, 2.5));
    const double expect = pow(2.5 * 0.7 / 2.0, 2);
    assert_true(ts_rel(variance(s), expect) < 1e-12);
    /* small-load slope sqrt(8/pi)/(E* g): erf(x) = (2/sqrt(pi)) x (1 - x^2/3 + ...), so at
     * sigma0 = 1e-6 E* g the relative deviation is ~1e-13 */
    double area = NAN;
    const double sigma0 = 1e-6 * 2.5 * 0.7;
    TS_OK(s, gfmd_persson_contact_area(s, sigma0, &area));
    assert_true(ts_rel(area, sqrt(8.0 / PI) * 1e-6) < 1e-10);
    /* the erf form itself at a finite load */
    TS_OK(s, gfmd_persson_contact_area(s, 0.4, &area));
    assert_true(ts_rel(area, erf(0.4 / sqrt(2.0 * expect))) < 1e-12);
    TS_OK(s, gfmd_persson_contact_area(s, 0.0, &area));
    assert_true(area == 0.0);
    gfmd_sim_destroy(&s);
}

/* V of a fresh handle made with the given substrate seed, modulus and layer width (0: half-space). */
static double fresh_variance(uint64_t seed, double e_star, double width) {
    gfmd_sim *f = ts_create_estimate(96, 64, 96.0, 64.0);
    if (width > 0.0) TS_OK(f, gfmd_set_green(f, GFMD_GREEN_LAYER_FLUID, width));
    TS_OK(f, gfmd_set_modulus(f, e_star));
    TS_OK(f, gfmd_generate_selfaffine(f, 0.8, 32.0, 4.0, 0.7, seed, GFMD_DIST_UNIFORM));
    const double v = variance(f);
    gfmd_sim_destroy(&f);
    return v;
}

/* V is kept with the substrate and the body (computed at its first use after either changed):
 * after every change of either it is, bit for bit, that of a fresh handle made with the new
 * settings; a change that fails, a change of load and a clone keep it. */
static void variance_follows_substrate_and_body(void **state) {
    (void)state;
    gfmd_sim *s = ts_create_estimate(96, 64, 96.0, 64.0);
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 32.0, 4.0, 0.7, 5, GFMD_DIST_UNIFORM));
    const double v0 = variance(s);
    assert_true(v0 == fresh_variance(5, 1.0, 0.0));
    TS_OK(s, gfmd_set_modulus(s, 2.5));
    assert_true(variance(s) == fresh_variance(5, 2.5, 0.0));
    TS_OK(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 2.0));
    const double layer = variance(s);
    assert_true(layer == fresh_variance(5, 2.5, 2.0));
    assert_true(layer != v0);
    assert_int_equal(gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, -1.0), GFMD_ERR_INVALID_ARG);
    TS_OK(s, gfmd_set_pressure(s, 0.3));
    assert_true(variance(s) == layer);
    gfmd_sim *c = NULL;
    TS_OK(s, gfmd_sim_clone(s, &c));
    assert_true(variance(c) == layer);
    gfmd_sim_destroy(&c);
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 32.0, 4.0, 0.7, 6, GFMD_DIST_UNIFORM));
    assert_true(variance(s) == fresh_variance(6, 2.5, 2.0));
    double *h = malloc(96 * 64 * sizeof *h);
    assert_non_null(h);
    for (int i = 0; i < 96 * 64; ++i) h[i] = 0.0;
    TS_OK(s, gfmd_set_heights(s, h)); /* flat: V = 0 */
    assert_true(variance(s) == 0.0);
    free(h);
    gfmd_sim_destroy(&s);
}

/* The header's promise that V needs no memory of its own (h's transform goes to the handle's FFT
 * scratch): in a child process whose address space is then exhausted, a handle that has computed V
 * returns it bit for bit, and a twin that has not (the same substrate) computes it, the same bits,
 * as its Persson area and load -- before the variance used the scratch the twin's first call
 * needed an 8 MB half-spectrum (1024^2) and failed with GFMD_ERR_NOMEM.  A new load and a failed
 * change keep V (that a change of the substrate or the body computes it again: the test above).
 * Natively only (ts_memory_cap_possible). */
static int variance_kept_child(void) {
    gfmd_sim *s[2] = {NULL, NULL};
    for (int k = 0; k < 2; ++k)
        if (gfmd_sim_create_ex(1024, 1024, 1024.0, 1024.0, 1, GFMD_PLANNER_ESTIMATE, &s[k]) != GFMD_OK ||
            gfmd_generate_selfaffine(s[k], 0.8, 128.0, 4.0, 1.0, 7, GFMD_DIST_UNIFORM) != GFMD_OK)
            return 3;
    double v = NAN, again = NAN, twin = NAN, area = NAN, load = NAN, twin_area = NAN, twin_load = NAN;
    if (gfmd_persson_variance(s[0], &v) != GFMD_OK || gfmd_set_pressure(s[0], 0.01) != GFMD_OK) return 4;
    if (gfmd_set_green(s[0], 99, 1.0) == GFMD_OK) return 5; /* a failed change */
    if (ts_exhaust_memory() != 0) return 6;
    int bad = 0;
    bad |= gfmd_persson_variance(s[0], &again) != GFMD_OK || again != v;
    bad |= gfmd_persson_contact_area(s[0], 0.02, &area) != GFMD_OK || gfmd_persson_load(s[0], 0.1, &load) != GFMD_OK;
    bad |= (gfmd_persson_variance(s[1], &twin) != GFMD_OK || twin != v) << 1;
    bad |= (gfmd_persson_contact_area(s[1], 0.02, &twin_area) != GFMD_OK || twin_area != area) << 1;
    bad |= (gfmd_persson_load(s[1], 0.1, &twin_load) != GFMD_OK || twin_load != load) << 1;
    if (bad) fprintf(stderr, "under the cap: failures %d\n", bad);
    return bad ? 1 : 0;
}

static void variance_kept_without_memory(void **state) {
    (void)state;
    if (!ts_memory_cap_possible()) skip();
    ts_run_in_child(variance_kept_child);
}

/* The load for a Persson area: on the half-space V = (E* g/2)^2, so the load for A/A0 = 1/2 is
 * sqrt(2 V) erfinv(1/2), erfinv(1/2) = 0.476936276204469873381418353643 (tabulated; 1e-12 for V's
 * own rounding, above).  Everywhere else the inverse is checked against erf and erfc themselves
 * with the library's V: near 1 the relative error of 1 - A/A0 is about 2 x^2 (x ~ 5) times the
 * rounding of the load, < 1e-13, where erf alone would keep only 1 - A/A0's absolute 1e-16. */
static void persson_load_inverts_area(void **state) {
    (void)state;
    gfmd_sim *s = ts_create_estimate(96, 64, 96.0, 64.0);
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 32.0, 4.0, 0.7, 5, GFMD_DIST_UNIFORM));
    TS_OK(s, gfmd_set_modulus(s, 2.5));
    double load = NAN;
    TS_OK(s, gfmd_persson_load(s, 0.5, &load));
    assert_true(ts_rel(load, 2.5 * 0.7 / 2.0 * sqrt(2.0) * 0.476936276204469873381418353643) < 1e-12);
    TS_OK(s, gfmd_persson_load(s, 0.0, &load));
    assert_true(load == 0.0);
    const double areas[] = {1e-300, 1e-12, 0.004, 0.3, 0.5, 0.5000000000000001, 0.7, 0.999, 1.0 - 1e-12, 0.9999999999999999};
    const int32_t kinds[] = {GFMD_GREEN_HALFSPACE, GFMD_GREEN_LAYER_FLUID};
    for (int k = 0; k < 2; ++k) {
        if (kinds[k] != GFMD_GREEN_HALFSPACE) TS_OK(s, gfmd_set_green(s, kinds[k], 0.3));
        const double v = variance(s);
        double prev = 0.0;
        for (size_t i = 0; i < sizeof areas / sizeof areas[0]; ++i) {
            TS_OK(s, gfmd_persson_load(s, areas[i], &load));
            assert_true(load > prev); /* increasing with the area */
            prev = load;
            const double x = load / sqrt(2.0 * v);
            if (areas[i] <= 0.5)
                assert_true(ts_rel(erf(x), areas[i]) < 1e-13);
            else
                assert_true(ts_rel(erfc(x), 1.0 - areas[i]) < 1e-13);
            double back = NAN;
            TS_OK(s, gfmd_persson_contact_area(s, load, &back));
            assert_true(fabs(back - areas[i]) <= 1e-13 * areas[i]);
        }
    }
    gfmd_sim_destroy(&s);
}

/* A single sinusoid h0 cos(q x) on a layer: two modes of amplitude h0/2, so
 * V = 2 (k(q) h0/2)^2 with k(q) = q E* /(2 f(q w)); f from the test's own series/closed form
 * (ts_stiffness), independent of the library's stiffness table.  Several widths, both foundations. */
static void sinusoid_layer_variance(void **state) {
    (void)state;
    const int64_t nx = 64, ny = 8;
    const double lx = 64.0, ly = 8.0, h0 = 0.3, q = 2.0 * PI * 4.0 / lx;
    double *h = ts_alloc((size_t)(nx * ny));
    for (int64_t y = 0; y < ny; ++y)
        for (int64_t x = 0; x < nx; ++x) h[y * nx + x] = h0 * cos(q * (double)x);
    gfmd_sim *s = ts_create_estimate(nx, ny, lx, ly);
    TS_OK(s, gfmd_set_heights(s, h));
    TS_OK(s, gfmd_set_poisson(s, 0.3));
    const double widths[] = {0.05, 0.5, 2.0, 40.0};
    const int32_t kinds[] = {GFMD_GREEN_LAYER_FLUID, GFMD_GREEN_LAYER_BONDED};
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < 4; ++i) {
            TS_OK(s, gfmd_set_green(s, kinds[k], widths[i]));
            const double kq = ts_stiffness(kinds[k], widths[i], 0.3, 1.0, q, 0.0);
            /* the FFT of a cosine carries ~1e-16 h0 of rounding into other modes, all stiffer by
             * at most (q_max/q)^... below the layer's own: 1e-9 relative covers it */
            assert_true(ts_rel(variance(s), 2.0 * pow(kq * h0 / 2.0, 2)) < 1e-9);
        }
    gfmd_sim_destroy(&s);
    free(h);
}

/* The thin layer is softer: at the same load Persson's area grows as W shrinks, and in the
 * thin-plate limit V scales as w^6 (k ~ q^4 w^3 E* /12), so A/A0 at small load as w^-3. */
static void persson_thin_plate_scaling(void **state) {
    (void)state;
    gfmd_sim *s = ts_create_estimate(128, 128, 128.0, 128.0);
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 32.0, 8.0, 1.0, 3, GFMD_DIST_UNIFORM));
    double prev = 0.0;
    const double widths[] = {64.0, 8.0, 1.0, 0.1, 0.01};
    double v[5];
    for (int i = 0; i < 5; ++i) {
        TS_OK(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, widths[i]));
        double area = NAN;
        v[i] = variance(s);
        TS_OK(s, gfmd_persson_contact_area(s, 1e-4, &area));
        assert_true(area > prev);
        prev = area;
    }
    /* q w <= 2 pi 0.1/8 for every resolved mode at w = 0.1: f = 6/t^3 (1 + t^2/5 + ...), so the
     * ratio of the last two variances is 10^6 to within ~2 (q_s w)^2/5 ~ 1e-3 */
    assert_true(fabs(v[3] / v[4] / 1e6 - 1.0) < 3e-3);
    gfmd_sim_destroy(&s);
}

static void persson_bad_input(void **state) {
    (void)state;
    gfmd_sim *s = ts_create_estimate(32, 32, 32.0, 32.0);
    double v = 7.0, a = 7.0;
    assert_int_equal(gfmd_persson_variance(NULL, &v), GFMD_ERR_NULL);
    assert_int_equal(gfmd_persson_variance(s, NULL), GFMD_ERR_NULL);
    assert_int_equal(gfmd_persson_contact_area(NULL, 0.1, &a), GFMD_ERR_NULL);
    assert_int_equal(gfmd_persson_contact_area(s, 0.1, NULL), GFMD_ERR_NULL);
    assert_int_equal(gfmd_persson_contact_area(s, -0.1, &a), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_persson_contact_area(s, NAN, &a), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_persson_contact_area(s, INFINITY, &a), GFMD_ERR_INVALID_ARG);
    assert_true(v == 7.0 && a == 7.0);
    char msg[128] = "";
    assert_int_equal(gfmd_last_error(s, msg, sizeof msg), GFMD_OK);
    assert_non_null(strstr(msg, "sigma0"));
    /* flat substrate (the initial state): V = 0, full contact under any load */
    TS_OK(s, gfmd_persson_variance(s, &v));
    assert_true(v == 0.0);
    TS_OK(s, gfmd_persson_contact_area(s, 1e-9, &a));
    assert_true(a == 1.0);
    /* the inverse: no positive load gives a flat substrate less than full contact */
    a = 7.0;
    assert_int_equal(gfmd_persson_load(s, 0.5, &a), GFMD_ERR_STATE);
    assert_int_equal(gfmd_last_error(s, msg, sizeof msg), GFMD_OK);
    assert_non_null(strstr(msg, "flat"));
    TS_OK(s, gfmd_persson_load(s, 0.0, &a));
    assert_true(a == 0.0);
    a = 7.0;
    assert_int_equal(gfmd_persson_load(NULL, 0.1, &a), GFMD_ERR_NULL);
    assert_int_equal(gfmd_persson_load(s, 0.1, NULL), GFMD_ERR_NULL);
    const double bad[] = {-1e-300, 1.0, 2.0, NAN, INFINITY, -INFINITY};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        assert_int_equal(gfmd_persson_load(s, bad[i], &a), GFMD_ERR_INVALID_ARG);
        assert_int_equal(gfmd_last_error(s, msg, sizeof msg), GFMD_OK);
        assert_non_null(strstr(msg, "rel_area"));
    }
    assert_true(a == 7.0);
    gfmd_sim_destroy(&s);
}

/* Least squares with known answers. */
static void least_squares_known(void **state) {
    (void)state;
    /* 1. an exact line y = 3 - 2x through 6 points: x = (3, -2), residual 0 (to rounding) */
    double a[12], b[6], x[2], rss = -1.0;
    for (int i = 0; i < 6; ++i) {
        a[i] = 1.0;
        a[6 + i] = 0.5 * i;
        b[i] = 3.0 - 2.0 * 0.5 * i;
    }
    assert_int_equal(gfmd_least_squares(6, 2, a, b, x, &rss), GFMD_OK);
    assert_true(fabs(x[0] - 3.0) < 1e-13 && fabs(x[1] + 2.0) < 1e-13 && rss < 1e-26);
    /* 2. a noisy line: slope Sxy/Sxx and intercept from the closed-form normal equations */
    const double yy[6] = {1.0, 2.5, 2.0, 4.5, 3.9, 6.2};
    double mx = 0, my = 0, sxx = 0, sxy = 0;
    for (int i = 0; i < 6; ++i) mx += a[6 + i] / 6.0, my += yy[i] / 6.0;
    for (int i = 0; i < 6; ++i) sxx += pow(a[6 + i] - mx, 2), sxy += (a[6 + i] - mx) * (yy[i] - my);
    const double slope = sxy / sxx, icpt = my - slope * mx;
    double expect_rss = 0.0;
    for (int i = 0; i < 6; ++i) expect_rss += pow(yy[i] - icpt - slope * a[6 + i], 2);
    const double a_copy0 = a[7];
    assert_int_equal(gfmd_least_squares(6, 2, a, yy, x, &rss), GFMD_OK);
    assert_true(fabs(x[1] - slope) < 1e-12 && fabs(x[0] - icpt) < 1e-12);
    assert_true(fabs(rss - expect_rss) < 1e-12);
    assert_true(a[7] == a_copy0); /* input not modified */
    /* 3. a power law c W^-3 fitted in log space: exponent -3 exactly */
    double la[16], lb[8];
    for (int i = 0; i < 8; ++i) {
        const double w = 0.05 * pow(1.7, i);
        la[i] = 1.0;
        la[8 + i] = log(w);
        lb[i] = log(2.5 * pow(w, -3.0));
    }
    assert_int_equal(gfmd_least_squares(8, 2, la, lb, x, NULL), GFMD_OK);
    assert_true(fabs(x[1] + 3.0) < 1e-12 && fabs(x[0] - log(2.5)) < 1e-12);
    /* 4. a square system is solved exactly */
    const double sq[4] = {2.0, 1.0, 1.0, 3.0}, sb[2] = {3.0, 5.0}; /* [[2,1],[1,3]] x = (3,5) */
    assert_int_equal(gfmd_least_squares(2, 2, sq, sb, x, &rss), GFMD_OK);
    assert_true(fabs(x[0] - 0.8) < 1e-14 && fabs(x[1] - 1.4) < 1e-14 && rss == 0.0);
}

static void least_squares_bad_input(void **state) {
    (void)state;
    double a[6] = {1, 1, 1, 2, 2, 2}, b[3] = {1, 2, 3}, x[2] = {7.0, 7.0};
    assert_int_equal(gfmd_least_squares(3, 2, NULL, b, x, NULL), GFMD_ERR_NULL);
    assert_int_equal(gfmd_least_squares(3, 2, a, NULL, x, NULL), GFMD_ERR_NULL);
    assert_int_equal(gfmd_least_squares(3, 2, a, b, NULL, NULL), GFMD_ERR_NULL);
    assert_int_equal(gfmd_least_squares(1, 2, a, b, x, NULL), GFMD_ERR_INVALID_ARG); /* m < n */
    assert_int_equal(gfmd_least_squares(3, 0, a, b, x, NULL), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_least_squares(-3, -1, a, b, x, NULL), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_least_squares(INT64_MAX, 1, a, b, x, NULL), GFMD_ERR_INVALID_ARG);
    /* the second column is twice the first: rank deficient (rounding-level pivot) */
    assert_int_equal(gfmd_least_squares(3, 2, a, b, x, NULL), GFMD_ERR_INVALID_ARG);
    double z[6] = {1, 2, 3, 0, 0, 0}; /* an exactly zero column */
    assert_int_equal(gfmd_least_squares(3, 2, z, b, x, NULL), GFMD_ERR_INVALID_ARG);
    double nan_a[6] = {1, 2, 3, 1, 0, NAN};
    assert_int_equal(gfmd_least_squares(3, 2, nan_a, b, x, NULL), GFMD_ERR_INVALID_ARG);
    double inf_b[3] = {1, INFINITY, 0};
    double good[6] = {1, 1, 1, 0, 1, 2};
    assert_int_equal(gfmd_least_squares(3, 2, good, inf_b, x, NULL), GFMD_ERR_INVALID_ARG);
    assert_true(x[0] == 7.0 && x[1] == 7.0); /* unchanged by every failed call */
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(halfspace_variance_is_gradient), cmocka_unit_test(sinusoid_layer_variance),
        cmocka_unit_test(persson_thin_plate_scaling),     cmocka_unit_test(persson_bad_input),
        cmocka_unit_test(persson_load_inverts_area),      cmocka_unit_test(variance_follows_substrate_and_body),
        cmocka_unit_test(variance_kept_without_memory),
        cmocka_unit_test(least_squares_known),
        cmocka_unit_test(least_squares_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
