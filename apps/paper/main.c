/* The seed paper's study (Putignano, Dapp & Mueser, Biomimetics 1, 7 (2016)) with the library:
 * load sweeps of a half-space and of layers on a fluid foundation pressed onto one self-affine
 * substrate, the collapse factor c(W), the separation, and the adhesive energy ratio theta; with
 * --pulloff also the pull-off stress of each adhesive sheet (pulloff.c, Fig. 8).
 *
 *   gfmd_paper [--n N] [--bandwidth R] [--full | --quick] [--out DIR] [--seed S] [--threads T] [--jobs J]
 *              [--no-adhesion | --adhesion-only] [--widths 0,W1,W2,...] [--adh-widths W1,...] [--pulloff]
 *              [--solver auto|fire|mass|cg] [--multilevel LEVELS] [--approach STEPS] [--plan] [--resume]
 *
 * Surface: H = 0.8, lambda_s = 4a, lambda_r = R lambda_s, cell L = N a (default N = 256, R = 32,
 * L = 2 lambda_r; --full: N = 2048, R = 64, L = 8 lambda_r as in the paper; --quick, the test's
 * mode: N = 128, R = 16, half of the bodies; options after --full/--quick override), g = 1,
 * E* = 1, uniform random amplitudes.  Every load step continues from the last equilibrium.
 * --multilevel LEVELS: each body's first load relaxed first on grids coarser by 2, 4, ... 2^(LEVELS-1)
 * (gfmd_relax_multilevel); 1 = a flat start; default 4 from N = 2048 on, 1 below.
 * --approach STEPS: each relaxation (but a multilevel first load) starts with at most STEPS
 * mass-weighted FIRE steps, then continues with the chosen solver to the tolerance (mass weighting
 * approaches the equilibrium fast and then converges slowly; docs/decisions.md).
 * --jobs J: J bodies at a time, each in its own thread with --threads threads (default 1 then);
 * the printed blocks keep the study's order and, with the same FFT plans (--planner estimate),
 * the numbers do not depend on J (bodies.c).  Default: as many bodies at a time as the machine has
 * cores, one thread each (measured faster than threads inside each relaxation, docs/paper/full.md),
 * but --threads T alone sweeps one body at a time on T threads.  --planner: FFTW's rigour (default measure).
 * --plan: print what the options resolve to (grid, bodies, jobs and threads, first-load start,
 * approach, solver) and exit without relaxing anything or writing DIR — a 2048^2 run costs hours,
 * so its defaults are checked this way (tests/paper/run_plan.cmake).
 * Every body's sweep is saved in DIR as soon as it is done (resume.c); --resume reads the bodies
 * found there, of the same study only, instead of relaxing them again: a run that was stopped
 * goes on where it was (the pull-offs of --pulloff are not saved and run again).
 * Writes CSV tables into DIR (one per figure, see docs/paper/README.md) and prints the fits
 * (fits.c says which). */
#define _POSIX_C_SOURCE 200809L /* sysconf */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "study.h"

/* Bodies: W = w/lambda_s, 0 = half-space.  W <= 0.25 are the thin sheets of the W^-3 regime
 * (with lambda_s = 4a, q_s w = 2 pi W is small only there). */
static const double ALL_WIDTHS[] = {0.0, 100.0, 10.0, 4.0, 2.0, 1.0, 0.5, 0.25, 0.177, 0.125, 0.088, 0.0625, 0.044};
static const double ALL_ADH_WIDTHS[] = {0.0, 4.0, 1.0, 0.5, 0.25, 0.177, 0.125, 0.088, 0.0625};
/* --quick (the test's mode): fewer bodies, still three or more in each small-W fit */
static const double QUICK_WIDTHS[] = {0.0, 4.0, 1.0, 0.25, 0.125, 0.088, 0.0625};
static const double QUICK_ADH_WIDTHS[] = {0.25, 0.177, 0.125, 0.088, 0.0625};
#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))

double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

_Noreturn void die(const gfmd_sim *s, int32_t st, const char *what) {
    char msg[512] = "";
    if (s) gfmd_last_error(s, msg, sizeof msg);
    fprintf(stderr, "gfmd_paper: %s failed: %s: %s\n", what, gfmd_status_string(st), msg);
    /* may be called from a body's thread (--jobs) while others still relax: end the process
     * without running exit handlers (the library's static state) under their feet */
    fflush(NULL);
    _Exit(1);
}

static void usage(const char *argv0) {
    fprintf(stderr, "usage: %s [--n N] [--bandwidth R] [--full | --quick] [--out DIR] [--seed S] [--threads T] [--jobs J] [--planner measure|estimate] [--no-adhesion | --adhesion-only] [--widths 0,W1,...] [--adh-widths W1,...] [--pulloff] [--solver auto|fire|mass|cg] [--multilevel LEVELS] [--approach STEPS] [--plan] [--resume]\n",
            argv0);
    exit(2);
}

static void set_widths(double *to, int *n, const double *from, int count) {
    memcpy(to, from, sizeof(double) * (size_t)count);
    *n = count;
}

static options parse_options(int argc, char **argv) {
    options o = {.n = 256, .bandwidth = 32.0, .seed = 2016, .threads = 0, .jobs = 0, .planner = GFMD_PLANNER_MEASURE, .adhesion = 1, .pulloff = 0,
                 .solver = GFMD_SOLVER_AUTO, .levels = 0, .approach = 0, .dir = "."};
    set_widths(o.widths, &o.n_widths, ALL_WIDTHS, COUNT(ALL_WIDTHS));
    set_widths(o.adh_widths, &o.n_adh, ALL_ADH_WIDTHS, COUNT(ALL_ADH_WIDTHS));
    int adhesion_only = 0; /* applied after the loop: --quick or --widths later cannot undo it */
    int threads_given = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--n") && i + 1 < argc) o.n = strtol(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--bandwidth") && i + 1 < argc) o.bandwidth = strtod(argv[++i], NULL);
        else if (!strcmp(argv[i], "--full")) o.n = 2048, o.bandwidth = 64.0;
        else if (!strcmp(argv[i], "--quick")) {
            o.n = 128, o.bandwidth = 16.0;
            set_widths(o.widths, &o.n_widths, QUICK_WIDTHS, COUNT(QUICK_WIDTHS));
            set_widths(o.adh_widths, &o.n_adh, QUICK_ADH_WIDTHS, COUNT(QUICK_ADH_WIDTHS));
        }
        else if (!strcmp(argv[i], "--out") && i + 1 < argc) o.dir = argv[++i];
        else if (!strcmp(argv[i], "--seed") && i + 1 < argc) o.seed = strtoull(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) o.threads = strtol(argv[++i], NULL, 10), threads_given = 1;
        else if (!strcmp(argv[i], "--jobs") && i + 1 < argc) {
            o.jobs = atoi(argv[++i]);
            if (o.jobs == 0) o.jobs = -1; /* refused below (0 stands for "not given") */
        }
        else if (!strcmp(argv[i], "--planner") && i + 1 < argc) {
            ++i; /* estimate: the same FFT plans in every run, so runs compare bit for bit (the test's) */
            if (!strcmp(argv[i], "measure")) o.planner = GFMD_PLANNER_MEASURE;
            else if (!strcmp(argv[i], "estimate")) o.planner = GFMD_PLANNER_ESTIMATE;
            else usage(argv[0]);
        }
        else if (!strcmp(argv[i], "--no-adhesion")) o.adhesion = 0;
        else if (!strcmp(argv[i], "--adhesion-only")) adhesion_only = 1; /* Fig. 7 (and 8) alone */
        else if (!strcmp(argv[i], "--pulloff")) o.pulloff = 1;
        else if (!strcmp(argv[i], "--adh-widths") && i + 1 < argc) {
            /* comma-separated W list of the adhesive sheets (Fig. 7, and the pull-off) */
            int k = 0;
            for (char *tok = strtok(argv[++i], ","); tok && k < MAX_BODIES; tok = strtok(NULL, ","))
                o.adh_widths[k++] = strtod(tok, NULL);
            o.n_adh = k;
        }
        else if (!strcmp(argv[i], "--multilevel") && i + 1 < argc) {
            o.levels = atoi(argv[++i]);
            if (o.levels == 0) o.levels = -1; /* refused below (0 stands for "not given") */
        }
        else if (!strcmp(argv[i], "--plan")) o.plan = 1;
        else if (!strcmp(argv[i], "--resume")) o.resume = 1;
        else if (!strcmp(argv[i], "--approach") && i + 1 < argc) o.approach = strtol(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--solver") && i + 1 < argc) {
            ++i;
            if (!strcmp(argv[i], "auto")) o.solver = GFMD_SOLVER_AUTO;
            else if (!strcmp(argv[i], "fire")) o.solver = GFMD_SOLVER_FIRE;
            else if (!strcmp(argv[i], "mass")) o.solver = GFMD_SOLVER_MASS_WEIGHTED_FIRE;
            else if (!strcmp(argv[i], "cg")) o.solver = GFMD_SOLVER_CG;
            else usage(argv[0]);
        }
        else if (!strcmp(argv[i], "--widths") && i + 1 < argc) {
            /* comma-separated W list for the sweeps without adhesion, 0 = half-space first */
            int k = 0;
            for (char *tok = strtok(argv[++i], ","); tok && k < MAX_BODIES; tok = strtok(NULL, ","))
                o.widths[k++] = strtod(tok, NULL);
            if (k < 1 || o.widths[0] != 0.0) {
                fprintf(stderr, "gfmd_paper: --widths must start with 0 (the half-space)\n");
                exit(2);
            }
            o.n_widths = k;
        }
        else usage(argv[0]);
    }
    if (o.n < 32 || !(o.bandwidth >= 1.0) || o.bandwidth * LAMBDA_S > (double)o.n || o.threads < 0) {
        fprintf(stderr, "gfmd_paper: need --n >= 32 and 1 <= bandwidth <= n/4 (lambda_r = R * 4a within the cell)\n");
        exit(2);
    }
    if (adhesion_only) o.n_widths = 0;
    if (o.n_widths == 0 && !o.adhesion) {
        fprintf(stderr, "gfmd_paper: --adhesion-only with --no-adhesion leaves nothing to run\n");
        exit(2);
    }
    if (o.jobs == 0) { /* not given: --threads T alone means one body at a time on T threads, as before --jobs */
        const long cores = sysconf(_SC_NPROCESSORS_ONLN);
        o.jobs = threads_given ? 1 : (int)(cores < 1 ? 1 : cores > MAX_JOBS ? MAX_JOBS : cores);
    } else if (o.jobs < 1 || o.jobs > MAX_JOBS) {
        fprintf(stderr, "gfmd_paper: --jobs takes 1 to %d bodies at a time\n", MAX_JOBS);
        exit(2);
    }
    if (o.jobs > 1 && !threads_given) o.threads = 1; /* J bodies at a time share the cores: one thread each */
    if (o.approach < 0 || o.approach > 1000000) {
        fprintf(stderr, "gfmd_paper: --approach takes 0 (none) to 1000000 mass-weighted steps\n");
        exit(2);
    }
    /* not given: every body's first load from 3 coarser grids from 2048^2 on (--full), a flat start
     * below.  The runs of docs/paper/full.md at 2048^2: the multilevel first loads of the thin sheets
     * W <= 0.25 took 0.45-0.76x the CG's from flat (W = 0.0625: 219.63 s against 485.68 s), the
     * half-space 0.52x FIRE's, most adhesive bodies 0.65-0.85x; slower on W = 100 (25.08 s against
     * 8.85 s), W = 1 (1.2x) and the adhesive W = 0.0625 (1.3x), far less in sum than the thin sheets
     * gain.  At 512^2 the CG from flat is faster (8.82 s against 11.96 s, docs/decisions.md), at
     * 1024^2 the two are about even: hence the size. */
    if (o.levels == 0) o.levels = o.n >= 2048 ? 4 : 1;
    else if (o.levels < 1 || o.levels > 8) {
        fprintf(stderr, "gfmd_paper: --multilevel takes 1 (a flat start) to 8 levels\n");
        exit(2);
    }
    if (!o.plan && mkdir(o.dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "gfmd_paper: cannot create %s: %s\n", o.dir, strerror(errno));
        exit(1);
    }
    return o;
}

/* What the options resolve to: the lines every run prints before its sweeps and, with --plan,
 * the rest of what the run would do. */
static void print_plan(const options *o) {
    const double l = (double)o->n, lambda_r = o->bandwidth * LAMBDA_S;
    printf("gfmd %s: the study of Putignano, Dapp & Mueser (2016)\n", gfmd_version());
    printf("grid %ldx%ld, L = %.0f a, lambda_s = %.0f a, lambda_r = %.0f a (= %.0f lambda_s, L = %.3g lambda_r), "
           "H = %.1f, g = %.0f, E* = %.0f, seed %llu\n",
           o->n, o->n, l, LAMBDA_S, lambda_r, o->bandwidth, l / lambda_r, HURST, GRADIENT, E_STAR, o->seed);
    if (o->jobs > 1 || o->plan) {
        if (o->threads > 0) printf("bodies swept %d at a time, %ld thread(s) each\n", o->jobs, o->threads);
        else printf("bodies swept %d at a time, the library's default threads each\n", o->jobs);
    }
    if (o->levels > 1) printf("each body's first load from %d coarser grids (--multilevel %d)\n", o->levels - 1, o->levels);
    else if (o->plan) printf("each body's first load from a flat surface (--multilevel 1)\n");
    if (o->resume) printf("bodies saved in %s by an earlier run of this study are read, not relaxed (--resume)\n", o->dir);
    if (!o->plan) return;
    printf("bodies without adhesion, W (0 = half-space):");
    for (int b = 0; b < o->n_widths; ++b) printf(" %g", o->widths[b]);
    printf(o->n_widths ? "\n" : " none\n");
    printf("adhesive bodies, W:");
    for (int b = 0; o->adhesion && b < o->n_adh; ++b) printf(" %g", o->adh_widths[b]);
    printf(o->adhesion && o->n_adh ? "%s\n" : " none%s\n", o->adhesion && o->pulloff ? ", each with its pull-off" : "");
    if (o->approach > 0) printf("every other load: up to %ld mass-weighted steps first (--approach %ld)\n", o->approach, o->approach);
    else printf("every other load: no approach steps (--approach 0)\n");
    static const char *const names[] = {[GFMD_SOLVER_AUTO] = "auto", [GFMD_SOLVER_FIRE] = "fire",
                                        [GFMD_SOLVER_MASS_WEIGHTED_FIRE] = "mass", [GFMD_SOLVER_CG] = "cg"};
    const int k = (int)o->solver; /* one of the four --solver sets */
    printf("solver: %s\n", k >= 0 && k < COUNT(names) && names[k] ? names[k] : "?");
    printf("plan only (--plan): nothing relaxed, nothing written\n");
}

/* The study's substrate on a handle that every body clones; *u_max = max h - <h>. */
static gfmd_sim *make_surface(const options *o, double *u_max) {
    const double l = (double)o->n, lambda_r = o->bandwidth * LAMBDA_S;
    gfmd_sim *surface = NULL;
    CHECK(NULL, gfmd_sim_create_ex(o->n, o->n, l, l, (int32_t)o->threads, o->planner, &surface));
    CHECK(surface, gfmd_generate_selfaffine(surface, HURST, lambda_r, LAMBDA_S, GRADIENT, o->seed, GFMD_DIST_UNIFORM));
    double *h = malloc(sizeof(double) * (size_t)(o->n * o->n));
    if (!h) die(NULL, GFMD_ERR_NOMEM, "heights");
    CHECK(surface, gfmd_get_heights(surface, h));
    double hmax = -INFINITY, hmean = 0.0;
    for (long i = 0; i < o->n * o->n; ++i) hmax = fmax(hmax, h[i]), hmean += h[i] / (double)(o->n * o->n);
    free(h);
    *u_max = hmax - hmean;
    return surface;
}

typedef struct {
    const gfmd_sim *surface;
    const options *o;
} persson_task;

static void persson_curves(void *arg) {
    const persson_task *t = arg;
    write_persson_curves(t->surface, t->o);
}

int main(int argc, char **argv) {
    const options o = parse_options(argc, argv);
    print_plan(&o);
    if (o.plan) return 0;
    double u_max = 0.0;
    gfmd_sim *surface = make_surface(&o, &u_max);
    const double t_start = now();
    fits f = {NAN, {0}, {NAN, NAN}, {{NAN, NAN}, {NAN, NAN}, {NAN, NAN}}, NAN};

    /* Every body's sweep (o.jobs at a time): those without adhesion first (Figs. 3-6), then the
     * adhesive sheets (Fig. 7) */
    static body bodies[2 * MAX_BODIES];
    int n = 0;
    for (int b = 0; b < o.n_widths; ++b) bodies[n++] = (body){.W = o.widths[b], .adhesive = 0};
    for (int b = 0; o.adhesion && b < o.n_adh; ++b) bodies[n++] = (body){.W = o.adh_widths[b], .adhesive = 1};
    int resumed = 0;       /* bodies read from their checkpoints */
    double resumed_s = 0.0; /* and their own seconds, spent by the runs that relaxed them */
    for (int k = 0; o.resume && k < n; ++k)
        if (load_body(&o, &bodies[k])) ++resumed, resumed_s += sweep_seconds(&bodies[k].out);
    /* Persson's curves (Fig. 3) need no sweep: written on the core the last bodies leave idle */
    persson_task task = {surface, &o};
    run_bodies(surface, u_max, &o, bodies, n, o.n_widths > 0 ? persson_curves : NULL, &task);
    double first = 0.0;  /* the sweeps' first loads, each from a flat start or from coarser grids */
    double own = 0.0;    /* the bodies' own seconds (the "this body:" lines; read bodies' too) */
    long long steps = 0; /* every relaxation step of every sweep */
    static sweep sw[MAX_BODIES], ad[MAX_BODIES];
    for (int k = 0; k < n; ++k) {
        first += bodies[k].out.p[0].seconds;
        own += sweep_seconds(&bodies[k].out);
        steps += sweep_steps(&bodies[k].out);
        if (k < o.n_widths) sw[k] = bodies[k].out;
        else ad[k - o.n_widths] = bodies[k].out;
    }

    if (o.n_widths > 0) { /* not with --adhesion-only */
        write_load_tables(sw, &o);

        /* kappa, and Fig. 5: the collapse factor c(W) */
        fit_kappa(&sw[0], &f);
        fit_collapse(sw, &o, &f);
        write_collapse_tables(sw, &o, &f);
    }

    /* Fig. 7: theta = U_el/U_ad with adhesion */
    if (o.adhesion) {
        write_theta_tables(ad, &o);
        fit_theta(ad, &o, &f);
        /* Fig. 8: the pull-off stress of the same sheets, beside theta */
        if (o.pulloff) {
            static pulloff po[MAX_BODIES];
            for (int b = 0; b < o.n_adh; ++b) run_pulloff(surface, o.adh_widths[b], u_max, o.solver, &po[b]);
            write_pulloff_table(po, o.n_adh, &o);
        }
    }

    write_fits(&o, &f);
    report_fits(&o, &f);
    /* with --jobs J > 1 the bodies' own seconds overlap: their sums exceed the wall time */
    printf("total %.1f s, %lld steps (bodies %.2f s, first loads %.2f s%s); tables in %s\n", now() - t_start, steps,
           own, first, o.jobs > 1 ? ", summed over the bodies" : "", o.dir);
    if (resumed > 0) /* the total is this run's wall time; the steps and first loads are the whole study's */
        printf("resumed: %d of %d bodies read from %s, relaxed by earlier runs in %.1f s of their own\n", resumed, n,
               o.dir, resumed_s);
    gfmd_sim_destroy(&surface);
    return 0;
}
