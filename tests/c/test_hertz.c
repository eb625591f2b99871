/* Hertz.  A paraboloid h = -r^2/(2R) pressed into a half-space by the force F = sigma0 A
 * makes a circular contact of radius a = (3 F R / (4 E*))^(1/3) with central pressure
 * p0 = 2 E* a / (pi R) (K. L. Johnson, Contact Mechanics, Sec. 4.2). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "gfmd.h"
#include "test_support.h"

static void check_hertz(int64_t n, double radius, double a_target, double e_star) {
    const double l = (double)n;
    gfmd_sim *s = ts_create(n, n, l, l);
    double *h = ts_alloc((size_t)(n * n));
    for (int64_t iy = 0; iy < n; ++iy)
        for (int64_t ix = 0; ix < n; ++ix) {
            double x = (double)ix - l / 2, y = (double)iy - l / 2;
            h[ix + n * iy] = -(x * x + y * y) / (2.0 * radius);
        }
    TS_OK(s, gfmd_set_heights(s, h));
    TS_OK(s, gfmd_set_modulus(s, e_star));
    const double force = 4.0 * e_star * a_target * a_target * a_target / (3.0 * radius);
    TS_OK(s, gfmd_set_pressure(s, force / (l * l)));
    int64_t steps = 0;
    TS_OK(s, gfmd_relax(s, 1e-8, 100000, &steps));
    double area = 0.0;
    TS_OK(s, gfmd_get_contact_area(s, &area));
    const double a_num = sqrt(area * l * l / M_PI);
    print_message("Hertz n=%lld: contact radius %.3f, expected %.3f (%lld steps)\n", (long long)n, a_num, a_target,
                  (long long)steps);
    /* The contact line is resolved to a grid spacing and the periodic images of the sphere
     * (cell 6-10 contact radii wide) shift it by a fraction of one: allow one spacing. */
    assert_true(fabs(a_num - a_target) < 1.0);

    /* Central pressure: the discretization error is of order (spacing/a)^2 with a = 12-20 spacings. */
    double *p = ts_alloc((size_t)(n * n));
    TS_OK(s, gfmd_get_pressure(s, p));
    const double p0 = 2.0 * e_star * a_target / (M_PI * radius);
    print_message("Hertz n=%lld: central pressure %.5f, expected %.5f\n", (long long)n, p[n / 2 + n * (n / 2)], p0);
    assert_true(ts_rel(p[n / 2 + n * (n / 2)], p0) < 0.02);
    /* Force balance: the pressures carry the load (relaxed to 1e-8 of sigma0). */
    double sum = 0.0;
    for (int64_t i = 0; i < n * n; ++i) sum += p[i];
    assert_true(ts_rel(sum, force) < 1e-6);
    free(p);
    free(h);
    gfmd_sim_destroy(&s);
}

/* Under valgrind the 128^2 sphere only: the 256^2 one runs the same calls at four times the cost
 * (three quarters of the test's time there). */
static void hertz_sphere(void **state) {
    (void)state;
    if (!ts_valgrind()) check_hertz(256, 100.0, 20.0, 1.0);
    check_hertz(128, 60.0, 12.0, 2.5);
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(hertz_sphere)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
