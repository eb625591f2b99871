/* Free boundaries (gfmd_set_boundary(s, GFMD_BOUNDARY_FREE)): the grid is the whole region of a
 * half-space whose surface beyond it carries no load.  Checked against Hertz's solution without
 * periodic images (K. L. Johnson, Contact Mechanics, Sec. 4.2: a = (3 F R / (4 E*))^(1/3),
 * p0 = 3 F / (2 pi a^2), approach a^2 / R) at two resolutions, against Boussinesq's field of the
 * computed pressure summed directly by the test (Love's uniformly loaded rectangle, independent of
 * the library's FFTs), against periodic cells of growing size, and for every refusal and the
 * checkpoint. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "gfmd.h"
#include "test_support.h"

/* The integral of 1/r over [0, x] x [0, y], and Love's displacement at (x, y) from the centre of a
 * cell ax x ay under unit pressure: (1/(pi E*)) times the integral over the cell (Johnson Eq. 3.25
 * in a form without cancellation). */
static double inv_r(double x, double y) {
    double s = 0.0;
    if (x != 0.0) s += x * asinh(y / fabs(x));
    if (y != 0.0) s += y * asinh(x / fabs(y));
    return s;
}
static double love(double x, double y, double ax, double ay, double e_star) {
    const double x0 = x - ax / 2, x1 = x + ax / 2, y0 = y - ay / 2, y1 = y + ay / 2;
    return (inv_r(x1, y1) - inv_r(x0, y1) - inv_r(x1, y0) + inv_r(x0, y0)) / (M_PI * e_star);
}

typedef struct {
    double radius, p0, approach, force_sum, u_el, u_direct, field_error, gap_error;
    int64_t steps;
} Hertz;

/* A sphere h = -r^2/(2R) centred in an n x n region of side l, pressed by F with free boundaries
 * (or in a periodic cell of `cells` regions a side when cells > 0), relaxed with `solver`. */
static Hertz hertz(int64_t n, double l, double radius, double force, double e_star, int32_t solver, int cells,
                   int check_field) {
    const int64_t m = cells > 0 ? n * cells : n;
    const double side = cells > 0 ? l * cells : l, a = l / (double)n;
    gfmd_sim *s = ts_create(m, m, side, side);
    double *h = ts_alloc((size_t)(m * m)), *p = ts_alloc((size_t)(m * m)), *z = ts_alloc((size_t)(m * m));
    for (int64_t iy = 0; iy < m; ++iy)
        for (int64_t ix = 0; ix < m; ++ix) {
            const double x = ((double)ix + 0.5) * a - side / 2, y = ((double)iy + 0.5) * a - side / 2;
            h[ix + m * iy] = -(x * x + y * y) / (2.0 * radius);
        }
    if (cells == 0) TS_OK(s, gfmd_set_boundary(s, GFMD_BOUNDARY_FREE));
    TS_OK(s, gfmd_set_solver(s, solver));
    TS_OK(s, gfmd_set_modulus(s, e_star));
    TS_OK(s, gfmd_set_heights(s, h));
    TS_OK(s, gfmd_set_pressure(s, force / (side * side)));
    Hertz r = {0};
    TS_OK(s, gfmd_relax(s, 1e-9, 200000, &r.steps));
    double area = 0.0, mean_z = 0.0, u_ad = 0.0;
    TS_OK(s, gfmd_get_contact_area(s, &area));
    TS_OK(s, gfmd_get_pressure(s, p));
    TS_OK(s, gfmd_get_surface(s, z));
    TS_OK(s, gfmd_get_mean_displacement(s, &mean_z));
    TS_OK(s, gfmd_get_energies(s, &r.u_el, &u_ad));
    r.radius = sqrt(area * side * side / M_PI);
    r.p0 = p[m / 2 + m * (m / 2)];
    for (int64_t i = 0; i < m * m; ++i) r.force_sum += p[i] * a * a;
    /* the approach: how far the surface far from the contact lies below the sphere's apex (h = 0
     * there, between the four central points) */
    r.approach = -mean_z;
    if (check_field) {
        /* z = delta + sum_j K(i - j) p_j at every point of the region (the contact pressure lifts
         * the surface), delta the far level */
        double worst = 0.0, worst_gap = 0.0;
        for (int64_t i = 0; i < m * m; ++i) {
            double u = 0.0;
            for (int64_t j = 0; j < m * m; ++j)
                if (p[j] != 0.0)
                    u += p[j] * love((double)(i % m - j % m) * a, (double)(i / m - j / m) * a, a, a, e_star);
            r.u_direct += 0.5 * a * a * p[i] * u;
            worst = fmax(worst, fabs(z[i] - (mean_z + u)));
            if (p[i] > 0.0) worst_gap = fmax(worst_gap, fabs(z[i] - h[i]));
        }
        r.field_error = worst;
        r.gap_error = worst_gap;
    }
    free(h);
    free(p);
    free(z);
    gfmd_sim_destroy(&s);
    return r;
}

/* Hertz at two resolutions of one physical problem: a region 4 contact radii wide (the periodic
 * cell would need ~10 for a 1 % radius), a = 8 and 16 spacings. */
static void hertz_two_resolutions(void **state) {
    (void)state;
    const double l = 1.0, radius = 1.0, e_star = 2.0, a_hertz = 0.25;
    const double force = 4.0 * e_star * a_hertz * a_hertz * a_hertz / (3.0 * radius);
    const double p0 = 3.0 * force / (2.0 * M_PI * a_hertz * a_hertz), d = a_hertz * a_hertz / radius;
    double err_a[2], err_p[2], err_d[2];
    const int64_t sizes[2] = {32, 64};
    /* under valgrind the 32^2 region only (the 64^2 one, a 128^2 padded cell, runs the same calls
     * at four times the cost); the native and sanitizer runs compare the two */
    const int runs = ts_valgrind() ? 1 : 2;
    for (int k = 0; k < runs; ++k) {
        const Hertz r = hertz(sizes[k], l, radius, force, e_star, GFMD_SOLVER_AUTO, 0, 0);
        err_a[k] = fabs(r.radius - a_hertz) / a_hertz;
        err_p[k] = fabs(r.p0 - p0) / p0;
        err_d[k] = fabs(r.approach - d) / d;
        print_message("free Hertz %lld^2: radius %.5f (%.5f), p0 %.5f (%.5f), approach %.6f (%.6f), %lld steps\n",
                      (long long)sizes[k], r.radius, a_hertz, r.p0, p0, r.approach, d, (long long)r.steps);
        /* force balance: the pressures carry sigma0 lx ly (relaxed to 1e-9) */
        assert_true(ts_rel(r.force_sum, force) < 1e-6);
    }
    /* The contact line is resolved to a spacing: the radius to half of one (1/16 and 1/32 of a;
     * measured 1.7 % and 0.5 %).  The central pressure and the approach converge as (spacing/a)^2,
     * the error of the piecewise-constant pressure: within half of it (measured 0.36 % -> 0.09 %
     * and 0.11 % -> 0.02 %), and falling with the spacing. */
    assert_true(err_a[0] < 0.5 / 8 && err_p[0] < 0.5 / 64 && err_d[0] < 0.5 / 64);
    if (runs == 1) return;
    assert_true(err_a[1] < 0.5 / 16);
    assert_true(err_p[1] < 0.5 / 256 && err_p[1] < err_p[0]);
    assert_true(err_d[1] < 0.5 / 256 && err_d[1] < err_d[0]);
}

/* Boussinesq's field of the computed pressure, summed directly (no FFT, no images): the surface
 * the library returns is delta - K p at every point of the region, in contact or not, to the
 * relaxation's precision; U_el = (1/2) sum p u. */
static void boussinesq_field(void **state) {
    (void)state;
    const double e_star = 1.5, radius = 2.0, a_hertz = 0.2;
    const double force = 4.0 * e_star * a_hertz * a_hertz * a_hertz / (3.0 * radius);
    const int32_t solvers[3] = {GFMD_SOLVER_CG, GFMD_SOLVER_FIRE, GFMD_SOLVER_VERLET};
    for (int k = 0; k < (ts_valgrind() ? 1 : 3); ++k) {
        const Hertz r = hertz(24, 0.8, radius, force, e_star, solvers[k], 0, 1);
        print_message("solver %d: |z - (delta + K p)| <= %.3e, gap on contacts %.3e, U_el %.9e direct %.9e (%lld steps)\n",
                      solvers[k], r.field_error, r.gap_error, r.u_el, r.u_direct, (long long)r.steps);
        /* the residual 1e-9 of sigma0 leaves displacements of ~1e-9 sigma0 / E* l: 1e-8 of the approach */
        assert_true(r.field_error < 1e-8 * (a_hertz * a_hertz / radius) + 1e-12);
        assert_true(r.gap_error < 1e-12);
        assert_true(ts_rel(r.u_el, r.u_direct) < 1e-7);
    }
}

/* A periodic cell growing around the same sphere approaches free boundaries as its images recede. */
static void periodic_cells_approach_free(void **state) {
    (void)state;
    const double e_star = 1.0, radius = 1.0, a_hertz = 0.25;
    const double force = 4.0 * e_star * a_hertz * a_hertz * a_hertz / (3.0 * radius);
    const Hertz f = hertz(32, 1.0, radius, force, e_star, GFMD_SOLVER_AUTO, 0, 0);
    double prev = INFINITY;
    for (int cells = 1; cells <= (ts_valgrind() ? 2 : 4); cells *= 2) {
        const Hertz r = hertz(32, 1.0, radius, force, e_star, GFMD_SOLVER_AUTO, cells, 0);
        const double dp = fabs(r.p0 - f.p0) / f.p0;
        print_message("periodic cell %d x the region: p0 %.6f, free %.6f, relative difference %.2e\n", cells, r.p0,
                      f.p0, dp);
        assert_true(dp < prev); /* images 1/cells as near: the difference falls */
        prev = dp;
    }
    /* at 4 regions (images 4 l away, a = l/4) the image pressure field is ~ (a / 4 l)^3: < 1e-3 */
    if (!ts_valgrind()) assert_true(prev < 2e-3);
}

/* Adhesion with free boundaries: the default (the adhesive surface CG) and FIRE reach the same
 * state, an independent second algorithm, and the region's adhesive energy is that of its gaps. */
static void adhesive_second_algorithm(void **state) {
    (void)state;
    const int64_t n = 32;
    double area[2], gap[2], u_el[2], u_ad[2];
    double *g = ts_alloc((size_t)(n * n));
    const double gamma0 = 5e-4, rho = 0.02;
    for (int k = 0; k < 2; ++k) {
        gfmd_sim *s = ts_create(n, n, 1.0, 1.0);
        TS_OK(s, gfmd_set_boundary(s, GFMD_BOUNDARY_FREE));
        TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 0.5, 0.125, 0.3, 5, GFMD_DIST_UNIFORM));
        TS_OK(s, gfmd_set_adhesion(s, gamma0, rho));
        TS_OK(s, gfmd_set_pressure(s, 0.01));
        TS_OK(s, gfmd_set_solver(s, k == 0 ? GFMD_SOLVER_AUTO : GFMD_SOLVER_FIRE));
        TS_OK(s, gfmd_relax(s, 1e-10, 400000, NULL));
        TS_OK(s, gfmd_get_contact_area(s, &area[k]));
        TS_OK(s, gfmd_get_mean_gap(s, &gap[k]));
        TS_OK(s, gfmd_get_energies(s, &u_el[k], &u_ad[k]));
        TS_OK(s, gfmd_get_gap(s, g));
        double sum = 0.0; /* gamma0 a^2 sum exp(-g/rho) over the region: the adhesive energy's magnitude */
        for (int64_t i = 0; i < n * n; ++i) sum += gamma0 * exp(-g[i] / rho) / (double)(n * n);
        print_message("adhesive free contact, solver %d: A/A0 %.6f, mean gap %.8f, U_el %.8e, U_ad %.8e (gaps %.8e)\n",
                      k, area[k], gap[k], u_el[k], u_ad[k], sum);
        assert_true(ts_rel(u_ad[k], sum) < 1e-12);
        assert_true(area[k] > 0.0 && area[k] < 0.5);
        gfmd_sim_destroy(&s);
    }
    /* relaxed to 1e-10: both minima agree to ~1e-8 (the contact set identical) */
    assert_true(area[0] == area[1]);
    assert_true(ts_rel(gap[0], gap[1]) < 1e-7);
    assert_true(ts_rel(u_el[0], u_el[1]) < 1e-7);
    free(g);
}

/* The boundary's round trip: periodic -> free -> periodic keeps the grid, the heights and the
 * parameters, and the periodic handle then computes what a handle that never left does, bit for
 * bit.  A generated surface with free boundaries is the region's part of a periodic one twice
 * its size, highest point at zero; a contact patch ends at the region's edge. */
static void round_trip_and_generation(void **state) {
    (void)state;
    const int64_t nx = 32, ny = 24;
    gfmd_sim *a = ts_create_estimate(nx, ny, 32.0, 24.0), *b = ts_create_estimate(nx, ny, 32.0, 24.0);
    for (int k = 0; k < 2; ++k) {
        gfmd_sim *s = k == 0 ? a : b;
        TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 1.0, 7, GFMD_DIST_UNIFORM));
        TS_OK(s, gfmd_set_pressure(s, 0.05));
        TS_OK(s, gfmd_set_adhesion(s, 1e-4, 0.5));
    }
    int32_t boundary = -1;
    TS_OK(a, gfmd_get_boundary(a, &boundary));
    assert_int_equal(boundary, GFMD_BOUNDARY_PERIODIC);
    TS_OK(a, gfmd_set_boundary(a, GFMD_BOUNDARY_FREE));
    TS_OK(a, gfmd_get_boundary(a, &boundary));
    assert_int_equal(boundary, GFMD_BOUNDARY_FREE);
    int64_t gx = 0, gy = 0;
    double lx = 0.0, ly = 0.0, p = 0.0;
    TS_OK(a, gfmd_get_grid(a, &gx, &gy, &lx, &ly));
    assert_true(gx == nx && gy == ny && lx == 32.0 && ly == 24.0);
    TS_OK(a, gfmd_get_mean_pressure(a, &p));
    assert_true(p == 0.05);
    TS_OK(a, gfmd_set_boundary(a, GFMD_BOUNDARY_FREE)); /* the same boundary: nothing changes */
    TS_OK(a, gfmd_set_boundary(a, GFMD_BOUNDARY_PERIODIC));
    TS_OK(a, gfmd_relax(a, 1e-8, 100000, NULL));
    TS_OK(b, gfmd_relax(b, 1e-8, 100000, NULL));
    double *za = ts_alloc((size_t)(nx * ny)), *zb = ts_alloc((size_t)(nx * ny));
    TS_OK(a, gfmd_get_surface(a, za));
    TS_OK(b, gfmd_get_surface(b, zb));
    assert_memory_equal(za, zb, sizeof(double) * (size_t)(nx * ny));

    TS_OK(a, gfmd_set_boundary(a, GFMD_BOUNDARY_FREE));
    TS_OK(a, gfmd_generate_selfaffine(a, 0.8, 16.0, 4.0, 1.0, 7, GFMD_DIST_UNIFORM));
    TS_OK(a, gfmd_get_heights(a, za));
    double top = -INFINITY;
    for (int64_t i = 0; i < nx * ny; ++i) top = fmax(top, za[i]);
    assert_true(top == 0.0);
    /* a sphere touching the region's left and right edges: two patches, not one across the edge */
    for (int64_t iy = 0; iy < ny; ++iy)
        for (int64_t ix = 0; ix < nx; ++ix) {
            const double x = (double)(ix < nx / 2 ? ix : ix - nx), y = (double)iy - ny / 2;
            za[ix + nx * iy] = -(x * x + y * y) / 40.0;
        }
    TS_OK(a, gfmd_set_adhesion(a, 0.0, 1.0));
    TS_OK(a, gfmd_set_heights(a, za));
    TS_OK(a, gfmd_set_pressure(a, 0.02));
    TS_OK(a, gfmd_relax(a, 1e-8, 100000, NULL));
    int64_t patches = 0;
    TS_OK(a, gfmd_get_contact_patches(a, 4, NULL, &patches));
    assert_int_equal(patches, 2);
    free(za);
    free(zb);
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
}

/* What free boundaries do not take is refused with GFMD_ERR_STATE (GFMD_ERR_BAD_ENUM for an
 * unknown boundary) and changes nothing: the handle is compared with a twin that never made the
 * call, every field and observable, then after 5 more steps. */
static gfmd_sim *free_twin(void) {
    gfmd_sim *s = ts_create_estimate(24, 16, 24.0, 16.0);
    TS_OK(s, gfmd_set_boundary(s, GFMD_BOUNDARY_FREE));
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 12.0, 4.0, 1.0, 3, GFMD_DIST_UNIFORM));
    TS_OK(s, gfmd_set_pressure(s, 0.05));
    TS_OK(s, gfmd_step(s, 7));
    return s;
}

static void same(gfmd_sim *a, gfmd_sim *b, const char *after) {
    enum { N = 24 * 16 };
    double fa[N], fb[N];
    int32_t (*const getters[])(const gfmd_sim *, double *) = {gfmd_get_surface, gfmd_get_gap, gfmd_get_pressure,
                                                             gfmd_get_heights};
    for (int round = 0; round < 2; ++round) {
        for (size_t g = 0; g < sizeof getters / sizeof getters[0]; ++g) {
            TS_OK(a, getters[g](a, fa));
            TS_OK(b, getters[g](b, fb));
            if (memcmp(fa, fb, sizeof fa) != 0) fail_msg("after %s: field %zu differs", after, g);
        }
        double xa[6], xb[6];
        int32_t ia[2], ib[2];
        gfmd_sim *h[2] = {a, b};
        for (int k = 0; k < 2; ++k) {
            double *x = k == 0 ? xa : xb;
            int32_t *iv = k == 0 ? ia : ib;
            TS_OK(h[k], gfmd_get_contact_area(h[k], &x[0]));
            TS_OK(h[k], gfmd_get_mean_gap(h[k], &x[1]));
            TS_OK(h[k], gfmd_get_energies(h[k], &x[2], &x[3]));
            TS_OK(h[k], gfmd_get_residual(h[k], &x[4]));
            TS_OK(h[k], gfmd_get_mean_displacement(h[k], &x[5]));
            TS_OK(h[k], gfmd_get_boundary(h[k], &iv[0]));
            TS_OK(h[k], gfmd_get_solver(h[k], &iv[1]));
        }
        if (memcmp(xa, xb, sizeof xa) != 0 || memcmp(ia, ib, sizeof ia) != 0)
            fail_msg("after %s: an observable differs", after);
        if (round == 0) {
            TS_OK(a, gfmd_step(a, 5));
            TS_OK(b, gfmd_step(b, 5));
        }
    }
}

static int32_t unknown_boundary(gfmd_sim *s) { return gfmd_set_boundary(s, 7); }
static int32_t layer(gfmd_sim *s) { return gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 2.0); }
static int32_t position(gfmd_sim *s) { return gfmd_set_mean_displacement(s, 0.0); }
static int32_t hardness(gfmd_sim *s) { return gfmd_set_hardness(s, 0.5); }
static int32_t mass_weighted(gfmd_sim *s) { return gfmd_set_solver(s, GFMD_SOLVER_MASS_WEIGHTED_FIRE); }
static int32_t approach(gfmd_sim *s) { return gfmd_set_solver(s, GFMD_SOLVER_APPROACH_THEN_FIRE); }
static int32_t newton(gfmd_sim *s) { return gfmd_set_solver(s, GFMD_SOLVER_NEWTON); }
static int32_t multilevel(gfmd_sim *s) { return gfmd_relax_multilevel(s, 1e-6, 100, 2, NULL, NULL); }
static int32_t persson(gfmd_sim *s) {
    double v = 0.0;
    return gfmd_persson_variance(s, &v);
}
static int32_t persson_area(gfmd_sim *s) {
    double v = 0.0;
    return gfmd_persson_contact_area(s, 0.1, &v);
}
static int32_t boundary_null(gfmd_sim *s) { return gfmd_get_boundary(s, NULL); }
/* moduli whose stiffness over the grid's spacing leaves the doubles (a denormal one made the
 * kernel infinite, reported as an internal error) */
static int32_t tiny_modulus(gfmd_sim *s) { return gfmd_set_modulus(s, 1e-310); }
static int32_t huge_modulus(gfmd_sim *s) { return gfmd_set_modulus(s, DBL_MAX); }

static void refusals_change_nothing(void **state) {
    (void)state;
    static const struct {
        const char *what;
        int32_t expected;
        int32_t (*call)(gfmd_sim *);
    } calls[] = {
        {"an unknown boundary", GFMD_ERR_BAD_ENUM, unknown_boundary},
        {"a layer", GFMD_ERR_STATE, layer},
        {"displacement control", GFMD_ERR_STATE, position},
        {"a hardness", GFMD_ERR_STATE, hardness},
        {"mass-weighted FIRE", GFMD_ERR_STATE, mass_weighted},
        {"the approach then FIRE", GFMD_ERR_STATE, approach},
        {"the Newton solver", GFMD_ERR_STATE, newton},
        {"the multilevel start", GFMD_ERR_STATE, multilevel},
        {"Persson's variance", GFMD_ERR_STATE, persson},
        {"Persson's A/A0", GFMD_ERR_STATE, persson_area},
        {"the boundary into NULL", GFMD_ERR_NULL, boundary_null},
        {"a denormal modulus", GFMD_ERR_RANGE, tiny_modulus},
        {"the largest modulus", GFMD_ERR_RANGE, huge_modulus},
    };
    gfmd_sim *a = free_twin(), *b = free_twin();
    same(a, b, "creation");
    for (size_t i = 0; i < sizeof calls / sizeof calls[0]; ++i) {
        const int32_t st = calls[i].call(a);
        if (st != calls[i].expected)
            fail_msg("%s: got %s, expected %s", calls[i].what, gfmd_status_string(st),
                     gfmd_status_string(calls[i].expected));
        char msg[256] = "";
        (void)gfmd_last_error(a, msg, sizeof msg);
        if (msg[0] == '\0') fail_msg("%s: no message", calls[i].what);
        same(a, b, calls[i].what);
    }
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
    assert_int_equal(gfmd_set_boundary(NULL, GFMD_BOUNDARY_FREE), GFMD_ERR_NULL);

    /* the periodic states free boundaries do not take: refused, the handle periodic as before */
    int32_t (*const setups[])(gfmd_sim *) = {layer, position, hardness, mass_weighted};
    for (size_t k = 0; k < sizeof setups / sizeof setups[0]; ++k) {
        gfmd_sim *s = ts_create_estimate(16, 16, 16.0, 16.0);
        TS_OK(s, gfmd_set_pressure(s, 0.1));
        TS_OK(s, setups[k](s));
        assert_int_equal(gfmd_set_boundary(s, GFMD_BOUNDARY_FREE), GFMD_ERR_STATE);
        int32_t boundary = -1;
        int64_t nx = 0;
        TS_OK(s, gfmd_get_boundary(s, &boundary));
        TS_OK(s, gfmd_get_grid(s, &nx, NULL, NULL, NULL));
        assert_true(boundary == GFMD_BOUNDARY_PERIODIC && nx == 16);
        gfmd_sim_destroy(&s);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hertz_two_resolutions),
        cmocka_unit_test(boussinesq_field),
        cmocka_unit_test(periodic_cells_approach_free),
        cmocka_unit_test(adhesive_second_algorithm),
        cmocka_unit_test(round_trip_and_generation),
        cmocka_unit_test(refusals_change_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
