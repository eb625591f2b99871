/* "A failed call changes nothing" on a distributed handle, as tests/c/test_failed_calls.c checks it
 * serially: twin handles a and b on MPI_COMM_WORLD made alike; each failing call is made on a, once
 * with the bad value on every rank and once on the last rank only, and must fail on every rank with
 * its status (on one rank only: GFMD_ERR_INVALID_ARG for the collective calls, whose ranks compare
 * their arguments first; the call's own status for the local-slab ones) and the same message
 * everywhere; then a is compared with b -- every rank's slab of every field, the observables, the
 * dynamics, and (the solver's adaptive state) what 5 more steps of both do -- bit for bit.  Run on
 * 1, 2 and 4 ranks. */
#include <gfmd_mpi.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpi_check.h"

enum { NX = 32, NY = 24 };
static int size = 1, here = 0; /* here: this rank passes the bad value */
static int64_t rows = 0;

static gfmd_sim *make_twin(void) {
    gfmd_sim *s = NULL;
    OK(gfmd_sim_create_mpi(MPI_COMM_WORLD, NX, NY, NX, NY, GFMD_PLANNER_ESTIMATE, &s));
    OK(gfmd_generate_selfaffine(s, 0.8, 8.0, 4.0, 1.0, 3, GFMD_DIST_UNIFORM));
    OK(gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 4.0));
    OK(gfmd_set_adhesion(s, 1e-3, 0.5));
    OK(gfmd_set_pressure(s, 0.05));
    OK(gfmd_step(s, 20)); /* FIRE has adapted its step: a restart would show */
    return s;
}

/* every rank's slabs and the observables of a and b, bit for bit; then 5 steps of both, again */
static int same_state(gfmd_sim *a, gfmd_sim *b) {
    int (*const getters[])(const gfmd_sim *, double *, int64_t) = {
        gfmd_mpi_get_local_surface, gfmd_mpi_get_local_gap, gfmd_mpi_get_local_pressure, gfmd_mpi_get_local_heights};
    double *fa = malloc(sizeof(double) * (size_t)(rows * NX + 1)), *fb = malloc(sizeof(double) * (size_t)(rows * NX + 1));
    int same = 1;
    for (int round = 0; round < 2; ++round) {
        for (size_t g = 0; g < 4; ++g) {
            OK(getters[g](a, fa, NX));
            OK(getters[g](b, fb, NX));
            same = same && memcmp(fa, fb, sizeof(double) * (size_t)(rows * NX)) == 0;
        }
        double xa[10], xb[10];
        gfmd_sim *both[2] = {a, b};
        double *x[2] = {xa, xb};
        for (int i = 0; i < 2; ++i) {
            OK(gfmd_get_contact_area(both[i], &x[i][0]));
            OK(gfmd_get_mean_gap(both[i], &x[i][1]));
            OK(gfmd_get_energies(both[i], &x[i][2], &x[i][3]));
            OK(gfmd_get_residual(both[i], &x[i][4]));
            OK(gfmd_get_dynamics(both[i], &x[i][5], &x[i][6]));
            OK(gfmd_persson_variance(both[i], &x[i][7]));
            OK(gfmd_get_plasticity(both[i], &x[i][8], &x[i][9]));
        }
        same = same && memcmp(xa, xb, sizeof xa) == 0;
        if (round == 0) {
            OK(gfmd_step(a, 5));
            OK(gfmd_step(b, 5));
        }
    }
    free(fa);
    free(fb);
    int all = 0;
    MPI_Allreduce(&same, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return all;
}

static double bad(double good, double value) { return here ? value : good; }

static double local_h[NX * NY];
static int32_t modulus_nan(gfmd_sim *s) { return gfmd_set_modulus(s, bad(1.0, NAN)); }
static int32_t modulus_zero(gfmd_sim *s) { return gfmd_set_modulus(s, bad(1.0, 0.0)); }
static int32_t modulus_overflow(gfmd_sim *s) { return gfmd_set_modulus(s, bad(1.0, 1e308)); }
static int32_t green_unknown(gfmd_sim *s) { return gfmd_set_green(s, here ? 7 : GFMD_GREEN_LAYER_FLUID, 4.0); }
static int32_t green_width_nan(gfmd_sim *s) { return gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, bad(4.0, NAN)); }
static int32_t green_bonded(gfmd_sim *s) {
    return gfmd_set_green(s, here ? GFMD_GREEN_LAYER_BONDED : GFMD_GREEN_LAYER_FLUID, 4.0);
}
static int32_t poisson_high(gfmd_sim *s) { return gfmd_set_poisson(s, bad(0.3, 0.51)); }
static int32_t local_heights_nan(gfmd_sim *s) {
    memset(local_h, 0, sizeof local_h);
    if (here && rows > 0) local_h[3] = NAN;
    return gfmd_mpi_set_local_heights(s, local_h, NX);
}
static int32_t local_heights_null(gfmd_sim *s) { return gfmd_mpi_set_local_heights(s, here ? NULL : local_h, NX); }
static int32_t gen_hurst(gfmd_sim *s) { return gfmd_generate_selfaffine(s, bad(0.8, 1.5), 8.0, 4.0, 1.0, 3, 0); }
static int32_t gen_lambda(gfmd_sim *s) { return gfmd_generate_selfaffine(s, 0.8, bad(8.0, 2.0), 4.0, 1.0, 3, 0); }
static int32_t gen_distribution(gfmd_sim *s) { return gfmd_generate_selfaffine(s, 0.8, 8.0, 4.0, 1.0, 3, here ? 9 : 0); }
static int32_t pressure_negative(gfmd_sim *s) { return gfmd_set_pressure(s, bad(0.05, -1.0)); }
static int32_t pressure_inf(gfmd_sim *s) { return gfmd_set_pressure(s, bad(0.05, INFINITY)); }
static int32_t adhesion_nan(gfmd_sim *s) { return gfmd_set_adhesion(s, bad(1e-3, NAN), 0.5); }
static int32_t adhesion_overflow(gfmd_sim *s) { return gfmd_set_adhesion(s, bad(1e-3, 1e300), bad(0.5, 1e-300)); }
static int32_t hardness_nan(gfmd_sim *s) { return gfmd_set_hardness(s, bad(INFINITY, NAN)); }
static int32_t hardness_with_adhesion(gfmd_sim *s) { return gfmd_set_hardness(s, bad(INFINITY, 0.1)); }
static int32_t position_below(gfmd_sim *s) { return gfmd_set_mean_displacement(s, bad(1.0, -1e6)); }
static int32_t position_nan(gfmd_sim *s) { return gfmd_set_mean_displacement(s, bad(1.0, NAN)); }
static int32_t timestep_negative(gfmd_sim *s) { return gfmd_set_timestep(s, bad(0.0, -1.0)); }
static int32_t damping_inf(gfmd_sim *s) { return gfmd_set_damping(s, bad(0.0, INFINITY)); }
static int32_t solver_unknown(gfmd_sim *s) { return gfmd_set_solver(s, here ? 42 : GFMD_SOLVER_AUTO); }
static int32_t solver_newton(gfmd_sim *s) { return gfmd_set_solver(s, here ? GFMD_SOLVER_NEWTON : GFMD_SOLVER_AUTO); }
static int32_t threads_negative(gfmd_sim *s) { return gfmd_set_threads(s, here ? -1 : 1); }
static int32_t planner_unknown(gfmd_sim *s) { return gfmd_set_fft_planner(s, here ? 9 : GFMD_PLANNER_ESTIMATE); }
static int32_t step_negative(gfmd_sim *s) { return gfmd_step(s, here ? -1 : 0); }
static int32_t relax_nan(gfmd_sim *s) { return gfmd_relax(s, bad(1e-6, NAN), 10, NULL); }
static int32_t relax_no_steps(gfmd_sim *s) { return gfmd_relax(s, 1e-6, here ? 0 : 10, NULL); }
static int32_t multilevel_zero(gfmd_sim *s) { return gfmd_relax_multilevel(s, 1e-6, 10, here ? 0 : 1, NULL, NULL); }
static int32_t persson_negative(gfmd_sim *s) {
    double a = 0.0;
    return gfmd_persson_contact_area(s, bad(0.05, -1.0), &a);
}
static int32_t persson_load_full(gfmd_sim *s) {
    double l = 0.0;
    return gfmd_persson_load(s, bad(0.5, 1.0), &l);
}
static int32_t save_nowhere(gfmd_sim *s) { return gfmd_sim_save(s, here ? "no/such/dir/x.gfmd" : "mpi_ok.gfmd"); }
static int32_t patches_connectivity(gfmd_sim *s) {
    int64_t n = 0;
    return gfmd_get_contact_patches(s, here ? 6 : 4, NULL, &n);
}
static int32_t patch_property(gfmd_sim *s) {
    int64_t n = 0;
    double v[64];
    return gfmd_get_patch_property(s, 4, here ? 77 : GFMD_PATCH_AREA, 64, v, &n);
}
static int32_t histogram_bins(gfmd_sim *s) {
    double r[2] = {0.0, 0.0}, f[4], m[4];
    return gfmd_get_pressure_histogram(s, here ? 0 : 4, r, f, m);
}
static int32_t local_labels_ld(gfmd_sim *s) {
    static int64_t labels[NX * NY];
    int64_t n = 0;
    return gfmd_mpi_get_local_contact_patches(s, 4, labels, here ? NX - 1 : NX, &n);
}

typedef struct {
    const char *what;
    int32_t everywhere; /* the status with the bad value on every rank */
    int32_t one;        /* with it on the last rank only, on more than one rank */
    int32_t (*call)(gfmd_sim *s);
} failing;

#define IA GFMD_ERR_INVALID_ARG
static const failing CALLS[] = {
    {"modulus NaN", IA, IA, modulus_nan},
    {"modulus 0", IA, IA, modulus_zero},
    {"modulus overflowing the stresses", GFMD_ERR_RANGE, IA, modulus_overflow},
    {"unknown Green's kind", GFMD_ERR_BAD_ENUM, IA, green_unknown},
    {"layer width NaN", IA, IA, green_width_nan},
    {"bonded layer without Poisson's ratio", GFMD_ERR_STATE, IA, green_bonded},
    {"Poisson 0.51", IA, IA, poisson_high},
    {"a NaN local height", IA, IA, local_heights_nan},
    {"local heights NULL", GFMD_ERR_NULL, GFMD_ERR_NULL, local_heights_null},
    {"hurst > 1", IA, IA, gen_hurst},
    {"lambda_r < lambda_s", IA, IA, gen_lambda},
    {"unknown distribution", GFMD_ERR_BAD_ENUM, IA, gen_distribution},
    {"pressure < 0", IA, IA, pressure_negative},
    {"pressure inf", IA, IA, pressure_inf},
    {"gamma0 NaN", IA, IA, adhesion_nan},
    {"adhesive stiffness overflowing", GFMD_ERR_RANGE, IA, adhesion_overflow},
    {"hardness NaN", IA, IA, hardness_nan},
    {"hardness with adhesion (several ranks: distributed)", GFMD_ERR_STATE, IA, hardness_with_adhesion},
    {"mean position below the substrate's mean", IA, IA, position_below},
    {"mean position NaN", IA, IA, position_nan},
    {"dt < 0", IA, IA, timestep_negative},
    {"damping inf", IA, IA, damping_inf},
    {"unknown solver", GFMD_ERR_BAD_ENUM, IA, solver_unknown},
    {"the Newton solver on a distributed fluid layer", GFMD_ERR_STATE, IA, solver_newton},
    {"threads < 0", IA, IA, threads_negative},
    {"unknown planner", GFMD_ERR_BAD_ENUM, IA, planner_unknown},
    {"steps < 0", IA, IA, step_negative},
    {"relax tol NaN", IA, IA, relax_nan},
    {"relax max_steps 0", IA, IA, relax_no_steps},
    {"multilevel relax with 0 levels", IA, IA, multilevel_zero},
    {"Persson at sigma0 < 0", IA, IA, persson_negative},
    {"Persson load for full contact", IA, IA, persson_load_full},
    {"save into a missing folder", GFMD_ERR_IO, IA, save_nowhere},
    {"patches with connectivity 6", IA, IA, patches_connectivity},
    {"an unknown patch property", GFMD_ERR_BAD_ENUM, IA, patch_property},
    {"a pressure histogram of 0 bins", IA, IA, histogram_bins},
    {"local patch labels with ld < nx", IA, IA, local_labels_ld},
};

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    gfmd_sim *a = make_twin(), *b = make_twin();
    int64_t y0 = 0;
    OK(gfmd_mpi_get_local_grid(a, &rows, &y0));
    CHECK(same_state(a, b), "twins differ after creation");
    int checked = 0;
    for (int variant = 0; variant < 2; ++variant) {
        if (variant == 1 && size == 1) break; /* one rank: the same as every rank */
        here = variant == 0 || rank == size - 1;
        for (size_t i = 0; i < sizeof CALLS / sizeof CALLS[0]; ++i) {
            const int32_t expected = variant == 0 ? CALLS[i].everywhere : CALLS[i].one;
            const int32_t st = CALLS[i].call(a);
            char msg[256] = "", first[256] = "";
            gfmd_last_error(a, msg, sizeof msg);
            memcpy(first, msg, sizeof msg);
            MPI_Bcast(first, sizeof first, MPI_CHAR, 0, MPI_COMM_WORLD);
            CHECK(st == expected, "%s (%s): status %d, expected %d: %s", CALLS[i].what,
                  variant == 0 ? "every rank" : "last rank", st, expected, msg);
            CHECK(msg[0] != '\0' && strcmp(msg, first) == 0, "%s: another message than rank 0's: %s",
                  CALLS[i].what, msg);
            CHECK(same_state(a, b), "%s (%s) changed the state", CALLS[i].what, variant == 0 ? "every rank" : "last rank");
            ++checked;
        }
    }
    gfmd_sim_destroy(&a);
    gfmd_sim_destroy(&b);
    remove("mpi_ok.gfmd");
    int total = 0;
    MPI_Allreduce(&failures, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    if (rank == 0)
        printf("test_mpi_failed_calls on %d ranks: %d failing calls, state unchanged: %s\n", size, checked,
               total ? "FAILED" : "passed");
    MPI_Finalize();
    return total ? 1 : 0;
}
