/* Perfect plasticity at a hardness H, against what does not depend on the solver: Hertz's onset of
 * yield (the central pressure p0 = 2 E* a / (pi R) reaches H at the load F_y = pi^3 R^2 H^3 /
 * (6 E*^2); K. L. Johnson, Contact Mechanics, Sec. 4.2), a flat punch pressed until every contact
 * point yields (the force is then H times the contact area), the volume balance of a dent left by
 * loading and unloading (the heights the handle reports against the plastic volume it reports),
 * the shakedown of reloading (elastic: no new plastic volume, the loaded contact again), the
 * elastic solution bit for bit where no point reaches H, the plastic run the same on one thread and
 * two, and checkpoints that resume the plastic run bit for bit. */
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

enum { N = 128 };
static const double kRadius = 60.0, kYieldRadius = 12.0; /* Hertz's contact radius at the onset */

static double hardness(void) { return 2.0 * kYieldRadius / (M_PI * kRadius); } /* E* = 1 */
static double yield_force(void) { return 4.0 * pow(kYieldRadius, 3) / (3.0 * kRadius); }

static gfmd_sim *sphere(double *h_out) {
    gfmd_sim *s = ts_create(N, N, N, N);
    double *h = h_out ? h_out : ts_alloc((size_t)(N * N));
    for (int64_t iy = 0; iy < N; ++iy)
        for (int64_t ix = 0; ix < N; ++ix) {
            const double x = (double)ix - N / 2, y = (double)iy - N / 2;
            h[ix + N * iy] = -(x * x + y * y) / (2.0 * kRadius);
        }
    TS_OK(s, gfmd_set_heights(s, h));
    if (!h_out) free(h);
    return s;
}

static void relax_to(gfmd_sim *s, double force) {
    TS_OK(s, gfmd_set_pressure(s, force / (N * N)));
    TS_OK(s, gfmd_relax(s, 1e-9, 200000, NULL));
}

static double max_pressure(gfmd_sim *s) {
    double *p = ts_alloc(N * N), top = 0.0;
    TS_OK(s, gfmd_get_pressure(s, p));
    for (int i = 0; i < N * N; ++i) top = fmax(top, p[i]);
    free(p);
    return top;
}

/* Hertz's central pressure is resolved to 2 % on this grid (a = 12 spacings, test_hertz): at
 * 0.88 F_y (p0 = 0.958 H) no point may yield, at 1.12 F_y (p0 = 1.038 H) the centre must. */
static void hertz_onset_of_yield(void **state) {
    (void)state;
    /* under valgrind: the sphere's yielding steps are the dent's test's, which runs there */
    if (ts_valgrind()) skip();
    const double hard = hardness();
    gfmd_sim *s = sphere(NULL), *e = sphere(NULL);
    TS_OK(s, gfmd_set_hardness(s, hard));
    int32_t solver = -1;
    TS_OK(s, gfmd_get_solver(s, &solver));
    assert_int_equal(solver, GFMD_SOLVER_FIRE); /* AUTO's choice with a hardness */
    TS_OK(e, gfmd_set_solver(e, GFMD_SOLVER_FIRE));
    relax_to(s, 0.88 * yield_force());
    relax_to(e, 0.88 * yield_force());
    double area = -1.0, volume = -1.0;
    TS_OK(s, gfmd_get_plasticity(s, &area, &volume));
    print_message("0.88 F_y: plastic area %.3g, max p / H = %.4f\n", area, max_pressure(s) / hard);
    assert_true(area == 0.0 && volume == 0.0);
    /* no point yielding: the elastic run, bit for bit */
    double *za = ts_alloc(N * N), *zb = ts_alloc(N * N);
    TS_OK(s, gfmd_get_surface(s, za));
    TS_OK(e, gfmd_get_surface(e, zb));
    assert_memory_equal(za, zb, sizeof(double) * N * N);
    relax_to(s, 1.12 * yield_force());
    TS_OK(s, gfmd_get_plasticity(s, &area, &volume));
    print_message("1.12 F_y: plastic area %.3g (%g points), volume %.3g, max p / H = %.17g\n", area, area * N * N,
                  volume, max_pressure(s) / hard);
    assert_true(area > 0.0 && volume > 0.0);
    assert_true(max_pressure(s) == hard); /* the cap, exactly */
    /* the yielding points sit at the centre: within a few spacings of the axis */
    double *p = ts_alloc(N * N);
    TS_OK(s, gfmd_get_pressure(s, p));
    assert_true(p[N / 2 + N * (N / 2)] == hard);
    for (int64_t iy = 0; iy < N; ++iy)
        for (int64_t ix = 0; ix < N; ++ix)
            if (p[ix + N * iy] == hard) assert_true(hypot((double)(ix - N / 2), (double)(iy - N / 2)) < 0.5 * kYieldRadius);
    free(p);
    free(za);
    free(zb);
    gfmd_sim_destroy(&s);
    gfmd_sim_destroy(&e);
}

/* An 8 x 8 flat punch on a 64 x 64 cell, the rest 5 below, the body's mean held 1.5 below the
 * punch (displacement control): under a uniform H the elastic surface rises over the punch by
 * ~0.3 only, so every punch point yields and the force the body carries is H times the contact
 * area -- to the relaxation's residual (1e-10 of the pressure). */
static void punch_pressed_until_all_yields(void **state) {
    (void)state;
    const int64_t n = 64;
    const double hard = 0.05;
    gfmd_sim *s = ts_create(n, n, n, n);
    double *h = ts_alloc((size_t)(n * n));
    for (int64_t iy = 0; iy < n; ++iy)
        for (int64_t ix = 0; ix < n; ++ix) h[ix + n * iy] = (ix >= 28 && ix < 36 && iy >= 28 && iy < 36) ? 0.0 : -5.0;
    TS_OK(s, gfmd_set_heights(s, h));
    TS_OK(s, gfmd_set_hardness(s, hard));
    TS_OK(s, gfmd_set_mean_displacement(s, -1.5));
    int64_t steps = 0;
    TS_OK(s, gfmd_relax(s, 1e-10, 200000, &steps));
    double area = 0.0, plastic = 0.0, volume = 0.0, mean_p = 0.0;
    TS_OK(s, gfmd_get_contact_area(s, &area));
    TS_OK(s, gfmd_get_plasticity(s, &plastic, &volume));
    TS_OK(s, gfmd_get_mean_pressure(s, &mean_p));
    print_message("punch: A/A0 %.6f, plastic %.6f, F / (H A) - 1 = %.2e, volume %.4f (%lld steps)\n", area, plastic,
                  mean_p / (hard * area) - 1.0, volume, (long long)steps);
    assert_true(area == 64.0 / (double)(n * n));
    assert_true(plastic == area);
    assert_true(fabs(mean_p / (hard * area) - 1.0) <= 1e-8);
    /* the volume: the punch's height lost, from the heights themselves */
    double *now = ts_alloc((size_t)(n * n)), lost = 0.0;
    TS_OK(s, gfmd_get_heights(s, now));
    for (int64_t i = 0; i < n * n; ++i) lost += h[i] - now[i];
    assert_true(fabs(lost - volume) <= 1e-12 * volume);
    free(now);
    free(h);
    gfmd_sim_destroy(&s);
}

/* Load to 3 F_y, unload to F_y / 10, reload to 3 F_y. */
static void dent_left_by_loading_and_unloading(void **state) {
    (void)state;
    /* under valgrind: its calls (loads committing steps, relaxations that yield) are the
     * checkpoint test's, which runs there */
    if (ts_valgrind()) skip();
    const double hard = hardness();
    double *h0 = ts_alloc(N * N), *h = ts_alloc(N * N);
    gfmd_sim *s = sphere(h0);
    TS_OK(s, gfmd_set_hardness(s, hard));
    relax_to(s, 3.0 * yield_force());
    double loaded_area = 0.0, plastic = 0.0, volume = 0.0;
    TS_OK(s, gfmd_get_contact_area(s, &loaded_area));
    TS_OK(s, gfmd_get_plasticity(s, &plastic, &volume));
    assert_true(plastic > 0.0 && volume > 0.0);
    relax_to(s, 0.1 * yield_force());
    double plastic_after = -1.0, volume_after = -1.0;
    TS_OK(s, gfmd_get_plasticity(s, &plastic_after, &volume_after));
    TS_OK(s, gfmd_get_heights(s, h));
    double dent = 0.0;
    for (int i = 0; i < N * N; ++i) dent += h0[i] - h[i];
    print_message("3 F_y: plastic area %.4f, volume %.5f; unloaded: plastic area %g, volume %.5f, dent %.5f\n", plastic,
                  volume, plastic_after, volume_after, dent);
    /* unloading is elastic: nothing yields, the volume stays; the dent's volume is the one reported */
    assert_true(plastic_after == 0.0);
    assert_true(fabs(volume_after - volume) <= 1e-12 * volume);
    assert_true(fabs(dent - volume) <= 1e-12 * volume);
    /* Persson's theory sees the flattened substrate after the change of load: the variance of a
     * fresh handle given these heights (another FFT plan: rounding, 1e-12) */
    double v_plastic = 0.0, v_fresh = 0.0;
    TS_OK(s, gfmd_persson_variance(s, &v_plastic));
    gfmd_sim *fresh = ts_create(N, N, N, N);
    TS_OK(fresh, gfmd_set_heights(fresh, h));
    TS_OK(fresh, gfmd_persson_variance(fresh, &v_fresh));
    assert_true(fabs(v_plastic / v_fresh - 1.0) <= 1e-12);
    gfmd_sim_destroy(&fresh);
    /* the dent is a flattened cap: its depth at the centre is positive, nothing rose anywhere */
    assert_true(h0[N / 2 + N * (N / 2)] - h[N / 2 + N * (N / 2)] > 0.0);
    for (int i = 0; i < N * N; ++i) assert_true(h[i] <= h0[i]);
    /* reloading to the same force is elastic on the flattened cap: the loaded contact again,
     * and no more than the residual's worth of new flow (1e-6 of the volume) */
    relax_to(s, 3.0 * yield_force());
    double area = 0.0, volume_re = 0.0;
    TS_OK(s, gfmd_get_contact_area(s, &area));
    TS_OK(s, gfmd_get_plasticity(s, NULL, &volume_re));
    print_message("reloaded: A/A0 %.6f (loaded %.6f), new volume %.2e of it\n", area, loaded_area, volume_re / volume - 1.0);
    assert_true(fabs(area - loaded_area) <= 2.0 / (N * N));
    assert_true(volume_re >= volume && volume_re - volume <= 1e-6 * volume);
    /* hardness off: the dent stays in the substrate, nothing is plastic any more */
    TS_OK(s, gfmd_set_hardness(s, INFINITY));
    double off_area = -1.0, off_volume = -1.0, off = 0.0;
    TS_OK(s, gfmd_get_plasticity(s, &off_area, &off_volume));
    TS_OK(s, gfmd_get_hardness(s, &off));
    assert_true(off_area == 0.0 && off_volume == 0.0 && isinf(off));
    TS_OK(s, gfmd_get_heights(s, h0));
    TS_OK(s, gfmd_get_surface(s, h));
    for (int i = 0; i < N * N; ++i) assert_true(h[i] >= h0[i]);
    free(h0);
    free(h);
    gfmd_sim_destroy(&s);
}

/* A rough contact with a hardness no point reaches follows the elastic run bit for bit, steps
 * included; one it does reach caps the pressure and flattens the substrate's tops, with the same
 * bits on two threads as on one. */
static void rough_contact_with_and_without_yield(void **state) {
    (void)state;
    gfmd_sim *s[4];
    const double hards[4] = {INFINITY, 1e6, 0.3, 0.3};
    int64_t steps[4];
    double *z[4];
    for (int k = 0; k < 4; ++k) {
        s[k] = NULL;
        assert_int_equal(gfmd_sim_create_ex(64, 64, 64.0, 64.0, k == 3 ? 2 : 1, GFMD_PLANNER_ESTIMATE, &s[k]), GFMD_OK);
        TS_OK(s[k], gfmd_generate_selfaffine(s[k], 0.8, 32.0, 4.0, 1.0, 11, GFMD_DIST_UNIFORM));
        TS_OK(s[k], gfmd_set_solver(s[k], GFMD_SOLVER_FIRE));
        if (!isinf(hards[k])) TS_OK(s[k], gfmd_set_hardness(s[k], hards[k]));
        TS_OK(s[k], gfmd_set_pressure(s[k], 0.05));
        TS_OK(s[k], gfmd_relax(s[k], 1e-9, 100000, &steps[k]));
        z[k] = ts_alloc(64 * 64);
        TS_OK(s[k], gfmd_get_surface(s[k], z[k]));
    }
    assert_int_equal(steps[0], steps[1]);
    assert_memory_equal(z[0], z[1], sizeof(double) * 64 * 64);
    assert_int_equal(steps[2], steps[3]);
    assert_memory_equal(z[2], z[3], sizeof(double) * 64 * 64);
    double plastic = 0.0, volume = 0.0, a0 = 0.0, a2 = 0.0;
    TS_OK(s[2], gfmd_get_plasticity(s[2], &plastic, &volume));
    TS_OK(s[0], gfmd_get_contact_area(s[0], &a0));
    TS_OK(s[2], gfmd_get_contact_area(s[2], &a2));
    print_message("H = 0.3: plastic area %.4f of contact %.4f (elastic %.4f), volume %.3g, %lld steps (elastic %lld)\n",
                  plastic, a2, a0, volume, (long long)steps[2], (long long)steps[0]);
    assert_true(plastic > 0.0 && volume > 0.0);
    assert_true(a2 > a0); /* the flattened tops spread the load over more contact */
    /* force balance: the capped pressures still carry sigma0 */
    double *p = ts_alloc(64 * 64), sum = 0.0;
    TS_OK(s[2], gfmd_get_pressure(s[2], p));
    for (int i = 0; i < 64 * 64; ++i) {
        assert_true(p[i] <= 0.3);
        sum += p[i];
    }
    assert_true(fabs(sum / (64 * 64) / 0.05 - 1.0) <= 1e-7);
    free(p);
    for (int k = 0; k < 4; ++k) {
        free(z[k]);
        gfmd_sim_destroy(&s[k]);
    }
}

static void checkpoint_resumes_the_plastic_run(void **state) {
    (void)state;
    const char *path = "plastic.gfmd";
    gfmd_sim *a = sphere(NULL), *b = NULL;
    TS_OK(a, gfmd_set_hardness(a, hardness()));
    TS_OK(a, gfmd_set_pressure(a, 2.0 * yield_force() / (N * N))); /* a first step, 150 steps in */
    TS_OK(a, gfmd_step(a, 150));
    TS_OK(a, gfmd_set_pressure(a, 3.0 * yield_force() / (N * N))); /* a second one, begun */
    TS_OK(a, gfmd_step(a, 40));
    TS_OK(a, gfmd_sim_save(a, path));
    char msg[256] = "";
    if (gfmd_sim_load(path, &b, msg, sizeof msg) != GFMD_OK) fail_msg("load: %s", msg);
    double hb = 0.0;
    TS_OK(b, gfmd_get_hardness(b, &hb));
    assert_true(hb == hardness());
    TS_OK(a, gfmd_step(a, 100));
    TS_OK(b, gfmd_step(b, 100));
    double *za = ts_alloc(N * N), *zb = ts_alloc(N * N), va[2], vb[2];
    TS_OK(a, gfmd_get_surface(a, za));
    TS_OK(b, gfmd_get_surface(b, zb));
    assert_memory_equal(za, zb, sizeof(double) * N * N);
    TS_OK(a, gfmd_get_heights(a, za));
    TS_OK(b, gfmd_get_heights(b, zb));
    assert_memory_equal(za, zb, sizeof(double) * N * N);
    TS_OK(a, gfmd_get_plasticity(a, &va[0], &va[1]));
    TS_OK(b, gfmd_get_plasticity(b, &vb[0], &vb[1]));
    assert_memory_equal(va, vb, sizeof va);
    assert_true(va[1] > 0.0);
    free(za);
    free(zb);
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
    remove(path);
}

static void refusals(void **state) {
    (void)state;
    gfmd_sim *s = sphere(NULL);
    assert_int_equal(gfmd_set_hardness(s, 0.0), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_set_hardness(s, -1.0), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_set_hardness(s, NAN), GFMD_ERR_INVALID_ARG);
    assert_int_equal(gfmd_set_hardness(NULL, 1.0), GFMD_ERR_NULL);
    assert_int_equal(gfmd_get_hardness(s, NULL), GFMD_ERR_NULL);
    assert_int_equal(gfmd_get_plasticity(NULL, NULL, NULL), GFMD_ERR_NULL);
    /* solvers that do not take the yielding wall, both ways round */
    TS_OK(s, gfmd_set_solver(s, GFMD_SOLVER_CG));
    assert_int_equal(gfmd_set_hardness(s, 0.1), GFMD_ERR_STATE);
    TS_OK(s, gfmd_set_solver(s, GFMD_SOLVER_AUTO));
    TS_OK(s, gfmd_set_hardness(s, 0.1));
    const int32_t refused[] = {GFMD_SOLVER_CG, GFMD_SOLVER_NEWTON, GFMD_SOLVER_MASS_WEIGHTED_FIRE,
                               GFMD_SOLVER_APPROACH_THEN_FIRE};
    for (int k = 0; k < 4; ++k) assert_int_equal(gfmd_set_solver(s, refused[k]), GFMD_ERR_STATE);
    TS_OK(s, gfmd_set_solver(s, GFMD_SOLVER_VERLET));
    TS_OK(s, gfmd_set_solver(s, GFMD_SOLVER_FIRE));
    /* adhesion, both ways round */
    assert_int_equal(gfmd_set_adhesion(s, 1e-3, 1.0), GFMD_ERR_STATE);
    TS_OK(s, gfmd_set_adhesion(s, 0.0, 1.0)); /* none is fine */
    gfmd_sim *t = sphere(NULL);
    TS_OK(t, gfmd_set_adhesion(t, 1e-3, 1.0));
    assert_int_equal(gfmd_set_hardness(t, 0.1), GFMD_ERR_STATE);
    /* the multilevel start */
    assert_int_equal(gfmd_relax_multilevel(s, 1e-6, 100, 2, NULL, NULL), GFMD_ERR_STATE);
    char msg[256];
    TS_OK(s, gfmd_last_error(s, msg, sizeof msg));
    print_message("multilevel refused: %s\n", msg);
    /* +infinity switches it off: the CG is taken again */
    TS_OK(s, gfmd_set_hardness(s, INFINITY));
    TS_OK(s, gfmd_set_solver(s, GFMD_SOLVER_CG));
    gfmd_sim_destroy(&s);
    gfmd_sim_destroy(&t);
}

/* The plastic state's 9 B/pt that cannot be had: GFMD_ERR_NOMEM, the hardness and the solver
 * unchanged.  In a child process whose address space is capped just above what it uses and then
 * filled (not under the sanitizers or valgrind, which need address space of their own). */
static int hardness_without_memory_child(void) {
    gfmd_sim *s = NULL;
    if (gfmd_sim_create_ex(1024, 1024, 1024.0, 1024.0, 1, GFMD_PLANNER_ESTIMATE, &s) != GFMD_OK) return 3;
    int32_t before = -1, after = -1;
    gfmd_get_solver(s, &before);
    if (ts_exhaust_memory() != 0) return 4;
    const int32_t st = gfmd_set_hardness(s, 0.1); /* needs 9 MB */
    double hard = 0.0;
    gfmd_get_solver(s, &after);
    gfmd_get_hardness(s, &hard);
    if (st != GFMD_ERR_NOMEM || after != before || !isinf(hard))
        fprintf(stderr, "set_hardness under the cap: status %d, solver %d -> %d, H %g\n", (int)st, (int)before,
                (int)after, hard);
    return st == GFMD_ERR_NOMEM && after == before && isinf(hard) ? 0 : 1;
}

static void hardness_without_memory(void **state) {
    (void)state;
    if (!ts_memory_cap_possible()) skip();
    ts_run_in_child(hardness_without_memory_child);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hertz_onset_of_yield),
        cmocka_unit_test(punch_pressed_until_all_yields),
        cmocka_unit_test(dent_left_by_loading_and_unloading),
        cmocka_unit_test(rough_contact_with_and_without_yield),
        cmocka_unit_test(checkpoint_resumes_the_plastic_run),
        cmocka_unit_test(refusals),
        cmocka_unit_test(hardness_without_memory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
