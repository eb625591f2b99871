/* The study's load sweeps, one body after another (--jobs 1) or several bodies at a time, each on
 * its own handle in its own POSIX thread (--jobs J; distinct handles are independent, gfmd.h).  A
 * body's printed block appears in the study's order, whatever order the bodies finish in.  Each
 * body's arithmetic is its own, so its numbers do not depend on J when the FFT plans are the same
 * (--planner estimate; FFTW_MEASURE times candidate plans, and bodies timed side by side may get
 * other plans, which round differently).  Each body is saved when it is done (resume.c); bodies read
 * back (--resume) are not relaxed again, only printed in their place. */
#define _POSIX_C_SOURCE 200809L /* open_memstream */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>

#include "study.h"

typedef struct {
    const gfmd_sim *surface;
    double u_max;
    const options *o;
    body *bodies;
    double t_start; /* now() when the sweeps began: the progress lines say the wall time so far */
    int pending, next, finished_count, n; /* bodies to relax, taken, done (read ones too), in all */
    int order[2 * MAX_BODIES];            /* the order the workers take the pending bodies in */
    void (*idle)(void *);                 /* run once by the first worker without a body to start */
    void *idle_arg;
    pthread_mutex_t mutex;
    pthread_cond_t finished;
} pool;

/* The longest bodies first, so that the last ones to start are short and the cores finish
 * together (longest processing time first; the order decided at the start, on estimates).  The
 * estimates: each body's seconds in the default's run of commit bd2e3fd at 2048^2, two at a time
 * (docs/paper/full.md; only their order matters), interpolated in log W between the widths of
 * the same kind and held at the ends.  The old order (W ascending, the half-spaces last) left one
 * core idle for the last 70 s of that run; this one, replayed on the same seconds, about 6 s (a
 * derived schedule).  A change that moves a body's cost much (another solver on its loads)
 * should refresh these from a new run's "bodies done" lines. */
static const double EST_W[] = {0.044, 0.0625, 0.088, 0.125, 0.177, 0.25, 0.5, 1.0, 2.0, 4.0, 10.0, 100.0};
static const double EST_DRY[] = {175.61, 168.10, 139.14, 124.18, 98.02, 81.77, 157.39, 137.68, 121.70, 113.22, 136.93, 125.37};
static const double EST_ADH_W[] = {0.0625, 0.088, 0.125, 0.177, 0.25, 0.5, 1.0, 4.0};
static const double EST_ADH[] = {297.62, 409.05, 309.33, 155.55, 89.74, 189.86, 167.88, 139.19};
static const double EST_HALFSPACE[2] = {134.46, 129.31}; /* without, with adhesion */

static double interpolate_log(const double *w, const double *t, int n, double W) {
    if (W <= w[0]) return t[0];
    for (int k = 1; k < n; ++k)
        if (W <= w[k]) return t[k - 1] + (t[k] - t[k - 1]) * log(W / w[k - 1]) / log(w[k] / w[k - 1]);
    return t[n - 1];
}

static double expected_seconds(const body *b) {
    if (!(b->W > 0.0)) return EST_HALFSPACE[b->adhesive ? 1 : 0];
    if (b->adhesive) return interpolate_log(EST_ADH_W, EST_ADH, (int)(sizeof EST_ADH_W / sizeof EST_ADH_W[0]), b->W);
    return interpolate_log(EST_W, EST_DRY, (int)(sizeof EST_W / sizeof EST_W[0]), b->W);
}

static void *worker(void *arg) {
    pool *p = arg;
    for (;;) {
        pthread_mutex_lock(&p->mutex);
        const int k = p->next < p->pending ? p->order[p->next++] : -1;
        void (*idle)(void *) = k < 0 ? p->idle : NULL;
        if (idle) p->idle = NULL; /* once */
        pthread_mutex_unlock(&p->mutex);
        if (idle) idle(p->idle_arg);
        if (k < 0) return NULL;
        body *b = &p->bodies[k];
        char *text = NULL;
        size_t len = 0;
        FILE *log = open_memstream(&text, &len);
        if (!log) die(NULL, GFMD_ERR_NOMEM, "open_memstream");
        run_sweep(p->surface, b->W, b->adhesive, p->u_max, p->o, &b->out, log);
        fclose(log);
        save_body(p->o, b);
        pthread_mutex_lock(&p->mutex);
        b->text = text;
        b->done = 1;
        /* progress: the blocks on stdout wait for the bodies before them in the study's order (a
         * --full run shows nothing on stdout for most of its hours) */
        fprintf(stderr, "gfmd_paper: %d of %d bodies done (W = %g%s, %lld steps, %.2f s), %.0f s since the sweeps began\n",
                ++p->finished_count, p->n, b->W, b->adhesive ? ", adhesive" : "", sweep_steps(&b->out),
                sweep_seconds(&b->out), now() - p->t_start);
        pthread_cond_broadcast(&p->finished);
        pthread_mutex_unlock(&p->mutex);
    }
}

void run_bodies(const gfmd_sim *surface, double u_max, const options *o, body *bodies, int n, void (*idle)(void *),
                void *idle_arg) {
    if (o->jobs <= 1) {
        for (int k = 0; k < n; ++k) {
            if (bodies[k].done) { /* read from its checkpoint (--resume) */
                fputs(bodies[k].text, stdout);
                free(bodies[k].text);
                bodies[k].text = NULL;
                continue;
            }
            run_sweep(surface, bodies[k].W, bodies[k].adhesive, u_max, o, &bodies[k].out, stdout);
            save_body(o, &bodies[k]);
        }
        if (idle) idle(idle_arg);
        return;
    }
    pool p = {surface, u_max, o, bodies, now(), 0, 0, 0, n, {0}, idle, idle_arg, PTHREAD_MUTEX_INITIALIZER,
              PTHREAD_COND_INITIALIZER};
    for (int k = 0; k < n; ++k) { /* the bodies still to relax, longest first: stable, n <= 2 MAX_BODIES */
        if (bodies[k].done) {
            ++p.finished_count; /* read from its checkpoint (--resume) */
            continue;
        }
        int j = p.pending++;
        for (; j > 0 && expected_seconds(&bodies[p.order[j - 1]]) < expected_seconds(&bodies[k]); --j)
            p.order[j] = p.order[j - 1];
        p.order[j] = k;
    }
    const int workers = o->jobs < p.pending ? o->jobs : p.pending;
    pthread_t tid[MAX_JOBS];
    for (int w = 0; w < workers; ++w)
        if (pthread_create(&tid[w], NULL, worker, &p) != 0) die(NULL, GFMD_ERR_NOMEM, "pthread_create");
    for (int k = 0; k < n; ++k) { /* print in the study's order as the bodies finish */
        pthread_mutex_lock(&p.mutex);
        while (!bodies[k].done) pthread_cond_wait(&p.finished, &p.mutex);
        pthread_mutex_unlock(&p.mutex);
        fputs(bodies[k].text, stdout);
        fflush(stdout);
        free(bodies[k].text);
        bodies[k].text = NULL;
    }
    for (int w = 0; w < workers; ++w) pthread_join(tid[w], NULL);
    if (p.idle) p.idle(p.idle_arg); /* no worker ran it (every body read back) */
}
