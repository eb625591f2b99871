/* Contact patches and the pressure distribution.  The labelling is checked on hand-made sets whose
 * patches are known (a ring across the periodic border, a checkerboard, full and empty contact)
 * and against a second algorithm written here (union-find over the same neighbour relation) on
 * random sets; the handle's patches against its own observables (areas summing to A/A0, loads to
 * the force sigma0 lx ly); the histogram against the pressure field it bins; Persson's P(p)
 * against its integrals (A/A0 from gfmd_persson_contact_area, first moment sigma0). */
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

static int64_t count_patches(int64_t nx, int64_t ny, const int32_t *mask, int32_t conn, int32_t periodic,
                             int64_t *labels) {
    int64_t n = -1;
    assert_int_equal(gfmd_label_patches(nx, ny, mask, conn, periodic, labels, &n), GFMD_OK);
    return n;
}

/* An annulus centred on the grid's corner: across the periodic border in both directions. */
static void ring_across_the_border(void **state) {
    (void)state;
    const int64_t nx = 40, ny = 32;
    int32_t *mask = calloc((size_t)(nx * ny), sizeof *mask);
    int64_t *labels = calloc((size_t)(nx * ny), sizeof *labels);
    for (int64_t iy = 0; iy < ny; ++iy)
        for (int64_t ix = 0; ix < nx; ++ix) {
            const double dx = (double)(ix < nx / 2 ? ix : ix - nx), dy = (double)(iy < ny / 2 ? iy : iy - ny);
            const double r = sqrt(dx * dx + dy * dy);
            mask[ix + nx * iy] = r >= 5.0 && r <= 8.0;
        }
    assert_int_equal(count_patches(nx, ny, mask, 4, 1, labels), 1);
    assert_int_equal(count_patches(nx, ny, mask, 8, 1, labels), 1);
    /* cut by the border into the four quarters around the corners */
    assert_int_equal(count_patches(nx, ny, mask, 4, 0, labels), 4);
    assert_int_equal(count_patches(nx, ny, mask, 8, 0, labels), 4);
    free(mask);
    free(labels);
}

static void checkerboard(void **state) {
    (void)state;
    const int64_t nx = 8, ny = 6;
    int32_t mask[48];
    int64_t labels[48];
    for (int64_t i = 0; i < nx * ny; ++i) mask[i] = ((i % nx) + (i / nx)) % 2 == 0;
    /* 4-connectivity: every point its own patch, numbered in index order */
    assert_int_equal(count_patches(nx, ny, mask, 4, 1, labels), nx * ny / 2);
    int64_t expect = 0;
    for (int64_t i = 0; i < nx * ny; ++i) assert_int_equal(labels[i], mask[i] ? ++expect : 0);
    /* 8-connectivity: the diagonals join them all (even sizes: the board continues over the border) */
    assert_int_equal(count_patches(nx, ny, mask, 8, 1, labels), 1);
    for (int64_t i = 0; i < nx * ny; ++i) assert_int_equal(labels[i], mask[i] ? 1 : 0);
}

static void full_and_empty(void **state) {
    (void)state;
    const int64_t nx = 16, ny = 8;
    gfmd_sim *s = ts_create_estimate(nx, ny, 16.0, 8.0);
    /* a flat substrate pressed: full contact, one patch without boundary */
    TS_OK(s, gfmd_set_pressure(s, 0.1));
    TS_OK(s, gfmd_relax(s, 1e-9, 1000, NULL));
    int64_t n = -1;
    double v[2] = {-1.0, -1.0};
    TS_OK(s, gfmd_get_patch_property(s, 4, GFMD_PATCH_EDGES, 2, v, &n));
    assert_int_equal(n, 1);
    assert_true(v[0] == 0.0);
    TS_OK(s, gfmd_get_patch_property(s, 8, GFMD_PATCH_POINTS, 2, v, &n));
    assert_true(v[0] == (double)(nx * ny));
    /* empty set: no patches */
    int32_t mask[128] = {0};
    int64_t labels[128];
    assert_int_equal(count_patches(nx, ny, mask, 8, 1, labels), 0);
    for (int i = 0; i < 128; ++i) assert_int_equal(labels[i], 0);
    gfmd_sim_destroy(&s);
}

/* A second algorithm: union-find with path halving, then labels renumbered by first index. */
static int64_t find(int64_t *parent, int64_t i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

static int64_t union_find_labels(int64_t nx, int64_t ny, const int32_t *mask, int conn, int periodic,
                                 int64_t *labels) {
    const int64_t n = nx * ny;
    int64_t *parent = malloc((size_t)n * sizeof *parent);
    for (int64_t i = 0; i < n; ++i) parent[i] = i;
    const int steps[4][2] = {{1, 0}, {0, 1}, {1, 1}, {-1, 1}}; /* forward half of the neighbours */
    for (int64_t iy = 0; iy < ny; ++iy)
        for (int64_t ix = 0; ix < nx; ++ix) {
            if (!mask[ix + nx * iy]) continue;
            for (int k = 0; k < (conn == 8 ? 4 : 2); ++k) {
                int64_t jx = ix + steps[k][0], jy = iy + steps[k][1];
                if (periodic) {
                    jx = (jx + nx) % nx;
                    jy = (jy + ny) % ny;
                } else if (jx < 0 || jx >= nx || jy >= ny) {
                    continue;
                }
                if (!mask[jx + nx * jy]) continue;
                const int64_t a = find(parent, ix + nx * iy), b = find(parent, jx + nx * jy);
                if (a != b) parent[a < b ? b : a] = a < b ? a : b;
            }
        }
    int64_t *name = calloc((size_t)n, sizeof *name), count = 0;
    for (int64_t i = 0; i < n; ++i) {
        if (!mask[i]) {
            labels[i] = 0;
            continue;
        }
        const int64_t r = find(parent, i);
        if (name[r] == 0) name[r] = ++count;
        labels[i] = name[r];
    }
    free(parent);
    free(name);
    return count;
}

static void random_sets_against_union_find(void **state) {
    (void)state;
    const int64_t sizes[][2] = {{37, 23}, {64, 64}, {5, 1}, {1, 7}, {2, 2}};
    const double densities[] = {0.2, 0.45, 0.6, 0.9};
    uint64_t seed = 12345;
    for (int s = 0; s < 5; ++s) {
        const int64_t nx = sizes[s][0], ny = sizes[s][1], n = nx * ny;
        int32_t *mask = malloc((size_t)n * sizeof *mask);
        int64_t *a = malloc((size_t)n * sizeof *a), *b = malloc((size_t)n * sizeof *b);
        for (int d = 0; d < 4; ++d) {
            for (int64_t i = 0; i < n; ++i) {
                seed = seed * 6364136223846793005u + 1442695040888963407u;
                mask[i] = (double)(seed >> 11) / 9007199254740992.0 < densities[d];
            }
            for (int conn = 4; conn <= 8; conn += 4)
                for (int periodic = 0; periodic <= 1; ++periodic) {
                    const int64_t na = count_patches(nx, ny, mask, conn, periodic, a);
                    const int64_t nb = union_find_labels(nx, ny, mask, conn, periodic, b);
                    assert_int_equal(na, nb);
                    assert_memory_equal(a, b, (size_t)n * sizeof *a);
                }
        }
        free(mask);
        free(a);
        free(b);
    }
}

/* A 3 x 2 block across the corner of a 32 x 16 grid on a 64 x 48 cell (spacing 2 x 3): its centroid
 * is at the corner's x (mean of -1, 0, 1) and half a spacing in y (mean of -1, 0) -- folded into
 * the cell: (0, ly - 1.5); 3 x 2 points, edges 2 x 2 along x and 2 x 3 along y. */
static void properties_of_a_block_across_the_corner(void **state) {
    (void)state;
    const int64_t nx = 32, ny = 16;
    gfmd_sim *s = ts_create_estimate(nx, ny, 64.0, 48.0);
    double *h = ts_alloc((size_t)(nx * ny));
    for (int64_t i = 0; i < nx * ny; ++i) h[i] = -1.0;
    const int64_t xs[] = {nx - 1, 0, 1}, ys[] = {ny - 1, 0};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 2; ++b) h[xs[a] + nx * ys[b]] = 0.0;
    TS_OK(s, gfmd_set_heights(s, h)); /* the body rests flat on the block's top: the block is the contact */
    int64_t n = 0;
    double v = 0.0;
    TS_OK(s, gfmd_get_patch_property(s, 4, GFMD_PATCH_POINTS, 1, &v, &n));
    assert_int_equal(n, 1);
    assert_true(v == 6.0);
    TS_OK(s, gfmd_get_patch_property(s, 4, GFMD_PATCH_AREA, 1, &v, &n));
    assert_true(v == 36.0);
    TS_OK(s, gfmd_get_patch_property(s, 4, GFMD_PATCH_EDGES, 1, &v, &n));
    assert_true(v == 10.0);
    /* the boundary's length: 4 edges across x of length dy = 3, 6 across y of length dx = 2 */
    TS_OK(s, gfmd_get_patch_property(s, 4, GFMD_PATCH_PERIMETER, 1, &v, &n));
    assert_true(fabs(v - 0.25 * M_PI * 24.0) <= 1e-13 * v);
    TS_OK(s, gfmd_get_patch_property(s, 4, GFMD_PATCH_CENTROID_X, 1, &v, &n));
    assert_true(v == 0.0);
    TS_OK(s, gfmd_get_patch_property(s, 8, GFMD_PATCH_CENTROID_Y, 1, &v, &n));
    assert_true(fabs(v - 46.5) <= 1e-13);
    /* unknown property, bad connectivity, too little room */
    assert_int_equal(gfmd_get_patch_property(s, 4, 99, 1, &v, &n), GFMD_ERR_BAD_ENUM);
    assert_int_equal(gfmd_get_patch_property(s, 6, GFMD_PATCH_AREA, 1, &v, &n), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_get_patch_property(s, 4, GFMD_PATCH_AREA, 0, NULL, &n), GFMD_ERR_TRUNCATED);
    assert_int_equal(n, 1);
    assert_int_equal(gfmd_get_patch_property(s, 4, GFMD_PATCH_AREA, -1, &v, &n), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_get_patch_property(s, 4, GFMD_PATCH_AREA, 1, NULL, &n), GFMD_ERR_NULL);
    assert_int_equal(gfmd_get_patch_property(s, 4, GFMD_PATCH_AREA, 1, &v, NULL), GFMD_ERR_NULL);
    assert_int_equal(gfmd_get_patch_property(NULL, 4, GFMD_PATCH_AREA, 1, &v, &n), GFMD_ERR_NULL);
    assert_int_equal(gfmd_get_contact_patches(s, 3, NULL, &n), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_get_contact_patches(s, 4, NULL, NULL), GFMD_ERR_NULL);
    int64_t lab[4];
    int32_t m[4] = {1, 0, 0, 1};
    assert_int_equal(gfmd_label_patches(0, 4, m, 4, 1, lab, &n), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_label_patches(4, 1, m, 5, 1, lab, &n), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_label_patches(4, 1, NULL, 4, 1, lab, &n), GFMD_ERR_NULL);
    /* periodic: the ends of a row of 4 touch */
    assert_int_equal(count_patches(4, 1, m, 4, 1, lab), 1);
    assert_int_equal(count_patches(4, 1, m, 4, 0, lab), 2);
    free(h);
    gfmd_sim_destroy(&s);
}

/* A relaxed rough contact, on one thread and on two. */
static gfmd_sim *rough_contact(int32_t threads, double sigma0) {
    gfmd_sim *s = NULL;
    assert_int_equal(gfmd_sim_create_ex(128, 128, 128.0, 128.0, threads, GFMD_PLANNER_ESTIMATE, &s), GFMD_OK);
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 64.0, 4.0, 1.0, 7, GFMD_DIST_UNIFORM));
    TS_OK(s, gfmd_set_pressure(s, sigma0));
    TS_OK(s, gfmd_relax(s, 1e-10, 100000, NULL));
    return s;
}

static void patches_of_a_rough_contact(void **state) {
    (void)state;
    const int64_t n = 128 * 128;
    const double sigma0 = 0.02, cell = 128.0 * 128.0;
    gfmd_sim *s = rough_contact(1, sigma0), *t = rough_contact(2, sigma0);
    int64_t *labels = malloc((size_t)n * sizeof *labels), *labels2 = malloc((size_t)n * sizeof *labels2);
    int64_t count = 0, count2 = 0;
    TS_OK(s, gfmd_get_contact_patches(s, 8, labels, &count));
    TS_OK(t, gfmd_get_contact_patches(t, 8, labels2, &count2));
    assert_int_equal(count, count2); /* the same at 1 and 2 threads, label for label */
    assert_memory_equal(labels, labels2, (size_t)n * sizeof *labels);
    print_message("sigma0 = %.3f: %lld patches (8-connected)\n", sigma0, (long long)count);
    assert_true(count > 5);
    /* the labels are those of the contact set seen from outside (zero gap) */
    double *gap = ts_alloc((size_t)n);
    int32_t *mask = malloc((size_t)n * sizeof *mask);
    TS_OK(s, gfmd_get_gap(s, gap));
    for (int64_t i = 0; i < n; ++i) mask[i] = gap[i] <= 0.0;
    assert_int_equal(count_patches(128, 128, mask, 8, 1, labels2), count);
    assert_memory_equal(labels, labels2, (size_t)n * sizeof *labels);
    /* areas sum to A/A0 (integers in doubles: exact), loads to the force sigma0 lx ly within the
     * relaxation's residual (1e-10 of sigma0 per point) */
    double *v = ts_alloc((size_t)count);
    double a = 0.0, sum = 0.0;
    int64_t k = 0;
    TS_OK(s, gfmd_get_contact_area(s, &a));
    TS_OK(s, gfmd_get_patch_property(s, 8, GFMD_PATCH_AREA, count, v, &k));
    for (int64_t i = 0; i < count; ++i) sum += v[i];
    assert_true(sum == a * cell);
    TS_OK(s, gfmd_get_patch_property(s, 8, GFMD_PATCH_LOAD, count, v, &k));
    sum = 0.0;
    for (int64_t i = 0; i < count; ++i) sum += v[i];
    print_message("sum of patch loads / (sigma0 A0) - 1 = %.2e\n", sum / (sigma0 * cell) - 1.0);
    assert_true(fabs(sum / (sigma0 * cell) - 1.0) <= 1e-8);
    /* 4-connectivity splits, never joins: at least as many patches */
    int64_t count4 = 0;
    TS_OK(s, gfmd_get_contact_patches(s, 4, NULL, &count4));
    assert_true(count4 >= count);
    free(v);
    free(gap);
    free(mask);
    free(labels);
    free(labels2);
    gfmd_sim_destroy(&s);
    gfmd_sim_destroy(&t);
}

static void pressure_histogram_balances(void **state) {
    (void)state;
    const int64_t n = 128 * 128;
    const double sigma0 = 0.05;
    gfmd_sim *s = rough_contact(1, sigma0);
    enum { kBins = 40 };
    double fraction[kBins], mean[kBins], range[2] = {0.0, 0.0};
    TS_OK(s, gfmd_get_pressure_histogram(s, kBins, range, fraction, mean));
    double *p = ts_alloc((size_t)n), *gap = ts_alloc((size_t)n);
    TS_OK(s, gfmd_get_pressure(s, p));
    TS_OK(s, gfmd_get_gap(s, gap));
    double pmax = 0.0, contact_sum = 0.0, a = 0.0, total = 0.0, moment = 0.0;
    for (int64_t i = 0; i < n; ++i)
        if (gap[i] <= 0.0) {
            pmax = fmax(pmax, p[i]);
            contact_sum += p[i];
        }
    assert_true(range[1] == pmax);
    for (int b = 0; b < kBins; ++b) {
        total += fraction[b];
        moment += fraction[b] * mean[b];
    }
    TS_OK(s, gfmd_get_contact_area(s, &a));
    /* sums of at most 40 terms of counts / n (exact) and of bin sums: rounding, 1e-14 */
    assert_true(fabs(total - a) <= 1e-14);
    assert_true(fabs(moment - contact_sum / (double)n) <= 1e-14 * sigma0);
    /* force balance: the contact carries sigma0 within the relaxation's residual */
    print_message("A/A0 = %.5f, first moment / sigma0 - 1 = %.2e\n", a, moment / sigma0 - 1.0);
    assert_true(fabs(moment / sigma0 - 1.0) <= 1e-8);
    /* a range given: pressures beyond it in the end bins, the totals kept */
    double r2[2] = {0.0, 0.5 * pmax};
    TS_OK(s, gfmd_get_pressure_histogram(s, kBins, r2, fraction, mean));
    total = 0.0;
    for (int b = 0; b < kBins; ++b) total += fraction[b];
    assert_true(fabs(total - a) <= 1e-14);
    double bad[2] = {1.0, 1.0};
    assert_int_equal(gfmd_get_pressure_histogram(s, kBins, bad, fraction, mean), GFMD_ERR_INVALID_ARG);
    bad[1] = NAN;
    assert_int_equal(gfmd_get_pressure_histogram(s, kBins, bad, fraction, mean), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_get_pressure_histogram(s, 0, range, fraction, mean), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_get_pressure_histogram(s, kBins, NULL, fraction, mean), GFMD_ERR_NULL);

    /* Persson's P(p): trapezoids on [0, sigma0 + 12 sqrt(V)] (the tail beyond is below 1e-30)
     * with 20 000 intervals: the rule's error (h^2/12 of P'' ~ 1/V) is below 1e-8 */
    double var = 0.0, theory = 0.0;
    TS_OK(s, gfmd_persson_variance(s, &var));
    TS_OK(s, gfmd_persson_contact_area(s, sigma0, &theory));
    enum { kPoints = 20001 };
    double *pp = ts_alloc(kPoints), *dens = ts_alloc(kPoints);
    const double top = sigma0 + 12.0 * sqrt(var), dp = top / (kPoints - 1);
    for (int i = 0; i < kPoints; ++i) pp[i] = i * dp;
    TS_OK(s, gfmd_persson_pressure_distribution(s, sigma0, kPoints, pp, dens));
    double area = 0.0, first = 0.0;
    for (int i = 0; i < kPoints; ++i) {
        const double w = (i == 0 || i == kPoints - 1) ? 0.5 : 1.0;
        area += w * dens[i] * dp;
        first += w * pp[i] * dens[i] * dp;
    }
    print_message("Persson: integral %.8f vs A/A0 %.8f, first moment / sigma0 = %.8f\n", area, theory, first / sigma0);
    assert_true(fabs(area - theory) <= 1e-8);
    assert_true(fabs(first / sigma0 - 1.0) <= 1e-7);
    assert_true(dens[0] == 0.0); /* the absorbing boundary */
    double neg = -1.0, dneg = -1.0;
    TS_OK(s, gfmd_persson_pressure_distribution(s, sigma0, 1, &neg, &dneg));
    assert_true(dneg == 0.0);
    neg = NAN;
    assert_int_equal(gfmd_persson_pressure_distribution(s, sigma0, 1, &neg, &dneg), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_persson_pressure_distribution(s, -1.0, 1, pp, dens), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_persson_pressure_distribution(s, sigma0, -1, pp, dens), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_persson_pressure_distribution(s, sigma0, 1, NULL, dens), GFMD_ERR_NULL);
    free(pp);
    free(dens);
    free(p);
    free(gap);
    gfmd_sim_destroy(&s);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ring_across_the_border),
        cmocka_unit_test(checkerboard),
        cmocka_unit_test(full_and_empty),
        cmocka_unit_test(random_sets_against_union_find),
        cmocka_unit_test(properties_of_a_block_across_the_corner),
        cmocka_unit_test(patches_of_a_rough_contact),
        cmocka_unit_test(pressure_histogram_balances),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
