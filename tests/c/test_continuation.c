/* A trajectory continues across calls: for every solver and three bodies (half-space, layer on a
 * fluid foundation, bonded layer with adhesion), relax in one call equals relax in chunks and step
 * in chunks (same steps, bit-identical z), a checkpoint taken between chunks resumes the same
 * trajectory in a new handle, and gfmd_restart_solver() restarts exactly as a change of the
 * landscape does (setting the same pressure again).  The reference is always a second handle of
 * the same setup run another way, so the comparison is exact: one code path against another.
 * And FIRE's step, whose ceiling the header states, read off a free fall's positions. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "gfmd.h"
#include "test_support.h"

enum { NX = 48, NY = 32 };
static const char *PATH = "test_continuation.gfmd";

/* Deterministic plans (ESTIMATE from the start, one thread): handles made in one process compare
 * bit for bit with handles loaded from a file. */
static gfmd_sim *make(int32_t solver, int body) {
    gfmd_sim *s = NULL;
    assert_int_equal(gfmd_sim_create_ex(NX, NY, NX, NY, 1, GFMD_PLANNER_ESTIMATE, &s), GFMD_OK);
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 0.5, 5, GFMD_DIST_UNIFORM));
    if (body == 1) TS_OK(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 4.0));
    if (body == 2) {
        TS_OK(s, gfmd_set_poisson(s, 0.3));
        TS_OK(s, gfmd_set_green(s, GFMD_GREEN_LAYER_BONDED, 8.0));
        TS_OK(s, gfmd_set_adhesion(s, 2e-3, 0.5));
    }
    TS_OK(s, gfmd_set_pressure(s, 0.01));
    TS_OK(s, gfmd_set_solver(s, solver));
    return s;
}

static void same_surface(const gfmd_sim *a, const gfmd_sim *b) {
    double za[NX * NY], zb[NX * NY];
    TS_OK(a, gfmd_get_surface(a, za));
    TS_OK(b, gfmd_get_surface(b, zb));
    assert_memory_equal(za, zb, sizeof za);
}

/* relax in chunks of `chunk` steps until converged; returns the total steps */
static int64_t relax_in_chunks(gfmd_sim *s, int64_t chunk, int save_between) {
    int64_t total = 0;
    for (int i = 0; i < 100000; ++i) {
        int64_t taken = 0;
        int32_t st = gfmd_relax(s, 0.0, chunk, &taken);
        total += taken;
        if (st == GFMD_OK) return total;
        assert_int_equal(st, GFMD_ERR_NOT_CONVERGED);
        if (save_between) { /* continue in a handle loaded from a checkpoint of this one */
            TS_OK(s, gfmd_sim_save(s, PATH));
            gfmd_sim *t = NULL;
            assert_int_equal(gfmd_sim_load(PATH, &t, NULL, 0), GFMD_OK);
            TS_OK(t, gfmd_set_threads(t, 1));
            /* move t's state into s: relax t one chunk and compare with s doing the same */
            int64_t ts = 0, ss = 0;
            int32_t st_t = gfmd_relax(t, 0.0, chunk, &ts);
            int32_t st_s = gfmd_relax(s, 0.0, chunk, &ss);
            assert_int_equal(st_t, st_s);
            assert_int_equal(ts, ss);
            same_surface(s, t);
            gfmd_sim_destroy(&t);
            total += ss;
            if (st_s == GFMD_OK) return total;
        }
    }
    fail_msg("relax in chunks did not converge");
    return -1;
}

/* Under valgrind one body per solver: the adhesive bonded layer, whose relax runs every call of
 * the others' with the adhesive forces on top (CG: the surface CG with its adhesive line search);
 * the three bodies' 14 relaxes, three handles each, took most of the test's 40 s there. */
static void chunked_relax_equals_one_call(void **state) {
    (void)state;
    for (int32_t solver = GFMD_SOLVER_VERLET; solver <= GFMD_SOLVER_AUTO; ++solver) {
        for (int body = 0; body < 3; ++body) {
            if (ts_valgrind() && body != 2) continue;
            gfmd_sim *one = make(solver, body), *chunks = make(solver, body), *saved = make(solver, body);
            int64_t steps = 0;
            TS_OK(one, gfmd_relax(one, 0.0, 100000, &steps));
            assert_true(steps > 14); /* the chunks below split it: at least twice, and once (CG on body 2: 18) */
            const int64_t chunked = relax_in_chunks(chunks, 7, 0);
            const int64_t resumed = relax_in_chunks(saved, 13, 1);
            print_message("solver %d body %d: %lld steps in one call, %lld in chunks, %lld through checkpoints\n",
                          (int)solver, body, (long long)steps, (long long)chunked, (long long)resumed);
            assert_int_equal(chunked, steps);
            assert_int_equal(resumed, steps);
            same_surface(one, chunks);
            same_surface(one, saved);
            gfmd_sim_destroy(&one);
            gfmd_sim_destroy(&chunks);
            gfmd_sim_destroy(&saved);
        }
    }
    remove(PATH);
}

static void chunked_steps_equal_one_call(void **state) {
    (void)state;
    for (int32_t solver = GFMD_SOLVER_VERLET; solver <= GFMD_SOLVER_AUTO; ++solver) {
        gfmd_sim *one = make(solver, 1), *chunks = make(solver, 1);
        TS_OK(one, gfmd_step(one, 60));
        for (int i = 0; i < 6; ++i) TS_OK(chunks, gfmd_step(chunks, 10));
        same_surface(one, chunks);
        gfmd_sim_destroy(&one);
        gfmd_sim_destroy(&chunks);
    }
}

static void restart_solver_is_a_landscape_restart(void **state) {
    (void)state;
    for (int32_t solver = GFMD_SOLVER_VERLET; solver <= GFMD_SOLVER_AUTO; ++solver) {
        gfmd_sim *a = make(solver, 0), *b = make(solver, 0), *c = make(solver, 0);
        TS_OK(a, gfmd_step(a, 30));
        TS_OK(b, gfmd_step(b, 30));
        TS_OK(c, gfmd_step(c, 30));
        TS_OK(a, gfmd_restart_solver(a));
        TS_OK(b, gfmd_set_pressure(b, 0.01)); /* the same pressure: only the restart changes */
        TS_OK(a, gfmd_step(a, 40));
        TS_OK(b, gfmd_step(b, 40));
        TS_OK(c, gfmd_step(c, 40));
        same_surface(a, b);
        if (solver != GFMD_SOLVER_VERLET) { /* FIRE's state matters: without a restart c moves on otherwise */
            double za[NX * NY], zc[NX * NY];
            TS_OK(a, gfmd_get_surface(a, za));
            TS_OK(c, gfmd_get_surface(c, zc));
            assert_true(memcmp(za, zc, sizeof za) != 0);
        }
        gfmd_sim_destroy(&a);
        gfmd_sim_destroy(&b);
        gfmd_sim_destroy(&c);
    }
    assert_int_equal(gfmd_restart_solver(NULL), GFMD_ERR_NULL);
}

/* FIRE's step, observed from outside: a half-space above a flat substrate (mean position 1, no
 * contact) pushed by sigma0 falls freely, the uniform mode having no stiffness.  With unit mass per
 * area and the velocity along the force (FIRE's mixing then only rescales it), two steps of the
 * same length D move the surface by dz_k = D v and dz_k+1 = D (v - sigma0 D): D follows from the
 * positions alone, D^2 = (dz_k - dz_k+1) / sigma0.  Once grown, the step must stay at the header's
 * ceiling, 1.3 times the time step in effect: with the automatic step and with a user's.
 * Tolerance 1e-8 relative: the positions (~1) carry ~1e-13 of rounding (the transforms' in the
 * forces, summed in v), dz_k - dz_k+1 = sigma0 D^2 ~ 3e-4 here, so D carries ~1e-9. */
static void fire_step_ceiling(void **state) {
    (void)state;
    for (int user = 0; user < 2; ++user) {
        gfmd_sim *s = NULL;
        assert_int_equal(gfmd_sim_create_ex(NX, NY, NX, NY, 1, GFMD_PLANNER_ESTIMATE, &s), GFMD_OK);
        double h[NX * NY] = {0};
        TS_OK(s, gfmd_set_heights(s, h));
        TS_OK(s, gfmd_set_solver(s, GFMD_SOLVER_FIRE));
        if (user) TS_OK(s, gfmd_set_timestep(s, 0.25));
        double dt0 = 0.0;
        TS_OK(s, gfmd_get_dynamics(s, &dt0, NULL));
        assert_true(user ? dt0 == 0.25 : dt0 > 0.25);  /* the automatic step: 1/omega_max ~ 0.64 here */
        TS_OK(s, gfmd_set_mean_displacement(s, 1.0));
        enum { STEPS = 60, PLATEAU = 20 };
        const double sigma0 = 1.0 / ((STEPS * 1.3 * dt0) * (STEPS * 1.3 * dt0));  /* falls < 0.5 */
        TS_OK(s, gfmd_set_pressure(s, sigma0));
        double z[STEPS + 1];
        TS_OK(s, gfmd_get_mean_displacement(s, &z[0]));
        assert_true(z[0] == 1.0);
        for (int k = 1; k <= STEPS; ++k) {
            double area = 1.0;
            TS_OK(s, gfmd_step(s, 1));
            TS_OK(s, gfmd_get_mean_displacement(s, &z[k]));
            TS_OK(s, gfmd_get_contact_area(s, &area));
            assert_true(area == 0.0 && z[k] > 0.0 && z[k] < z[k - 1]);  /* still falling freely */
        }
        for (int k = STEPS - PLATEAU; k < STEPS; ++k) {
            const double second = (z[k] - z[k - 1]) - (z[k + 1] - z[k]);
            assert_true(fabs(sqrt(second / sigma0) / (1.3 * dt0) - 1.0) <= 1e-8);
        }
        gfmd_sim_destroy(&s);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(chunked_relax_equals_one_call),
        cmocka_unit_test(chunked_steps_equal_one_call),
        cmocka_unit_test(restart_solver_is_a_landscape_restart),
        cmocka_unit_test(fire_step_ceiling),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
