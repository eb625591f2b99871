/* The seed paper's study as a program: its settings, its data, and the three steps of its outline
 * (sweep.c: load sweeps; fits.c: kappa, c(W), theta; tables.c: the CSV tables and the report).
 * No global state: everything a step needs is passed in. */
#ifndef GFMD_APPS_PAPER_STUDY_H
#define GFMD_APPS_PAPER_STUDY_H

#include <gfmd.h>
#include <stddef.h>
#include <stdio.h>

enum { MAX_LOADS = 16, MAX_BODIES = 16, N_TARGETS = 3, MAX_JOBS = 2 * MAX_BODIES };

/* The paper's surface and body (Putignano, Dapp & Mueser 2016, Sec. 3): H = 0.8, lambda_s = 4a,
 * rms gradient g = 1, E* = 1; adhesion gamma0 = 5e-4 E* a with range rho = a. */
#define LAMBDA_S 4.0
#define HURST 0.8
#define GRADIENT 1.0
#define E_STAR 1.0
#define GAMMA0 5e-4
#define RHO 1.0
/* Upper ends of the small-W fits.  c(W): the thin-plate limit f = 6/t^3 (1 + t^2/5 + ...) holds at
 * the shortest roughness wavelength, t = q_s w = 2 pi W, to about 10 % only for W <= 1/8.  theta:
 * with adhesion the thinnest sheets are sticky (their area at vanishing load exceeds the target
 * areas), so its fit spans W <= 1/4 where the targets are reached. */
#define SMALL_W_C (0.125 + 1e-9)
#define SMALL_W_THETA (0.25 + 1e-9)
#define KAPPA_MAX_AREA 0.1    /* the linear (small-load) regime */
#define COLLAPSE_MAX_AREA 0.3 /* points used for c(W) */

typedef struct {
    long n;                 /* grid points per side */
    double bandwidth;       /* lambda_r / lambda_s */
    unsigned long long seed;
    long threads;           /* each body's handle: 0 = the library's default */
    int jobs;               /* bodies swept at a time (bodies.c) */
    int32_t planner;        /* GFMD_PLANNER_* of every handle */
    int adhesion;           /* run the adhesive sweeps of Fig. 7 */
    int pulloff;            /* and the pull-off of each adhesive sheet (Fig. 8) */
    int32_t solver;         /* GFMD_SOLVER_* */
    int levels;             /* the first load of each body: gfmd_relax_multilevel with these levels (1: flat start) */
    int plan;               /* --plan: print what the options resolve to and exit */
    int resume;             /* --resume: bodies with a checkpoint in dir are read, not relaxed (resume.c) */
    long approach;          /* each other relaxation: up to this many mass-weighted FIRE steps first (0: none) */
    const char *dir;        /* output folder */
    double widths[MAX_BODIES], adh_widths[MAX_BODIES]; /* W = w/lambda_s, 0 = half-space first */
    int n_widths, n_adh;
} options;

typedef struct {
    double W, sigma0, area, persson, gap, sep, u_el, u_ad, seconds;
    long long steps;
} point;

typedef struct {
    double W;
    int n;
    point p[MAX_LOADS];
} sweep;

/* One body of the study: its sweep, and (bodies.c) its printed block while it waits to be printed. */
typedef struct {
    double W;
    int adhesive;
    sweep out;
    char *text;
    int done;
    int resumed; /* read from its checkpoint (--resume, resume.c) */
} body;

typedef struct {
    double kappa;
    double cw[MAX_BODIES];           /* c(W) of each body of the sweeps without adhesion */
    double cfit[2];                  /* ln prefactor, exponent of c(W) for W <= SMALL_W_C */
    double tfit[N_TARGETS][2];       /* theta ~ W^beta at each target area */
    double theta_common;             /* the common beta */
} fits;

typedef struct {
    double W, pull_off, area_max, seconds; /* pull-off: the most tensile mean pressure on retraction */
    double lift;                           /* how far above the start the retraction ended */
    long long steps;
    int points, detached;
} pulloff;

extern const double TARGETS[N_TARGETS]; /* contact areas of the theta fits */

/* Failures end the program with the library's message (a study has nothing to recover). */
_Noreturn void die(const gfmd_sim *s, int32_t st, const char *what);
#define CHECK(s, call)                            \
    do {                                          \
        int32_t st_ = (call);                     \
        if (st_ != GFMD_OK) die((s), st_, #call); \
    } while (0)
double now(void);

/* sweep.c */
gfmd_sim *make_body(const gfmd_sim *surface, double W, int32_t solver);
/* The relaxation steps of one sweep (this grid's; a multilevel start's coarse steps not counted). */
long long sweep_steps(const sweep *s);
/* The seconds of its loads (a multilevel start's coarse grids included). */
double sweep_seconds(const sweep *s);
void run_sweep(const gfmd_sim *surface, double W, int adhesive, double u_max, const options *o, sweep *out,
               FILE *log);
void print_sweep_head(FILE *log, double W, int adhesive);
void print_point(FILE *log, const point *p);
void print_sweep_tail(FILE *log, const sweep *s, int levels);
void print_sweep(FILE *log, const sweep *s, int adhesive, int levels);
/* The first and the last load of a sweep on this body (Persson's loads for the sweep's areas). */
void sweep_load_range(const gfmd_sim *body, double *first, double *last);
/* resume.c: a body's checkpoint in o->dir, written when it is done; read: 1 if there is one (its
 * sweep and printed block filled in), 0 if not; another study's or a damaged file ends the run (2) */
void save_body(const options *o, const body *b);
int load_body(const options *o, body *b);
/* bodies.c: the sweeps of n bodies, o->jobs at a time, their blocks printed in the given order;
 * idle(arg), if given, runs once on the first thread that finds no body left to start (with
 * --jobs 1: after the sweeps), so that it fills a core the last bodies leave idle */
void run_bodies(const gfmd_sim *surface, double u_max, const options *o, body *bodies, int n, void (*idle)(void *),
                void *idle_arg);
/* pulloff.c */
void run_pulloff(const gfmd_sim *surface, double W, double u_max, int32_t solver, pulloff *out);
/* fits.c */
void fit_kappa(const sweep *halfspace, fits *f);
void fit_collapse(const sweep *sw, const options *o, fits *f);
void fit_theta(const sweep *ad, const options *o, fits *f);
double at_area(const sweep *c, double area, size_t field);
/* tables.c */
void write_pulloff_table(const pulloff *p, int n, const options *o);
void write_load_tables(const sweep *sw, const options *o);
void write_persson_curves(const gfmd_sim *surface, const options *o);
void write_collapse_tables(const sweep *sw, const options *o, const fits *f);
void write_theta_tables(const sweep *ad, const options *o);
void write_fits(const options *o, const fits *f);
void report_fits(const options *o, const fits *f);

#endif
