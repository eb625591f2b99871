/* Checkpoints: every body's sweep, as soon as it is done, in DIR/body_W<W>[_adhesive].sweep; with
 * --resume a later run reads the bodies it finds there instead of relaxing them again.  A --full
 * study takes hours, longer than a machine may be lent (docs/paper/full.md): an interrupted run
 * loses at most the bodies that were relaxing.
 *
 * A checkpoint holds the study it belongs to (every option that changes the numbers: the library's
 * version, grid, spectrum, seed, first-load levels, approach steps, solver, planner) and the sweep's
 * points as hexadecimal floating point, so a body read back is bit for bit the body that was
 * written, and the tables and fits of a resumed study are those of an uninterrupted one.  A file of
 * another study, or one that does not parse, ends the program with status 2 and the file's name:
 * mixing two studies silently is the one thing a resume must not do. */
#define _POSIX_C_SOURCE 200809L /* open_memstream */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "study.h"

static const char MAGIC[] = "gfmd_paper sweep checkpoint 1\n";

static void checkpoint_path(const options *o, const body *b, char *path, size_t size) {
    snprintf(path, size, "%s/body_W%.10g%s.sweep", o->dir, b->W, b->adhesive ? "_adhesive" : "");
}

/* The options that change a body's numbers, as one line (threads and jobs do not, bodies.c) */
static void study_key(const options *o, char *key, size_t size) {
    snprintf(key, size, "study gfmd %s n %ld bandwidth %a seed %llu levels %d approach %ld solver %d planner %d\n",
             gfmd_version(), o->n, o->bandwidth, o->seed, o->levels, o->approach, (int)o->solver, (int)o->planner);
}

void save_body(const options *o, const body *b) {
    char path[4096], tmp[4200], key[512];
    checkpoint_path(o, b, path, sizeof path);
    snprintf(tmp, sizeof tmp, "%s.part", path);
    study_key(o, key, sizeof key);
    int ok = 0;
    FILE *f = fopen(tmp, "w");
    if (f) {
        fputs(MAGIC, f);
        fputs(key, f);
        fprintf(f, "body %a %d %d\n", b->W, b->adhesive, b->out.n);
        for (int k = 0; k < b->out.n; ++k) {
            const point *p = &b->out.p[k];
            fprintf(f, "%a %a %a %a %a %a %a %a %a %lld\n", p->W, p->sigma0, p->area, p->persson, p->gap, p->sep,
                    p->u_el, p->u_ad, p->seconds, p->steps);
        }
        fputs("end\n", f);
        ok = !ferror(f);
        ok = fclose(f) == 0 && ok;
    }
    /* written whole, then renamed: a run stopped while writing leaves no half a checkpoint */
    if (!ok || rename(tmp, path) != 0) {
        fprintf(stderr, "gfmd_paper: warning: cannot write the checkpoint %s (the study goes on without it)\n", path);
        remove(tmp);
    }
}

_Noreturn static void refuse(FILE *f, const char *path, const char *why) {
    fclose(f);
    fprintf(stderr, "gfmd_paper: --resume: %s %s\n", path, why);
    exit(2);
}

int load_body(const options *o, body *b) {
    char path[4096], key[512], line[1024];
    checkpoint_path(o, b, path, sizeof path);
    FILE *f = fopen(path, "r");
    if (!f) return 0; /* not done yet */
    study_key(o, key, sizeof key);
    if (!fgets(line, sizeof line, f) || strcmp(line, MAGIC) != 0) refuse(f, path, "is not a checkpoint of gfmd_paper");
    if (!fgets(line, sizeof line, f) || strcmp(line, key) != 0) {
        fclose(f);
        fprintf(stderr, "gfmd_paper: --resume: %s belongs to another study:\n  its   %s  these %s", path, line, key);
        exit(2);
    }
    double W = NAN;
    int adhesive = -1, n = -1;
    if (!fgets(line, sizeof line, f) || sscanf(line, "body %lf %d %d", &W, &adhesive, &n) != 3 || W != b->W ||
        adhesive != b->adhesive || n < 1 || n > MAX_LOADS)
        refuse(f, path, "is not this body's checkpoint");
    sweep s = {.W = W, .n = n};
    for (int k = 0; k < n; ++k) {
        point *p = &s.p[k];
        if (!fgets(line, sizeof line, f) ||
            sscanf(line, "%lf %lf %lf %lf %lf %lf %lf %lf %lf %lld", &p->W, &p->sigma0, &p->area, &p->persson, &p->gap,
                   &p->sep, &p->u_el, &p->u_ad, &p->seconds, &p->steps) != 10 ||
            !isfinite(p->sigma0 + p->area + p->persson + p->gap + p->sep + p->u_el + p->u_ad + p->seconds) ||
            p->W != W || p->steps < 0)
            refuse(f, path, "is damaged (a load's line does not parse)");
    }
    if (!fgets(line, sizeof line, f) || strcmp(line, "end\n") != 0) refuse(f, path, "is damaged (no end)");
    fclose(f);
    b->out = s;
    /* its printed block, as the run that relaxed it printed it */
    size_t len = 0;
    FILE *log = open_memstream(&b->text, &len);
    if (!log) die(NULL, GFMD_ERR_NOMEM, "open_memstream");
    else {
        print_sweep(log, &b->out, b->adhesive, o->levels);
        fclose(log);
    }
    b->done = b->resumed = 1;
    fprintf(stderr, "gfmd_paper: W = %g%s read from %s (%lld steps, %.2f s when it was relaxed)\n", b->W,
            b->adhesive ? ", adhesive" : "", path, sweep_steps(&b->out), sweep_seconds(&b->out));
    return 1;
}
