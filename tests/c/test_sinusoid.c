/* A sinusoidal substrate h = h0 cos(2 pi x / lambda).  For complete contact the body
 * takes the substrate's shape, a single Fourier mode, and the pressure needed is exactly
 * p* = h0 q E* / (2 f(q w)) on the grid too.  For the half-space the contact width below p*
 * follows Westergaard: A/A0 = (2/pi) arcsin(sqrt(sigma0/p*)) (K. L. Johnson, Contact Mechanics,
 * Sec. 13.2). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "gfmd.h"
#include "test_support.h"

static gfmd_sim *sinusoid(int64_t nx, int64_t ny, double h0, int32_t kind, double width) {
    gfmd_sim *s = ts_create(nx, ny, (double)nx, (double)ny);
    double *h = ts_alloc((size_t)(nx * ny));
    for (int64_t iy = 0; iy < ny; ++iy)
        for (int64_t ix = 0; ix < nx; ++ix) h[ix + nx * iy] = h0 * cos(2.0 * M_PI * (double)ix / (double)nx);
    TS_OK(s, gfmd_set_heights(s, h));
    free(h);
    if (kind != GFMD_GREEN_HALFSPACE) TS_OK(s, gfmd_set_green(s, kind, width));
    return s;
}

static double relaxed_area(gfmd_sim *s, double sigma0) {
    int64_t steps = 0;
    double a = -1.0;
    TS_OK(s, gfmd_set_pressure(s, sigma0));
    TS_OK(s, gfmd_relax(s, 1e-9, 200000, &steps));
    TS_OK(s, gfmd_get_contact_area(s, &a));
    return a;
}

static double full_contact_pressure(double h0, double lambda, int32_t kind, double width) {
    double q = 2.0 * M_PI / lambda, f = 1.0;
    if (kind != GFMD_GREEN_HALFSPACE) assert_int_equal(gfmd_green_factor(kind, q * width, 0.0, &f), GFMD_OK);
    return h0 * q / (2.0 * f);
}

static void complete_contact_threshold(void **state) {
    (void)state;
    /* Half-space and two layer widths (q w = 0.5: bending-dominated, q w = 2: nearly half-space).
     * The threshold is exact on the grid, so +-2 % around it is far beyond the relaxation's
     * tolerance (residual 1e-9 of sigma0) and the answer must be clean: A = 1 above, A < 1 below. */
    const int64_t nx = 64, ny = 4;
    const double h0 = 1.0, lambda = (double)nx;
    const int32_t kinds[] = {GFMD_GREEN_HALFSPACE, GFMD_GREEN_LAYER_FLUID, GFMD_GREEN_LAYER_FLUID};
    const double widths[] = {0.0, 0.5 * lambda / (2.0 * M_PI), 2.0 * lambda / (2.0 * M_PI)};
    for (int k = 0; k < 3; ++k) {
        double pstar = full_contact_pressure(h0, lambda, kinds[k], widths[k]);
        gfmd_sim *s = sinusoid(nx, ny, h0, kinds[k], widths[k]);
        assert_true(relaxed_area(s, 1.02 * pstar) == 1.0);
        double below = relaxed_area(s, 0.98 * pstar);
        print_message("kind %d: A/A0 = 1 at 1.02 p*, %.4f at 0.98 p*\n", kinds[k], below);
        assert_true(below < 1.0);
        assert_true(below > 0.8); /* only the valleys open up */
        gfmd_sim_destroy(&s);
    }
}

static void westergaard_contact_width(void **state) {
    (void)state;
    /* Each of the two edges of the contact strip is resolved to one grid spacing, so A/A0 may
     * differ from Westergaard's by up to 2 spacings / lambda. */
    const int64_t nx = 256, ny = 2;
    const double h0 = 2.0, lambda = (double)nx;
    const double pstar = full_contact_pressure(h0, lambda, GFMD_GREEN_HALFSPACE, 0.0);
    gfmd_sim *s = sinusoid(nx, ny, h0, GFMD_GREEN_HALFSPACE, 0.0);
    const double loads[] = {0.05, 0.2, 0.5, 0.8};
    for (int i = 0; i < 4; ++i) {
        double a = relaxed_area(s, loads[i] * pstar);
        double expected = 2.0 / M_PI * asin(sqrt(loads[i]));
        print_message("Westergaard sigma0/p* = %.2f: A/A0 = %.5f, expected %.5f\n", loads[i], a, expected);
        assert_true(fabs(a - expected) <= 2.0 / lambda);
    }
    gfmd_sim_destroy(&s);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(complete_contact_threshold),
        cmocka_unit_test(westergaard_contact_width),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
