/* The Green's function factors f(t) against independent evaluations: reference values of the
 * fluid-layer f(t) computed to 7 digits outside this library, the closed forms in long double where they do not cancel, the small-t series
 * (thin-plate limit t^3 f -> 6) and the large-t limit f -> 1. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "gfmd.h"
#include "test_support.h"

static double fluid(double t) {
    double f = NAN;
    assert_int_equal(gfmd_green_factor(GFMD_GREEN_LAYER_FLUID, t, 0.0, &f), GFMD_OK);
    return f;
}

static double bonded(double t, double nu) {
    double f = NAN;
    assert_int_equal(gfmd_green_factor(GFMD_GREEN_LAYER_BONDED, t, nu, &f), GFMD_OK);
    return f;
}

/* Direct closed forms in double.  Where they cancel, their own rounding error is bounded by a few
 * ulps of the largest term divided by the result: that bound (plus 1e-14 for the library's
 * rounding) is the tolerance, so the comparison is as tight as the reference allows (1e-14 at
 * t = 5, 1e-11 at t = 0.1).  Plain double keeps the test exact under valgrind, which has no
 * 80-bit long double. */
static const double EPS = 2.220446049250313e-16;

static double fluid_closed(double t, double *tol) {
    double x = 2.0 * t, num = sinh(x) + x, den = cosh(x) - 1.0 - 0.5 * x * x;
    *tol = 1e-14 + 8.0 * EPS * (cosh(x) + 1.0 + 0.5 * x * x) / den;
    return num / den;
}

static double bonded_closed(double t, double nu, double *tol) {
    double x = 2.0 * t, k = 3.0 - 4.0 * nu, num = k * sinh(x) - x;
    *tol = 1e-14 + 8.0 * EPS * (k * sinh(x) + x) / num;
    return num / (k * cosh(x) + 0.5 * x * x + 0.5 * (1.0 + k * k));
}

static void reference_values(void **state) {
    (void)state;
    /* Reference values of f(t) = (sinh 2t + 2t)/(cosh 2t - 1 - 2t^2) to 7 significant digits:
     * agree to half a unit in the 7th. */
    const double t[] = {0.1, 0.5, 1.0, 2.0, 5.0};
    const double f[] = {6012.018, 50.49139, 7.382435, 1.709063, 1.005565};
    for (int i = 0; i < 5; ++i) assert_true(ts_rel(fluid(t[i]), f[i]) < 1e-6);
}

static void closed_form_overlap(void **state) {
    (void)state;
    /* The library switches from series to scaled exponentials at t = 1; on both sides it must
     * agree with the direct closed form within the latter's rounding bound. */
    double tol = 0.0;
    for (double t = 0.05; t <= 20.0; t *= 1.07) {
        assert_true(ts_rel(fluid(t), fluid_closed(t, &tol)) < tol);
        for (double nu = -0.5; nu <= 0.5; nu += 0.25) /* 0.5: kappa = 1, the cancelling case */
            assert_true(ts_rel(bonded(t, nu), bonded_closed(t, nu, &tol)) < tol);
    }
    /* Continuity across the switch at t = 1: the two forms agree to 1e-11 over a 2e-12 step (both
     * are accurate to ~1e-15 there; f changes by ~1e-11 relative over the step itself). */
    assert_true(ts_rel(fluid(1.0 - 1e-12), fluid(1.0 + 1e-12)) < 1e-11);
    assert_true(ts_rel(bonded(1.0 - 1e-12, 0.5), bonded(1.0 + 1e-12, 0.5)) < 1e-11);
}

static void thin_plate_limit(void **state) {
    (void)state;
    /* f = 6/t^3 + 6/(5t) + 32t/175 + O(t^3): for t <= 1e-2 the omitted terms are below 1e-12 of f. */
    for (double t = 1e-8; t <= 1e-2; t *= 3.0) {
        double series = 6.0 / (t * t * t) + 6.0 / (5.0 * t) + 32.0 * t / 175.0;
        assert_true(ts_rel(fluid(t), series) < 1e-12);
    }
    /* t^3 f -> 6 */
    assert_true(fabs(fluid(1e-8) * 1e-24 - 6.0) < 1e-12);
    /* bonded, incompressible (kappa = 1): f_b -> (2/3) t^3; compressible: f_b -> 4 t (kappa-1)/(1+kappa)^2 */
    assert_true(ts_rel(bonded(1e-6, 0.5), 2.0 / 3.0 * 1e-18) < 1e-9);
    assert_true(ts_rel(bonded(1e-9, 0.25), 4.0 * 1e-9 * 1.0 / 9.0) < 1e-9);
}

static void large_t_limit(void **state) {
    (void)state;
    /* f - 1 = (x^2 + 2x + 2) e^-x + O(x^4 e^-2x), x = 2t: the omitted term is below 1e-12 for
     * t >= 10 (7e-13 at t = 10), and f is within an ulp or two of 1 there. */
    for (double t = 10.0; t < 40.0; t += 1.5) {
        double x = 2.0 * t;
        assert_true(fabs(fluid(t) - 1.0 - (x * x + 2.0 * x + 2.0) * exp(-x)) < 2e-12);
    }
    assert_true(fluid(1e8) == 1.0);
    assert_true(bonded(1e8, 0.3) == 1.0);
    /* out to the largest double: e^-2t underflows to 0 from t = 373 on, where f is 1 exactly;
     * (2t)^2 e^-2t was inf * 0 = NaN from t = 6.7e153 on (and 2t inf beyond DBL_MAX / 2) */
    const double huge[] = {400.0, 1e153, 6.7e153, 1e154, 1e200, 1e300, DBL_MAX / 2.0, DBL_MAX};
    for (size_t i = 0; i < sizeof huge / sizeof huge[0]; ++i) {
        assert_true(fluid(huge[i]) == 1.0);
        assert_true(bonded(huge[i], 0.3) == 1.0);
        assert_true(bonded(huge[i], 0.5) == 1.0);
        assert_true(bonded(huge[i], -0.9) == 1.0);
    }
    double f = 0.0;
    assert_int_equal(gfmd_green_factor(GFMD_GREEN_HALFSPACE, 3.0, 0.0, &f), GFMD_OK);
    assert_true(f == 1.0);
}

/* A layer far thicker than the cell is the half-space: its stiffness is the half-space's on every
 * mode (f = 1 to the last bit), so the same solver's relaxation gives the same bits.  The
 * widths 1e200 and 1e300 failed with GFMD_ERR_RANGE before f was set to 1 there. */
static void thick_layer_is_the_half_space(void **state) {
    (void)state;
    double ref[3] = {0.0, 0.0, 0.0};
    const double widths[] = {0.0, 1e6, 1e200, 1e300, DBL_MAX};
    for (size_t i = 0; i < sizeof widths / sizeof widths[0]; ++i) {
        for (int32_t kind = GFMD_GREEN_LAYER_FLUID; kind <= GFMD_GREEN_LAYER_BONDED; ++kind) {
            gfmd_sim *s = NULL;
            assert_int_equal(gfmd_sim_create_ex(32, 24, 32.0, 24.0, 1, GFMD_PLANNER_ESTIMATE, &s), GFMD_OK);
            assert_int_equal(gfmd_generate_selfaffine(s, 0.8, 12.0, 3.0, 1.0, 5, GFMD_DIST_UNIFORM), GFMD_OK);
            if (kind == GFMD_GREEN_LAYER_BONDED) assert_int_equal(gfmd_set_poisson(s, 0.3), GFMD_OK);
            if (widths[i] > 0.0) assert_int_equal(gfmd_set_green(s, kind, widths[i]), GFMD_OK);
            assert_int_equal(gfmd_set_pressure(s, 0.05), GFMD_OK);
            /* one solver for all: the default's choice reads the kind of body */
            assert_int_equal(gfmd_set_solver(s, GFMD_SOLVER_FIRE), GFMD_OK);
            int64_t steps = 0;
            assert_int_equal(gfmd_relax(s, 0.0, 100000, &steps), GFMD_OK);
            double out[3] = {(double)steps, 0.0, 0.0};
            assert_int_equal(gfmd_get_contact_area(s, &out[1]), GFMD_OK);
            assert_int_equal(gfmd_get_mean_gap(s, &out[2]), GFMD_OK);
            if (i == 0) memcpy(ref, out, sizeof ref);
            /* 1e6: f - 1 ~ (2qw)^2 e^-2qw, far below an ulp on this grid (q >= 2 pi / 32) */
            assert_memory_equal(out, ref, sizeof out);
            gfmd_sim_destroy(&s);
            if (widths[i] == 0.0) break; /* the half-space once */
        }
    }
}

static void finite_and_monotone_everywhere(void **state) {
    (void)state;
    /* From 1e-8 to 1e8: finite, positive, never NaN; the fluid f decreases monotonically to 1,
     * the bonded f_b increases monotonically to 1 (a soft layer on a rigid base only stiffens). */
    double prev_f = INFINITY, prev_b = 0.0;
    for (double t = 1e-8; t <= 1e8; t *= 1.01) {
        double f = fluid(t), b = bonded(t, 0.3);
        assert_true(isfinite(f) && f >= 1.0);
        assert_true(isfinite(b) && b > 0.0 && b <= 1.0);
        assert_true(f <= prev_f);
        assert_true(b >= prev_b * (1.0 - 1e-15));
        prev_f = f;
        prev_b = b;
    }
}

static void bad_arguments(void **state) {
    (void)state;
    double f = 42.0;
    assert_int_equal(gfmd_green_factor(GFMD_GREEN_LAYER_FLUID, 0.0, 0.0, &f), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_green_factor(GFMD_GREEN_LAYER_FLUID, -1.0, 0.0, &f), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_green_factor(GFMD_GREEN_LAYER_FLUID, NAN, 0.0, &f), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_green_factor(GFMD_GREEN_LAYER_FLUID, INFINITY, 0.0, &f), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_green_factor(GFMD_GREEN_LAYER_FLUID, 1e-120, 0.0, &f), GFMD_ERR_RANGE);
    /* an incompressible bonded layer: f_b ~ (2/3) t^3 underflows to 0 (found by the fuzzer) */
    assert_int_equal(gfmd_green_factor(GFMD_GREEN_LAYER_BONDED, 1e-257, 0.5, &f), GFMD_ERR_RANGE);
    assert_int_equal(gfmd_green_factor(GFMD_GREEN_LAYER_BONDED, 1.0, 0.7, &f), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_green_factor(GFMD_GREEN_LAYER_BONDED, 1.0, NAN, &f), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_green_factor(7, 1.0, 0.0, &f), GFMD_ERR_BAD_ENUM);
    assert_int_equal(gfmd_green_factor(GFMD_GREEN_LAYER_FLUID, 1.0, 0.0, NULL), GFMD_ERR_NULL);
    assert_true(f == 42.0); /* failed calls leave the output alone */
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(reference_values),      cmocka_unit_test(closed_form_overlap),
        cmocka_unit_test(thin_plate_limit),      cmocka_unit_test(large_t_limit), cmocka_unit_test(thick_layer_is_the_half_space),
        cmocka_unit_test(finite_and_monotone_everywhere), cmocka_unit_test(bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
