/* gfmd benchmark: steps, time per step against the bare FFTW transforms a step needs, peak
 * memory, and the same problem solved by a constrained-CG reference (Polonsky-Keer) in the same
 * run, for half-space and layers on a fluid foundation.
 *
 *   gfmd_bench [--sizes 256,512,1024,2048] [--widths 0,0.5,1,4] [--threads N]
 *              [--cg-seconds S] [--no-cg] [--no-alt] [--sigma0 S] [--solver auto|fire|mass|mass+fire|verlet|cg]
 *   gfmd_bench ... --bonded NU   the layers bonded to a rigid base (Poisson's ratio NU) instead of on a
 *                                fluid foundation, in both GFMD and the CG reference
 *   gfmd_bench --contention [--sizes 512,1024,2048]
 *   gfmd_bench --loads 0.002,0.01,0.05,0.2 [--sizes 256] [--widths 0.25,1,4]
 *                                FIRE, mass-weighted FIRE and CG from flat at each load, layers on
 *                                a fluid foundation, with Persson's A/A0 at the load, f(q_min w)
 *                                and the default's choice
 *   gfmd_bench --choices 0.003,0.05,0.2 [--gaps 1,0.25] [--sizes 256] [--widths 0,1] [--bonded NU]
 *                                nothing relaxed: the default's choice at each load and (--gaps)
 *                                mean position, with what its rule reads (S, f(q_min w), Persson's
 *                                A/A0, the fraction of the substrate above the mean position)
 *   gfmd_bench --free [--sizes 256,512] [--loads 0.05,0.2]
 *                                free boundaries (a half-space region on the zero-padded cell), with
 *                                and without adhesion: the default (CG) against FIRE from flat
 *   gfmd_bench --multilevel [--sizes 256] [--widths 0.0625,0.125] [--sigma0 S] [--solver fire|mass]
 *                                gfmd_relax_multilevel with 1-4 levels from flat, to 1e-10
 *   gfmd_bench --first-load [--sizes 512,1024,2048] [--widths 0.0625,0.25] [--threads N] [--levels L] [--tol T]
 *              [--adhesion | --no-adhesion] [--levers fire,mass,multilevel,default,cg,newton] [--areas 0.004,..]
 *                                a thin sheet's first load from flat, with and without adhesion
 *                                (--adhesion: with only; --no-adhesion: without only), by FIRE,
 *                                mass-weighted FIRE, the multilevel start (named by the solver
 *                                its finest grid took), the default solver, the CG and the Newton
 *                                method (--levers: those only; default: the first four), at the
 *                                loads of Persson's A/A0 = 0.004 (--areas: those), beside a
 *                                half-space on the same substrate and load (its seconds the /hs
 *                                column's unit)
 *   gfmd_bench --sweep [--sizes 2048] [--widths 0.25,1,100] [--threads N]
 *        [--adhesion] [--no-cg] [--verbose] [--from A] [--to A] [--columns fire,m+fire,mass,cg,newton,auto]
 *        [--substrate H,LS,R,SEED]
 *                                the study's continuing loads on each body by FIRE, the approach
 *                                then FIRE, mass-weighted FIRE, CG and the default (its choices);
 *                                --from: those at Persson's A/A0 >= A only (the lower ones
 *                                relaxed once by the default, untimed); --to: those at
 *                                Persson's A/A0 <= A only; --columns: those
 *                                columns only; --substrate: Hurst exponent H, lambda_s = LS a,
 *                                lambda_r = n a/R and the seed instead of the study's 0.8,4,8,2016
 *   gfmd_bench --big [--sigma0 S] [--threads 2] [--sizes 4096]
 *                                one W = 1 layer from flat to the default tolerance at 4096^2
 *   gfmd_bench --displacement [--sizes 256] [--widths 0.25,1,4,8,16,0] [--below B | --gap R [--positions K]]
 *        [--adhesion | --no-adhesion] [--bonded NU]
 *                                displacement control: from flat to the mean position B a (default
 *                                1) below the highest peak, or R rms heights above the substrate's
 *                                mean height (--gap), by FIRE, mass-weighted FIRE, the
 *                                library's CG (without adhesion) and the default (its choice),
 *                                without and with adhesion (--adhesion: with only; --no-adhesion:
 *                                without only), then (--positions) K positions each 0.1 rms
 *                                heights closer, relaxed from the last (a load sweep), layers on a
 *                                fluid foundation or bonded (--bonded); the runs fail the program
 *                                if their A/A0 differ by more than two points or their mean
 *                                pressures by more than 1e-4 of the pressure scale (without
 *                                adhesion: one equilibrium)
 *
 *   gfmd_bench --random K [--seed S] [--sizes 128,256]
 *                                K bodies drawn at random (body, width, roughness, load, control,
 *                                adhesion), each by the default and every solver that takes it,
 *                                with the ratio of the default's seconds to the fastest's
 *
 * --contention: threads on a shared machine.  For each size, a half-space (seed 1, sigma0 = 0.05)
 * is created (planning included) and relaxed from flat to the default tolerance with one thread
 * and with the default thread count, on a quiet machine and while a busy-loop competitor (a child
 * process started and stopped by the benchmark, pinned to the last CPU this process may use, and
 * ending itself after 10 minutes at the latest) keeps one core busy.
 *
 * Problem: self-affine, H = 0.8, lambda_s = 4a, lambda_r = n a/8, rms gradient 1,
 * E* = 1, sigma0 = 0.05 (--sigma0); W = w/lambda_s, 0 = half-space.  The "fft" column is the
 * bare r2c + c2r pairs (timed just before and just after the row's run, the two averaged) one step
 * of the solver that ran needs (two for mass-weighted FIRE, 7/3 for
 * CG on the pressure (two, and the convergence test's every third iteration), two and a half for
 * the preconditioned CG on the surface; the approach then FIRE: two for its first 100 steps, then one); "solver" is that solver
 * (with the default --solver auto, the library's own choice), and "other" the time to 0.1 % of the
 * library's other method for this body (FIRE where the choice was CG or the approach then FIRE, CG
 * where it was FIRE; --no-alt skips it), so that each row shows whether the choice was right.  The converged A/A0 comes from an
 * untimed GFMD relaxation to 1e-10.  Then, from the same start, GFMD and CG are timed: the time
 * after which A/A0 stays within 0.1 % of the converged value ("to 0.1 %", the speed-up compares
 * these; both counted to the iteration, GFMD's by an untimed run first, timed_relax), and GFMD
 * also until its default tolerance. */
#define _GNU_SOURCE /* sched_setaffinity, CPU_SET */
#include <fftw3.h>
#include <gfmd.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench_clock.h"
#include "cg_reference.h"

/* The bare transforms one step needs: one r2c and one c2r of n x n, same threads and planner,
 * on the same kind of memory as the library's grids.  Timed around each row's run (pair_run
 * before and after it, each for at least a second): the machine's speed drifts, and a pair timed
 * once per size, in a fraction of a second, moved the printed ratio by up to a fifth between
 * runs of the same steps. */
typedef struct {
    int n;
    double *r;
    fftw_complex *c;
    fftw_plan f, b;
} pair_timer;

static void pair_init(pair_timer *p, int n, int threads) {
    p->n = n;
    p->r = cg_grid_alloc(sizeof(double) * (size_t)n * (size_t)n);
    p->c = cg_grid_alloc(sizeof(fftw_complex) * (size_t)n * (size_t)(n / 2 + 1));
    if (!p->r || !p->c) {
        fprintf(stderr, "gfmd_bench: no memory for the bare transforms of %d^2\n", n);
        exit(1);
    }
    fftw_init_threads();
    fftw_plan_with_nthreads(threads);
    p->f = fftw_plan_dft_r2c_2d(n, n, p->r, p->c, FFTW_MEASURE);
    p->b = fftw_plan_dft_c2r_2d(n, n, p->c, p->r, FFTW_MEASURE);
    fftw_plan_with_nthreads(1);
    for (size_t i = 0; i < (size_t)n * (size_t)n; ++i) p->r[i] = sin(0.001 * (double)i);
}

/* seconds per pair, over at least 1 s and 3 pairs (c2r leaves r scaled by n^2: rescaled every
 * pair, outside the clock, so that the data stay the same) */
static double pair_run(pair_timer *p) {
    const size_t points = (size_t)p->n * (size_t)p->n;
    const double scale = 1.0 / (double)points;
    double busy = 0.0;
    int pairs = 0;
    while (busy < 1.0 || pairs < 3) {
        const double t0 = now();
        fftw_execute(p->f);
        fftw_execute(p->b);
        busy += now() - t0;
        ++pairs;
        for (size_t i = 0; i < points; ++i) p->r[i] *= scale;
    }
    return busy / pairs;
}

static void pair_free(pair_timer *p) {
    fftw_destroy_plan(p->f);
    fftw_destroy_plan(p->b);
    free(p->r);
    free(p->c);
}

static int parse_list(const char *s, double *out, int max) {
    int k = 0;
    while (*s && k < max) {
        char *end;
        out[k++] = strtod(s, &end);
        if (*end != ',') break;
        s = end + 1;
    }
    return k;
}

static void die(gfmd_sim *s, int32_t st, const char *what) {
    char msg[256] = "";
    if (s) gfmd_last_error(s, msg, sizeof msg);
    fprintf(stderr, "%s: %s: %s\n", what, gfmd_status_string(st), msg);
    exit(1);
}

/* A child process spinning on the last CPU of this process's affinity mask; -1 if none started. */
static pid_t start_competitor(void) {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) != 0) return -1;
    int last = -1;
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (CPU_ISSET(c, &set)) last = c;
    const pid_t pid = fork();
    if (pid == 0) {
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(last, &one);
        sched_setaffinity(0, sizeof one, &one);
        alarm(600); /* bounded: ends itself even if the benchmark dies */
        volatile unsigned long x = 0;
        for (;;) x = x * 1664525UL + 1013904223UL;
    }
    usleep(100000); /* let it reach its core */
    return pid;
}

static void stop_competitor(pid_t pid) {
    if (pid <= 0) return;
    kill(pid, SIGKILL);
    waitpid(pid, NULL, 0);
}

/* create (with planning) and relax of the contention table; returns the seconds of each */
static void create_and_relax(int n, int threads, double *t_create, double *t_relax, long long *steps) {
    fftw_forget_wisdom(); /* every configuration plans afresh: the create column is the planning's cost */
    const double l = n, t0 = now();
    gfmd_sim *s = NULL;
    int32_t st;
    if ((st = gfmd_sim_create_ex(n, n, l, l, threads, GFMD_PLANNER_MEASURE, &s)) != GFMD_OK) die(NULL, st, "create");
    *t_create = now() - t0;
    if ((st = gfmd_generate_selfaffine(s, 0.8, l / 8.0, 4.0, 1.0, 1, GFMD_DIST_UNIFORM)) != GFMD_OK) die(s, st, "substrate");
    if ((st = gfmd_set_pressure(s, 0.05)) != GFMD_OK) die(s, st, "pressure");
    int64_t k = 0;
    const double t1 = now();
    if ((st = gfmd_relax(s, 0.0, 10000000, &k)) != GFMD_OK) die(s, st, "relax");
    *t_relax = now() - t1;
    *steps = (long long)k;
    gfmd_sim_destroy(&s);
}

typedef struct {
    int64_t steps, steps_acc;
    double seconds, seconds_acc, peak_mb;
    int32_t active;
    int converged; /* to tol within the step limit */
} gfmd_run;

/* From the start (reset + pressure, which restarts the solver's adaptive state) to tol, at most
 * limit steps: the steps and seconds, and those after which A/A0 stays within 0.1 % of area_conv
 * (NAN: of the run's own last value), counted to the step.  An untimed run, one step per call,
 * finds that step count k (the end of a call evaluates the forces, which CG otherwise does every
 * third iteration only, and snapshots the fields for "a failed call changes nothing": costs a relax
 * in one call does not pay); the timed run, from the same start, makes k steps in one call and
 * relaxes on in a second.  The iterates do not depend on where calls end, so both runs take the
 * same steps (checked). */
static void restart_run(gfmd_sim *s, double sigma0) {
    gfmd_reset(s);
    gfmd_set_pressure(s, sigma0);
}

static gfmd_run timed_relax_to(gfmd_sim *s, int32_t solver, double sigma0, double area_conv, double tol, int64_t limit) {
    gfmd_run out = {0, -1, 0.0, -1.0, 0.0, -1, 0};
    int32_t st;
    if ((st = gfmd_set_solver(s, solver)) != GFMD_OK) die(s, st, "solver");
    restart_run(s, sigma0);
    gfmd_get_solver(s, &out.active);
    int64_t probe = 0, k = 1, cap = 1 << 14;
    double *trace = malloc(sizeof(double) * (size_t)cap); /* A/A0 after each step */
    if (!trace) die(s, GFMD_ERR_NOMEM, "trace");
    while (k > 0 && probe < limit) { /* a relax of at most one step: none once converged */
        st = gfmd_relax(s, tol, 1, &k);
        if (st != GFMD_OK && st != GFMD_ERR_NOT_CONVERGED) die(s, st, "step");
        if (k == 0) break;
        if (probe == cap) {
            double *grown = realloc(trace, sizeof(double) * (size_t)(cap *= 2));
            if (!grown) {
                free(trace);
                die(s, GFMD_ERR_NOMEM, "trace");
            }
            trace = grown;
        }
        gfmd_get_contact_area(s, &trace[probe++]);
    }
    double residual = 1.0;
    gfmd_get_residual(s, &residual);
    out.converged = (k == 0) || residual <= tol;
    double final_area = 0.0;
    gfmd_get_contact_area(s, &final_area);
    const double target = isnan(area_conv) ? final_area : area_conv;
    out.steps_acc = fabs(final_area - target) <= 1e-3 * target ? probe : -1;
    for (int64_t j = probe - 1; j >= 0 && fabs(trace[j] - target) <= 1e-3 * target; --j) out.steps_acc = j + 1;
    free(trace);
    restart_run(s, sigma0);
    int64_t more = 0;
    const double t0 = now();
    if (out.steps_acc > 0 && (st = gfmd_step(s, out.steps_acc)) != GFMD_OK) die(s, st, "step");
    out.seconds_acc = out.steps_acc >= 0 ? now() - t0 : -1.0;
    const int64_t rest = probe - (out.steps_acc > 0 ? out.steps_acc : 0);
    if (out.converged) {
        if (rest > 0 && (st = gfmd_relax(s, tol, rest, &more)) != GFMD_OK) die(s, st, "relax");
    } else if (rest > 0) {
        if ((st = gfmd_step(s, rest)) != GFMD_OK) die(s, st, "step");
        more = rest;
    }
    out.seconds = now() - t0;
    out.steps = (out.steps_acc > 0 ? out.steps_acc : 0) + more;
    if (out.steps != probe) {
        fprintf(stderr, "gfmd_bench: the timed run took %lld steps, the untimed one %lld\n", (long long)out.steps,
                (long long)probe);
        exit(1);
    }
    return out;
}

static gfmd_run timed_relax(gfmd_sim *s, int32_t solver, double sigma0, double area_conv) {
    return timed_relax_to(s, solver, sigma0, area_conv, GFMD_DEFAULT_TOL, 10000000);
}

/* The substrate of bench_body: H, lambda_s (in a), lambda_r = n a / ratio, seed (--substrate, with
 * --sweep only; the study's by default) */
static double substrate_hurst = 0.8, substrate_lambda_s = 4.0, substrate_ratio = 8.0;
static uint64_t substrate_seed = 2016;

/* A body of the benchmark's problem on an n x n grid: half-space (W = 0) or a layer on a fluid
 * foundation, w = 4 W a; FFTW_MEASURE plans, one thread. */
static gfmd_sim *bench_body(int n, double W, double sigma0, int32_t solver) {
    gfmd_sim *s = NULL;
    int32_t st;
    const double l = n;
    if ((st = gfmd_sim_create_ex(n, n, l, l, 1, GFMD_PLANNER_MEASURE, &s)) != GFMD_OK) die(NULL, st, "create");
    if ((st = gfmd_generate_selfaffine(s, substrate_hurst, l / substrate_ratio, substrate_lambda_s, 1.0, substrate_seed,
                                       GFMD_DIST_UNIFORM)) != GFMD_OK)
        die(s, st, "substrate");
    if (W > 0 && (st = gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, W * 4.0)) != GFMD_OK) die(s, st, "green");
    if ((st = gfmd_set_pressure(s, sigma0)) != GFMD_OK) die(s, st, "pressure");
    if ((st = gfmd_set_solver(s, solver)) != GFMD_OK) die(s, st, "solver");
    return s;
}

/* A solver's short name in the tables (GFMD_SOLVER_*). */
static const char *solver_name(int32_t solver) {
    static const char *const names[] = {"Verlet", "FIRE", "mass", "CG", "auto", "mass+FIRE", "Newton"};
    return solver >= 0 && solver < (int32_t)(sizeof names / sizeof names[0]) ? names[solver] : "?";
}

/* f(q_min w) of an n x n grid (spacing a, q_min = 2 pi/(n a)) for a layer of width 4 W a: the
 * longest wave's softness against the half-space; 1 for the half-space (W = 0), NaN if the
 * library refuses it. */
static double longest_wave_factor(int32_t layer, int n, double W, double nu) {
    double f = 1.0;
    if (W > 0 && gfmd_green_factor(layer, 2.0 * 3.141592653589793 / n * 4.0 * W, nu, &f) != GFMD_OK) f = NAN;
    return f;
}

/* --loads: FIRE, mass-weighted FIRE, the approach then FIRE and CG from flat to the default
 * tolerance at each load, with the default's choice (from the same flat start) and f(q_min w), the
 * long-wave softness of the layer against the half-space (1 for the half-space, 6/(q_min w)^3 for
 * a thin plate). */
static int loads_table(const double *sizes, int nsizes, const double *widths, int nwidths, const double *loads,
                       int nloads) {
    const int32_t solvers[4] = {GFMD_SOLVER_FIRE, GFMD_SOLVER_MASS_WEIGHTED_FIRE, GFMD_SOLVER_APPROACH_THEN_FIRE, GFMD_SOLVER_CG};
    printf("gfmd %s: FIRE, mass-weighted FIRE, the approach then FIRE and CG from flat, layers on a fluid foundation "
           "(w = 4 W a), H = 0.8, lambda_s = 4a, lambda_r = n a/8, seed 2016, one thread, default tolerance\n",
           gfmd_version());
    printf("%5s %6s %9s %8s | %8s %8s | %7s %8s | %7s %8s | %7s %8s | %7s %8s | %9s\n", "n", "W", "f(qmin w)", "sigma0",
           "A/A0", "Persson", "FIRE", "s", "mass", "s", "m+FIRE", "s", "CG its", "s", "auto");
    for (int a = 0; a < nsizes; ++a)
        for (int b = 0; b < nwidths; ++b)
            for (int c = 0; c < nloads; ++c) {
                const int n = (int)sizes[a];
                double secs[4], area = 0.0, persson = 0.0;
                const double f = longest_wave_factor(GFMD_GREEN_LAYER_FLUID, n, widths[b], 0.0);
                int64_t steps[4];
                int32_t choice = -1;
                for (int k = 0; k < 4; ++k) {
                    gfmd_sim *s = bench_body(n, widths[b], loads[c], solvers[k]);
                    const double t0 = now();
                    int32_t st = gfmd_relax(s, 0.0, 10000000, &steps[k]);
                    secs[k] = now() - t0;
                    if (st != GFMD_OK) die(s, st, "relax");
                    gfmd_get_contact_area(s, &area);
                    gfmd_persson_contact_area(s, loads[c], &persson);
                    if (k == 0) {
                        gfmd_set_solver(s, GFMD_SOLVER_AUTO);
                        gfmd_reset(s);
                        gfmd_set_pressure(s, loads[c]); /* the choice from a flat start */
                        gfmd_get_solver(s, &choice);
                    }
                    gfmd_sim_destroy(&s);
                }
                printf("%5d %6g %9.3g %8g | %8.3f %8.3f | %7lld %8.3f | %7lld %8.3f | %7lld %8.3f | %7lld %8.3f | %9s\n", n,
                       widths[b], widths[b] > 0 ? f : 1.0, loads[c], area, persson, (long long)steps[0], secs[0],
                       (long long)steps[1], secs[1], (long long)steps[2], secs[2], (long long)steps[3], secs[3],
                       solver_name(choice));
                fflush(stdout);
            }
    return 0;
}

/* --multilevel: gfmd_relax_multilevel with 1 ... 4 levels from flat, to 1e-10. */
static int multilevel_table(const double *sizes, int nsizes, const double *widths, int nwidths, double sigma0,
                            int32_t solver) {
    printf("gfmd %s: multilevel start, layers on a fluid foundation (w = 4 W a), sigma0 = %g, H = 0.8, lambda_s = 4a, "
           "lambda_r = n a/8, seed 2016, one thread, tol 1e-10, solver %d\n", gfmd_version(), sigma0, (int)solver);
    printf("%5s %6s | %8s | %6s %7s %8s | %s\n", "n", "W", "A/A0", "levels", "steps", "coarse", "seconds");
    for (int a = 0; a < nsizes; ++a)
        for (int b = 0; b < nwidths; ++b)
            for (int levels = 1; levels <= 4; ++levels) {
                const int n = (int)sizes[a];
                gfmd_sim *s = bench_body(n, widths[b], sigma0, solver);
                int64_t steps = 0, coarse = 0;
                double area = 0.0;
                const double t0 = now();
                int32_t st = gfmd_relax_multilevel(s, 1e-10, 10000000, levels, &steps, &coarse);
                const double t = now() - t0;
                if (st != GFMD_OK) die(s, st, "relax_multilevel");
                gfmd_get_contact_area(s, &area);
                printf("%5d %6g | %8.5f | %6d %7lld %8lld | %.3f\n", n, widths[b], area, levels, (long long)steps,
                       (long long)coarse, t);
                fflush(stdout);
                gfmd_sim_destroy(&s);
            }
    return 0;
}

/* Free boundaries: the benchmark's substrate on an n x n region (the padded cell 2n x 2n), relaxed
 * from flat by the default (CG) and by FIRE at each load, without and with adhesion (gamma0 =
 * 5e-4 E* a, rho = a); one thread, default tolerance.  A time counts where both reach the same A/A0. */
static int free_table(const double *sizes, int nsizes, const double *loads, int nloads) {
    printf("gfmd %s: free boundaries, half-space, H = 0.8, lambda_s = 4a, lambda_r = n a/8, rms gradient 1, seed "
           "2016, one thread, default tol, from flat\n", gfmd_version());
    printf("%5s %7s %8s | %8s | %-6s %7s %8s | %-6s %7s %8s | %s\n", "n", "sigma0", "gamma0", "A/A0", "dflt", "steps",
           "seconds", "alt", "steps", "seconds", "alt/dflt");
    for (int a = 0; a < nsizes; ++a)
        for (int b = 0; b < nloads; ++b)
            for (int adhesive = 0; adhesive < 2; ++adhesive) {
                const int n = (int)sizes[a];
                gfmd_sim *s = bench_body(n, 0.0, loads[b], GFMD_SOLVER_AUTO);
                int32_t st;
                if ((st = gfmd_set_boundary(s, GFMD_BOUNDARY_FREE)) != GFMD_OK) die(s, st, "boundary");
                if ((st = gfmd_generate_selfaffine(s, substrate_hurst, n / substrate_ratio, substrate_lambda_s, 1.0,
                                                   substrate_seed, GFMD_DIST_UNIFORM)) != GFMD_OK)
                    die(s, st, "substrate");
                const double gamma0 = adhesive ? 5e-4 : 0.0;
                if (adhesive && (st = gfmd_set_adhesion(s, gamma0, 1.0)) != GFMD_OK) die(s, st, "adhesion");
                double area[2] = {0.0, 0.0};
                const gfmd_run d = timed_relax(s, GFMD_SOLVER_AUTO, loads[b], NAN);
                gfmd_get_contact_area(s, &area[0]);
                const gfmd_run f = timed_relax(s, GFMD_SOLVER_FIRE, loads[b], NAN);
                gfmd_get_contact_area(s, &area[1]);
                const int agree = fabs(area[0] - area[1]) <= 1e-3 * area[0] && d.converged && f.converged;
                printf("%5d %7g %8g | %8.5f | %-6s %7lld %8.3f | %-6s %7lld %8.3f | ", n, loads[b], gamma0, area[0],
                       solver_name(d.active), (long long)d.steps, d.seconds, "FIRE", (long long)f.steps, f.seconds);
                if (agree) printf("%.2f\n", f.seconds / d.seconds);
                else printf("(A/A0 %.5f: not the same state)\n", area[1]);
                fflush(stdout);
                gfmd_sim_destroy(&s);
            }
    return 0;
}

/* The load at which Persson's A/A0 equals `area` (the study's loads). */
static double persson_load(gfmd_sim *s, double area) {
    double load = 0.0;
    int32_t st = gfmd_persson_load(s, area, &load);
    if (st != GFMD_OK) die(s, st, "persson load");
    return load;
}

/* --sweep: the study's load sweep on one body (gfmd_paper: Persson's A/A0 = 0.004 ... 0.4, each
 * load continuing from the last equilibrium), bench_body's substrate (at 2048^2 the one of
 * gfmd_paper --full: lambda_r = n a/8, seed 2016), with the study's adhesion if asked.  The first
 * load is relaxed once, untimed, by the default solver (from 3 coarser grids at >= 2048^2, flat
 * below, as the study does); from that equilibrium the nine continuing loads are relaxed by each
 * solver on a clone: FIRE, the approach then FIRE, mass-weighted FIRE throughout, CG (not with
 * --no-cg; with adhesion the adhesive CG), the active-set Newton method (with adhesion its trust
 * region) and the default, which chooses again at every load.  Prints their
 * steps and seconds, the default's choices (one name per run of loads), A/A0 at the last load of
 * each, and with --verbose each solver's steps and seconds per load. */
enum { SWEEP_LOADS = 10, SWEEP_SOLVERS = 6 };

typedef struct {
    long long steps[SWEEP_LOADS], total;
    double secs[SWEEP_LOADS], seconds, area;
} sweep_run;

/* The nine continuing loads on a clone of s by `solver`, timed load by load (total -1: the Newton
 * method refused the body). */
static sweep_run sweep_continue(gfmd_sim *s, int32_t solver, const double *loads, int first, int last) {
    sweep_run r = {{0}, 0, {0}, 0.0, 0.0};
    gfmd_sim *c = NULL;
    int32_t st = gfmd_sim_clone(s, &c);
    if (st != GFMD_OK) die(s, st, "clone");
    if ((st = gfmd_set_solver(c, solver)) == GFMD_ERR_STATE && solver == GFMD_SOLVER_NEWTON) {
        gfmd_sim_destroy(&c); /* a body the Newton method does not take (a half-space): no column */
        r.total = -1;
        return r;
    }
    if (st != GFMD_OK) die(c, st, "solver");
    for (int l = first; l < last; ++l) {
        int64_t steps = 0;
        if ((st = gfmd_set_pressure(c, loads[l])) != GFMD_OK) die(c, st, "pressure");
        const double t0 = now();
        if ((st = gfmd_relax(c, 0.0, 10000000, &steps)) != GFMD_OK) die(c, st, "relax");
        r.secs[l] = now() - t0;
        r.steps[l] = (long long)steps;
        r.total += r.steps[l];
        r.seconds += r.secs[l];
    }
    gfmd_get_contact_area(c, &r.area);
    gfmd_sim_destroy(&c);
    return r;
}

/* The default's choices over the continuing loads, e.g. "mass/m+FIRE" (one name per run). */
static void sweep_choices(const int32_t *choice, int first, int last, char *out, size_t size) {
    static const char *const shortnames[] = {"Verlet", "FIRE", "mass", "CG", "auto", "m+FIRE", "Newton"};
    out[0] = '\0';
    for (int l = first; l < last; ++l) {
        if (l > first && l > 0 && choice[l] == choice[l - 1]) continue;
        const int32_t k = choice[l];
        const char *name = k >= 0 && k < 7 ? shortnames[k] : "?";
        const size_t used = strlen(out);
        snprintf(out + used, size - used, "%s%s", l > first ? "/" : "", name);
    }
}

static const char *const sweep_names[SWEEP_SOLVERS] = {"fire", "m+fire", "mass", "cg", "newton", "auto"};

/* columns: a bit per column to run (--columns, parse_names on sweep_names), so that a 2048^2
 * comparison need not run all six */
static int sweep_table(const double *sizes, int nsizes, const double *widths, int nwidths, int threads, int adhesion,
                       int cg, int verbose, double from, double to, int columns) {
    static const double targets[SWEEP_LOADS] = {0.004, 0.008, 0.016, 0.03, 0.05, 0.08, 0.12, 0.18, 0.27, 0.4};
    static const char *const heads[SWEEP_SOLVERS] = {"FIRE", "m+FIRE", "mass", "CG", "Newton", "auto"};
    printf("gfmd %s: the study's continuing loads (Persson A/A0 = 0.008 ... 0.4 after the first load 0.004), "
           "layers on a fluid foundation (w = 4 W a), H = %g, lambda_s = %ga, lambda_r = n a/%g, seed %llu, "
           "%d thread(s), default tolerance%s\n", gfmd_version(), substrate_hurst, substrate_lambda_s, substrate_ratio,
           (unsigned long long)substrate_seed, threads, adhesion ? ", adhesion gamma0 = 5e-4, rho = a" : "");
    if (from > 0.0) printf("the loads below Persson's A/A0 = %g relaxed once by the default, untimed; the columns from there\n", from);
    if (to < 1.0) printf("the loads up to Persson's A/A0 = %g only\n", to);
    printf("%5s %7s %9s |", "n", "W", "f(qmin w)");
    for (int k = 0; k < SWEEP_SOLVERS; ++k) printf(" %7s %8s %8s |", heads[k], "s", "A/A0");
    printf(" %-14s\n", "auto chose");
    for (int a = 0; a < nsizes; ++a)
        for (int b = 0; b < nwidths; ++b) {
            const int n = (int)sizes[a];
            const double W = widths[b];
            gfmd_sim *s = bench_body(n, W, 0.01, GFMD_SOLVER_AUTO);
            int32_t st = gfmd_set_threads(s, threads);
            if (st == GFMD_OK && adhesion) st = gfmd_set_adhesion(s, 5e-4, 1.0);
            double loads[SWEEP_LOADS];
            for (int k = 0; k < SWEEP_LOADS; ++k) loads[k] = persson_load(s, targets[k]);
            const double f = longest_wave_factor(GFMD_GREEN_LAYER_FLUID, n, W, 0.0);
            int64_t steps = 0, coarse = 0;
            if (st == GFMD_OK) st = gfmd_set_pressure(s, loads[0]);
            if (st == GFMD_OK)
                st = n >= 2048 ? gfmd_relax_multilevel(s, 0.0, 10000000, 4, &steps, &coarse)
                               : gfmd_relax(s, 0.0, 10000000, &steps);
            if (st != GFMD_OK) die(s, st, "first load");
            int first = 1; /* --from: the lower continuing loads once, by the default, untimed */
            for (; first < SWEEP_LOADS && targets[first] < from; ++first)
                if ((st = gfmd_set_pressure(s, loads[first])) != GFMD_OK ||
                    (st = gfmd_relax(s, 0.0, 10000000, &steps)) != GFMD_OK)
                    die(s, st, "a load below --from");
            int last = first; /* --to: the loads up to it only */
            while (last < SWEEP_LOADS && targets[last] <= to) ++last;
            if (first == last) {
                fprintf(stderr, "gfmd_bench: --from %g and --to %g leave no load to compare\n", from, to);
                return 1;
            }
            const int32_t solvers[SWEEP_SOLVERS] = {GFMD_SOLVER_FIRE, GFMD_SOLVER_APPROACH_THEN_FIRE, GFMD_SOLVER_MASS_WEIGHTED_FIRE,
                                                    GFMD_SOLVER_CG, GFMD_SOLVER_NEWTON, GFMD_SOLVER_AUTO};
            /* the default's choice at each load from this equilibrium (it depends on the body, the
             * load and whether the surface is flat, not on the solver's state, which every column
             * restarts on its clone): asked of s itself, its surface unchanged; where it is one
             * solver at every load and that solver has a column, the default is that column's
             * run, not run again */
            int32_t same = -1;
            int32_t asked[SWEEP_LOADS] = {0}; /* the choices asked of s (printed whether or not the auto column runs) */
            for (int l = first; l < last; ++l) {
                int32_t choice = -1;
                if ((st = gfmd_set_pressure(s, loads[l])) != GFMD_OK) die(s, st, "pressure");
                gfmd_get_solver(s, &choice);
                asked[l] = choice;
                same = l == first ? choice : same == choice ? same : -2;
            }
            sweep_run runs[SWEEP_SOLVERS];
            for (int k = 0; k < SWEEP_SOLVERS; ++k) {
                runs[k].total = -1;
                if (!(columns & (1 << k)) || (solvers[k] == GFMD_SOLVER_CG && !cg)) continue;
                for (int j = 0; j < k && solvers[k] == GFMD_SOLVER_AUTO; ++j)
                    if (runs[j].total >= 0 && solvers[j] == same) runs[k] = runs[j];
                if (runs[k].total < 0) runs[k] = sweep_continue(s, solvers[k], loads, first, last);
            }
            gfmd_sim_destroy(&s);
            char chose[64];
            sweep_choices(asked, first, last, chose, sizeof chose);
            printf("%5d %7g %9.3g |", n, W, f);
            for (int k = 0; k < SWEEP_SOLVERS; ++k)
                if (runs[k].total < 0)
                    printf(" %7s %8s %8s |", "-", "-", "-");
                else
                    printf(" %7lld %8.2f %8.5f |", runs[k].total, runs[k].seconds, runs[k].area);
            printf(" %-14s\n", chose);
            if (verbose)
                for (int k = 0; k < SWEEP_SOLVERS; ++k) {
                    if (runs[k].total < 0) continue;
                    printf("#   %-6s steps (s) per load:", heads[k]);
                    for (int l = first; l < last; ++l) printf(" %lld (%.2f)", runs[k].steps[l], runs[k].secs[l]);
                    printf("\n");
                }
            fflush(stdout);
            /* all stop at the default tolerance of the force residual, not in the same state: their
             * contact sets may differ by a few points (1 % is 40 points of 64^2 at A/A0 ~ 0.1) */
            int ref = 0; /* the first column run */
            while (ref < SWEEP_SOLVERS - 1 && runs[ref].total < 0) ++ref;
            for (int k = ref + 1; k < SWEEP_SOLVERS; ++k)
                if (runs[k].total >= 0 && !(fabs(runs[k].area - runs[ref].area) <= 0.01 * runs[ref].area)) {
                    fprintf(stderr, "gfmd_bench: the solvers disagree on A/A0 at the last load (%s %.5f, %s %.5f)\n",
                            heads[ref], runs[ref].area, heads[k], runs[k].area);
                    return 1;
                }
        }
    return 0;
}

/* --first-load: a thin sheet's first load from flat (the study's first load: Persson's A/A0 =
 * 0.004, or each of `areas`), without and with adhesion (gamma0 = 5e-4, rho = a), before and after each lever the
 * library has: FIRE (before), mass-weighted FIRE, the multilevel start (--levels, 3 unless given;
 * the default solver on each grid), the default solver, the CG (with adhesion the adhesive CG)
 * and the Newton method.  Steps and seconds to the default tolerance, and
 * (counted to the step, as in the main table: timed_relax_to) until A/A0 stays within 0.1 % of the
 * run's final value (the multilevel start: not counted, "-"); with --tol T every lever relaxes to
 * T instead and A/A0 is printed to 8 digits.  Mass-weighted FIRE is not run
 * with adhesion beyond 20 000 steps.  adhesive_only: the rows with adhesion only; levers: a bit
 * per lever to run (parse_levers), so that a 2048^2 comparison need not run all eight rows. */
enum { LEVERS = 6 };
static const char *const lever_names[LEVERS] = {"fire", "mass", "multilevel", "default", "cg", "newton"};
static const int32_t lever_solvers[LEVERS] = {GFMD_SOLVER_FIRE, GFMD_SOLVER_MASS_WEIGHTED_FIRE, GFMD_SOLVER_AUTO,
                                              GFMD_SOLVER_AUTO, GFMD_SOLVER_CG, GFMD_SOLVER_NEWTON};

/* --levers LIST (first_load_table's levers, lever_names) and --columns LIST (sweep_table's
 * columns, sweep_names): a bit per name, in the order of names[0..count); -1 for a name not there
 * or an empty list */
static int parse_names(const char *list, const char *const *names, int count) {
    int mask = 0;
    while (*list) {
        const char *end = strchr(list, ',');
        const size_t len = end ? (size_t)(end - list) : strlen(list);
        int bit = -1;
        for (int k = 0; k < count; ++k)
            if (strlen(names[k]) == len && !strncmp(list, names[k], len)) bit = k;
        if (bit < 0) return -1;
        mask |= 1 << bit;
        list += len + (end ? 1 : 0);
    }
    return mask > 0 ? mask : -1;
}

static int first_load_table(const double *sizes, int nsizes, const double *widths, int nwidths, int threads,
                            int levels, double tol, int adhesive_only, int plain_only, int levers,
                            const double *areas, int nareas) {
    const int digits = tol > 0.0 ? 8 : 5;
    if (!(tol > 0.0)) tol = GFMD_DEFAULT_TOL;
    printf("gfmd %s: a thin sheet's first load from flat at Persson's A/A0 (P), fluid foundation (w = 4 W a), "
           "H = 0.8, lambda_s = 4a, lambda_r = n a/8, g = 1, seed 2016, %d thread(s), tol %.0e\n",
           gfmd_version(), threads, tol);
    printf("%5s %6s %7s %4s %-13s | %8s | %7s %8s | %7s %8s | %s\n", "n", "P", "W", "adh", "lever", "A/A0", "steps", "s",
           "to 0.1%", "s", "/hs");
    for (int a = 0; a < nsizes; ++a)
    for (int pa = 0; pa < nareas; ++pa) {
        const double persson = areas[pa];
        /* the reference: a half-space on the same substrate and grid at the same Persson A/A0, by
         * the default, from flat (W = 0 rows); "/hs" is each row's seconds over its one */
        double hs[2] = {0.0, 0.0};
        for (int adh = adhesive_only; adh < (plain_only ? 1 : 2); ++adh) {
            const int n = (int)sizes[a];
            gfmd_sim *s = bench_body(n, 0.0, 0.01, GFMD_SOLVER_AUTO);
            int32_t st = gfmd_set_threads(s, threads);
            if (st == GFMD_OK && adh) st = gfmd_set_adhesion(s, 5e-4, 1.0);
            const double load = persson_load(s, persson);
            if (st == GFMD_OK) st = gfmd_reset(s);
            if (st != GFMD_OK) die(s, st, "first-load half-space");
            const gfmd_run g = timed_relax_to(s, GFMD_SOLVER_AUTO, load, NAN, tol, 4000000);
            double area = 0.0;
            gfmd_get_contact_area(s, &area);
            hs[adh] = g.seconds;
            char what[32];
            snprintf(what, sizeof what, "hs %s", solver_name(g.active));
            printf("%5d %6g %7g %4s %-13s | %8.*f | %7lld %8.2f | %7s %8s | %.2f\n", n, persson, 0.0, adh ? "yes" : "no",
                   what, digits, area, (long long)g.steps, g.seconds, "-", "-", 1.0);
            fflush(stdout);
            gfmd_sim_destroy(&s);
        }
        for (int b = 0; b < nwidths; ++b)
            for (int adh = adhesive_only; adh < (plain_only ? 1 : 2); ++adh)
                for (int lever = 0; lever < LEVERS; ++lever) {
                    if (!(levers & (1 << lever))) continue;
                    const int n = (int)sizes[a];
                    const int32_t solver = lever_solvers[lever];
                    gfmd_sim *s = bench_body(n, widths[b], 0.01, solver);
                    int32_t st = gfmd_set_threads(s, threads);
                    if (st == GFMD_OK && adh) st = gfmd_set_adhesion(s, 5e-4, 1.0);
                    const double load = persson_load(s, persson);
                    if (st == GFMD_OK) st = gfmd_reset(s);
                    if (st == GFMD_OK) st = gfmd_set_pressure(s, load);
                    if (st != GFMD_OK) die(s, st, "first-load body");
                    double area = 0.0, t = 0.0, t_acc = -1.0;
                    int64_t steps = 0, steps_acc = -1;
                    int converged = 1;
                    int32_t active = -1;
                    if (lever == 2) {
                        int64_t coarse = 0;
                        const double t0 = now();
                        st = gfmd_relax_multilevel(s, tol, 10000000, levels, &steps, &coarse);
                        t = now() - t0;
                        if (st != GFMD_OK) die(s, st, "relax_multilevel");
                        gfmd_get_solver(s, &active); /* the finest grid's, chosen for its interpolated start */
                        steps += coarse; /* coarse steps are cheaper, counted all the same */
                    } else {
                        /* "to 0.1 %": from the step after which A/A0 stays within 0.1 % of the run's last value */
                        const int64_t limit = (adh && lever == 1) ? 20000 : 4000000;
                        const gfmd_run g = timed_relax_to(s, solver, load, NAN, tol, limit);
                        steps = g.steps, steps_acc = g.steps_acc, t = g.seconds, t_acc = g.seconds_acc;
                        active = g.active, converged = g.converged;
                    }
                    gfmd_get_contact_area(s, &area);
                    char acc_steps[32] = "-", acc_s[32] = "-", total[32];
                    if (steps_acc >= 0) {
                        snprintf(acc_steps, sizeof acc_steps, "%lld", (long long)steps_acc);
                        snprintf(acc_s, sizeof acc_s, "%.2f", t_acc);
                    }
                    if (!converged) snprintf(total, sizeof total, ">%lld", (long long)steps);
                    else snprintf(total, sizeof total, "%lld", (long long)steps);
                    char what[32];
                    if (lever == 2) snprintf(what, sizeof what, "ml%d+%s", levels, solver_name(active));
                    else snprintf(what, sizeof what, "%s", solver_name(active));
                    printf("%5d %6g %7g %4s %-13s | %8.*f | %7s %8.2f | %7s %8s | %.1f\n", n, persson, widths[b],
                           adh ? "yes" : "no", what, digits, area, total, t, acc_steps, acc_s,
                           hs[adh] > 0.0 ? t / hs[adh] : 0.0);
                    fflush(stdout);
                    gfmd_sim_destroy(&s);
                }
    }
    return 0;
}

/* Two runs of one non-adhesive problem: A/A0 within two points, the mean pressure within 1e-4 of
 * its scale. */
static int same_equilibrium(int n, double area, double area_ref, double pressure, double pressure_ref) {
    const double scale = fabs(pressure_ref) + 1e-8;
    return fabs(area - area_ref) <= 2.0 / ((double)n * n) && fabs(pressure - pressure_ref) <= 1e-4 * scale;
}

/* The n x n substrate of s, malloc'd (the caller frees it). */
static double *heights_of(gfmd_sim *s, int n) {
    double *h = malloc((size_t)n * (size_t)n * sizeof *h);
    if (h == NULL) die(s, GFMD_ERR_NOMEM, "heights");
    const int32_t st = gfmd_get_heights(s, h);
    if (st != GFMD_OK) die(s, st, "heights");
    return h;
}

/* The mean and rms of the np heights h. */
static void height_stats(const double *h, size_t np, double *mean, double *rms) {
    double m = 0.0, m2 = 0.0;
    for (size_t i = 0; i < np; ++i) m += h[i];
    m /= (double)np;
    for (size_t i = 0; i < np; ++i) m2 += (h[i] - m) * (h[i] - m);
    *mean = m;
    *rms = sqrt(m2 / (double)np);
}

typedef struct {
    double below;      /* the mean position this far below the highest peak ... */
    double gap_rms;    /* ... or, if > 0, this many rms heights above the substrate's mean */
    int adhesive_only; /* --adhesion */
    int plain_only;    /* --no-adhesion */
    int positions;     /* --positions K: then K positions closer by 0.1 rms heights each */
    double nu;         /* bonded layers' Poisson ratio, NaN: layers on a fluid foundation */
} displacement_options;

/* K more mean positions, each 0.1 rms heights closer than the last and relaxed from its
 * equilibrium (a load sweep): the steps and seconds summed, the last position's A/A0 and mean
 * pressure. */
static void displacement_sweep(gfmd_sim *s, double mean, double rms, double gap_rms, int positions, int64_t *steps,
                               double *seconds, double *area, double *pressure) {
    *steps = 0;
    const double t0 = now();
    for (int j = 1; j <= positions; ++j) {
        int64_t k = 0;
        int32_t st = gfmd_set_mean_displacement(s, mean + (gap_rms - 0.1 * j) * rms);
        if (st == GFMD_OK) st = gfmd_relax(s, 0.0, 100000000, &k);
        if (st != GFMD_OK) die(s, st, "sweep");
        *steps += k;
    }
    *seconds = now() - t0;
    gfmd_get_contact_area(s, area);
    gfmd_get_mean_pressure(s, pressure);
}

/* --displacement: layers (on a fluid foundation, or bonded with Poisson's ratio nu unless nu is
 * NaN) and the half-space (W = 0) under displacement control from flat, to the default
 * tolerance, by FIRE, mass-weighted FIRE, the library's constrained CG (without adhesion: it
 * refuses adhesion; the reference CG of the other tables prescribes the pressure, not the
 * position) and the default. */
static int displacement_table(const double *sizes, int nsizes, const double *widths, int nwidths,
                              const displacement_options *o) {
    const double nu = o->nu, below = o->below, gap_rms = o->gap_rms;
    const int bonded = !isnan(nu);
    char where[96];
    if (gap_rms > 0.0) snprintf(where, sizeof where, "%g rms heights above the substrate's mean height", gap_rms);
    else snprintf(where, sizeof where, "%g a below the highest peak", below);
    printf("gfmd %s: displacement control from flat to the mean position %s, %s (w = 4 W a), "
           "H = 0.8, lambda_s = 4a, lambda_r = n a/8, g = 1, seed 2016, one thread, FFTW_MEASURE, tol %.0e; "
           "adhesion gamma0 = 5e-4, rho = 1\n",
           gfmd_version(), where, bonded ? "layers bonded to a rigid base" : "layers on a fluid foundation",
           GFMD_DEFAULT_TOL);
    if (bonded) printf("bonded layers: nu = %g\n", nu);
    if (o->positions > 0)
        printf("then %d positions, each 0.1 rms heights closer, relaxed from the last (the rows '+%d pos': steps and "
               "seconds summed, A/A0 and mean pressure of the last)\n", o->positions, o->positions);
    printf("%5s %7s %4s %-9s | %8s %8s | %9s %14s\n", "n", "W", "adh", "solver", "steps", "s", "A/A0", "mean pressure");
    enum { kSolvers = 4 };
    const int32_t solvers[kSolvers] = {GFMD_SOLVER_FIRE, GFMD_SOLVER_MASS_WEIGHTED_FIRE, GFMD_SOLVER_CG, GFMD_SOLVER_AUTO};
    int bad = 0;
    for (int a = 0; a < nsizes; ++a)
        for (int b = 0; b < nwidths; ++b)
            for (int adh = o->adhesive_only; adh < (o->plain_only ? 1 : 2); ++adh) {
                double area[kSolvers], pressure[kSolvers], last_area[kSolvers], last_pressure[kSolvers];
                for (int k = 0; k < kSolvers; ++k) {
                    if (adh && solvers[k] == GFMD_SOLVER_CG) continue;
                    const int n = (int)sizes[a];
                    const double W = widths[b];
                    gfmd_sim *s = bench_body(n, bonded ? 0.0 : W, 0.05, solvers[k]);
                    int32_t st = GFMD_OK;
                    if (bonded && W > 0) {
                        st = gfmd_set_poisson(s, nu);
                        if (st == GFMD_OK) st = gfmd_set_green(s, GFMD_GREEN_LAYER_BONDED, W * 4.0);
                    }
                    if (st == GFMD_OK && adh) st = gfmd_set_adhesion(s, 5e-4, 1.0);
                    double mean = 0.0, rms = 0.0;
                    if (gap_rms > 0.0) {
                        double *h = heights_of(s, n);
                        height_stats(h, (size_t)n * (size_t)n, &mean, &rms);
                        free(h);
                    }
                    if (st == GFMD_OK) st = gfmd_set_mean_displacement(s, gap_rms > 0.0 ? mean + gap_rms * rms : -below);
                    if (st != GFMD_OK) die(s, st, "displacement body");
                    int32_t active = -1;
                    gfmd_get_solver(s, &active);
                    int64_t steps = 0;
                    const double t0 = now();
                    if ((st = gfmd_relax(s, 0.0, 100000000, &steps)) != GFMD_OK) die(s, st, "relax");
                    const double t = now() - t0;
                    gfmd_get_contact_area(s, &area[k]);
                    gfmd_get_mean_pressure(s, &pressure[k]);
                    char what[32];
                    snprintf(what, sizeof what, "%s%s", solvers[k] == GFMD_SOLVER_AUTO ? "auto:" : "", solver_name(active));
                    printf("%5d %7g %4s %-9s | %8lld %8.2f | %9.6f %14.6e\n", n, W, adh ? "yes" : "no", what,
                           (long long)steps, t, area[k], pressure[k]);
                    fflush(stdout);
                    if (o->positions > 0) {
                        int64_t sweep_steps = 0;
                        double sweep_s = 0.0;
                        displacement_sweep(s, mean, rms, gap_rms, o->positions, &sweep_steps, &sweep_s, &last_area[k],
                                           &last_pressure[k]);
                        char label[16];
                        snprintf(label, sizeof label, "+%d pos", o->positions);
                        printf("%5d %7g %4s %-9s | %8lld %8.2f | %9.6f %14.6e\n", n, W, adh ? "yes" : "no", label,
                               (long long)sweep_steps, sweep_s, last_area[k], last_pressure[k]);
                        fflush(stdout);
                    }
                    if (k > 0 && !adh) { /* one equilibrium without adhesion, at each position */
                        int disagree = !same_equilibrium(n, area[k], area[0], pressure[k], pressure[0]);
                        if (o->positions > 0)
                            disagree |= !same_equilibrium(n, last_area[k], last_area[0], last_pressure[k], last_pressure[0]);
                        if (disagree) {
                            printf("  the runs disagree\n");
                            bad = 1;
                        }
                    }
                    gfmd_sim_destroy(&s);
                }
            }
    return bad;
}

/* The fraction of the np heights h above the height m (the points above it counted). */
static double fraction_above(const double *h, size_t np, double m) {
    size_t above = 0;
    for (size_t i = 0; i < np; ++i) above += h[i] > m;
    return (double)above / (double)np;
}

/* --choices: what the default's rule reads and what it chooses, nothing relaxed.  For each body
 * (a layer on a fluid foundation, bonded with --bonded NU, W = 0 the half-space) its long-wave
 * softness S = k_halfspace(q_max)/k(q_min) = (q_max/q_min) f(q_min w) and f(q_min w); at each
 * load (pressure control, without adhesion) Persson's A/A0, A/A0 sqrt(N), S A/A0 and the choice;
 * at each mean position (--gaps: G rms heights above the substrate's mean height; displacement
 * control) the fraction of the substrate above it and the choice without and with adhesion
 * (gamma0 = 5e-4, rho = 1). */
static int choices_table(const double *sizes, int nsizes, const double *widths, int nwidths, double nu,
                         const double *loads, int nloads, const double *gaps, int ngaps) {
    const int bonded = !isnan(nu);
    const int32_t layer = bonded ? GFMD_GREEN_LAYER_BONDED : GFMD_GREEN_LAYER_FLUID;
    printf("gfmd %s: the default's choices from flat, %s (w = 4 W a), H = 0.8, lambda_s = 4a, lambda_r = n a/8, "
           "g = 1, seed 2016\n", gfmd_version(), bonded ? "layers bonded to a rigid base" : "layers on a fluid foundation");
    if (bonded) printf("bonded layers: nu = %g\n", nu);
    printf("%5s %7s %9s %9s | %-12s %9s %9s %9s %-6s\n", "n", "W", "f(qmin w)", "S", "load", "A/A0 or", "A sqrtN",
           "S A", "choice");
    for (int a = 0; a < nsizes; ++a)
        for (int b = 0; b < nwidths; ++b) {
            const int n = (int)sizes[a];
            const double W = widths[b], f = longest_wave_factor(layer, n, W, bonded ? nu : 0.0);
            const double S = sqrt(2.0) * n / 2.0 * f; /* q_max/q_min = sqrt(2) pi/(2 pi/n) */
            gfmd_sim *s = NULL;
            int32_t st = gfmd_sim_create_ex(n, n, n, n, 1, GFMD_PLANNER_ESTIMATE, &s);
            if (st != GFMD_OK) die(NULL, st, "create");
            if ((st = gfmd_generate_selfaffine(s, 0.8, n / 8.0, 4.0, 1.0, 2016, GFMD_DIST_UNIFORM)) != GFMD_OK)
                die(s, st, "substrate");
            if (bonded && (st = gfmd_set_poisson(s, nu)) != GFMD_OK) die(s, st, "poisson");
            if (W > 0 && (st = gfmd_set_green(s, layer, W * 4.0)) != GFMD_OK) die(s, st, "green");
            for (int c = 0; c < nloads; ++c) {
                double area = 0.0;
                int32_t choice = -1;
                if ((st = gfmd_set_pressure(s, loads[c])) != GFMD_OK) die(s, st, "pressure");
                gfmd_persson_contact_area(s, loads[c], &area);
                gfmd_get_solver(s, &choice);
                char what[16];
                snprintf(what, sizeof what, "sigma0 %g", loads[c]);
                printf("%5d %7g %9.3g %9.3g | %-12s %9.4f %9.3g %9.3g %-6s\n", n, W, f, S, what, area, area * n,
                       S * area, solver_name(choice));
            }
            if (ngaps > 0) {
                double mean = 0.0, rms = 0.0, *h = heights_of(s, n);
                const size_t np = (size_t)n * (size_t)n;
                height_stats(h, np, &mean, &rms);
                for (int c = 0; c < ngaps; ++c) {
                    int32_t plain = -1, sticky = -1;
                    if ((st = gfmd_set_mean_displacement(s, mean + gaps[c] * rms)) != GFMD_OK) die(s, st, "displacement");
                    gfmd_get_solver(s, &plain);
                    if ((st = gfmd_set_adhesion(s, 5e-4, 1.0)) != GFMD_OK) die(s, st, "adhesion");
                    gfmd_get_solver(s, &sticky);
                    if ((st = gfmd_set_adhesion(s, 0.0, 1.0)) != GFMD_OK) die(s, st, "adhesion");
                    char what[16], chose[24];
                    snprintf(what, sizeof what, "gap %g rms", gaps[c]);
                    snprintf(chose, sizeof chose, "%s, adh. %s", solver_name(plain), solver_name(sticky));
                    printf("%5d %7g %9.3g %9.3g | %-12s %9.4f %9s %9s %s\n", n, W, f, S, what,
                           fraction_above(h, np, mean + gaps[c] * rms), "-", "-", chose);
                }
                free(h);
            }
            gfmd_sim_destroy(&s);
        }
    printf("(A/A0 or: Persson's A/A0 at a load; at a mean position the fraction of the substrate above it)\n");
    return 0;
}

/* --random: bodies drawn at random, none chosen by hand, so that the default's choice is timed
 * on bodies its rule was not measured on.  Each body, from a portable generator seeded by --seed:
 * the grid from --sizes; a half-space, a layer on a fluid foundation or a bonded one (w = 0.5a ...
 * 2000a log-uniform, nu = 0 ... 0.5); a self-affine substrate (H = 0.3 ... 1, lambda_s = 2, 4 or 8
 * a, lambda_r = 2 ... 16 lambda_s up to the cell, uniform or Gaussian, rms gradient 1); a load at
 * Persson's A/A0 = 0.001 ... 0.8 (log-uniform), under displacement control in a quarter of the
 * bodies (the mean position where that fraction of the substrate lies above, at least 0.05 rms
 * above its mean); adhesion in a third (gamma0 = g (0.05 sigma0 + 1e-4 E*) a, g = e^-2 ... e^2,
 * rho = a/2, a or 2a).  From flat to the default tolerance by the default and by every solver
 * that takes the body (FIRE, mass-weighted FIRE, the approach then FIRE, and the library's
 * constrained CG -- with adhesion under pressure control only -- which the main table's reference
 * CG did not beat on any half-space or bonded row of docs/performance.md), each on a clone of the same start, one thread; a run under 0.05 s is repeated up to five
 * times and its fastest kept.  Prints each body with the default's choice and the ratio of its
 * seconds to the fastest solver's, then the sums over the bodies (what one fixed solver for all of
 * them would have cost).  Without adhesion (one equilibrium) the runs must agree (A/A0 within
 * 0.1 % or two points, the mean pressure within 1e-4 of its scale): the program fails otherwise. */
enum { RANDOM_SOLVERS = 5 };
static const int32_t random_solvers[RANDOM_SOLVERS] = {GFMD_SOLVER_AUTO, GFMD_SOLVER_FIRE, GFMD_SOLVER_MASS_WEIGHTED_FIRE,
                                                       GFMD_SOLVER_APPROACH_THEN_FIRE, GFMD_SOLVER_CG};

/* splitmix64: the same bodies from a seed on every machine */
static double random_unit(uint64_t *state) {
    uint64_t z = (*state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}

static double random_log(uint64_t *state, double lo, double hi) {
    return exp(log(lo) + random_unit(state) * (log(hi) - log(lo)));
}

static int compare_doubles(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* seconds of one solver on a clone of start (the fastest of up to five runs under 0.05 s) */
static double random_run(const gfmd_sim *start, int32_t solver, int32_t *active, double *area, double *pressure) {
    double best = INFINITY;
    for (int rep = 0; rep < 5 && (rep == 0 || best < 0.05); ++rep) {
        gfmd_sim *s = NULL;
        int32_t st;
        if ((st = gfmd_sim_clone(start, &s)) != GFMD_OK) die(NULL, st, "clone");
        if ((st = gfmd_set_solver(s, solver)) != GFMD_OK) die(s, st, "solver");
        int64_t steps = 0;
        const double t0 = now();
        if ((st = gfmd_relax(s, 0.0, 10000000, &steps)) != GFMD_OK) die(s, st, "relax");
        const double t = now() - t0;
        best = t < best ? t : best;
        gfmd_get_solver(s, active);
        gfmd_get_contact_area(s, area);
        gfmd_get_mean_pressure(s, pressure);
        gfmd_sim_destroy(&s);
    }
    return best;
}

static int random_table(const double *sizes, int nsizes, int count, uint64_t seed) {
    static const char *const kinds[3] = {"half", "fluid", "bonded"};
    static const char *const heads[RANDOM_SOLVERS] = {"auto", "FIRE", "mass", "m+FIRE", "CG"};
    uint64_t rng = seed;
    double sums[2][RANDOM_SOLVERS + 1] = {{0}}; /* [adhesive][solver], the last: the fastest's */
    int bodies[2] = {0, 0}, within12 = 0, within15 = 0, failed = 0, worst_body = -1;
    double worst = 0.0;
    printf("gfmd %s benchmark: %d random bodies (seed %llu), one thread, FFTW_MEASURE, default tol %.0e; seconds "
           "from flat, '-': the solver does not take the body\n", gfmd_version(), count, (unsigned long long)seed,
           GFMD_DEFAULT_TOL);
    printf("%4s %5s %6s %8s %4s %4s %3s %4s %4s %8s %5s %3s | %-10s %8s | %8s %8s %8s %8s | %6s\n", "#", "n", "body",
           "w/a", "nu", "H", "ls", "lr", "dist", "Persson", "ctrl", "adh", "default", "s", "FIRE", "mass", "m+FIRE", "CG",
           "ratio");
    for (int b = 0; b < count; ++b) {
        const int n = (int)sizes[(int)(random_unit(&rng) * nsizes)];
        const int kind = (int)(random_unit(&rng) * 3.0);
        const double width = random_log(&rng, 0.5, 2000.0), nu = 0.5 * random_unit(&rng);
        const double hurst = 0.3 + 0.7 * random_unit(&rng);
        const double ls = (double)(2 << (int)(random_unit(&rng) * 3.0));
        double lr = ls * (double)(2 << (int)(random_unit(&rng) * 4.0));
        lr = lr > n ? n : lr;
        const int gaussian = random_unit(&rng) < 0.5;
        const double area = random_log(&rng, 1e-3, 0.8);
        const int displacement = random_unit(&rng) < 0.25, adhesive = random_unit(&rng) < 1.0 / 3.0;
        const double gfac = random_log(&rng, exp(-2.0), exp(2.0));
        const double rho = 0.5 * (double)(1 << (int)(random_unit(&rng) * 3.0));
        gfmd_sim *s = NULL;
        int32_t st;
        if ((st = gfmd_sim_create_ex(n, n, n, n, 1, GFMD_PLANNER_MEASURE, &s)) != GFMD_OK) die(NULL, st, "create");
        if ((st = gfmd_generate_selfaffine(s, hurst, lr, ls, 1.0, seed * 1000u + (uint64_t)b,
                                           gaussian ? GFMD_DIST_GAUSSIAN : GFMD_DIST_UNIFORM)) != GFMD_OK)
            die(s, st, "substrate");
        if (kind == 2 && (st = gfmd_set_poisson(s, nu)) != GFMD_OK) die(s, st, "poisson");
        if (kind > 0 && (st = gfmd_set_green(s, kind == 1 ? GFMD_GREEN_LAYER_FLUID : GFMD_GREEN_LAYER_BONDED, width)) != GFMD_OK)
            die(s, st, "green");
        const double sigma0 = persson_load(s, area);
        if (displacement) {
            const size_t np = (size_t)n * (size_t)n;
            double *h = heights_of(s, n), mean, rms;
            height_stats(h, np, &mean, &rms);
            qsort(h, np, sizeof *h, compare_doubles);
            double d = h[(size_t)((1.0 - area) * (double)(np - 1))];
            d = d > mean + 0.05 * rms ? d : mean + 0.05 * rms;
            free(h);
            if ((st = gfmd_set_mean_displacement(s, d)) != GFMD_OK) die(s, st, "mean displacement");
        } else if ((st = gfmd_set_pressure(s, sigma0)) != GFMD_OK)
            die(s, st, "pressure");
        if (adhesive && (st = gfmd_set_adhesion(s, gfac * (0.05 * sigma0 + 1e-4), rho)) != GFMD_OK) die(s, st, "adhesion");
        double secs[RANDOM_SOLVERS], areas[RANDOM_SOLVERS], pressures[RANDOM_SOLVERS];
        int32_t active[RANDOM_SOLVERS] = {0};
        double fastest = INFINITY;
        char cols[RANDOM_SOLVERS][16];
        for (int k = 0; k < RANDOM_SOLVERS; ++k) {
            secs[k] = NAN;
            snprintf(cols[k], sizeof cols[k], "-");
            if (adhesive && displacement && random_solvers[k] == GFMD_SOLVER_CG) continue;
            secs[k] = random_run(s, random_solvers[k], &active[k], &areas[k], &pressures[k]);
            snprintf(cols[k], sizeof cols[k], "%.3g", secs[k]);
            if (k > 0 && secs[k] < fastest) fastest = secs[k];
            /* at the default tolerance a point whose pressure or gap is that small may fall
             * either side of the contact line: on a long line (dense contacts, 1024^2) tens of
             * points, so A/A0 within the benchmark's 0.1 % (or two points) and the pressure as
             * same_equilibrium's */
            const double area_slack = fmax(1e-3 * fabs(areas[0]), 2.0 / ((double)n * n));
            if (!adhesive && k > 0 && !(fabs(areas[k] - areas[0]) <= area_slack &&
                                        same_equilibrium(n, areas[0], areas[0], pressures[k], pressures[0]))) {
                printf("body %d: %s and the default disagree: A/A0 %.8f against %.8f, pressure %.10g against %.10g\n", b,
                       heads[k], areas[k], areas[0], pressures[k], pressures[0]);
                failed = 1;
            }
        }
        gfmd_sim_destroy(&s);
        const double ratio = secs[0] / fastest;
        bodies[adhesive] += 1;
        for (int k = 0; k < RANDOM_SOLVERS; ++k)
            if (!isnan(secs[k])) sums[adhesive][k] += secs[k];
        sums[adhesive][RANDOM_SOLVERS] += fastest;
        within12 += ratio <= 1.2;
        within15 += ratio <= 1.5;
        if (ratio > worst) worst = ratio, worst_body = b;
        printf("%4d %5d %6s %8.3g %4.2f %4.2f %3.0f %4.0f %4s %8.2g %5s %3s | %-10s %8.3g | %8s %8s %8s %8s | %6.2f\n", b, n,
               kinds[kind], kind > 0 ? width : 0.0, nu, hurst, ls, lr, gaussian ? "gaus" : "unif", area,
               displacement ? "disp" : "pres", adhesive ? "yes" : "no", solver_name(active[0]), secs[0], cols[1], cols[2],
               cols[3], cols[4], ratio);
        fflush(stdout);
    }
    printf("the default within 1.2x of the fastest solver on %d of %d bodies, within 1.5x on %d; worst %.2fx (body %d)\n",
           within12, count, within15, worst, worst_body);
    for (int a = 0; a < 2; ++a) {
        if (bodies[a] == 0) continue;
        printf("seconds summed over the %d bodies %s adhesion: default %.3f, FIRE %.3f, mass %.3f, m+FIRE %.3f", bodies[a],
               a ? "with" : "without", sums[a][0], sums[a][1], sums[a][2], sums[a][3]);
        printf(", CG %.3f%s", sums[a][4], a ? " (under pressure control)" : "");
        printf("; the fastest of each body %.3f\n", sums[a][RANDOM_SOLVERS]);
    }
    return failed;
}

/* --big: one point at 4096^2 (or --sizes), a W = 1 layer on a fluid foundation from flat to the
 * default tolerance with the default solver, on --threads threads (default 2): planning and
 * relaxation timed apart. */
static int big_point(const double *sizes, int nsizes, double sigma0, int threads) {
    for (int a = 0; a < nsizes; ++a)
        for (int levels = 1; levels <= 3; levels += 2) {
            const int n = (int)sizes[a];
            const double l = n, t0 = now();
            gfmd_sim *s = NULL;
            int32_t st = gfmd_sim_create_ex(n, n, l, l, threads, GFMD_PLANNER_MEASURE, &s);
            if (st != GFMD_OK) die(NULL, st, "create");
            const double t_create = now() - t0;
            if ((st = gfmd_generate_selfaffine(s, 0.8, l / 8.0, 4.0, 1.0, 2016, GFMD_DIST_UNIFORM)) != GFMD_OK)
                die(s, st, "substrate");
            if ((st = gfmd_set_green(s, GFMD_GREEN_LAYER_FLUID, 4.0)) != GFMD_OK) die(s, st, "green");
            if ((st = gfmd_set_pressure(s, sigma0)) != GFMD_OK) die(s, st, "pressure");
            int32_t active = -1;
            gfmd_get_solver(s, &active);
            int64_t steps = 0, coarse = 0;
            const double t1 = now();
            if ((st = gfmd_relax_multilevel(s, 0.0, 10000000, levels, &steps, &coarse)) != GFMD_OK) die(s, st, "relax");
            const double t_relax = now() - t1;
            double area = 0.0;
            gfmd_get_contact_area(s, &area);
            printf("big point: %d x %d, W = 1 on a fluid foundation, sigma0 = %g, %d threads, solver %s, %s: A/A0 = %.4f, "
                   "%lld steps (+%lld on coarser grids), relax %.1f s (plan + create %.1f s)\n",
                   n, n, sigma0, threads, solver_name(active),
                   levels == 1 ? "from flat" : "multilevel start (3 levels)", area, (long long)steps, (long long)coarse,
                   t_relax, t_create);
            fflush(stdout);
            gfmd_sim_destroy(&s);
        }
    return 0;
}

static int contention_table(const double *sizes, int nsizes) {
    gfmd_sim *probe = NULL;
    int32_t def = 0;
    if (gfmd_sim_create_ex(8, 8, 8.0, 8.0, 0, GFMD_PLANNER_ESTIMATE, &probe) != GFMD_OK ||
        gfmd_get_threads(probe, &def) != GFMD_OK)
        die(probe, GFMD_ERR_INTERNAL, "default threads");
    gfmd_sim_destroy(&probe);
    printf("gfmd %s: threads on a shared machine; half-space, seed 1, sigma0 = 0.05, FFTW_MEASURE; default = %d "
           "thread(s)\n", gfmd_version(), (int)def);
    printf("%5s %7s | %6s | %9s %9s | %9s %9s | %s\n", "n", "threads", "steps", "quiet: create", "relax",
           "busy core: create", "relax", "relax / 1-thread relax (quiet, busy)");
    for (int a = 0; a < nsizes; ++a) {
        const int n = (int)sizes[a];
        double tc[2][2], tr[2][2];
        long long steps[2][2];
        for (int busy = 0; busy < 2; ++busy) {
            const pid_t competitor = busy ? start_competitor() : -1;
            for (int c = 0; c < 2; ++c) create_and_relax(n, c == 0 ? 1 : 0, &tc[c][busy], &tr[c][busy], &steps[c][busy]);
            stop_competitor(competitor);
        }
        for (int c = 0; c < 2; ++c)
            printf("%5d %7s | %6lld | %13.3f %9.3f | %17.3f %9.3f | %.2f, %.2f\n", n, c == 0 ? "1" : "default",
                   steps[c][0], tc[c][0], tr[c][0], tc[c][1], tr[c][1], tr[c][0] / tr[0][0], tr[c][1] / tr[0][1]);
        fflush(stdout);
    }
    return 0;
}

int main(int argc, char **argv) {
    double sizes[8] = {256, 512, 1024, 2048}, widths[8] = {0, 0.5, 1, 4};
    int nsizes = 4, nwidths = 4, threads = 1, cg = 1, alt = 1, contention = 0, multilevel = 0, nloads = 0, big = 0,
        first_load = 0, sweep = 0, displacement = 0, verbose = 0, from_given = 0, to_given = 0, threads_given = 0, sizes_given = 0, widths_given = 0, sigma0_given = 0, adhesion = 0,
        no_adhesion = 0;
    double gap_rms = 0.0;
    int below_given = 0, positions = 0;
    double loads[8], choice_loads[8], gaps[8], areas[8] = {0.004};
    int nareas = 1;
    int choices = 0, nchoice_loads = 0, ngaps = 0, random_bodies = 0;
    unsigned long long random_seed = 1;
    double cg_seconds = 120.0, sigma0 = 0.05, bonded_nu = NAN, first_tol = 0.0, sweep_from = 0.0, sweep_to = 1.0, below = 1.0;
    int levels = 3, levers = 15, columns = 63, substrate_given = 0, free_mode = 0;
    int32_t solver = GFMD_SOLVER_AUTO;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--sizes") && i + 1 < argc) nsizes = parse_list(argv[++i], sizes, 7), sizes_given = 1;
        else if (!strcmp(argv[i], "--big")) big = 1;
        else if (!strcmp(argv[i], "--first-load")) first_load = 1;
        else if (!strcmp(argv[i], "--sweep")) sweep = 1;
        else if (!strcmp(argv[i], "--displacement")) displacement = 1;
        else if (!strcmp(argv[i], "--below") && i + 1 < argc) below = atof(argv[++i]), below_given = 1;
        else if (!strcmp(argv[i], "--positions") && i + 1 < argc) positions = atoi(argv[++i]), positions = positions > 0 ? positions : -1;
        else if (!strcmp(argv[i], "--gap") && i + 1 < argc) gap_rms = atof(argv[++i]), gap_rms = gap_rms > 0.0 ? gap_rms : -1.0;
        else if (!strcmp(argv[i], "--verbose")) verbose = 1;
        else if (!strcmp(argv[i], "--from") && i + 1 < argc) sweep_from = atof(argv[++i]), from_given = 1;
        else if (!strcmp(argv[i], "--to") && i + 1 < argc) sweep_to = atof(argv[++i]), to_given = 1;
        else if (!strcmp(argv[i], "--levels") && i + 1 < argc) levels = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--columns") && i + 1 < argc) columns = parse_names(argv[++i], sweep_names, SWEEP_SOLVERS);
        else if (!strcmp(argv[i], "--substrate") && i + 1 < argc) {
            double v[5] = {0}; /* room for a fifth number, which is refused */
            const int k = parse_list(argv[++i], v, 5);
            substrate_given = 1;
            if (k != 4 || !(v[0] > 0.0 && v[0] <= 1.0) || !(v[1] >= 2.0) || !(v[2] >= 1.0) || !(v[3] >= 0.0 && v[3] < 1e15) ||
                v[3] != floor(v[3]))
                substrate_given = -1;
            else
                substrate_hurst = v[0], substrate_lambda_s = v[1], substrate_ratio = v[2], substrate_seed = (uint64_t)v[3];
        }
        else if (!strcmp(argv[i], "--levers") && i + 1 < argc) levers = parse_names(argv[++i], lever_names, LEVERS);
        else if (!strcmp(argv[i], "--areas") && i + 1 < argc) nareas = parse_list(argv[++i], areas, 8);
        else if (!strcmp(argv[i], "--tol") && i + 1 < argc) first_tol = atof(argv[++i]), first_tol = first_tol > 0.0 ? first_tol : -1.0;
        else if (!strcmp(argv[i], "--widths") && i + 1 < argc) nwidths = parse_list(argv[++i], widths, 8), widths_given = 1;
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) threads = atoi(argv[++i]), threads_given = 1;
        else if (!strcmp(argv[i], "--cg-seconds") && i + 1 < argc) cg_seconds = atof(argv[++i]);
        else if (!strcmp(argv[i], "--no-cg")) cg = 0;
        else if (!strcmp(argv[i], "--no-alt")) alt = 0;
        else if (!strcmp(argv[i], "--contention")) contention = 1;
        else if (!strcmp(argv[i], "--loads") && i + 1 < argc) nloads = parse_list(argv[++i], loads, 8);
        else if (!strcmp(argv[i], "--choices") && i + 1 < argc) nchoice_loads = parse_list(argv[++i], choice_loads, 8), choices = 1;
        else if (!strcmp(argv[i], "--gaps") && i + 1 < argc) ngaps = parse_list(argv[++i], gaps, 8);
        else if (!strcmp(argv[i], "--multilevel")) multilevel = 1;
        else if (!strcmp(argv[i], "--free")) free_mode = 1;
        else if (!strcmp(argv[i], "--random") && i + 1 < argc) random_bodies = atoi(argv[++i]), random_bodies = random_bodies > 0 ? random_bodies : -1;
        else if (!strcmp(argv[i], "--seed") && i + 1 < argc) random_seed = strtoull(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--adhesion")) adhesion = 1;
        else if (!strcmp(argv[i], "--no-adhesion")) no_adhesion = 1;
        else if (!strcmp(argv[i], "--bonded") && i + 1 < argc) bonded_nu = atof(argv[++i]);
        else if (!strcmp(argv[i], "--sigma0") && i + 1 < argc) sigma0 = atof(argv[++i]), sigma0_given = 1;
        else if (!strcmp(argv[i], "--solver") && i + 1 < argc) {
            ++i;
            solver = !strcmp(argv[i], "mass") ? GFMD_SOLVER_MASS_WEIGHTED_FIRE : !strcmp(argv[i], "verlet") ? GFMD_SOLVER_VERLET
                   : !strcmp(argv[i], "fire") ? GFMD_SOLVER_FIRE : !strcmp(argv[i], "cg") ? GFMD_SOLVER_CG
                   : !strcmp(argv[i], "auto") ? GFMD_SOLVER_AUTO : !strcmp(argv[i], "mass+fire") ? GFMD_SOLVER_APPROACH_THEN_FIRE : -1;
        } else
            solver = -1;
        if (solver < 0 || !(sigma0 > 0.0) || levels < 1 || first_tol < 0.0 || levers < 0 || columns < 0 || random_bodies < 0 || !(below >= 0.0) || gap_rms < 0.0 || positions < 0) {
            fprintf(stderr, "usage: %s [--sizes 256,512,...] [--big] [--widths 0,0.5,1,4] [--threads N] "
                            "[--cg-seconds S] [--no-cg] [--no-alt] [--sigma0 S] [--solver auto|fire|mass|mass+fire|verlet|cg] "
                            "[--bonded NU] [--adhesion] | --contention | --sweep [--verbose] [--from A] [--to A] [--columns fire,m+fire,mass,cg,newton,auto] [--substrate H,LS,R,SEED] | --loads L,.. | --choices L,.. [--gaps G,..] | --multilevel | --first-load [--levels L] [--tol T] [--levers fire,mass,multilevel,default,cg,newton] [--areas A,..] [--adhesion | --no-adhesion] | --big | --displacement [--below B | --gap R [--positions K]] [--no-adhesion] [--bonded NU] | --random K [--seed S]\n", argv[0]);
            return 2;
        }
    }
    if (substrate_given && (substrate_given < 0 || !sweep)) {
        fprintf(stderr, "gfmd_bench: --substrate H,LS,R,SEED (with --sweep only) takes 0 < H <= 1, lambda_s = LS >= 2 "
                        "(in a), lambda_r = n a/R with R >= 1, an integer seed >= 0\n");
        return 2;
    }
    if (adhesion && no_adhesion) { /* in every mode that reads them (--first-load, --displacement) */
        fprintf(stderr, "gfmd_bench: --adhesion and --no-adhesion exclude each other\n");
        return 2;
    }
    if (contention) return contention_table(sizes, nsizes);
    if (random_bodies > 0) {
        const double random_sizes[2] = {128, 256};
        return random_table(sizes_given ? sizes : random_sizes, sizes_given ? nsizes : 2, random_bodies, random_seed);
    }
    if (big) {
        const double big_size[1] = {4096};
        /* sigma0 = 0.025 gives A/A0 ~ 0.1 on this body (0.118 at 0.03, 512^2) */
        return big_point(sizes_given ? sizes : big_size, sizes_given ? nsizes : 1, sigma0_given ? sigma0 : 0.025,
                         threads_given ? threads : 2);
    }
    if (choices) {
        int bad = !isnan(bonded_nu) && !(bonded_nu > -1.0 && bonded_nu <= 0.5);
        for (int c = 0; c < nchoice_loads; ++c) bad |= !(choice_loads[c] > 0.0);
        for (int c = 0; c < ngaps; ++c) bad |= !(gaps[c] > 0.0);
        if (bad || nchoice_loads == 0) {
            fprintf(stderr, "gfmd_bench: --choices takes loads > 0 (--gaps: positions > 0 rms), --bonded a Poisson ratio in (-1, 0.5]\n");
            return 2;
        }
        return choices_table(sizes, nsizes, widths, nwidths, bonded_nu, choice_loads, nchoice_loads, gaps, ngaps);
    }
    if (first_load) {
        const double thin[2] = {0.0625, 0.25}, first_sizes[3] = {512, 1024, 2048};
        int bad = nareas < 1;
        for (int c = 0; c < nareas; ++c) bad |= !(areas[c] > 0.0 && areas[c] < 1.0);
        if (bad) {
            fprintf(stderr, "gfmd_bench: --areas takes Persson's A/A0 values in (0, 1)\n");
            return 2;
        }
        return first_load_table(sizes_given ? sizes : first_sizes, sizes_given ? nsizes : 3, widths_given ? widths : thin,
                                widths_given ? nwidths : 2, threads < 1 ? 1 : threads, levels, first_tol, adhesion,
                                no_adhesion, levers, areas, nareas);
    }
    if (displacement) {
        const double disp_sizes[1] = {256}, disp_widths[6] = {0.25, 1, 4, 8, 16, 0};
        if (!isnan(bonded_nu) && !(bonded_nu > -1.0 && bonded_nu <= 0.5)) {
            fprintf(stderr, "gfmd_bench: --bonded needs a Poisson ratio in (-1, 0.5]\n");
            return 2;
        }
        if (below_given && gap_rms > 0.0) {
            fprintf(stderr, "gfmd_bench: --below and --gap exclude each other (two ways to set the mean position)\n");
            return 2;
        }
        if (positions > 0 && !(gap_rms - 0.1 * positions > 0.0)) {
            fprintf(stderr, "gfmd_bench: --positions K needs --gap R with R > 0.1 K (the last position above the "
                            "substrate's mean height)\n");
            return 2;
        }
        const displacement_options options = {below, gap_rms, adhesion, no_adhesion, positions, bonded_nu};
        return displacement_table(sizes_given ? sizes : disp_sizes, sizes_given ? nsizes : 1,
                                  widths_given ? widths : disp_widths, widths_given ? nwidths : 6, &options);
    }
    if (from_given && !(sweep_from > 0.0 && sweep_from <= 0.4)) {
        fprintf(stderr, "gfmd_bench: --from takes a Persson area in (0, 0.4]\n");
        return 2;
    }
    if (to_given && !(sweep_to >= 0.008 && sweep_to <= 0.4 && sweep_to >= sweep_from)) {
        fprintf(stderr, "gfmd_bench: --to takes a Persson area in [0.008, 0.4], not below --from\n");
        return 2;
    }
    if (sweep) {
        const double sweep_sizes[1] = {2048}, sweep_widths[3] = {0.25, 1, 100};
        return sweep_table(sizes_given ? sizes : sweep_sizes, sizes_given ? nsizes : 1,
                           widths_given ? widths : sweep_widths, widths_given ? nwidths : 3, threads < 1 ? 1 : threads, adhesion, cg,
                           verbose, sweep_from, sweep_to, columns);
    }
    if (free_mode) {
        const double free_sizes[2] = {256, 512}, free_loads[2] = {0.05, 0.2};
        return free_table(sizes_given ? sizes : free_sizes, sizes_given ? nsizes : 2, nloads > 0 ? loads : free_loads,
                          nloads > 0 ? nloads : 2);
    }
    if (nloads > 0) return loads_table(sizes, nsizes, widths, nwidths, loads, nloads);
    if (multilevel) return multilevel_table(sizes, nsizes, widths, nwidths, sigma0, solver);
    const int32_t layer = isnan(bonded_nu) ? GFMD_GREEN_LAYER_FLUID : GFMD_GREEN_LAYER_BONDED;
    if (layer == GFMD_GREEN_LAYER_BONDED && !(bonded_nu > -1.0 && bonded_nu <= 0.5)) {
        fprintf(stderr, "gfmd_bench: --bonded needs a Poisson ratio in (-1, 0.5]\n");
        return 2;
    }
    if (threads < 1) threads = 1;
    /* the study's adhesion (gamma0 = 5e-4 E* a, rho = a): neither CG takes it, so no CG columns */
    if (adhesion) cg = 0, alt = 0;
    printf("gfmd %s benchmark: H = 0.8, lambda_s = 4a, lambda_r = n a/8, g = 1, E* = 1, sigma0 = %g, "
           "%d thread(s), FFTW_MEASURE, default tol %.0e, solver %s\n", gfmd_version(), sigma0,
           threads, GFMD_DEFAULT_TOL, solver_name(solver));
    if (adhesion) printf("with adhesion: gamma0 = 5e-4, rho = 1 (no CG columns: neither CG takes adhesion)\n");
    if (layer == GFMD_GREEN_LAYER_BONDED)
        printf("layers (W > 0) bonded to a rigid base, nu = %g, w = 4 W a\n", bonded_nu);
    else
        printf("layers (W > 0) on a fluid foundation, w = 4 W a\n");
    printf("%5s %5s %6s | %6s %8s %9s %9s %6s | %8s | %6s %8s | %8s | %7s %8s | %8s | %7s %6s\n", "n", "W", "solver",
           "steps", "seconds", "s/step", "fft", "ratio", "A/A0", "steps", "s", "other s", "CG its", "CG s", "speedup",
           "peak MB", "B/pt");
    printf("%5s %5s %6s | %-43s | %8s | %-15s | %8s | %-16s | %8s | %14s\n", "", "", "", "GFMD to the default tolerance",
           "", "GFMD to 0.1 %", "to 0.1 %", "reference CG to 0.1 %", "", "memory");
    for (int a = 0; a < nsizes; ++a) {
        const int n = (int)sizes[a];
        const double l = n;
        pair_timer pairs;
        pair_init(&pairs, n, threads);
        for (int b = 0; b < nwidths; ++b) {
            const double W = widths[b];
            gfmd_sim *s = NULL;
            int32_t st;
            int64_t more = 0;
            reset_peak();
            const double base_kb = read_status_kb("VmRSS:");
            if ((st = gfmd_sim_create(n, n, l, l, &s)) != GFMD_OK) die(NULL, st, "create");
            if ((st = gfmd_set_threads(s, threads)) != GFMD_OK) die(s, st, "threads");
            if ((st = gfmd_generate_selfaffine(s, 0.8, l / 8.0, 4.0, 1.0, 2016, GFMD_DIST_UNIFORM)) != GFMD_OK)
                die(s, st, "substrate");
            if (W > 0 && layer == GFMD_GREEN_LAYER_BONDED && (st = gfmd_set_poisson(s, bonded_nu)) != GFMD_OK)
                die(s, st, "poisson");
            if (W > 0 && (st = gfmd_set_green(s, layer, W * 4.0)) != GFMD_OK) die(s, st, "green");
            if (adhesion && (st = gfmd_set_adhesion(s, 5e-4, 1.0)) != GFMD_OK) die(s, st, "adhesion");
            if ((st = gfmd_set_solver(s, solver)) != GFMD_OK) die(s, st, "solver");
            if ((st = gfmd_set_pressure(s, sigma0)) != GFMD_OK) die(s, st, "pressure");
            /* the converged value, untimed, then the same start again */
            double area_conv = 0;
            if ((st = gfmd_relax(s, 1e-10, 10000000, &more)) != GFMD_OK) die(s, st, "relax to 1e-10");
            gfmd_get_contact_area(s, &area_conv);
            const double pair_before = pair_run(&pairs);
            const gfmd_run g = timed_relax(s, solver, sigma0, area_conv);
            const double t_pair = 0.5 * (pair_before + pair_run(&pairs));
            const double peak_mb = (read_status_kb("VmHWM:") - base_kb) / 1024.0;
            const int64_t steps = g.steps, steps_acc = g.steps_acc;
            const double t_gfmd = g.seconds, t_acc = g.seconds_acc;
            /* FFT pairs per step: mass weighting transforms the projected force as well; CG on the
             * pressure (half-space, bonded) convolves its direction and its pressure and evaluates
             * the forces every third iteration, CG on the surface (fluid foundation, under the
             * benchmark's pressure control) preconditions the force (one pair) and transforms its
             * direction forward */
            const double cg_pairs = (W > 0 && layer == GFMD_GREEN_LAYER_FLUID) ? 2.5 : 7.0 / 3.0;
            /* the approach then FIRE: its first (at most 100, gfmd_set_solver()) steps take two pairs */
            const double approach_pairs = 1.0 + (double)(steps < 100 ? steps : 100) / (double)(steps > 0 ? steps : 1);
            const double t_fft = t_pair * (g.active == GFMD_SOLVER_MASS_WEIGHTED_FIRE ? 2.0
                                           : g.active == GFMD_SOLVER_APPROACH_THEN_FIRE ? approach_pairs
                                           : g.active == GFMD_SOLVER_CG ? cg_pairs : 1.0);
            char other[32] = "-";
            if (alt && (g.active == GFMD_SOLVER_CG || g.active == GFMD_SOLVER_FIRE || g.active == GFMD_SOLVER_APPROACH_THEN_FIRE)) {
                const gfmd_run o = timed_relax(s, g.active == GFMD_SOLVER_FIRE ? GFMD_SOLVER_CG : GFMD_SOLVER_FIRE, sigma0,
                                               area_conv);
                snprintf(other, sizeof other, "%s %.3g", solver_name(o.active), o.seconds_acc);
            }
            double *h = NULL;
            cg_result r = {0, 0, 0, 0, 0, 0, -1, -1};
            if (cg) h = heights_of(s, n);
            gfmd_sim_destroy(&s);
            if (cg) {
                cg_options opt = {1e-12, 100000000, cg_seconds, threads, FFTW_MEASURE, area_conv, 1e-3};
                r = cg_solve_opts(n, n, l, l, h, W > 0 ? layer : GFMD_GREEN_HALFSPACE, W * 4.0,
                                  isnan(bonded_nu) ? 0.0 : bonded_nu, 1.0, sigma0, &opt, NULL, NULL);
                free(h);
            }
            char cg_its[32] = "-", cg_s[32] = "-", speed[32] = "-";
            if (cg && r.seconds_to_target >= 0.0) {
                snprintf(cg_its, sizeof cg_its, "%lld", (long long)r.iterations_to_target);
                snprintf(cg_s, sizeof cg_s, "%.3g", r.seconds_to_target);
                snprintf(speed, sizeof speed, "%.1fx", r.seconds_to_target / t_acc);
            } else if (cg) { /* never settled within the time limit: a lower bound */
                snprintf(cg_its, sizeof cg_its, ">%lld", (long long)r.iterations);
                snprintf(cg_s, sizeof cg_s, ">%.3g", r.seconds);
                snprintf(speed, sizeof speed, ">%.0fx", r.seconds / t_acc);
            }
            printf("%5d %5.2g %6s | %6lld %8.3f %9.2e %9.2e %6.2f | %8.5f | %6lld %8.3f | %8s | %7s %8s | %8s | %7.1f %6.1f\n",
                   n, W, solver_name(g.active), (long long)steps, t_gfmd, t_gfmd / (double)steps, t_fft, t_gfmd / (double)steps / t_fft,
                   area_conv, (long long)steps_acc, t_acc, other, cg_its, cg_s, speed, peak_mb,
                   peak_mb * 1048576.0 / ((double)n * (double)n));
            fflush(stdout);
        }
        pair_free(&pairs);
    }
    return 0;
}
