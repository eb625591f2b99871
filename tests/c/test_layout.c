/* Array layout: fields are x fastest, C [ny][nx], on non-square grids and cells.  A substrate that
 * varies along one axis must give a gap constant along the other, the full-contact pressure must
 * follow that axis' own wavelength, and the transposed problem must give the transposed answer. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "gfmd.h"
#include "test_support.h"

static void relax(gfmd_sim *s, double sigma0) {
    int64_t steps = 0;
    TS_OK(s, gfmd_set_pressure(s, sigma0));
    TS_OK(s, gfmd_relax(s, 1e-10, 200000, &steps));
}

static void one_axis(int along_x) {
    const int64_t nx = 48, ny = 32;
    const double lx = 48.0, ly = 64.0; /* rectangular cells: spacing 1 in x, 2 in y */
    gfmd_sim *s = ts_create(nx, ny, lx, ly);
    double *h = ts_alloc(nx * ny), *g = ts_alloc(nx * ny);
    const double h0 = 0.5;
    for (int64_t iy = 0; iy < ny; ++iy)
        for (int64_t ix = 0; ix < nx; ++ix)
            h[ix + nx * iy] = along_x ? h0 * cos(2.0 * M_PI * ix / nx) : h0 * cos(2.0 * M_PI * iy / ny);
    TS_OK(s, gfmd_set_heights(s, h));
    const double lambda = along_x ? lx : ly, pstar = h0 * (2.0 * M_PI / lambda) / 2.0;
    relax(s, 0.4 * pstar);
    TS_OK(s, gfmd_get_gap(s, g));
    /* constant along the other axis to rounding (the relaxation is 1-D) */
    for (int64_t iy = 0; iy < ny; ++iy)
        for (int64_t ix = 0; ix < nx; ++ix) {
            double ref = along_x ? g[ix] : g[nx * iy];
            assert_true(fabs(g[ix + nx * iy] - ref) < 1e-9);
        }
    double a = 0.0;
    TS_OK(s, gfmd_get_contact_area(s, &a));
    assert_true(a > 0.0 && a < 1.0);
    relax(s, 1.02 * pstar); /* full contact just above this axis' threshold */
    TS_OK(s, gfmd_get_contact_area(s, &a));
    assert_true(a == 1.0);
    relax(s, 0.98 * pstar);
    TS_OK(s, gfmd_get_contact_area(s, &a));
    assert_true(a < 1.0);
    free(h);
    free(g);
    gfmd_sim_destroy(&s);
}

static void substrate_along_x(void **state) {
    (void)state;
    one_axis(1);
}

static void substrate_along_y(void **state) {
    (void)state;
    one_axis(0);
}

static void transposed_problem(void **state) {
    (void)state;
    const int64_t nx = 40, ny = 24;
    gfmd_sim *a = ts_create(nx, ny, 40.0, 24.0), *b = ts_create(ny, nx, 24.0, 40.0);
    double *h = ts_alloc(nx * ny), *ht = ts_alloc(nx * ny), *ga = ts_alloc(nx * ny), *gb = ts_alloc(nx * ny);
    TS_OK(a, gfmd_generate_selfaffine(a, 0.7, 12.0, 3.0, 1.0, 5, GFMD_DIST_GAUSSIAN));
    TS_OK(a, gfmd_get_heights(a, h));
    for (int64_t iy = 0; iy < ny; ++iy)
        for (int64_t ix = 0; ix < nx; ++ix) ht[iy + ny * ix] = h[ix + nx * iy];
    TS_OK(b, gfmd_set_heights(b, ht));
    TS_OK(a, gfmd_set_green(a, GFMD_GREEN_LAYER_FLUID, 3.0));
    TS_OK(b, gfmd_set_green(b, GFMD_GREEN_LAYER_FLUID, 3.0));
    relax(a, 0.05);
    relax(b, 0.05);
    TS_OK(a, gfmd_get_gap(a, ga));
    TS_OK(b, gfmd_get_gap(b, gb));
    /* same physics, transposed storage: gaps agree to the relaxation tolerance (1e-10) */
    for (int64_t iy = 0; iy < ny; ++iy)
        for (int64_t ix = 0; ix < nx; ++ix) assert_true(fabs(ga[ix + nx * iy] - gb[iy + ny * ix]) < 1e-6);
    free(h);
    free(ht);
    free(ga);
    free(gb);
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(substrate_along_x),
        cmocka_unit_test(substrate_along_y),
        cmocka_unit_test(transposed_problem),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
