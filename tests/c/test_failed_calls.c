/* "A failed call changes nothing", for every setter, generator and dynamics call and every way
 * the header says it can fail: after each failing call the handle is compared with a twin that
 * never made it — every observable, every field, the dynamics, and what the next steps do (so the
 * solver's adaptive state is compared too).  Twins are made alike and planned alike (ESTIMATE,
 * one thread), so the comparison is bit for bit. */
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

enum { NX = 32, NY = 24, N = NX * NY };

static gfmd_sim *make_twin(void) {
    gfmd_sim *s = NULL;
    assert_int_equal(gfmd_sim_create_ex(NX, NY, NX, NY, 1, GFMD_PLANNER_ESTIMATE, &s), GFMD_OK);
    TS_OK(s, gfmd_generate_selfaffine(s, 0.8, 8.0, 4.0, 1.0, 3, GFMD_DIST_UNIFORM));
    TS_OK(s, gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 4.0)); /* Poisson's ratio left unset */
    TS_OK(s, gfmd_set_adhesion(s, 1e-3, 0.5));
    TS_OK(s, gfmd_set_pressure(s, 0.05));
    TS_OK(s, gfmd_step(s, 20)); /* FIRE has adapted its step: a restart would show */
    return s;
}

/* Every observable and field of a and b, bit for bit; then 5 steps of both, compared again. */
static void same_state(gfmd_sim *a, gfmd_sim *b, const char *after) {
    static double fa[N], fb[N];
    int32_t (*const getters[])(const gfmd_sim *, double *) = {gfmd_get_surface, gfmd_get_gap, gfmd_get_pressure,
                                                             gfmd_get_heights};
    for (int round = 0; round < 2; ++round) {
        for (size_t g = 0; g < sizeof getters / sizeof getters[0]; ++g) {
            TS_OK(a, getters[g](a, fa));
            TS_OK(b, getters[g](b, fb));
            if (memcmp(fa, fb, sizeof fa) != 0) fail_msg("after %s: field %zu differs (round %d)", after, g, round);
        }
        double xa[10], xb[10];
        TS_OK(a, gfmd_get_contact_area(a, &xa[0]));
        TS_OK(b, gfmd_get_contact_area(b, &xb[0]));
        TS_OK(a, gfmd_get_mean_gap(a, &xa[1]));
        TS_OK(b, gfmd_get_mean_gap(b, &xb[1]));
        TS_OK(a, gfmd_get_energies(a, &xa[2], &xa[3]));
        TS_OK(b, gfmd_get_energies(b, &xb[2], &xb[3]));
        TS_OK(a, gfmd_get_residual(a, &xa[4]));
        TS_OK(b, gfmd_get_residual(b, &xb[4]));
        TS_OK(a, gfmd_get_dynamics(a, &xa[5], &xa[6]));
        TS_OK(b, gfmd_get_dynamics(b, &xb[5], &xb[6]));
        TS_OK(a, gfmd_persson_variance(a, &xa[7]));
        TS_OK(b, gfmd_persson_variance(b, &xb[7]));
        TS_OK(a, gfmd_get_plasticity(a, &xa[8], &xa[9]));
        TS_OK(b, gfmd_get_plasticity(b, &xb[8], &xb[9]));
        if (memcmp(xa, xb, sizeof xa) != 0) fail_msg("after %s: an observable differs (round %d)", after, round);
        int32_t ta = 0, tb = 0;
        TS_OK(a, gfmd_get_threads(a, &ta));
        TS_OK(b, gfmd_get_threads(b, &tb));
        assert_int_equal(ta, tb);
        if (round == 0) {
            TS_OK(a, gfmd_step(a, 5));
            TS_OK(b, gfmd_step(b, 5));
        }
    }
}

typedef struct {
    const char *what;
    int32_t expected;
    int32_t (*call)(gfmd_sim *s);
} failing;

static double bad_heights[N];
static int32_t modulus_nan(gfmd_sim *s) { return gfmd_set_modulus(s, NAN); }
static int32_t modulus_inf(gfmd_sim *s) { return gfmd_set_modulus(s, INFINITY); }
static int32_t modulus_zero(gfmd_sim *s) { return gfmd_set_modulus(s, 0.0); }
static int32_t modulus_negative(gfmd_sim *s) { return gfmd_set_modulus(s, -1.0); }
static int32_t modulus_overflow(gfmd_sim *s) { return gfmd_set_modulus(s, 1e308); }
static int32_t green_unknown(gfmd_sim *s) { return gfmd_set_green(s, 7, 1.0); }
static int32_t green_width_zero(gfmd_sim *s) { return gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 0.0); }
static int32_t green_width_negative(gfmd_sim *s) { return gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, -2.0); }
static int32_t green_width_nan(gfmd_sim *s) { return gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, NAN); }
static int32_t green_width_inf(gfmd_sim *s) { return gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, INFINITY); }
static int32_t green_bonded_without_nu(gfmd_sim *s) { return gfmd_set_green(s, GFMD_GREEN_LAYER_BONDED, 2.0); }
static int32_t poisson_low(gfmd_sim *s) { return gfmd_set_poisson(s, -1.0); }
static int32_t poisson_high(gfmd_sim *s) { return gfmd_set_poisson(s, 0.51); }
static int32_t poisson_nan(gfmd_sim *s) { return gfmd_set_poisson(s, NAN); }
static int32_t heights_null(gfmd_sim *s) { return gfmd_set_heights(s, NULL); }
static int32_t heights_nan(gfmd_sim *s) {
    bad_heights[N / 2] = NAN;
    return gfmd_set_heights(s, bad_heights);
}
static int32_t heights_huge(gfmd_sim *s) {
    bad_heights[N / 2] = 2e100;
    return gfmd_set_heights(s, bad_heights);
}
static int32_t heights_inf(gfmd_sim *s) {
    bad_heights[N - 1] = -INFINITY;
    bad_heights[N / 2] = 0.0;
    return gfmd_set_heights(s, bad_heights);
}
static int32_t gen(gfmd_sim *s, double h, double lr, double ls, double g, int32_t d) {
    return gfmd_generate_selfaffine(s, h, lr, ls, g, 3, d);
}
static int32_t gen_hurst_low(gfmd_sim *s) { return gen(s, -0.1, 8.0, 4.0, 1.0, 0); }
static int32_t gen_hurst_high(gfmd_sim *s) { return gen(s, 1.1, 8.0, 4.0, 1.0, 0); }
static int32_t gen_hurst_nan(gfmd_sim *s) { return gen(s, NAN, 8.0, 4.0, 1.0, 0); }
static int32_t gen_lr_below_ls(gfmd_sim *s) { return gen(s, 0.8, 3.0, 4.0, 1.0, 0); }
static int32_t gen_lr_huge(gfmd_sim *s) { return gen(s, 0.8, 1e300, 4.0, 1.0, 0); }
static int32_t gen_lr_inf(gfmd_sim *s) { return gen(s, 0.8, INFINITY, 4.0, 1.0, 0); }
static int32_t gen_ls_below_grid(gfmd_sim *s) { return gen(s, 0.8, 8.0, 1.0, 1.0, 0); }
static int32_t gen_ls_above_cell(gfmd_sim *s) { return gen(s, 0.8, 80.0, 40.0, 1.0, 0); }
static int32_t gen_gradient_zero(gfmd_sim *s) { return gen(s, 0.8, 8.0, 4.0, 0.0, 0); }
static int32_t gen_gradient_nan(gfmd_sim *s) { return gen(s, 0.8, 8.0, 4.0, NAN, 0); }
static int32_t gen_gradient_huge(gfmd_sim *s) { return gen(s, 0.8, 8.0, 4.0, 1e99, 0); }
static int32_t gen_distribution(gfmd_sim *s) { return gen(s, 0.8, 8.0, 4.0, 1.0, 9); }
static int32_t pressure_negative(gfmd_sim *s) { return gfmd_set_pressure(s, -0.1); }
static int32_t pressure_nan(gfmd_sim *s) { return gfmd_set_pressure(s, NAN); }
static int32_t pressure_inf(gfmd_sim *s) { return gfmd_set_pressure(s, INFINITY); }
static int32_t adhesion_negative(gfmd_sim *s) { return gfmd_set_adhesion(s, -1e-3, 0.5); }
static int32_t adhesion_nan(gfmd_sim *s) { return gfmd_set_adhesion(s, NAN, 0.5); }
static int32_t adhesion_rho_zero(gfmd_sim *s) { return gfmd_set_adhesion(s, 1e-3, 0.0); }
static int32_t adhesion_rho_inf(gfmd_sim *s) { return gfmd_set_adhesion(s, 1e-3, INFINITY); }
static int32_t adhesion_overflow(gfmd_sim *s) { return gfmd_set_adhesion(s, 1e300, 1e-300); }
static int32_t hardness_zero(gfmd_sim *s) { return gfmd_set_hardness(s, 0.0); }
static int32_t hardness_negative(gfmd_sim *s) { return gfmd_set_hardness(s, -1.0); }
static int32_t hardness_nan(gfmd_sim *s) { return gfmd_set_hardness(s, NAN); }
static int32_t hardness_with_adhesion(gfmd_sim *s) { return gfmd_set_hardness(s, 0.1); }
static int32_t patches_connectivity(gfmd_sim *s) {
    int64_t n = 0;
    return gfmd_get_contact_patches(s, 6, NULL, &n);
}
static int32_t patch_unknown_property(gfmd_sim *s) {
    int64_t n = 0;
    return gfmd_get_patch_property(s, 4, 77, 0, NULL, &n);
}
static int32_t patch_values_truncated(gfmd_sim *s) {
    int64_t n = 0;
    return gfmd_get_patch_property(s, 4, GFMD_PATCH_AREA, 0, NULL, &n);
}
static int32_t histogram_no_bins(gfmd_sim *s) {
    double r[2] = {0.0, 0.0}, f = 0.0, m = 0.0;
    return gfmd_get_pressure_histogram(s, 0, r, &f, &m);
}
static int32_t persson_density_nan(gfmd_sim *s) {
    const double p = NAN;
    double d = 0.0;
    return gfmd_persson_pressure_distribution(s, 0.05, 1, &p, &d);
}
static int32_t position_below_substrate(gfmd_sim *s) { return gfmd_set_mean_displacement(s, -1e6); }
static int32_t position_nan(gfmd_sim *s) { return gfmd_set_mean_displacement(s, NAN); }
static int32_t mean_pressure_null(gfmd_sim *s) { return gfmd_get_mean_pressure(s, NULL); }
static int32_t timestep_negative(gfmd_sim *s) { return gfmd_set_timestep(s, -1.0); }
static int32_t timestep_nan(gfmd_sim *s) { return gfmd_set_timestep(s, NAN); }
static int32_t damping_negative(gfmd_sim *s) { return gfmd_set_damping(s, -1.0); }
static int32_t damping_inf(gfmd_sim *s) { return gfmd_set_damping(s, INFINITY); }
static int32_t solver_unknown(gfmd_sim *s) { return gfmd_set_solver(s, GFMD_SOLVER_NEWTON + 1); }
/* the Newton solver on the twin: its grid not square (test_newton has each reason) */
static int32_t solver_newton(gfmd_sim *s) { return gfmd_set_solver(s, GFMD_SOLVER_NEWTON); }
static int32_t threads_negative(gfmd_sim *s) { return gfmd_set_threads(s, -1); }
static int32_t threads_too_many(gfmd_sim *s) { return gfmd_set_threads(s, 5000); }
static int32_t planner_unknown(gfmd_sim *s) { return gfmd_set_fft_planner(s, 9); }
static int32_t step_negative(gfmd_sim *s) { return gfmd_step(s, -1); }
static int32_t relax_nan_tol(gfmd_sim *s) { return gfmd_relax(s, NAN, 10, NULL); }
static int32_t relax_no_steps(gfmd_sim *s) { return gfmd_relax(s, 0.0, 0, NULL); }
static int32_t multilevel_no_levels(gfmd_sim *s) { return gfmd_relax_multilevel(s, 0.0, 10, 0, NULL, NULL); }
static int32_t multilevel_too_deep(gfmd_sim *s) { return gfmd_relax_multilevel(s, 0.0, 10, 4, NULL, NULL); }
static int32_t persson_negative(gfmd_sim *s) {
    double a = 0.0;
    return gfmd_persson_contact_area(s, -1.0, &a);
}
static int32_t persson_null(gfmd_sim *s) { return gfmd_persson_contact_area(s, 0.1, NULL); }
static int32_t persson_load_full(gfmd_sim *s) {
    double load = 0.0;
    return gfmd_persson_load(s, 1.0, &load);
}
static int32_t persson_load_nan(gfmd_sim *s) {
    double load = 0.0;
    return gfmd_persson_load(s, NAN, &load);
}
static int32_t persson_load_null(gfmd_sim *s) { return gfmd_persson_load(s, 0.1, NULL); }
static int32_t save_nowhere(gfmd_sim *s) { return gfmd_sim_save(s, "no/such/dir/x.gfmd"); }
static int32_t clone_null(gfmd_sim *s) { return gfmd_sim_clone(s, NULL); }

static const failing CALLS[] = {
    {"modulus NaN", GFMD_ERR_INVALID_ARG, modulus_nan},
    {"modulus inf", GFMD_ERR_INVALID_ARG, modulus_inf},
    {"modulus 0", GFMD_ERR_INVALID_ARG, modulus_zero},
    {"modulus < 0", GFMD_ERR_INVALID_ARG, modulus_negative},
    {"modulus overflowing the stresses", GFMD_ERR_RANGE, modulus_overflow},
    {"unknown Green's kind", GFMD_ERR_BAD_ENUM, green_unknown},
    {"layer width 0", GFMD_ERR_INVALID_ARG, green_width_zero},
    {"layer width < 0", GFMD_ERR_INVALID_ARG, green_width_negative},
    {"layer width NaN", GFMD_ERR_INVALID_ARG, green_width_nan},
    {"layer width inf", GFMD_ERR_INVALID_ARG, green_width_inf},
    {"bonded layer without Poisson's ratio", GFMD_ERR_STATE, green_bonded_without_nu},
    {"Poisson -1", GFMD_ERR_INVALID_ARG, poisson_low},
    {"Poisson 0.51", GFMD_ERR_INVALID_ARG, poisson_high},
    {"Poisson NaN", GFMD_ERR_INVALID_ARG, poisson_nan},
    {"heights NULL", GFMD_ERR_NULL, heights_null},
    {"a NaN height", GFMD_ERR_INVALID_ARG, heights_nan},
    {"a height above 1e100", GFMD_ERR_INVALID_ARG, heights_huge},
    {"an infinite height", GFMD_ERR_INVALID_ARG, heights_inf},
    {"hurst < 0", GFMD_ERR_INVALID_ARG, gen_hurst_low},
    {"hurst > 1", GFMD_ERR_INVALID_ARG, gen_hurst_high},
    {"hurst NaN", GFMD_ERR_INVALID_ARG, gen_hurst_nan},
    {"lambda_r < lambda_s", GFMD_ERR_INVALID_ARG, gen_lr_below_ls},
    {"lambda_r 1e300", GFMD_ERR_INVALID_ARG, gen_lr_huge},
    {"lambda_r inf", GFMD_ERR_INVALID_ARG, gen_lr_inf},
    {"lambda_s below two spacings", GFMD_ERR_INVALID_ARG, gen_ls_below_grid},
    {"lambda_s beyond the cell", GFMD_ERR_INVALID_ARG, gen_ls_above_cell},
    {"rms gradient 0", GFMD_ERR_INVALID_ARG, gen_gradient_zero},
    {"rms gradient NaN", GFMD_ERR_INVALID_ARG, gen_gradient_nan},
    {"rms gradient times cell above 1e100", GFMD_ERR_INVALID_ARG, gen_gradient_huge},
    {"unknown distribution", GFMD_ERR_BAD_ENUM, gen_distribution},
    {"pressure < 0", GFMD_ERR_INVALID_ARG, pressure_negative},
    {"pressure NaN", GFMD_ERR_INVALID_ARG, pressure_nan},
    {"pressure inf", GFMD_ERR_INVALID_ARG, pressure_inf},
    {"gamma0 < 0", GFMD_ERR_INVALID_ARG, adhesion_negative},
    {"gamma0 NaN", GFMD_ERR_INVALID_ARG, adhesion_nan},
    {"rho 0", GFMD_ERR_INVALID_ARG, adhesion_rho_zero},
    {"rho inf", GFMD_ERR_INVALID_ARG, adhesion_rho_inf},
    {"adhesive stiffness overflowing", GFMD_ERR_RANGE, adhesion_overflow},
    {"hardness 0", GFMD_ERR_INVALID_ARG, hardness_zero},
    {"hardness < 0", GFMD_ERR_INVALID_ARG, hardness_negative},
    {"hardness NaN", GFMD_ERR_INVALID_ARG, hardness_nan},
    {"hardness with adhesion", GFMD_ERR_STATE, hardness_with_adhesion},
    {"patches with connectivity 6", GFMD_ERR_INVALID_ARG, patches_connectivity},
    {"an unknown patch property", GFMD_ERR_BAD_ENUM, patch_unknown_property},
    {"patch values into no room", GFMD_ERR_TRUNCATED, patch_values_truncated},
    {"a pressure histogram of 0 bins", GFMD_ERR_INVALID_ARG, histogram_no_bins},
    {"Persson's P(p) at a NaN pressure", GFMD_ERR_INVALID_ARG, persson_density_nan},
    {"mean position below the substrate's mean", GFMD_ERR_INVALID_ARG, position_below_substrate},
    {"mean position NaN", GFMD_ERR_INVALID_ARG, position_nan},
    {"mean pressure into NULL", GFMD_ERR_NULL, mean_pressure_null},
    {"dt < 0", GFMD_ERR_INVALID_ARG, timestep_negative},
    {"dt NaN", GFMD_ERR_INVALID_ARG, timestep_nan},
    {"damping < 0", GFMD_ERR_INVALID_ARG, damping_negative},
    {"damping inf", GFMD_ERR_INVALID_ARG, damping_inf},
    {"unknown solver", GFMD_ERR_BAD_ENUM, solver_unknown},
    {"the Newton solver on a body and grid it does not take", GFMD_ERR_STATE, solver_newton},
    {"threads < 0", GFMD_ERR_INVALID_ARG, threads_negative},
    {"threads > 4096", GFMD_ERR_INVALID_ARG, threads_too_many},
    {"unknown planner", GFMD_ERR_BAD_ENUM, planner_unknown},
    {"steps < 0", GFMD_ERR_INVALID_ARG, step_negative},
    {"relax tol NaN", GFMD_ERR_INVALID_ARG, relax_nan_tol},
    {"relax max_steps 0", GFMD_ERR_INVALID_ARG, relax_no_steps},
    {"multilevel relax with 0 levels", GFMD_ERR_INVALID_ARG, multilevel_no_levels},
    {"multilevel relax coarser than 8 points a side (32 x 24 / 8)", GFMD_ERR_INVALID_ARG, multilevel_too_deep},
    {"Persson at sigma0 < 0", GFMD_ERR_INVALID_ARG, persson_negative},
    {"Persson into NULL", GFMD_ERR_NULL, persson_null},
    {"Persson load for full contact", GFMD_ERR_INVALID_ARG, persson_load_full},
    {"Persson load for a NaN area", GFMD_ERR_INVALID_ARG, persson_load_nan},
    {"Persson load into NULL", GFMD_ERR_NULL, persson_load_null},
    {"save into a missing folder", GFMD_ERR_IO, save_nowhere},
    {"clone into NULL", GFMD_ERR_NULL, clone_null},
};

/* Each call on a, expected to fail with its status and a message; a then compared with b. */
static void run_calls(gfmd_sim *a, gfmd_sim *b, const failing *calls, size_t count) {
    for (size_t i = 0; i < count; ++i) {
        const int32_t st = calls[i].call(a);
        if (st != calls[i].expected)
            fail_msg("%s: got %s, expected %s", calls[i].what, gfmd_status_string(st),
                     gfmd_status_string(calls[i].expected));
        char msg[256] = "";
        assert_int_equal(gfmd_last_error(a, msg, sizeof msg) == GFMD_ERR_NULL, 0);
        if (msg[0] == '\0') fail_msg("%s: no message recorded", calls[i].what);
        same_state(a, b, calls[i].what);
    }
}

static void every_failure_changes_nothing(void **state) {
    (void)state;
    gfmd_sim *a = make_twin(), *b = make_twin();
    same_state(a, b, "creation");
    run_calls(a, b, CALLS, sizeof CALLS / sizeof CALLS[0]);
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
}

/* The CG takes adhesion under pressure control only: on the twin (adhesive, under pressure) it is
 * accepted, and then the call that would hand it displacement control is refused with
 * GFMD_ERR_STATE and changes nothing; under displacement control so are the CG on the adhesive
 * twin and adhesion on the CG's. */
static int32_t cg_to_position(gfmd_sim *s) { return gfmd_set_mean_displacement(s, 1.0); }
static int32_t cg_under_position(gfmd_sim *s) { return gfmd_set_solver(s, GFMD_SOLVER_CG); }
static int32_t adhesion_on_cg_under_position(gfmd_sim *s) { return gfmd_set_adhesion(s, 1e-3, 0.5); }

static void cg_refusals_change_nothing(void **state) {
    (void)state;
    static const failing pressure_calls[] = {
        {"an adhesive CG handed displacement control", GFMD_ERR_STATE, cg_to_position}};
    static const failing position_calls[] = {
        {"CG on an adhesive body under displacement control", GFMD_ERR_STATE, cg_under_position}};
    static const failing position_cg_calls[] = {
        {"adhesion on the CG under displacement control", GFMD_ERR_STATE, adhesion_on_cg_under_position}};
    gfmd_sim *a = make_twin(), *b = make_twin();
    gfmd_sim *both[2] = {a, b};
    for (int i = 0; i < 2; ++i) {
        TS_OK(both[i], gfmd_set_solver(both[i], GFMD_SOLVER_CG));
        TS_OK(both[i], gfmd_step(both[i], 5));
    }
    same_state(a, b, "the adhesive CG's steps");
    run_calls(a, b, pressure_calls, 1);
    for (int i = 0; i < 2; ++i) {
        TS_OK(both[i], gfmd_set_solver(both[i], GFMD_SOLVER_AUTO));
        TS_OK(both[i], gfmd_set_mean_displacement(both[i], 1.0));
    }
    run_calls(a, b, position_calls, 1);
    for (int i = 0; i < 2; ++i) {
        TS_OK(both[i], gfmd_set_adhesion(both[i], 0.0, 0.5));
        TS_OK(both[i], gfmd_set_solver(both[i], GFMD_SOLVER_CG));
        TS_OK(both[i], gfmd_step(both[i], 5));
    }
    run_calls(a, b, position_cg_calls, 1);
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
}

/* Twins a and b on Verlet at 50 times its automatic time step, far beyond the stability limit:
 * a's run diverges, restoring the configuration and the solver's state of the call's start, and
 * (both back at a stable step) a is compared with b. */
static void diverge_one(gfmd_sim *a, gfmd_sim *b, const char *what) {
    double dt = 0.0;
    TS_OK(a, gfmd_get_dynamics(a, &dt, NULL));
    gfmd_sim *both[2] = {a, b};
    for (int i = 0; i < 2; ++i) {
        TS_OK(both[i], gfmd_set_solver(both[i], GFMD_SOLVER_VERLET));
        TS_OK(both[i], gfmd_step(both[i], 7));
        TS_OK(both[i], gfmd_set_timestep(both[i], 50.0 * dt));
    }
    assert_int_equal(gfmd_step(a, 100000), GFMD_ERR_DIVERGED);
    TS_OK(a, gfmd_set_timestep(a, dt));
    TS_OK(b, gfmd_set_timestep(b, dt));
    same_state(a, b, what);
}

/* With a hardness, on twins without adhesion that have yielded (a load step half made): the
 * calls the plastic state refuses, and the bad values, change nothing -- the substrate of the
 * step's start, the yielding points and the plastic volume included. */
static int32_t adhesion_on_plastic(gfmd_sim *s) { return gfmd_set_adhesion(s, 1e-3, 0.5); }
static int32_t cg_on_plastic(gfmd_sim *s) { return gfmd_set_solver(s, GFMD_SOLVER_CG); }
static int32_t mass_on_plastic(gfmd_sim *s) { return gfmd_set_solver(s, GFMD_SOLVER_MASS_WEIGHTED_FIRE); }
static int32_t multilevel_on_plastic(gfmd_sim *s) { return gfmd_relax_multilevel(s, 1e-6, 100, 2, NULL, NULL); }
static int32_t pressure_nan_on_plastic(gfmd_sim *s) { return gfmd_set_pressure(s, NAN); }

static void plastic_refusals_change_nothing(void **state) {
    (void)state;
    static const failing calls[] = {
        {"adhesion with a hardness", GFMD_ERR_STATE, adhesion_on_plastic},
        {"the CG with a hardness", GFMD_ERR_STATE, cg_on_plastic},
        {"mass-weighted FIRE with a hardness", GFMD_ERR_STATE, mass_on_plastic},
        {"the multilevel start with a hardness", GFMD_ERR_STATE, multilevel_on_plastic},
        {"hardness NaN on a plastic run", GFMD_ERR_INVALID_ARG, hardness_nan},
        {"a NaN load on a plastic run", GFMD_ERR_INVALID_ARG, pressure_nan_on_plastic},
    };
    gfmd_sim *a = make_twin(), *b = make_twin();
    gfmd_sim *both[2] = {a, b};
    for (int i = 0; i < 2; ++i) {
        TS_OK(both[i], gfmd_set_adhesion(both[i], 0.0, 0.5));
        TS_OK(both[i], gfmd_set_hardness(both[i], 0.2));
        TS_OK(both[i], gfmd_set_pressure(both[i], 0.1));
        TS_OK(both[i], gfmd_step(both[i], 60));
    }
    double plastic = 0.0;
    TS_OK(a, gfmd_get_plasticity(a, &plastic, NULL));
    assert_true(plastic > 0.0); /* points are yielding: the state the refusals must keep */
    same_state(a, b, "the plastic steps");
    run_calls(a, b, calls, sizeof calls / sizeof calls[0]);
    diverge_one(a, b, "a diverged plastic run"); /* and a plastic run that diverges */
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
}

/* A run that diverges (damped dynamics at 50 times its automatic time step, far beyond the
 * stability limit) restores the configuration and the solver's state of the call's start. */
static void divergence_changes_nothing(void **state) {
    (void)state;
    gfmd_sim *a = make_twin(), *b = make_twin();
    diverge_one(a, b, "a diverged run");
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_failure_changes_nothing),
        cmocka_unit_test(divergence_changes_nothing),
        cmocka_unit_test(cg_refusals_change_nothing),
        cmocka_unit_test(plastic_refusals_change_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
