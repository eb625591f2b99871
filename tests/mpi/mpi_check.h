/* The MPI tests' checks: a failed CHECK prints its rank and place and counts; main() adds the
 * counts of all ranks at the end (MPI_Allreduce) and fails if any rank failed. */
#ifndef GFMD_TESTS_MPI_CHECK_H
#define GFMD_TESTS_MPI_CHECK_H

#include <stdio.h>

static int failures = 0;
static int rank = 0;

#define CHECK(cond, ...)                                                   \
    do {                                                                   \
        if (!(cond)) {                                                     \
            ++failures;                                                    \
            fprintf(stderr, "rank %d, %s:%d: ", rank, __FILE__, __LINE__); \
            fprintf(stderr, __VA_ARGS__);                                  \
            fprintf(stderr, "\n");                                         \
        }                                                                  \
    } while (0)

#define OK(call) CHECK((call) == GFMD_OK, "%s failed", #call)

/* The process's virtual memory size in bytes (VmSize of /proc/self/status), 0 if unknown. */
static inline long long vm_size(void) {
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    long long kb = 0;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "VmSize: %lld kB", &kb) == 1) break;
    if (f) fclose(f);
    return kb * 1024;
}

#endif
