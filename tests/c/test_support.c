#include "test_support.h"

#include <fftw3.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

void ts_check_ok(const gfmd_sim *s, int32_t st, const char *what, const char *file, int line) {
    if (st == GFMD_OK) return;
    char msg[512] = "";
    if (s != NULL) gfmd_last_error(s, msg, sizeof msg);
    fail_msg("%s:%d: %s -> %s (%s): %s", file, line, what, gfmd_status_string(st), "status", msg);
}

/* the handle a create call made, the test failed unless it made one */
static gfmd_sim *created(int32_t st, gfmd_sim *s) {
    assert_int_equal(st, GFMD_OK);
    assert_non_null(s);
    return s;
}

gfmd_sim *ts_create(int64_t nx, int64_t ny, double lx, double ly) {
    gfmd_sim *s = NULL;
    const int32_t st = gfmd_sim_create(nx, ny, lx, ly, &s); /* before s is read */
    return created(st, s);
}

gfmd_sim *ts_create_estimate(int64_t nx, int64_t ny, double lx, double ly) {
    gfmd_sim *s = NULL;
    const int32_t st = gfmd_sim_create_ex(nx, ny, lx, ly, 0, GFMD_PLANNER_ESTIMATE, &s);
    return created(st, s);
}

double *ts_alloc(size_t n) {
    double *p = calloc(n, sizeof *p);
    assert_non_null(p);
    return p;
}

double ts_qx(int64_t kx, int64_t nx, double lx) {
    (void)nx;
    return 2.0 * M_PI * (double)kx / lx;
}

double ts_qy(int64_t ky, int64_t ny, double ly) {
    int64_t k = (2 * ky > ny) ? ky - ny : ky;
    return 2.0 * M_PI * (double)k / ly;
}

double ts_stiffness(int32_t kind, double width, double nu, double e_star, double qx, double qy) {
    double q = sqrt(qx * qx + qy * qy);
    if (q == 0.0) return 0.0;
    double f = 1.0;
    if (kind != GFMD_GREEN_HALFSPACE) assert_int_equal(gfmd_green_factor(kind, q * width, nu, &f), GFMD_OK);
    return 0.5 * q * e_star / f;
}

double ts_elastic_energy(int64_t nx, int64_t ny, double lx, double ly, int32_t kind, double width, double nu,
                         double e_star, const double *z) {
    int64_t nxh = nx / 2 + 1, n = nx * ny;
    double *in = fftw_alloc_real((size_t)n);
    fftw_complex *out = fftw_alloc_complex((size_t)(nxh * ny));
    fftw_plan p = fftw_plan_dft_r2c_2d((int)ny, (int)nx, in, out, FFTW_ESTIMATE);
    memcpy(in, z, sizeof(double) * (size_t)n);
    fftw_execute(p);
    double e = 0.0;
    for (int64_t ky = 0; ky < ny; ++ky)
        for (int64_t kx = 0; kx < nxh; ++kx) {
            double w = (kx == 0 || 2 * kx == nx) ? 1.0 : 2.0;
            double re = out[ky * nxh + kx][0], im = out[ky * nxh + kx][1];
            double k = ts_stiffness(kind, width, nu, e_star, ts_qx(kx, nx, lx), ts_qy(ky, ny, ly));
            e += w * k * (re * re + im * im) / ((double)n * (double)n);
        }
    fftw_destroy_plan(p);
    fftw_free(in);
    fftw_free(out);
    return 0.5 * lx * ly * e;
}

double ts_rel(double a, double b) {
    double d = fabs(b) > 1e-300 ? fabs(b) : 1e-300;
    return fabs(a - b) / d;
}

int ts_exhaust_memory(void) {
    long vm_kb = 0;
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, "VmSize:", 7)) vm_kb = atol(line + 7);
    if (f) fclose(f);
    struct rlimit cap = {(rlim_t)(vm_kb + 4096) * 1024, (rlim_t)(vm_kb + 4096) * 1024}; /* 4 MB more */
    if (vm_kb <= 0 || setrlimit(RLIMIT_AS, &cap) != 0) return 1;
    void *last = NULL;
    for (void *p = malloc(1 << 20); p != NULL; p = malloc(1 << 20)) last = p;
    free(last);
    return 0;
}

int ts_valgrind(void) {
    const char *preload = getenv("LD_PRELOAD");
    return preload != NULL && strstr(preload, "vgpreload") != NULL;
}

int ts_memory_checked(void) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    return 1; /* this file is built with the tests' sanitizer flags */
#else
    return ts_valgrind();
#endif
}

int ts_memory_cap_possible(void) { return !ts_memory_checked(); }

/* Wait for the child pid; fail the current test unless it exited with 0. */
static void expect_clean_exit(pid_t pid) {
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 0);
}

void ts_run_in_child(int (*body)(void)) {
    const pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) _exit(body());
    expect_clean_exit(pid);
}

double ts_value_in_child(double (*body)(const void *arg), const void *arg) {
    int fd[2];
    assert_int_equal(pipe(fd), 0);
    const pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        close(fd[0]);
        const double value = body(arg);
        _exit(write(fd[1], &value, sizeof value) == (ssize_t)sizeof value ? 0 : 1);
    }
    close(fd[1]);
    double value = NAN;
    const ssize_t got = read(fd[0], &value, sizeof value);
    close(fd[0]);
    expect_clean_exit(pid);
    assert_int_equal(got, (ssize_t)sizeof value);
    return value;
}
