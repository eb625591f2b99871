/* The benchmarks' clock and memory probes (Linux); test_api's memory test uses the probes too. */
#ifndef GFMD_BENCH_CLOCK_H
#define GFMD_BENCH_CLOCK_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

static inline double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Peak resident memory since the last reset, in bytes (Linux: VmHWM, reset via clear_refs).  The
 * heap freed so far is given back to the system first (glibc): else memory freed before the reset
 * but still resident would count in a base read after it, and the allocations it serves later
 * would not count in the rise -- a rise that undercounts. */
static inline void reset_peak(void) {
#if defined(__GLIBC__)
    (void)malloc_trim(0);
#endif
    FILE *f = fopen("/proc/self/clear_refs", "w");
    if (f) {
        fputs("5", f);
        fclose(f);
    }
}

/* A "key:" line of /proc/self/status in kB (VmRSS:, VmHWM:), or -1. */
static inline double read_status_kb(const char *key) {
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    double kb = -1.0;
    if (!f) return -1.0;
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, key, strlen(key))) kb = atof(line + strlen(key));
    fclose(f);
    return kb;
}

#endif
