// libFuzzer target: drives the public C API with arbitrary grid sizes, parameters (NaN, inf,
// denormals, huge, negative), height fields and call orders, and checks after every call that
// the library answered with a known status and that the state it reports is sane.  Any crash,
// sanitizer report, hang or broken invariant is a finding.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "gfmd.h"

namespace {

class Input {
public:
    Input(const uint8_t *d, size_t n) : d_(d), n_(n) {}
    bool empty() const { return i_ >= n_; }
    uint8_t u8() { return i_ < n_ ? d_[i_++] : 0; }
    int64_t i64() {
        uint64_t x = 0;
        for (int k = 0; k < 8; ++k) x |= static_cast<uint64_t>(u8()) << (8 * k);
        return static_cast<int64_t>(x);
    }
    // Either a raw bit pattern or one of the values that break numerical code.
    double f64() {
        static const double table[] = {0.0,   -0.0,    1.0,     -1.0,  0.5,     2.0,    1e-8,    1e8,
                                       1e-310, -1e-310, 1e300,  -1e300, INFINITY, -INFINITY, NAN, 0.05,
                                       4.0,   64.0,    0.8,     1e-4,  1e100,   1e-100, 3.0,     0.3};
        const uint8_t sel = u8();
        if (sel < 200) return table[sel % (sizeof table / sizeof table[0])];
        uint64_t x = static_cast<uint64_t>(i64());
        double d;
        std::memcpy(&d, &x, 8);
        return d;
    }

private:
    const uint8_t *d_;
    size_t n_;
    size_t i_ = 0;
};

[[noreturn]] void finding_at(int line) {
    std::fprintf(stderr, "fuzz_api: invariant broken at fuzz_api.cpp:%d\n", line);
    __builtin_trap();
}
#define finding() finding_at(__LINE__)

void check_status(int32_t st) {
    if (std::strcmp(gfmd_status_string(st), "unknown status") == 0) finding();
    if (st == GFMD_ERR_INTERNAL) finding();  // every failure must have a proper cause
}

// The observable state of a handle must always be sane.
void check_state(gfmd_sim *s, int64_t n) {
    double area = -1, gap = -1, el = -1, ad = -1, res = -1;
    if (gfmd_get_contact_area(s, &area) != GFMD_OK || !(area >= 0.0 && area <= 1.0)) finding();
    if (gfmd_get_mean_gap(s, &gap) != GFMD_OK || !(gap >= 0.0) || !std::isfinite(gap)) finding();
    if (gfmd_get_energies(s, &el, &ad) != GFMD_OK || !(el >= 0.0) || !(ad >= 0.0)) finding();
    if (gfmd_get_residual(s, &res) != GFMD_OK || std::isnan(res)) finding();
    std::vector<double> g(static_cast<size_t>(n));
    if (gfmd_get_gap(s, g.data()) != GFMD_OK) finding();
    for (double x : g)
        if (!(x >= 0.0) || !std::isfinite(x)) finding();
    // Persson's theory of any state: OK with a finite variance and an area in [0, 1], or RANGE;
    // with free boundaries refused (STATE) on every call.
    int32_t boundary = -1;
    if (gfmd_get_boundary(s, &boundary) != GFMD_OK) finding();
    if (boundary == GFMD_BOUNDARY_FREE) {
        double x = 0.0;
        if (gfmd_persson_variance(s, &x) != GFMD_ERR_STATE || gfmd_persson_contact_area(s, 0.01, &x) != GFMD_ERR_STATE ||
            gfmd_persson_load(s, 0.3, &x) != GFMD_ERR_STATE)
            finding();
        return;
    }
    double v = -1, pa = -1;
    const int32_t sv = gfmd_persson_variance(s, &v);
    if (sv == GFMD_OK ? !(v >= 0.0 && std::isfinite(v)) : sv != GFMD_ERR_RANGE) finding();
    const int32_t sa = gfmd_persson_contact_area(s, 0.01, &pa);
    if (sa == GFMD_OK ? !(pa >= 0.0 && pa <= 1.0) : sa != GFMD_ERR_RANGE) finding();
    // its inverse at an area in (0, 1): a finite load >= 0, or STATE (a flat substrate) or RANGE
    double load = -1;
    const int32_t sl = gfmd_persson_load(s, 0.3, &load);
    if (sl == GFMD_OK ? !(load >= 0.0 && std::isfinite(load)) : (sl != GFMD_ERR_STATE && sl != GFMD_ERR_RANGE)) finding();
}

// Least squares on a matrix made from the input's remaining bytes: a known status, and on
// success a finite solution and residual.
void fuzz_least_squares(Input &in) {
    const int64_t m = static_cast<int64_t>(in.u8() % 9) - 1, n = static_cast<int64_t>(in.u8() % 5) - 1;
    std::vector<double> a(static_cast<size_t>(std::max<int64_t>(m * n, 1))), b(static_cast<size_t>(std::max<int64_t>(m, 1)));
    for (auto &x : a) x = in.f64();
    for (auto &x : b) x = in.f64();
    std::vector<double> x(static_cast<size_t>(std::max<int64_t>(n, 1)), 0.0);
    double rss = -1;
    const int32_t st = gfmd_least_squares(m, n, a.data(), b.data(), x.data(), &rss);
    check_status(st);
    if (st == GFMD_OK) {
        if (!(rss >= 0.0) || !std::isfinite(rss)) finding();
        for (int64_t j = 0; j < n; ++j)
            if (!std::isfinite(x[static_cast<size_t>(j)])) finding();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    Input in(data, size);
    const int64_t nx = static_cast<int64_t>(in.u8() % 33) - 1;  // includes 0 and -1
    const int64_t ny = static_cast<int64_t>(in.u8() % 33) - 1;
    const double lx = in.f64(), ly = in.f64();
    gfmd_sim *s = nullptr;
    int32_t st = gfmd_sim_create(nx, ny, lx, ly, &s);
    check_status(st);
    if (st != GFMD_OK) {
        if (s != nullptr) finding();
        return 0;
    }
    gfmd_set_threads(s, 1);
    const int64_t n = nx * ny;
    std::vector<double> field(static_cast<size_t>(n));
    const bool trace = std::getenv("FUZZ_TRACE") != nullptr;  // replaying a finding: show the calls
    for (int op = 0; op < 48 && !in.empty(); ++op) {
        const int code = in.u8() % 20;
        switch (code) {
            case 0: st = gfmd_set_modulus(s, in.f64()); break;
            case 1: {
                const int32_t kind = static_cast<int32_t>(in.u8() % 5) - 1;
                st = gfmd_set_green(s, kind, in.f64());
                break;
            }
            case 2: st = gfmd_set_poisson(s, in.f64()); break;
            case 3:
                for (auto &x : field) x = in.f64();
                st = gfmd_set_heights(s, field.data());
                break;
            case 4: {
                // one read per statement: argument evaluation order differs between compilers
                const double hurst = in.f64(), lr = in.f64(), ls = in.f64(), g = in.f64();
                const auto seed = static_cast<uint64_t>(in.i64());
                const auto dist = static_cast<int32_t>(in.u8() % 3);
                st = gfmd_generate_selfaffine(s, hurst, lr, ls, g, seed, dist);
                break;
            }
            case 5: st = gfmd_set_pressure(s, in.f64()); break;
            case 6: {
                const double g0 = in.f64();
                st = gfmd_set_adhesion(s, g0, in.f64());
                break;
            }
            case 7: st = gfmd_set_timestep(s, in.f64()); break;
            case 8: st = gfmd_set_damping(s, in.f64()); break;
            case 9: {  // bytes >= 128 (added later): CG, AUTO and one unknown value
                const int b = in.u8();
                st = gfmd_set_solver(s, static_cast<int32_t>(b < 128 ? b % 4 : 3 + b % 3));
                break;
            }
            case 10: st = gfmd_step(s, static_cast<int64_t>(in.u8() % 40) - 2); break;
            case 11: {
                int64_t taken = -1;
                const double tol = in.f64();
                const int b = in.u8();
                if (b < 200) {
                    st = gfmd_relax(s, tol, static_cast<int64_t>(b) - 1, &taken);
                } else {  // bytes >= 200 (added later): the multilevel start, levels -1 ... 54
                    int64_t coarse = -1;
                    st = gfmd_relax_multilevel(s, tol, 50, static_cast<int32_t>(b) - 201, &taken, &coarse);
                    if (st == GFMD_OK && (taken < 0 || coarse < 0)) finding();
                }
                break;
            }
            case 12: st = gfmd_reset(s); break;
            case 13: st = gfmd_get_pressure(s, field.data()); break;
            case 14: st = gfmd_get_surface(s, field.data()); break;
            case 15: {
                gfmd_sim *c = nullptr;
                st = gfmd_sim_clone(s, &c);
                if (st == GFMD_OK) {
                    check_state(c, n);
                    gfmd_sim_destroy(&c);
                }
                break;
            }
            case 16: st = gfmd_set_fft_planner(s, static_cast<int32_t>(in.u8() % 4) - 1); break;
            case 17: {
                double f = 0;
                const auto kind = static_cast<int32_t>(in.u8() % 4);
                const double t = in.f64();
                const double nu = in.f64();
                st = gfmd_green_factor(kind, t, nu, &f);
                if (st == GFMD_OK && !(f > 0.0 && std::isfinite(f))) finding();
                break;
            }
            case 18: {
                char buf[16];
                st = gfmd_last_error(s, buf, static_cast<int64_t>(in.u8() % 17));
                if (st == GFMD_OK && std::strlen(buf) >= sizeof buf) finding();
                if (st == GFMD_ERR_INVALID_ARG) st = GFMD_OK;
                break;
            }
            default: {
                // the top four bytes switch the boundary (-1 .. 2: two valid, two not); the rest
                // set threads as before the boundary existed (older inputs replay as they did)
                const int b = in.u8();
                st = b >= 252 ? gfmd_set_boundary(s, b - 253) : gfmd_set_threads(s, b % 4 - 1);
                break;
            }
        }
        if (trace) {
            double r = 0;
            gfmd_get_residual(s, &r);
            std::fprintf(stderr, "op %d: call %d -> status %d, residual %g\n", op, code, st, r);
        }
        check_status(st);
        check_state(s, n);
    }
    gfmd_sim_destroy(&s);
    if (s != nullptr) finding();
    if (!in.empty()) fuzz_least_squares(in);  // after the 48 operations: older inputs replay as before
    return 0;
}
