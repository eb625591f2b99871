/* Test 5: randomly rough substrates, GFMD against an independent second algorithm, the
 * constrained conjugate-gradient method of Polonsky & Keer on the pressure (cg_reference.c), on
 * the same grid and Green's function.  Plus force balance, the elastic energy as half the work of
 * the contact pressure, and the two GFMD solvers against each other. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "cg_reference.h"
#include "gfmd.h"
#include "test_support.h"

typedef struct {
    int64_t n;
    int32_t kind;
    double width; /* in grid spacings */
    double nu;
    double sigma0;
} rough_case;

static void compare_with_cg(const rough_case *c) {
    const int64_t n = c->n, nn = n * n;
    const double l = (double)n;
    gfmd_sim *s = ts_create(n, n, l, l);
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, l / 4.0, 4.0, 1.0, 2016, GFMD_DIST_UNIFORM));
    if (c->kind == GFMD_GREEN_LAYER_BONDED) TS_OK(s, gfmd_set_poisson(s, c->nu));
    if (c->kind != GFMD_GREEN_HALFSPACE) TS_OK(s, gfmd_set_green(s, c->kind, c->width));
    TS_OK(s, gfmd_set_pressure(s, c->sigma0));
    int64_t steps = 0;
    /* the default tolerance: what a user gets */
    TS_OK(s, gfmd_relax(s, 0.0, 200000, &steps));

    double area = 0, gap = 0, u_el = 0, u_ad = 0;
    TS_OK(s, gfmd_get_contact_area(s, &area));
    TS_OK(s, gfmd_get_mean_gap(s, &gap));
    TS_OK(s, gfmd_get_energies(s, &u_el, &u_ad));
    double *h = ts_alloc((size_t)nn), *p = ts_alloc((size_t)nn), *z = ts_alloc((size_t)nn);
    TS_OK(s, gfmd_get_heights(s, h));
    TS_OK(s, gfmd_get_pressure(s, p));
    TS_OK(s, gfmd_get_surface(s, z));

    cg_result ref = cg_solve(n, n, l, l, h, c->kind, c->width, c->nu, 1.0, c->sigma0, 1e-10, 200000, NULL, NULL);
    assert_true(ref.converged);
    print_message("n=%lld kind=%d w=%.2f sigma0=%.3g: GFMD A/A0 %.5f gap %.5f (%lld steps) | CG A/A0 %.5f gap %.5f "
                  "(%lld iterations)\n",
                  (long long)n, c->kind, c->width, c->sigma0, area, gap, (long long)steps, ref.rel_area, ref.mean_gap,
                  (long long)ref.iterations);
    /* The acceptance: A/A0 within 1 %, mean gap within 0.5 %. */
    assert_true(ts_rel(area, ref.rel_area) < 0.01);
    assert_true(ts_rel(gap, ref.mean_gap) < 0.005);

    /* Force balance: mean pressure = sigma0.  The residual criterion bounds the rms force error
     * by 1e-6 sigma0 per point, so the mean is off by less than that. */
    double psum = 0.0, zbar = 0.0;
    for (int64_t i = 0; i < nn; ++i) {
        psum += p[i];
        zbar += z[i];
    }
    zbar /= (double)nn;
    assert_true(ts_rel(psum / (double)nn, c->sigma0) < 1e-5);

    /* U_el = (1/2) integral p (u - <u>) dA at equilibrium (Clapeyron), and the library's U_el equals
     * the test's own FFT evaluation of (A/2) sum |u(q)|^2/G(q) for the same surface. */
    double work = 0.0;
    for (int64_t i = 0; i < nn; ++i) work += p[i] * (z[i] - zbar);
    work *= 0.5 * l * l / (double)nn;
    double direct = ts_elastic_energy(n, n, l, l, c->kind, c->width, c->nu, 1.0, z);
    assert_true(ts_rel(u_el, direct) < 1e-10);
    assert_true(ts_rel(u_el, work) < 1e-4);
    assert_true(ts_rel(u_el, ref.elastic) < 0.01);
    free(h);
    free(p);
    free(z);
    gfmd_sim_destroy(&s);
}

static void halfspace(void **state) {
    (void)state;
    rough_case c = {64, GFMD_GREEN_HALFSPACE, 0.0, 0.0, 0.05};
    compare_with_cg(&c);
    c.n = 128;
    c.sigma0 = 0.2;
    compare_with_cg(&c);
}

static void fluid_layers(void **state) {
    (void)state;
    rough_case c = {64, GFMD_GREEN_LAYER_FLUID, 4.0, 0.0, 0.05}; /* W = w/lambda_s = 1 */
    compare_with_cg(&c);
    c.n = 128;
    c.width = 16.0; /* W = 4 */
    c.sigma0 = 0.02;
    compare_with_cg(&c);
}

static void bonded_layer(void **state) {
    (void)state;
    rough_case c = {64, GFMD_GREEN_LAYER_BONDED, 4.0, 0.3, 0.05};
    compare_with_cg(&c);
}

static void solvers_agree(void **state) {
    (void)state;
    /* The seed paper's damped dynamics and FIRE must reach the same equilibrium. */
    const int64_t n = 64;
    double a[2], g[2];
    for (int k = 0; k < 2; ++k) {
        gfmd_sim *s = ts_create(n, n, 64.0, 64.0);
        TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 1.0, 99, GFMD_DIST_UNIFORM));
        TS_OK(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 8.0));
        TS_OK(s, gfmd_set_solver(s, k == 0 ? GFMD_SOLVER_VERLET : GFMD_SOLVER_FIRE));
        TS_OK(s, gfmd_set_pressure(s, 0.05));
        int64_t steps = 0;
        TS_OK(s, gfmd_relax(s, 1e-8, 500000, &steps));
        TS_OK(s, gfmd_get_contact_area(s, &a[k]));
        TS_OK(s, gfmd_get_mean_gap(s, &g[k]));
        print_message("%s: A/A0 %.6f gap %.6f in %lld steps\n", k == 0 ? "Verlet" : "FIRE", a[k], g[k],
                      (long long)steps);
        gfmd_sim_destroy(&s);
    }
    /* Both relaxed to 1e-8: the contact sets agree but for points at the edge (1/4096 each). */
    assert_true(fabs(a[0] - a[1]) <= 2.0 / (double)(n * n));
    assert_true(ts_rel(g[0], g[1]) < 1e-5);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(halfspace),
        cmocka_unit_test(fluid_layers),
        cmocka_unit_test(bonded_layer),
        cmocka_unit_test(solvers_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
