/* Shared helpers of the C tests: checked calls and an independent FFT-based evaluation of the
 * model's elastic quantities (test-side code, not the library's). */
#ifndef GFMD_TEST_SUPPORT_H
#define GFMD_TEST_SUPPORT_H

#include <stddef.h>
#include <stdint.h>

#include "gfmd.h"

/* Fail the current CMocka test with the library's message if st != GFMD_OK. */
#define TS_OK(sim, call) ts_check_ok((sim), (call), #call, __FILE__, __LINE__)
void ts_check_ok(const gfmd_sim *s, int32_t st, const char *what, const char *file, int line);

gfmd_sim *ts_create(int64_t nx, int64_t ny, double lx, double ly);
/* The same with FFTW_ESTIMATE plans, for tests that take no steps: the measuring planner's trial
 * transforms cost more than all their transforms (about 3 s a size under valgrind). */
gfmd_sim *ts_create_estimate(int64_t nx, int64_t ny, double lx, double ly);
double *ts_alloc(size_t n); /* zeroed doubles; freed with free() */

/* Stiffness 1/G(q) = q E* / (2 f(q w)) of mode (kx, ky) of the r2c half-spectrum; 0 for q = 0. */
double ts_stiffness(int32_t kind, double width, double nu, double e_star, double qx, double qy);
double ts_qx(int64_t kx, int64_t nx, double lx);
double ts_qy(int64_t ky, int64_t ny, double ly);

/* Elastic energy (A/2) sum_q |u(q)|^2/G(q) of the field z, evaluated with FFTW by the test. */
double ts_elastic_energy(int64_t nx, int64_t ny, double lx, double ly, int32_t kind, double width, double nu,
                         double e_star, const double *z);

/* For a forked child: cap the address space just above what the process uses and fill it in 1 MB
 * pieces, giving one back for the small allocations of a call, so that an allocation of a few MB
 * more cannot be had.  0 on success.  Not under the sanitizers or valgrind, which need address
 * space of their own: see ts_memory_cap_possible(). */
int ts_exhaust_memory(void);
/* Run body() in a forked child process and fail the current test unless it exits with 0 (for
 * tests that must change the process, e.g. cap its memory). */
void ts_run_in_child(int (*body)(void));
/* Run body(arg) in a forked child process and return the number it computed (passed back through
 * a pipe); fail the current test unless the child exits with 0 after passing it. */
double ts_value_in_child(double (*body)(const void *arg), const void *arg);
/* Whether ts_exhaust_memory() may be used here: not in a sanitizer build, not under valgrind. */
int ts_memory_cap_possible(void);
/* Whether the test runs under valgrind (its preload library is loaded).  Under valgrind, which
 * runs these tests many times slower, a test that loops over cases of the same code paths may
 * run one case of each path (the native and sanitizer runs take them all); it says which. */
int ts_valgrind(void);
/* Whether the test runs under a memory checker: valgrind, or a build with AddressSanitizer or
 * ThreadSanitizer (whose ctest takes every test too).  A test whose calls another test runs there
 * at lower cost may skip; it names that test. */
int ts_memory_checked(void);

/* Relative difference |a - b| / max(|b|, tiny). */
double ts_rel(double a, double b);

#endif
