// The element-wise passes (src/kernels.hpp: the completion, the stiffness, the FIRE updates, the
// surface CG's and Polonsky & Keer's passes) of both builds against a plain scalar transcription of
// their definition, and against each other, bit for bit: every length of a block's tail (0 .. 40
// points, and whole blocks of 16384 and 16387), with and without adhesion, with points in
// contact, on the wall and below it, and forces of both signs.  The scalar reference adds point i
// to lane i mod 8 and the lanes in order (the sums' definition); it is compiled with the test's
// own flags, so it also checks that no contraction or reassociation entered either build.  With
// adhesion the passes use their own exponential (the C library's differs between builds): it is
// checked against std::exp (within 2 units in the last place), the adhesive completion against the
// reference to that accuracy, and both builds against each other bit for bit.
//
// The x86-64-v3 build is compared where the library has it and the CPU runs it; elsewhere the test
// says so and checks the baseline alone.
#include <algorithm>
#include <cfenv>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#include "kernels.hpp"

namespace {

using gfmd::kernels::Completion;
using gfmd::kernels::FireUpdate;
using gfmd::kernels::kLanes;
using gfmd::kernels::MassUpdate;

int failures = 0;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_same(const char *what, int64_t n, const double *a, const double *b, int64_t count) {
    for (int64_t i = 0; i < count; ++i)
        if (!same_bits(a[i], b[i])) {
            std::printf("FAIL %s, n = %" PRId64 ", element %" PRId64 ": %a against %a\n", what, n, i, a[i], b[i]);
            ++failures;
            return;
        }
}

// The completion's definition, one point at a time.
void complete_reference(const Completion &in, double *f, int64_t n, double *acc) {
    double lanes[6][kLanes] = {};
    for (int64_t i = 0; i < n; ++i) {
        const int l = static_cast<int>(i % kLanes);
        const double g = in.z[i] - in.h[i];
        double fi = f[i] - in.sigma0;
        if (in.adh_coef > 0.0) {
            const double w = std::exp(-g * in.inv_rho);
            lanes[0][l] += w;
            fi -= in.adh_coef * w;
        }
        f[i] = fi;
        const bool contact = g <= 0.0;
        lanes[5][l] += contact ? 1.0 : 0.0;
        const double r = contact ? (fi > 0.0 ? fi : 0.0) : fi;
        const double rs = r * in.inv_ref;
        lanes[1][l] += r * r;
        lanes[4][l] += rs * rs;
        lanes[2][l] += r * in.v[i];
        lanes[3][l] += in.v[i] * in.v[i];
    }
    for (int k = 0; k < 6; ++k) {
        double t = 0.0;
        for (int l = 0; l < kLanes; ++l) t += lanes[k][l];
        acc[k] += t;
    }
}

// The free points' stress sums (free_stress_sums) by their definition, in the passes' lanes.
void free_stress_reference(const double *z, const double *h, const double *f, double adh_coef, double inv_rho,
                           int64_t n, double *acc) {
    double lanes[2][kLanes] = {};
    for (int64_t i = 0; i < n; ++i) {
        const double g = z[i] - h[i];
        if (!(g > 0.0)) continue;
        const double s = f[i] - (adh_coef > 0.0 ? adh_coef * std::exp(-g * inv_rho) : 0.0);
        lanes[0][i % kLanes] += s;
        lanes[1][i % kLanes] += 1.0;
    }
    for (int k = 0; k < 2; ++k) {
        double t = 0.0;
        for (int l = 0; l < kLanes; ++l) t += lanes[k][l];
        acc[k] += t;
    }
}

double ulps(double got, double want) {
    if (got == want) return 0.0;
    return std::fabs(got - want) / (std::nextafter(std::fabs(want), HUGE_VAL) - std::fabs(want));
}

// mark_held against its definition, one point at a time: held where z <= h and f <= 0, the force
// in contact std::max(f, 0) (-0 and NaN kept), elsewhere untouched; on every tail length, with
// the edge values (z == h, f = +-0, NaN) among the points, and the byte after the last not written.
void check_mark_held(const gfmd::kernels::Table &b) {
    const double edge_f[] = {0.0, -0.0, 1.0, -1.0, std::nan(""), 1e-300, -1e-300};
    const double edge_z[] = {0.0, -1e-300, 1e-300, -1.0, 1.0};
    for (int64_t n = 1; n <= 37; ++n) {
        std::vector<double> z(n), h(n, 0.0), f(n), expect(n);
        std::vector<unsigned char> marks(static_cast<std::size_t>(n) + 1, 7), want(static_cast<std::size_t>(n) + 1, 7);
        for (int64_t i = 0; i < n; ++i) {
            z[i] = edge_z[(i * 3 + n) % 5];
            f[i] = edge_f[(i + n) % 7];
            const bool contact = z[i] <= h[i];
            want[i] = (contact && f[i] <= 0.0) ? 1 : 0;
            expect[i] = contact ? std::max(f[i], 0.0) : f[i];
        }
        b.mark_held(z.data(), h.data(), f.data(), marks.data(), n);
        expect_same("mark_held", n, expect.data(), f.data(), n);
        if (marks != want) {
            std::printf("FAIL mark_held's marks, n = %" PRId64 " (%s)\n", n, b.name);
            ++failures;
        }
    }
}

// The passes' exponential, read off the adhesive weight sum of single points (h = 0, z = -x,
// inv_rho = 1: the sum of one point with zero start is exp(x) itself), against std::exp; the
// normal range and its ends: 0 below -708.39, infinity above 709.78, NaN for NaN.
void check_exp(const gfmd::kernels::Table &b) {
    const char *name = b.name;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-708.3, 709.7), small(-1.0, 1.0);
    double worst = 0.0, worst_x = 0.0;
    auto one = [&](double x) {
        const double z = -x, h = 0.0, v = 0.0;
        double f = 0.0, acc[6] = {};
        b.complete_forces(Completion{&z, &h, &v, 0.0, 1.0, 1.0, 1.0}, &f, 1, acc);
        return acc[0];
    };
    for (int i = 0; i < 200000; ++i) {
        const double x = (i % 2 == 0) ? u(rng) : small(rng);
        const double e = ulps(one(x), std::exp(x));
        if (e > worst) {
            worst = e;
            worst_x = x;
        }
    }
    for (const double x : {0.0, -0.0, 1.0, -1.0, 0.5 * 0.6931471805599453, -708.3, 709.7, -30.0, -36.7})
        worst = std::max(worst, ulps(one(x), std::exp(x)));
    std::printf("test_kernels: %s exp within %.2f ulp of std::exp (worst at x = %.17g)\n", name, worst, worst_x);
    // 2 ulp: the reduction's rounding (r to about 1e-16 absolute, |r| <= 0.35) and 14 Horner steps
    // of about half an ulp each, damped by the small coefficients; measured about 1 ulp.
    if (!(worst <= 2.0)) {
        std::printf("FAIL %s exp: %.2f ulp\n", name, worst);
        ++failures;
    }
    // No floating-point exception on the way for finite arguments (a Fortran program built with
    // -ffpe-trap=invalid,zero,overflow would stop on one): far points have x far below -708.
    std::feclearexcept(FE_ALL_EXCEPT);
    for (const double x : {-708.5, -750.0, -1e3, -4e4, -1e5, -1e12, -1e300, 709.9, 800.0, 1e300}) (void)one(x);
    if (std::fetestexcept(FE_INVALID | FE_OVERFLOW | FE_DIVBYZERO)) {
        std::printf("FAIL %s exp: a floating-point exception (invalid, overflow or division by zero)\n", name);
        ++failures;
    }
    if (one(-708.5) != 0.0 || one(-1e300) != 0.0 || one(-HUGE_VAL) != 0.0 || one(709.9) != HUGE_VAL ||
        one(HUGE_VAL) != HUGE_VAL || !std::isnan(one(NAN))) {
        std::printf("FAIL %s exp: the ends of the range or NaN\n", name);
        ++failures;
    }
}

// Within `ulp` units in the last place of the larger magnitude, element by element.
void expect_close(const char *what, int64_t n, const double *a, const double *b, int64_t count, double ulp) {
    for (int64_t i = 0; i < count; ++i) {
        const double scale = std::max(std::fabs(a[i]), std::fabs(b[i]));
        const double unit = std::nextafter(scale, HUGE_VAL) - scale;
        if (!(std::fabs(a[i] - b[i]) <= ulp * unit)) {
            std::printf("FAIL %s, n = %" PRId64 ", element %" PRId64 ": %a against %a\n", what, n, i, a[i], b[i]);
            ++failures;
            return;
        }
    }
}

struct Data {
    std::vector<double> z, h, v, f;
    explicit Data(int64_t n, std::mt19937_64 &rng) : z(n), h(n), v(n), f(n) {
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (int64_t i = 0; i < n; ++i) {
            h[i] = u(rng);
            const double kind = u(rng);  // a third on the wall, some below it, the rest above
            z[i] = kind < -0.33 ? h[i] : (kind < -0.2 ? h[i] - 0.1 * std::fabs(u(rng)) : h[i] + std::fabs(u(rng)));
            v[i] = 1e-3 * u(rng);
            f[i] = 1e-2 * u(rng);
        }
    }
};

// The surface CG's passes on the data: the masked force, the restriction of a preconditioned
// force, the direction (b = 0.7), two moves (to the wall, and by alpha = 0.3), the Fourier scaling;
// every array and sum appended to out.
template <class Build>
void run_cg(const Build &b, const Data &d, int64_t n, std::vector<double> &out) {
    std::vector<double> zp(n), t = d.v, z = d.z, zp2 = d.v;
    double acc[4] = {};
    b.cg_mask(d.z.data(), d.h.data(), d.f.data(), zp.data(), n);
    b.cg_restrict(d.z.data(), d.h.data(), d.f.data(), zp2.data(), n, acc);
    b.cg_direction(d.z.data(), d.h.data(), d.f.data(), zp2.data(), t.data(), 0.7, 0.0, n, acc + 1);
    std::vector<double> saved(n);
    b.cg_move(z.data(), d.h.data(), t.data(), HUGE_VAL, true, n, acc + 2, nullptr);
    b.cg_move(z.data(), d.h.data(), t.data(), 0.3, false, n, acc + 2, saved.data());
    std::vector<std::complex<double>> work(static_cast<std::size_t>(n));
    for (int64_t i = 0; i < n; ++i) work[i] = {d.f[i], d.v[i]};
    const double w_last = (n % 2 == 0) ? 1.0 : 2.0;  // both kinds of last column, by the length
    acc[3] = b.precondition_modes(work.data(), d.h.data() /* any positive and negative "stiffness" */, 0, 1, n,
                                  1.0 / 3.0, 0.2, w_last);
    for (const auto *a : {&zp, &zp2, &t, &z, &saved}) out.insert(out.end(), a->begin(), a->end());
    for (const auto &w : work) {
        out.push_back(w.real());
        out.push_back(w.imag());
    }
    out.insert(out.end(), acc, acc + 4);
}

// Their definition, one point at a time (a point is held where z <= h and f <= 0).
struct CgReference {
    void cg_mask(const double *z, const double *h, const double *f, double *zp, int64_t n) const {
        for (int64_t i = 0; i < n; ++i) zp[i] = (z[i] <= h[i] && f[i] <= 0.0) ? 0.0 : f[i];
    }
    // the modes scaled, and per row the sum of |scaled mode|^2 as the mode energy's (test_stiffness)
    double precondition_modes(std::complex<double> *work, const double *stiff, int64_t r0, int64_t r1, int64_t nxh,
                              double inv_n, double floor, double w_last) const {
        double sum = 0.0;
        for (int64_t r = r0; r < r1; ++r) {
            std::complex<double> *row = work + r * nxh;
            for (int64_t kx = 0; kx < nxh; ++kx) row[kx] *= inv_n / std::max(stiff[r * nxh + kx], floor);
            double e = std::norm(row[0]);
            if (nxh > 1) e += (w_last - 2.0) * std::norm(row[nxh - 1]);
            double lanes[kLanes] = {};
            for (int64_t j = 0; j < 2 * (nxh - 1); ++j) {
                const double x = (j % 2 == 0) ? row[1 + j / 2].real() : row[1 + j / 2].imag();
                lanes[j % kLanes] += x * x;
            }
            double pairs = 0.0;
            for (const double x : lanes) pairs += x;
            sum += e + 2.0 * pairs;
        }
        return sum;
    }
    static void lanes_to(const double (&lanes)[kLanes], double *acc) {
        double t = 0.0;
        for (const double x : lanes) t += x;
        acc[0] += t;
    }
    void cg_restrict(const double *z, const double *h, const double *f, double *zp, int64_t n, double *acc) const {
        double lanes[kLanes] = {};
        for (int64_t i = 0; i < n; ++i) {
            zp[i] = (z[i] <= h[i] && f[i] <= 0.0) ? 0.0 : zp[i];
            lanes[i % kLanes] += f[i] * zp[i];
        }
        lanes_to(lanes, acc);
    }
    void cg_direction(const double *z, const double *h, const double *f, const double *s, double *t, double b,
                      double /* inv_rho: 0, no adhesion */, int64_t n, double *acc) const {
        double lanes[kLanes] = {};
        for (int64_t i = 0; i < n; ++i) {
            t[i] = (z[i] <= h[i] && f[i] <= 0.0) ? 0.0 : s[i] + b * t[i];
            lanes[i % kLanes] += f[i] * t[i];
        }
        lanes_to(lanes, acc);
    }
    void cg_move(double *z, const double *h, const double *t, double alpha, bool to_wall, int64_t n,
                 double *acc, double *save) const {
        for (int64_t i = 0; i < n; ++i) {
            if (save != nullptr) save[i] = z[i];
            const double zn = to_wall ? (t[i] < 0.0 ? h[i] : z[i]) : z[i] + alpha * t[i];
            const bool hit = zn < h[i] || (to_wall && t[i] < 0.0);
            acc[0] += hit ? 1.0 : 0.0;
            z[i] = hit ? h[i] : zn;
        }
    }
};

// Polonsky & Keer's passes on the data: pressures in contact where f > 0, u = z, a negative
// approach (points on the wall and outside the set penetrate and join), the direction (beta = 0.4),
// the sums, the update (tau = 0.7), the scaling, the approach's sums, the gap with and without the
// surface, and the compliance in Fourier space; every array and sum appended to out.
constexpr double kPkApproach = -0.05;

template <class Build>
void run_pk(const Build &b, const Data &d, int64_t n, std::vector<double> &out) {
    std::vector<double> p(n), r(n), t = d.v, z = d.z;
    for (int64_t i = 0; i < n; ++i) {
        p[i] = d.f[i] > 0.0 ? d.f[i] : 0.0;
        r[i] = 3.0 * d.v[i] + d.f[i];
    }
    const double *u = d.z.data(), *h = d.h.data(), a = kPkApproach;
    double acc[9] = {};
    b.pk_direction(p.data(), u, h, t.data(), a, 0.4, n);
    b.pk_sums(p.data(), r.data(), t.data(), u, h, a, n, acc);
    b.pk_update(p.data(), u, h, t.data(), a, 0.7, n, acc + 4);
    b.pk_scale(p.data(), 1.3, n);
    b.pk_approach(p.data(), u, h, n, acc + 6);
    b.pk_gap(p.data(), u, h, z.data(), a, n, acc + 8);
    b.pk_gap(p.data(), u, h, nullptr, a, n, acc + 8);
    std::vector<std::complex<double>> work(static_cast<std::size_t>(n));
    for (int64_t i = 0; i < n; ++i) work[i] = {d.f[i], d.v[i]};
    b.pk_scale_modes(work.data(), h /* positive and negative "stiffness" */, 0, 1, n, 1.0 / 3.0);
    for (const auto *x : {&p, &t, &z}) out.insert(out.end(), x->begin(), x->end());
    for (const auto &w : work) {
        out.push_back(w.real());
        out.push_back(w.imag());
    }
    out.insert(out.end(), acc, acc + 9);
}

// Their definition, one point at a time (in the set where p > 0, the gap g = (u + a) - h).
struct PkReference {
    using Lanes = double[kLanes];
    static void lanes_to(const Lanes &lanes, double *acc) { CgReference::lanes_to(lanes, acc); }
    void pk_direction(const double *p, const double *u, const double *h, double *t, double a, double beta,
                      int64_t n) const {
        for (int64_t i = 0; i < n; ++i) t[i] = p[i] > 0.0 ? ((u[i] + a) - h[i]) + beta * t[i] : 0.0;
    }
    void pk_sums(const double *p, const double *r, const double *t, const double *u, const double *h, double a,
                 int64_t n, double *acc) const {
        Lanes l[4] = {};
        for (int64_t i = 0; i < n; ++i)
            if (p[i] > 0.0) {
                l[0][i % kLanes] += r[i];
                l[1][i % kLanes] += t[i];
                l[2][i % kLanes] += r[i] * t[i];
                l[3][i % kLanes] += ((u[i] + a) - h[i]) * t[i];
            }
        for (int k = 0; k < 4; ++k) lanes_to(l[k], acc + k);
    }
    void pk_update(double *p, const double *u, const double *h, const double *t, double a, double tau, int64_t n,
                   double *acc) const {
        Lanes l[2] = {};
        for (int64_t i = 0; i < n; ++i) {
            const double g = (u[i] + a) - h[i];
            const bool in = p[i] > 0.0, join = !in && g < 0.0;
            p[i] = in ? std::max(p[i] - tau * t[i], 0.0) : (join ? -tau * g : 0.0);
            l[0][i % kLanes] += p[i];
            l[1][i % kLanes] += join ? 1.0 : 0.0;
        }
        for (int k = 0; k < 2; ++k) lanes_to(l[k], acc + k);
    }
    void pk_scale(double *p, double scale, int64_t n) const {
        for (int64_t i = 0; i < n; ++i) p[i] *= scale;
    }
    void pk_approach(const double *p, const double *u, const double *h, int64_t n, double *acc) const {
        Lanes l[2] = {};
        for (int64_t i = 0; i < n; ++i)
            if (p[i] > 0.0) {
                l[0][i % kLanes] += h[i] - u[i];
                l[1][i % kLanes] += 1.0;
            }
        for (int k = 0; k < 2; ++k) lanes_to(l[k], acc + k);
    }
    void pk_gap(const double *p, const double *u, const double *h, double *z, double a, int64_t n, double *acc) const {
        Lanes l = {};
        for (int64_t i = 0; i < n; ++i) {
            const double g = (u[i] + a) - h[i];
            if (p[i] > 0.0) l[i % kLanes] += g * g;
            if (z) z[i] = p[i] > 0.0 ? h[i] : std::max(h[i], u[i] + a);
        }
        lanes_to(l, acc);
    }
    void pk_scale_modes(std::complex<double> *work, const double *stiff, int64_t r0, int64_t r1, int64_t nxh,
                        double inv_n) const {
        for (int64_t i = r0 * nxh; i < r1 * nxh; ++i) work[i] *= stiff[i] > 0.0 ? inv_n / stiff[i] : 0.0;
    }
};

void run_build(const gfmd::kernels::Table &b, int64_t n, bool adhesive, const Data &d, std::vector<double> &f_out,
               std::vector<double> &zv_out, double *acc, double &energy) {
    const Completion in{d.z.data(), d.h.data(), d.v.data(), 0.05, adhesive ? 5e-4 : 0.0, 1.0 / 0.7, 1.0 / 0.0505};
    f_out = d.f;
    for (int k = 0; k < 6; ++k) acc[k] = 0.25;  // adds onto acc
    b.complete_forces(in, f_out.data(), n, acc);
    double free_acc[2] = {0.25, 0.25};  // adds onto acc
    b.free_stress_sums(d.z.data(), d.h.data(), d.f.data(), in.adh_coef, in.inv_rho, n, free_acc);
    // the FIRE update (downhill, then uphill), the mass-weighted one
    std::vector<double> z = d.z, v = d.v, a = d.f;
    b.fire_update(FireUpdate{0.3, 0.9, 0.07, 0.0, false}, z.data(), v.data(), d.h.data(), d.f.data(), n);
    b.fire_update(FireUpdate{0.15, 0.9, 0.0, 0.075, true}, z.data(), v.data(), d.h.data(), d.f.data(), n);
    std::vector<unsigned char> held(static_cast<std::size_t>(n) + 1);
    b.mark_held(z.data(), d.h.data(), a.data(), held.data(), n);
    b.mass_update(MassUpdate{0.2, 0.8, 0.23, 0.1}, z.data(), v.data(), d.h.data(), a.data(), held.data(), n);
    zv_out = z;
    zv_out.insert(zv_out.end(), v.begin(), v.end());
    zv_out.insert(zv_out.end(), a.begin(), a.end());
    for (int64_t i = 0; i < n; ++i) zv_out.push_back(held[i]);
    zv_out.insert(zv_out.end(), free_acc, free_acc + 2);
    // Fourier space: the rows of a spectrum of n / 3 + 1 columns (odd and even widths)
    const int64_t nxh = n / 3 + 1, rows = 3;
    std::vector<std::complex<double>> work(static_cast<std::size_t>(nxh * rows));
    std::vector<double> stiff(static_cast<std::size_t>(nxh * rows));
    for (int64_t i = 0; i < nxh * rows; ++i) {
        work[i] = {d.h[i % n], d.v[i % n]};
        stiff[i] = 1.0 + std::fabs(d.z[i % n]);
    }
    const double w_last = (n % 2 == 0) ? 1.0 : 2.0;
    // the energy's definition: per row, column 0 and the last once (the last with weight w_last),
    // the others twice, k re^2 and k im^2 of column kx >= 1 in lanes 2 (kx - 1) and 2 (kx - 1) + 1
    // mod 8; the same sum without the scaling (mode_energy), then with it (apply_stiffness)
    double reference = 0.0;
    for (int64_t r = 0; r < rows; ++r) {
        const std::complex<double> *row = work.data() + r * nxh;
        const double *k = stiff.data() + r * nxh;
        double e = k[0] * std::norm(row[0]);
        if (nxh > 1) e += (w_last - 2.0) * k[nxh - 1] * std::norm(row[nxh - 1]);
        double lanes[kLanes] = {};
        for (int64_t j = 0; j < 2 * (nxh - 1); ++j) {
            const double d = (j % 2 == 0) ? row[1 + j / 2].real() : row[1 + j / 2].imag();
            lanes[j % kLanes] += k[1 + j / 2] * (d * d);
        }
        double pairs = 0.0;
        for (const double x : lanes) pairs += x;
        reference += e + 2.0 * pairs;
    }
    const double unscaled = b.mode_energy(work.data(), stiff.data(), 0, rows, nxh, w_last);
    std::vector<std::complex<double>> scaled = work;  // each mode times -k inv_n
    for (int64_t i = 0; i < nxh * rows; ++i) scaled[i] *= -stiff[i] * (1.0 / 7.0);
    energy = b.apply_stiffness(work.data(), stiff.data(), 0, rows, nxh, 1.0 / 7.0, w_last);
    expect_same("stiffness", n, reinterpret_cast<const double *>(scaled.data()),
                reinterpret_cast<const double *>(work.data()), 2 * nxh * rows);
    if (!same_bits(unscaled, reference) || !same_bits(energy, reference)) {
        std::printf("FAIL mode energy, n = %" PRId64 ": %a, %a against %a\n", n, unscaled, energy, reference);
        ++failures;
    }
    for (const auto &w : work) {
        zv_out.push_back(w.real());
        zv_out.push_back(w.imag());
    }
}

const gfmd::kernels::Table base = GFMD_KERNEL_TABLE(kernels_base, "baseline");
#ifdef GFMD_KERNELS_V3
const gfmd::kernels::Table v3 = GFMD_KERNEL_TABLE(kernels_v3, "x86-64-v3");
#endif

// run(build, out) with the reference against the baseline, and the baseline against x86-64-v3
// where the CPU runs it, bit for bit.
template <class Run, class Reference>
void compare_builds(const char *what, int64_t n, Run &&run, const Reference &ref, bool have_v3) {
    std::vector<double> out_ref, out_base;
    run(ref, out_ref);
    run(base, out_base);
    expect_same(what, n, out_ref.data(), out_base.data(), static_cast<int64_t>(out_ref.size()));
#ifdef GFMD_KERNELS_V3
    if (have_v3) {
        std::vector<double> out_v3;
        run(v3, out_v3);
        expect_same(what, n, out_base.data(), out_v3.data(), static_cast<int64_t>(out_base.size()));
    }
#else
    (void)have_v3;
#endif
}

// The adhesive surface CG's passes (rho = 0.5): the direction with the line search's sums at 0,
// the line search's sums at alpha = 0 and 0.3, the step's sums with the adhesive weight after the
// move by 0.3.  Against their definition with std::exp, summed in long double, each sum within
// (n/kLanes + 16) units of rounding of its terms' magnitudes summed: the bound of a sum of n/kLanes
// terms in each lane (Higham's gamma_n), the exponential's 2 ulp and the lanes' addition within
// it (the sums of w t cancel, so a bound relative to the result would not hold); the baseline
// against x86-64-v3 bit for bit, and the direction's sums at 0 bit for bit those of the line pass
// at 0 (the solver takes one for the other).
void check_adhesive_cg(const Data &d, int64_t n, bool have_v3) {
    const double inv_rho = 2.0, alpha = 0.3, b = 0.7;
    const auto run = [&](const gfmd::kernels::Table &k, std::vector<double> &out) {
        std::vector<double> t = d.v, z(n), s(n);
        for (int64_t i = 0; i < n; ++i) s[i] = d.f[i] + 3.0 * d.v[i];
        double acc[13] = {};
        k.cg_direction(d.z.data(), d.h.data(), d.f.data(), s.data(), t.data(), b, inv_rho, n, acc);
        k.cg_adhesive_line(d.z.data(), d.h.data(), t.data(), 0.0, inv_rho, n, acc + 4);
        k.cg_adhesive_line(d.z.data(), d.h.data(), t.data(), alpha, inv_rho, n, acc + 7);
        for (int64_t i = 0; i < n; ++i) z[i] = std::max(d.h[i], d.z[i] + alpha * t[i]);
        k.cg_step_sums(z.data(), d.z.data(), d.f.data(), d.h.data(), inv_rho, true, n, acc + 10);
        out = t;
        out.insert(out.end(), acc, acc + 13);
    };
    std::vector<double> out_base;
    run(base, out_base);
    const double *acc = out_base.data() + n;
    expect_same("adhesive CG: direction's sums at 0 against the line's", n, acc + 1, acc + 4, 3);
    // the reference: t as the direction defines it, then each sum with its magnitude
    std::vector<double> t(n);
    std::vector<long double> ref(13, 0.0L), mag(13, 0.0L);
    const auto add = [&](int k, double x) {
        ref[k] += x;
        mag[k] += std::fabs(x);
    };
    for (int64_t i = 0; i < n; ++i) {
        const double s = d.f[i] + 3.0 * d.v[i];
        t[i] = (d.z[i] <= d.h[i] && d.f[i] <= 0.0) ? 0.0 : s + b * d.v[i];
        add(0, d.f[i] * t[i]);
        for (const auto &[k, a] : {std::pair<int, double>{4, 0.0}, {7, alpha}}) {
            const double g = (d.z[i] - d.h[i]) + a * t[i], w = g > 0.0 ? std::exp(-g * inv_rho) : 1.0;
            add(k, w * t[i]);
            add(k + 1, g > 0.0 ? w * t[i] * t[i] : 0.0);
            add(k + 2, w);
        }
        const double zn = std::max(d.h[i], d.z[i] + alpha * t[i]), dz = zn - d.z[i];
        add(10, dz);
        add(11, d.f[i] * dz);
        add(12, std::exp(-(zn - d.h[i]) * inv_rho));
    }
    for (int k = 1; k <= 3; ++k) {
        ref[k] = ref[k + 3];
        mag[k] = mag[k + 3];
    }
    expect_same("adhesive CG: direction", n, t.data(), out_base.data(), n);
    const long double units = static_cast<long double>(n / kLanes + 16) * 0x1p-52L;
    for (int k = 0; k < 13; ++k)
        if (!(std::fabs(acc[k] - ref[k]) <= units * mag[k])) {
            std::printf("FAIL adhesive CG sum %d, n = %" PRId64 ": %a against %La\n", k, n, acc[k], ref[k]);
            ++failures;
        }
#ifdef GFMD_KERNELS_V3
    if (have_v3) {
        std::vector<double> out_v3;
        run(v3, out_v3);
        expect_same("adhesive CG: x86-64-v3", n, out_base.data(), out_v3.data(), static_cast<int64_t>(out_base.size()));
    }
#else
    (void)have_v3;
#endif
}

}  // namespace

int main() {
    bool have_v3 = false;
#ifdef GFMD_KERNELS_V3
    __builtin_cpu_init();
    have_v3 = __builtin_cpu_supports("x86-64-v3");
#endif
    std::printf("test_kernels: %s\n", have_v3 ? "baseline and x86-64-v3 builds" : "the baseline build only");
    // The library's choice (kernels_dispatch.cpp, linked here as in the library): the x86-64-v3 build
    // where the CPU runs it, the baseline where it does not or GFMD_KERNELS=baseline says so (ctest
    // runs this program both ways, test_kernels and test_kernels_baseline).
    const char *forced = std::getenv("GFMD_KERNELS");
    const bool want_base = !have_v3 || (forced != nullptr && std::strcmp(forced, "baseline") == 0);
    const gfmd::kernels::Table &chosen = gfmd::kernels::use();
    std::printf("test_kernels: the library runs the %s build\n", chosen.name);
#ifdef GFMD_KERNELS_V3
    const gfmd::kernels::Table &expected = want_base ? base : v3;
#else
    const gfmd::kernels::Table &expected = base;
#endif
    if (std::strcmp(chosen.name, expected.name) != 0 || chosen.complete_forces != expected.complete_forces) {
        std::printf("FAIL the library chose the %s build\n", chosen.name);
        ++failures;
    }
    check_exp(base);
    check_mark_held(base);
#ifdef GFMD_KERNELS_V3
    if (have_v3) {
        check_exp(v3);
        check_mark_held(v3);
    }
#endif
    std::mt19937_64 rng(2016);
    std::vector<int64_t> lengths;
    for (int64_t n = 1; n <= 40; ++n) lengths.push_back(n);
    lengths.push_back(16384);
    lengths.push_back(16387);
    for (const int64_t n : lengths) {
        const Data d(n, rng);
        for (const bool adhesive : {false, true}) {
            const char *what = adhesive ? "adhesive" : "non-adhesive";
            // the definition against the baseline build
            std::vector<double> f_ref = d.f;
            double acc_ref[6];
            for (double &a : acc_ref) a = 0.25;
            const Completion in{d.z.data(), d.h.data(), d.v.data(), 0.05, adhesive ? 5e-4 : 0.0, 1.0 / 0.7,
                                1.0 / 0.0505};
            complete_reference(in, f_ref.data(), n, acc_ref);
            std::vector<double> f_base, out_base;
            double acc_base[6], e_base = 0.0;
            run_build(base, n, adhesive, d, f_base, out_base, acc_base, e_base);
            if (!adhesive) {
                expect_same(what, n, f_ref.data(), f_base.data(), n);
                expect_same(what, n, acc_ref, acc_base, 6);
            } else {
                // The forces are f - sigma0 - adh_coef w with |adh_coef w| <= 5e-4 e^0.07 against
                // |f - sigma0| >= 0.04: a 2-ulp w moves them by far less than one ulp of theirs, but
                // a rounding boundary may be crossed (1 ulp).  The sums add 2-ulp terms (weights) or
                // terms of 1-ulp forces (squares, products: 2-3 ulp): within 4 ulp of the sum.
                expect_close(what, n, f_ref.data(), f_base.data(), n, 1.0);
                expect_close(what, n, acc_ref, acc_base, 6, 4.0);
            }
            // the free points' stress sums: exact without adhesion; with it the terms f - adh_coef w
            // move by at most one ulp (as the forces above), the sum (from 0.25) within 4 ulp
            double free_ref[2] = {0.25, 0.25}, free_base[2] = {0.25, 0.25};
            free_stress_reference(d.z.data(), d.h.data(), d.f.data(), in.adh_coef, in.inv_rho, n, free_ref);
            base.free_stress_sums(d.z.data(), d.h.data(), d.f.data(), in.adh_coef, in.inv_rho, n, free_base);
            if (!adhesive)
                expect_same("free stress", n, free_ref, free_base, 2);
            else
                expect_close("free stress", n, free_ref, free_base, 2, 4.0);
            // the contacts are counted exactly
            int64_t touching = 0;
            for (int64_t i = 0; i < n; ++i) touching += (d.z[i] <= d.h[i]) ? 1 : 0;
            if (acc_base[5] != 0.25 + static_cast<double>(touching)) {
                std::printf("FAIL contacts, n = %" PRId64 ": %g against %" PRId64 "\n", n, acc_base[5] - 0.25, touching);
                ++failures;
            }
            if (adhesive) check_adhesive_cg(d, n, have_v3);
            if (!adhesive) {  // the CGs' passes without adhesion
                compare_builds("CG", n, [&](const auto &b, std::vector<double> &out) { run_cg(b, d, n, out); },
                               CgReference{}, have_v3);
                compare_builds("PK", n, [&](const auto &b, std::vector<double> &out) { run_pk(b, d, n, out); },
                               PkReference{}, have_v3);
            }
#ifdef GFMD_KERNELS_V3
            if (have_v3) {
                std::vector<double> f_v3, out_v3;
                double acc_v3[6], e_v3 = 0.0;
                run_build(v3, n, adhesive, d, f_v3, out_v3, acc_v3, e_v3);
                expect_same(what, n, f_base.data(), f_v3.data(), n);
                expect_same(what, n, acc_base, acc_v3, 6);
                expect_same(what, n, out_base.data(), out_v3.data(), static_cast<int64_t>(out_base.size()));
                expect_same(what, n, &e_base, &e_v3, 1);
            }
#endif
        }
    }
    std::printf("test_kernels: %d failure(s)\n", failures);
    return failures == 0 ? 0 : 1;
}
