#include "kernels.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

// Built as gfmd::kernels_base, and where the compiler can, once more with -march=x86-64-v3 as
// gfmd::kernels_v3 (GFMD_KERNELS_NS; CMakeLists.txt).
#ifndef GFMD_KERNELS_NS
#define GFMD_KERNELS_NS kernels_base
#endif

namespace gfmd {
namespace GFMD_KERNELS_NS {

using kernels::Completion;
using kernels::FireUpdate;
using kernels::kLanes;
using kernels::MassUpdate;

namespace {

// Four doubles as one value (GCC's vector extension): each operation is the IEEE operation on
// every element, in one AVX register or two SSE2 ones, so the lanes' arithmetic and hence the bits
// are the same for every instruction set.
typedef double Quad __attribute__((vector_size(32)));
typedef long long QuadMask __attribute__((vector_size(32)));
typedef unsigned long long QuadBits __attribute__((vector_size(32)));

inline __attribute__((always_inline)) Quad load(const double *p) {
    Quad x;
    __builtin_memcpy(&x, p, sizeof x);
    return x;
}
inline __attribute__((always_inline)) void store(double *p, Quad x) { __builtin_memcpy(p, &x, sizeof x); }

// x where the mask is set, +0 elsewhere; blend: x where it is set, y elsewhere
inline __attribute__((always_inline)) Quad select(QuadMask mask, Quad x) {
    return reinterpret_cast<Quad>(reinterpret_cast<QuadMask>(x) & mask);
}
inline __attribute__((always_inline)) Quad blend(QuadMask mask, Quad x, Quad y) {
    return reinterpret_cast<Quad>((reinterpret_cast<QuadMask>(x) & mask) | (reinterpret_cast<QuadMask>(y) & ~mask));
}

// body(full, i, m, half) for the quads of 8 points: i the first point of a quad, m <= 4 the points
// of it that exist (full: std::true_type, all 4), half 0 or 1: the lanes 0-3 or 4-7 of an octet.
template <class Body>
inline __attribute__((always_inline)) void over_octets(int64_t n, Body &&body) {
    int64_t i = 0;
    for (; i + 2 * 4 <= n; i += 2 * 4) {
        body(std::true_type{}, i, int64_t{4}, 0);
        body(std::true_type{}, i + 4, int64_t{4}, 1);
    }
    if (i < n) {
        body(std::false_type{}, i, n - i, 0);
        body(std::false_type{}, i + 4, n - i - 4, 1);
    }
}
// m of the 4 values at p, pad for the others; and the first m of x stored.
template <class Full>
inline __attribute__((always_inline)) Quad load_some(Full, const double *p, int64_t m, double pad) {
    if constexpr (Full::value) {
        return load(p);
    } else {
        double t[4];
        for (int64_t l = 0; l < 4; ++l) t[l] = l < m ? p[l] : pad;
        return load(t);
    }
}
template <class Full>
inline __attribute__((always_inline)) void store_some(Full, double *p, Quad x, int64_t m) {
    if constexpr (Full::value) {
        store(p, x);
    } else {
        for (int64_t l = 0; l < m && l < 4; ++l) p[l] = x[l];
    }
}
// The two halves' lanes added in order, onto acc.
inline void add_lanes(const Quad (&q)[2], double *acc) {
    double t = 0.0;
    for (int half = 0; half < 2; ++half)
        for (int l = 0; l < 4; ++l) t += q[half][l];
    acc[0] += t;
}
// Where the wall holds a point of the surface CG: in contact and pushed into it.
inline __attribute__((always_inline)) QuadMask held(Quad z, Quad h, Quad f) { return (z <= h) & (f <= 0.0); }

// exp(x) of each element in IEEE operations alone, so that it has the same bits in every build
// (the C library's exp is scalar, and its vector forms differ between instruction sets).
// Cody & Waite's reduction x = k ln2 + r, |r| <= ln2/2 (ln2 split so that k ln2_hi is exact), the
// Taylor polynomial of degree 13 for e^r (remainder below r^14/14! < 4e-18 relative), then 2^k from
// the exponent bits (exact: p 2^k is a normal number in this range); k is read off the bits of
// x log2(e) + 1.5 * 2^52 (no conversion to an integer type).  Within 2 units in the last place of
// std::exp (test_kernels asserts 2, measures 1);
// below x = -708.39 (where exp(x) is no longer a normal number) it returns 0, above 709.78
// infinity, NaN for NaN.
inline __attribute__((always_inline)) Quad exp_quad(Quad x) {
    const Quad zero = {};
    constexpr double lowest = -708.39, highest = 709.78;
    // the arithmetic on the range's ends only: no overflow or invalid operation on the way for any
    // argument (a program that traps floating-point exceptions would stop on one)
    const Quad xr = blend(x < lowest, zero + lowest, blend(x > highest, zero + highest, x));
    const Quad magic = zero + 6755399441055744.0;  // 1.5 * 2^52
    const Quad t = xr * 1.4426950408889634 + magic;  // round(x log2(e)) in the low bits
    const Quad k = t - magic;
    const Quad r = (xr - k * 0.693145751953125) - k * 1.4286068203094172321e-6;  // ln2 = hi + lo
    // Estrin's scheme (pairs in r, then in r^2, r^4, r^8: a short dependency chain) for
    // e^r - 1, and the 1 added last, so that the sums' rounding is relative to |e^r - 1| <= 0.42
    const Quad r2 = r * r, r4 = r2 * r2, r8 = r4 * r4;
    const Quad a1 = 0.5 + r * (1.0 / 6.0), a2 = 1.0 / 24.0 + r * (1.0 / 120.0),
               a3 = 1.0 / 720.0 + r * (1.0 / 5040.0), a4 = 1.0 / 40320.0 + r * (1.0 / 362880.0),
               a5 = 1.0 / 3628800.0 + r * (1.0 / 39916800.0), a6 = 1.0 / 479001600.0 + r * (1.0 / 6227020800.0);
    const Quad b0 = r + r2 * a1, b1 = a2 + r2 * a3, b2 = a4 + r2 * a5;
    const Quad c0 = b0 + r4 * b1, c1 = b2 + r4 * a6;
    const Quad p = 1.0 + (c0 + r8 * c1);
    const QuadMask ki = reinterpret_cast<QuadMask>(t) - reinterpret_cast<QuadMask>(magic);
    // k = 1024 (x above 709.09) has no exponent field of its own: 2^1023, then times 2
    const QuadMask top = ki > 1023;  // -1 where set
    const Quad scale = reinterpret_cast<Quad>(reinterpret_cast<QuadBits>(ki + top + 1023) << 52);
    const Quad y0 = p * scale;
    const Quad y = blend(top, y0 * 2.0, y0);
    const Quad inf = zero + HUGE_VAL;
    // x below the normal range: 0; above: infinity; NaN stays NaN (both comparisons false)
    return blend(x < lowest, zero, blend(x > highest, inf, y));
}

// The completion in kLanes = 8 lanes (over_octets).  Pads of the last octet: an infinite gap (no
// adhesion, no contact), the force sigma0 (zero once completed) and zero velocity: they add
// nothing.
template <bool Adhesive>
inline __attribute__((always_inline)) void complete(const Completion &in, double *f, int64_t n, double *acc) {
    static_assert(kLanes == 2 * 4, "two Quads");
    const Quad one = Quad{} + 1.0;
    Quad adh[2] = {}, f2[2] = {}, power[2] = {}, v2[2] = {}, rel2[2] = {}, touching[2] = {};
    over_octets(n, [&](auto full, int64_t i, int64_t m, int half) {
        const Quad g = load_some(full, in.z + i, m, HUGE_VAL) - load_some(full, in.h + i, m, 0.0);
        Quad fi = load_some(full, f + i, m, in.sigma0) - in.sigma0;
        if constexpr (Adhesive) {
            const Quad w = exp_quad(-g * in.inv_rho);
            adh[half] += w;
            fi -= in.adh_coef * w;
        }
        store_some(full, f + i, fi, m);
        // selects as bit masks (SSE2 has no blend instruction; GCC's lowering of ?: to it is slow)
        const QuadMask contact = g <= 0.0;
        touching[half] += select(contact, one);
        const Quad r = blend(contact, select(fi > 0.0, fi), fi);  // in contact only pulling away counts
        const Quad rs = r * in.inv_ref;                           // the residual, scaled first: no overflow
        const Quad vq = load_some(full, in.v + i, m, 0.0);
        f2[half] += r * r;
        rel2[half] += rs * rs;
        power[half] += r * vq;
        v2[half] += vq * vq;
    });
    add_lanes(adh, acc);
    add_lanes(f2, acc + 1);
    add_lanes(power, acc + 2);
    add_lanes(v2, acc + 3);
    add_lanes(rel2, acc + 4);
    add_lanes(touching, acc + 5);
}

}  // namespace

void complete_forces(const Completion &in, double *f, int64_t n, double *acc) {
    if (in.adh_coef > 0.0)
        complete<true>(in, f, n, acc);
    else
        complete<false>(in, f, n, acc);
}

namespace {
// The free points' stress sums in lanes (over_octets).  Pads of the last octet: a point on the
// wall (z = 0, h = 1), which is not free and adds nothing.
template <bool Adhesive>
inline __attribute__((always_inline)) void free_sums(const double *z, const double *h, const double *f,
                                                     double adh_coef, double inv_rho, int64_t n, double *acc) {
    const Quad one = Quad{} + 1.0;
    Quad stress[2] = {}, count[2] = {};
    over_octets(n, [&](auto full, int64_t i, int64_t m, int half) {
        const Quad g = load_some(full, z + i, m, 0.0) - load_some(full, h + i, m, 1.0);
        Quad si = load_some(full, f + i, m, 0.0);
        if constexpr (Adhesive) si -= adh_coef * exp_quad(-g * inv_rho);
        const QuadMask free = g > 0.0;
        stress[half] += select(free, si);
        count[half] += select(free, one);
    });
    add_lanes(stress, acc);
    add_lanes(count, acc + 1);
}
}  // namespace

void free_stress_sums(const double *z, const double *h, const double *f, double adh_coef, double inv_rho, int64_t n,
                      double *acc) {
    if (adh_coef > 0.0)
        free_sums<true>(z, h, f, adh_coef, inv_rho, n, acc);
    else
        free_sums<false>(z, h, f, adh_coef, inv_rho, n, acc);
}

namespace {
// The pass over the modes of rows [r0, r1) of width nxh behind apply_stiffness, mode_energy and
// precondition_modes: per row a sum over the full plane (column 0 and a Nyquist column, weight
// w_last, once; the others twice, their re and im terms summed in kLanes lanes of the row's
// interleaved doubles, the lanes added in order), the rows in order; with Mode::kScale each mode is
// scaled on the way (Modes then non-const; without, read only).  Mode gives a column's term
// (column 0 and the Nyquist correction, weight * ...), the quads' factor and term.
template <class Mode, class Modes>
inline __attribute__((always_inline)) double row_sums(Modes *work, const double *stiff, int64_t r0, int64_t r1,
                                                      int64_t nxh, double w_last, const Mode &mode) {
    static_assert(Mode::kScale ? !std::is_const_v<Modes> : true, "scaling writes the modes");
    using Real = std::conditional_t<std::is_const_v<Modes>, const double, double>;
    double energy = 0.0;
    for (int64_t r = r0; r < r1; ++r) {
        Real *row = reinterpret_cast<Real *>(work + r * nxh);  // re, im interleaved
        const double *krow = stiff + r * nxh;
        double e = mode.column(1.0, krow[0], work[r * nxh]);
        if (nxh > 1) e += mode.column(w_last - 2.0, krow[nxh - 1], work[r * nxh + nxh - 1]);
        if constexpr (Mode::kScale) work[r * nxh] = mode.scaled(krow[0], work[r * nxh]);
        // columns 1 .. nxh - 1: 2 (nxh - 1) doubles, a quad holding two modes
        Quad lanes[2] = {};
        over_octets(2 * (nxh - 1), [&](auto full, int64_t i, int64_t m, int half) {
            const double *k = krow + 1 + i / 2;
            const double k0 = m > 0 ? k[0] : 0.0, k1 = m > 2 ? k[1] : 0.0;  // no k past the row
            const Quad kk = {k0, k0, k1, k1};
            const Quad d = load_some(full, row + 2 + i, m, 0.0);
            const Quad ds = d * mode.factor(kk);
            lanes[half] += mode.term(kk, d, ds);
            if constexpr (Mode::kScale) store_some(full, row + 2 + i, ds, m);
        });
        double pairs = 0.0;
        add_lanes(lanes, &pairs);
        energy += e + 2.0 * pairs;
    }
    return energy;
}

// The elastic energy sum of k |Z|^2, each mode scaled by -k inv_n if Scale.
template <bool Scale>
struct Energy {
    static constexpr bool kScale = Scale;
    double inv_n;
    double column(double weight, double k, std::complex<double> z) const { return weight * k * std::norm(z); }
    std::complex<double> scaled(double k, std::complex<double> z) const { return z * (-k * inv_n); }
    Quad factor(Quad kk) const { return -kk * inv_n; }
    Quad term(Quad kk, Quad d, Quad) const { return kk * (d * d); }
};

// Each mode scaled by inv_n / max(k, floor), and the sum of |scaled mode|^2.
struct Precondition {
    static constexpr bool kScale = true;
    double inv_n, floor;
    double column(double weight, double k, std::complex<double> z) const { return weight * std::norm(scaled(k, z)); }
    std::complex<double> scaled(double k, std::complex<double> z) const { return z * (inv_n / std::max(k, floor)); }
    Quad factor(Quad kk) const { return inv_n / blend(kk < floor, Quad{} + floor, kk); }  // std::max(k, floor)
    Quad term(Quad, Quad, Quad ds) const { return ds * ds; }
};
}  // namespace

double apply_stiffness(std::complex<double> *work, const double *stiff, int64_t r0, int64_t r1, int64_t nxh,
                       double inv_n, double w_last) {
    return row_sums(work, stiff, r0, r1, nxh, w_last, Energy<true>{inv_n});
}

double mode_energy(const std::complex<double> *work, const double *stiff, int64_t r0, int64_t r1, int64_t nxh,
                   double w_last) {
    return row_sums(work, stiff, r0, r1, nxh, w_last, Energy<false>{1.0});
}

double precondition_modes(std::complex<double> *work, const double *stiff, int64_t r0, int64_t r1, int64_t nxh,
                          double inv_n, double floor, double w_last) {
    return row_sums(work, stiff, r0, r1, nxh, w_last, Precondition{inv_n, floor});
}

void fire_update(const FireUpdate &u, double *__restrict z, double *__restrict v,
                             const double *__restrict h, const double *__restrict f, int64_t n) {
    const double dt = u.dt, keep = u.keep, mix = u.mix, back = u.back;
    const bool uphill = u.uphill;
    // Branch-free (selects), so that scattered contact points cost no mispredictions and the loop
    // vectorizes.
#pragma omp simd
    for (int64_t i = 0; i < n; ++i) {
        const double zo = z[i], vo = v[i], hi = h[i], fo = f[i];
        const double fi = (zo <= hi) ? std::max(fo, 0.0) : fo;
        double vi = uphill ? 0.0 : vo;
        vi += dt * fi;
        vi = keep * vi + mix * fi;
        const double zn = zo - back * vo + dt * vi;
        const bool hit = zn < hi;  // the wall stops a point that reaches it
        v[i] = hit ? 0.0 : vi;
        z[i] = hit ? hi : zn;
    }
}

// In quads with selects: GCC left the loop of bools stored as bytes scalar, with a branch on the
// contact that mispredicts at scattered contact points.
// Pads of the last octet are not stored.
void mark_held(const double *z, const double *h, double *f, unsigned char *marks, int64_t n) {
    over_octets(n, [&](auto full, int64_t i, int64_t m, int) {
        const Quad zq = load_some(full, z + i, m, 1.0), hq = load_some(full, h + i, m, 0.0),
                   fo = load_some(full, f + i, m, 0.0);
        const QuadMask hold = held(zq, hq, fo);
        // in contact: std::max(fo, 0.0), which keeps -0 and NaN as the scalar pass did
        store_some(full, f + i, blend(zq <= hq, select(~(fo < 0.0), fo), fo), m);
        for (int64_t l = 0; l < m && l < 4; ++l) marks[i + l] = static_cast<unsigned char>(hold[l] & 1);
    });
}

void mass_update(const MassUpdate &u, double *__restrict z, double *__restrict v,
                             const double *__restrict h, const double *__restrict a,
                             const unsigned char *__restrict held, int64_t n) {
    const double dt = u.dt, keep = u.keep, mix_dt = u.mix_dt, back = u.back;
#pragma omp simd
    for (int64_t i = 0; i < n; ++i) {  // branch-free, as fire_update()
        const double zo = z[i], vo = v[i], hi = h[i], ao = a[i];
        const double ai = held[i] ? 0.0 : ao;
        const double vi = keep * vo + mix_dt * ai;
        const double zn = zo - back * vo + dt * vi;
        const bool hit = zn < hi;
        v[i] = hit ? 0.0 : vi;
        z[i] = hit ? hi : zn;
    }
}

// The surface CG's passes.  Pads of the last octet: a free point (z = 1 > h = 0) with zero force,
// direction and preconditioned force, which adds nothing and stops nothing.
void cg_mask(const double *z, const double *h, const double *f, double *zp, int64_t n) {
    over_octets(n, [&](auto full, int64_t i, int64_t m, int) {
        const Quad fq = load_some(full, f + i, m, 0.0);
        store_some(full, zp + i, select(~held(load_some(full, z + i, m, 1.0), load_some(full, h + i, m, 0.0), fq), fq), m);
    });
}

void cg_restrict(const double *z, const double *h, const double *f, double *zp, int64_t n, double *acc) {
    Quad rz[2] = {};
    over_octets(n, [&](auto full, int64_t i, int64_t m, int half) {
        const Quad fq = load_some(full, f + i, m, 0.0);
        const QuadMask free = ~held(load_some(full, z + i, m, 1.0), load_some(full, h + i, m, 0.0), fq);
        const Quad p = select(free, load_some(full, zp + i, m, 0.0));
        store_some(full, zp + i, p, m);
        rz[half] += fq * p;
    });
    add_lanes(rz, acc);
}

namespace {
// The adhesive line search's terms at the gap g along t (cg_adhesive_line): the weight w =
// exp(-g inv_rho) above the wall, 1 at it, added to s0, w t to s1, w t^2 above the wall to s2.
inline __attribute__((always_inline)) void add_line_terms(Quad g, Quad t, double inv_rho, Quad &s0, Quad &s1,
                                                          Quad &s2) {
    const Quad one = Quad{} + 1.0;
    const Quad w = blend(g > 0.0, exp_quad(-g * inv_rho), one);
    s0 += w;
    s1 += w * t;
    s2 += select(g > 0.0, w * (t * t));
}

// Pads of the last octet: an infinite gap, so t = 0 and no weight.
template <bool Adhesive>
inline __attribute__((always_inline)) void direction(const double *z, const double *h, const double *f, const double *s,
                                                     double *t, double b, double inv_rho, int64_t n, double *acc) {
    Quad rt[2] = {}, s1[2] = {}, s2[2] = {}, s0[2] = {};
    over_octets(n, [&](auto full, int64_t i, int64_t m, int half) {
        const Quad fq = load_some(full, f + i, m, 0.0);
        const Quad zq = load_some(full, z + i, m, HUGE_VAL), hq = load_some(full, h + i, m, 0.0);
        const QuadMask free = ~held(zq, hq, fq);
        const Quad ti = select(free, load_some(full, s + i, m, 0.0) + b * load_some(full, t + i, m, 0.0));
        store_some(full, t + i, ti, m);
        rt[half] += fq * ti;
        if constexpr (Adhesive) add_line_terms(zq - hq, ti, inv_rho, s0[half], s1[half], s2[half]);  // alpha = 0
    });
    add_lanes(rt, acc);
    if constexpr (Adhesive) {
        add_lanes(s1, acc + 1);
        add_lanes(s2, acc + 2);
        add_lanes(s0, acc + 3);
    }
}
}  // namespace

void cg_direction(const double *z, const double *h, const double *f, const double *s, double *t, double b,
                  double inv_rho, int64_t n, double *acc) {
    if (inv_rho > 0.0)
        direction<true>(z, h, f, s, t, b, inv_rho, n, acc);
    else
        direction<false>(z, h, f, s, t, b, inv_rho, n, acc);
}

// Pads of the last octet: t = 0 and an infinite gap, adding nothing.
void cg_adhesive_line(const double *z, const double *h, const double *t, double alpha, double inv_rho, int64_t n,
                      double *acc) {
    Quad s1[2] = {}, s2[2] = {}, s0[2] = {};
    over_octets(n, [&](auto full, int64_t i, int64_t m, int half) {
        const Quad ti = load_some(full, t + i, m, 0.0);
        const Quad g = (load_some(full, z + i, m, HUGE_VAL) - load_some(full, h + i, m, 0.0)) + alpha * ti;
        add_line_terms(g, ti, inv_rho, s0[half], s1[half], s2[half]);
    });
    add_lanes(s1, acc);
    add_lanes(s2, acc + 1);
    add_lanes(s0, acc + 2);
}

namespace {
template <bool Adhesive>
inline __attribute__((always_inline)) void step_sums(const double *z, const double *z0, const double *f,
                                                     const double *h, double inv_rho, int64_t n, double *acc) {
    Quad dz[2] = {}, fdz[2] = {}, w[2] = {};
    over_octets(n, [&](auto full, int64_t i, int64_t m, int half) {
        const Quad zi = load_some(full, z + i, m, HUGE_VAL);
        const Quad d = select(zi < HUGE_VAL, zi - load_some(full, z0 + i, m, 0.0));
        dz[half] += d;
        fdz[half] += load_some(full, f + i, m, 0.0) * d;
        if constexpr (Adhesive) w[half] += exp_quad(-(zi - load_some(full, h + i, m, 0.0)) * inv_rho);
    });
    add_lanes(dz, acc);
    add_lanes(fdz, acc + 1);
    if constexpr (Adhesive) add_lanes(w, acc + 2);
}
}  // namespace

void cg_step_sums(const double *z, const double *z0, const double *f, const double *h, double inv_rho,
                  bool adhesive, int64_t n, double *acc) {
    if (adhesive)
        step_sums<true>(z, z0, f, h, inv_rho, n, acc);
    else
        step_sums<false>(z, z0, f, h, inv_rho, n, acc);
}

void cg_move(double *z, const double *h, const double *t, double alpha, bool to_wall, int64_t n, double *acc,
             double *save) {
    const Quad zero = {}, one = zero + 1.0;
    const double step = to_wall ? 0.0 : alpha;  // alpha may be infinite when the step goes to the wall
    const QuadMask wall = (zero + (to_wall ? 1.0 : 0.0)) > 0.0;
    Quad stopped[2] = {};
    over_octets(n, [&](auto full, int64_t i, int64_t m, int half) {
        const Quad zo = load_some(full, z + i, m, 1.0), hi = load_some(full, h + i, m, 0.0),
                   ti = load_some(full, t + i, m, 0.0);
        const QuadMask down = ti < 0.0;
        const Quad zn = blend(wall, blend(down, hi, zo), zo + step * ti);
        const QuadMask hit = (zn < hi) | (wall & down);
        stopped[half] += select(hit, one);
        if (save != nullptr) store_some(full, save + i, zo, m);
        store_some(full, z + i, blend(hit, hi, zn), m);
    });
    add_lanes(stopped, acc);
}

// Polonsky & Keer's passes (PolonskyKeer, pk.cpp): a point is in the contact set where p > 0, its
// gap is g = (u + a) - h.  Pads of the last octet: p = u = 0 (outside the set) and h = a (gap 0: it
// does not penetrate, so it joins nothing), which add nothing.
namespace {
inline __attribute__((always_inline)) QuadMask in_set(Quad p) { return p > 0.0; }
// The gap (u + a) - h of the quad at i, its pads 0.
template <class Full>
inline __attribute__((always_inline)) Quad pk_gap_of(Full full, const double *u, const double *h, int64_t i, int64_t m,
                                                     double a) {
    return (load_some(full, u + i, m, 0.0) + a) - load_some(full, h + i, m, a);
}
}  // namespace

void pk_direction(const double *p, const double *u, const double *h, double *t, double a, double beta, int64_t n) {
    over_octets(n, [&](auto full, int64_t i, int64_t m, int) {
        const Quad g = pk_gap_of(full, u, h, i, m, a);
        const Quad ti = g + beta * load_some(full, t + i, m, 0.0);
        store_some(full, t + i, select(in_set(load_some(full, p + i, m, 0.0)), ti), m);
    });
}

void pk_sums(const double *p, const double *r, const double *t, const double *u, const double *h, double a,
             int64_t n, double *acc) {
    Quad sr[2] = {}, st[2] = {}, srt[2] = {}, sgt[2] = {};
    over_octets(n, [&](auto full, int64_t i, int64_t m, int half) {
        const QuadMask in = in_set(load_some(full, p + i, m, 0.0));
        const Quad ri = load_some(full, r + i, m, 0.0), ti = load_some(full, t + i, m, 0.0);
        const Quad g = pk_gap_of(full, u, h, i, m, a);
        sr[half] += select(in, ri);
        st[half] += select(in, ti);
        srt[half] += select(in, ri * ti);
        sgt[half] += select(in, g * ti);
    });
    add_lanes(sr, acc);
    add_lanes(st, acc + 1);
    add_lanes(srt, acc + 2);
    add_lanes(sgt, acc + 3);
}

void pk_update(double *p, const double *u, const double *h, const double *t, double a, double tau, int64_t n,
               double *acc) {
    const Quad zero = {}, one = zero + 1.0;
    Quad total[2] = {}, joined[2] = {};
    over_octets(n, [&](auto full, int64_t i, int64_t m, int half) {
        const Quad pi = load_some(full, p + i, m, 0.0);
        const Quad g = pk_gap_of(full, u, h, i, m, a);
        const QuadMask in = in_set(pi), join = ~in & (g < 0.0);
        const Quad down = pi - tau * load_some(full, t + i, m, 0.0);
        const Quad kept = blend(down < 0.0, zero, down);  // std::max(down, 0.0), NaN kept
        const Quad pn = blend(in, kept, select(join, -tau * g));
        store_some(full, p + i, pn, m);
        total[half] += pn;
        joined[half] += select(join, one);
    });
    add_lanes(total, acc);
    add_lanes(joined, acc + 1);
}

void pk_scale(double *p, double scale, int64_t n) {
#pragma omp simd
    for (int64_t i = 0; i < n; ++i) p[i] *= scale;
}

void pk_approach(const double *p, const double *u, const double *h, int64_t n, double *acc) {
    const Quad one = Quad{} + 1.0;
    Quad s[2] = {}, count[2] = {};
    over_octets(n, [&](auto full, int64_t i, int64_t m, int half) {
        const QuadMask in = in_set(load_some(full, p + i, m, 0.0));
        s[half] += select(in, load_some(full, h + i, m, 0.0) - load_some(full, u + i, m, 0.0));
        count[half] += select(in, one);
    });
    add_lanes(s, acc);
    add_lanes(count, acc + 1);
}

void pk_gap(const double *p, const double *u, const double *h, double *z, double a, int64_t n, double *acc) {
    Quad g2[2] = {};
    over_octets(n, [&](auto full, int64_t i, int64_t m, int half) {
        const QuadMask in = in_set(load_some(full, p + i, m, 0.0));
        const Quad hi = load_some(full, h + i, m, a), ua = load_some(full, u + i, m, 0.0) + a;
        const Quad g = ua - hi;
        g2[half] += select(in, g * g);
        if (z != nullptr) store_some(full, z + i, blend(in, hi, blend(hi < ua, ua, hi)), m);
    });
    add_lanes(g2, acc);
}

void pk_scale_modes(std::complex<double> *work, const double *stiff, int64_t r0, int64_t r1, int64_t nxh,
                    double inv_n) {
    for (int64_t r = r0; r < r1; ++r) {
        std::complex<double> *row = work + r * nxh;
        const double *krow = stiff + r * nxh;
#pragma omp simd
        for (int64_t kx = 0; kx < nxh; ++kx) row[kx] *= (krow[kx] > 0.0) ? inv_n / krow[kx] : 0.0;
    }
}

}  // namespace GFMD_KERNELS_NS
}  // namespace gfmd
