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
    pthread_mutex_t mutex;
    pthread_cond_t finished;
} pool;

/* The thin sheets take by far the most steps (docs/paper/full.md): start them first, so that the
 * thick bodies fill the gaps at the end.  Cost rank: W ascending, the half-space last, an adhesive
 * sheet before the same W without adhesion. */
static double cost_rank(const body *b) { return (b->W > 0.0 ? b->W : INFINITY) - (b->adhesive ? 1e-9 : 0.0); }

static void *worker(void *arg) {
    pool *p = arg;
    for (;;) {
        pthread_mutex_lock(&p->mutex);
        const int k = p->next < p->pending ? p->order[p->next++] : -1;
        pthread_mutex_unlock(&p->mutex);
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

void run_bodies(const gfmd_sim *surface, double u_max, const options *o, body *bodies, int n) {
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
        return;
    }
    pool p = {surface, u_max, o, bodies, now(), 0, 0, 0, n, {0}, PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER};
    for (int k = 0; k < n; ++k) { /* the bodies still to relax, by cost rank: stable, n <= 2 MAX_BODIES */
        if (bodies[k].done) {
            ++p.finished_count; /* read from its checkpoint (--resume) */
            continue;
        }
        int j = p.pending++;
        for (; j > 0 && cost_rank(&bodies[p.order[j - 1]]) > cost_rank(&bodies[k]); --j) p.order[j] = p.order[j - 1];
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
}
