#include "stencil_mg.hpp"

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "free_part.hpp"

namespace gfmd {

namespace {
// Built for the baseline x86-64 and for x86-64-v3 (AVX2), chosen by the CPU at load time, as the
// library's kernels are (kernels_dispatch.cpp): the cycle's row loops are bound by memory traffic,
// and the wider lanes halve their instructions.  Not in the sanitizers' builds: an ifunc resolver
// runs before ThreadSanitizer's runtime is set up and crashed test_threads at its start.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__) && \
    !defined(__SANITIZE_THREAD__)
#define GFMD_CLONES __attribute__((target_clones("default", "arch=x86-64-v3")))
#else
#define GFMD_CLONES
#endif

constexpr int kCoefficients = 25;  // a coarse row: offsets -2..2 in each direction
// The Galerkin operators are symmetric, A(P, P + o) = A(P + o, P): a row keeps the 13 entries of
// its forward offsets (dy > 0, or dy = 0 and dx >= 0) and reads the 12 others from the neighbours
// they belong to -- half the planes, whose reading bounds a coarse level's cycle.
constexpr int kStored = 13;
inline bool forward(int dy, int dx) { return dy > 0 || (dy == 0 && dx >= 0); }
inline int plane(int dy, int dx) { return dy == 0 ? dx : 3 + (dy - 1) * 5 + dx + 2; }  // forward offsets only
constexpr int64_t kCoarsest = 16;  // the last level's side
constexpr int kCoarsestSweeps = 40;
// The smoother: Chebyshev's polynomial of degree 2 in D^-1 A (D the l1 weights, which put its
// spectrum in (0, 1]) that is smallest on [1/16, 1], the part of the spectrum the coarse grid
// does not correct: the 13-point L^2's symbol over D is 1/16 at the smallest mode a coarse grid
// cannot hold, (pi/2, 0), and 1 at (pi, pi).  Before and after the coarse correction, the same
// polynomial (a symmetric cycle, as the CG needs).  Measured from flat at 1024^2 against one
// plain l1-Jacobi sweep each side (docs/decisions.md): 0.57-0.69x the CG iterations, 0.82-0.98x
// the time, with and without adhesion; degree 1 over [0.125, 1] and [0.2, 1] (over-relaxed
// Jacobi) won only without it, degree 3 no more than 2.
constexpr int kDegree = 2;
constexpr double kLow = 1.0 / 16.0;

inline int64_t wrap(int64_t i, int64_t m) { return i & (m - 1); }  // m a power of 2

inline float out(int mode, float x, float ax, float b, float dinv) {
    return mode == 0 ? ax : mode == 2 ? b - ax : x + dinv * (b - ax);  // apply, Jacobi, residual
}

// The 13-point L^2 as a 5 x 5 table, entry [dy + 2][dx + 2]
constexpr double kL2[5][5] = {{0, 0, 1, 0, 0}, {0, 2, -8, 2, 0}, {1, -8, 20, -8, 1}, {0, 2, -8, 2, 0}, {0, 0, 1, 0, 0}};

// L^2 at column j of row r0 (rows rm2 .. rp2 around it), columns jm2 .. jp2 around j
#define GFMD_L2(j0, jm2, jm1, jp1, jp2)                                                                     \
    (20.0f * r0[j0] - 8.0f * (r0[jm1] + r0[jp1] + rm1[j0] + rp1[j0]) + r0[jm2] + r0[jp2] + rm2[j0] + rp2[j0] + \
     2.0f * (rm1[jm1] + rm1[jp1] + rp1[jm1] + rp1[jp1]))

GFMD_CLONES void fine_rows(int64_t m, const unsigned char *held, const float *x, float *y, const float *b,
                           const float *dinv, int mode) {
    for (int64_t i = 0; i < m; i++) {
        const float *rm2 = x + wrap(i - 2, m) * m, *rm1 = x + wrap(i - 1, m) * m, *r0 = x + i * m,
                    *rp1 = x + wrap(i + 1, m) * m, *rp2 = x + wrap(i + 2, m) * m;
        const unsigned char *h = held + i * m;
        float *yr = y + i * m;
        const float *br = b ? b + i * m : r0, *dr = dinv ? dinv + i * m : r0;
        for (int64_t j : {int64_t{0}, int64_t{1}, m - 2, m - 1}) {  // the wrapped ends
            const float s = GFMD_L2(j, wrap(j - 2, m), wrap(j - 1, m), wrap(j + 1, m), wrap(j + 2, m));
            yr[j] = out(mode, r0[j], h[j] ? 0.0f : s, br[j], dr[j]);
        }
        // the interior without branches, so that it vectorizes (free_part.hpp)
        if (mode == 0)
            for (int64_t j = 2; j < m - 2; j++) yr[j] = free_part(GFMD_L2(j, j - 2, j - 1, j + 1, j + 2), h[j]);
        else if (mode == 2)
            for (int64_t j = 2; j < m - 2; j++) yr[j] = br[j] - free_part(GFMD_L2(j, j - 2, j - 1, j + 1, j + 2), h[j]);
        else
            for (int64_t j = 2; j < m - 2; j++)
                yr[j] = r0[j] + dr[j] * (br[j] - free_part(GFMD_L2(j, j - 2, j - 1, j + 1, j + 2), h[j]));
    }
}
#undef GFMD_L2

GFMD_CLONES void coarse_rows(int64_t m, const float *c, const float *x, float *y, const float *b, const float *dinv,
                             int mode) {
    const int64_t mm = m * m;
    for (int64_t i = 0; i < m; i++) {
        float *yr = y + i * m;
        for (int64_t j = 0; j < m; j++) yr[j] = 0.0f;
        for (int a = -2; a <= 2; a++) {
            const float *row = x + wrap(i + a, m) * m;
            for (int e = -2; e <= 2; e++) {
                // entry (a, e) of row (i, j): its own plane's, or that of (-a, -e) at (i + a, j + e)
                const bool own = forward(a, e);
                const float *ck = own ? c + plane(a, e) * mm + i * m : c + plane(-a, -e) * mm + wrap(i + a, m) * m;
                const int64_t s = own ? 0 : e;
                yr[0] += ck[wrap(s, m)] * row[wrap(e, m)];
                yr[1] += ck[wrap(1 + s, m)] * row[wrap(1 + e, m)];
                for (int64_t j = 2; j < m - 2; j++) yr[j] += ck[j + s] * row[j + e];
                yr[m - 2] += ck[wrap(m - 2 + s, m)] * row[wrap(m - 2 + e, m)];
                yr[m - 1] += ck[wrap(m - 1 + s, m)] * row[wrap(m - 1 + e, m)];
            }
        }
        if (mode != 0) {
            const float *xr = x + i * m, *br = b + i * m, *dr = dinv ? dinv + i * m : xr;
            for (int64_t j = 0; j < m; j++) yr[j] = out(mode, xr[j], yr[j], br[j], dr[j]);
        }
    }
}

// A fine point j - 2I = r (-3..3, in one direction) spread to the coarse offsets P gives it: r/2
// with weight 1 if r is even, (r -+ 1)/2 with weight 1/2 each if odd; indexed by r + 3.
struct Spread {
    int count, to[2];
    double weight;
};
constexpr Spread kSpread[7] = {{2, {-2, -1}, 0.5}, {1, {-1, 0}, 1.0}, {2, {-1, 0}, 0.5}, {1, {0, 0}, 1.0},
                               {2, {0, 1}, 0.5},   {1, {1, 0}, 1.0},  {2, {1, 2}, 0.5}};
// coarse (side m/2) <- P^T fine (side m): bilinear weights 1, 1/2, 1/4, the nine terms summed
// in the order (a, e) = (-1, -1), (-1, 0) ... (1, 1) of the fine offsets (2I + a, 2J + e); row by
// row, the wrapped column J = 0 apart, so that the interior needs no index arithmetic.  (Not built
// for x86-64-v3 as the cycle's row loops are: its contraction to FMA would change the bits.)
void restrict_rows(int64_t m, const float *f, float *c) {
    const int64_t mc = m / 2;
    for (int64_t I = 0; I < mc; I++) {
        const float *u = f + wrap(2 * I - 1, m) * m, *v = f + 2 * I * m, *w = f + (2 * I + 1) * m;
        float *cr = c + I * mc;
        const auto at = [&](int64_t J, int64_t jm, int64_t j0, int64_t jp) {
            float s = 0.0f;
            s += 0.25f * u[jm];
            s += 0.5f * u[j0];
            s += 0.25f * u[jp];
            s += 0.5f * v[jm];
            s += 1.0f * v[j0];
            s += 0.5f * v[jp];
            s += 0.25f * w[jm];
            s += 0.5f * w[j0];
            s += 0.25f * w[jp];
            cr[J] = s;
        };
        at(0, m - 1, 0, 1);
        for (int64_t J = 1; J < mc; J++) at(J, 2 * J - 1, 2 * J, 2 * J + 1);
    }
}

// fine (side m) += P coarse, 1/4 of the sum of the coarse points around (the same point four times
// at an even row and column), summed in the order (I0, J0), (I0, J1), (I1, J0), (I1, J1); on the
// fine grid (held given) the held points stay zero
void prolong_rows(int64_t m, const float *c, float *f, const unsigned char *held) {
    const int64_t mc = m / 2;
    for (int64_t i = 0; i < m; i++) {
        const float *r0 = c + (i / 2) * mc, *r1 = (i % 2) ? c + wrap(i / 2 + 1, mc) * mc : r0;
        float *fr = f + i * m;
        // the value at fine column 2J (Jn = J) or 2J + 1 (Jn the next coarse column)
        const auto value = [&](int64_t J, int64_t Jn) { return 0.25f * (r0[J] + r0[Jn] + r1[J] + r1[Jn]); };
        if (held) {  // the held points keep their +0 (+0 + +0: the masked value added is +0 there)
            const unsigned char *h = held + i * m;
            for (int64_t J = 0; J + 1 < mc; J++) {
                fr[2 * J] += free_part(value(J, J), h[2 * J]);
                fr[2 * J + 1] += free_part(value(J, J + 1), h[2 * J + 1]);
            }
        } else {
            for (int64_t J = 0; J + 1 < mc; J++) {
                fr[2 * J] += value(J, J);
                fr[2 * J + 1] += value(J, J + 1);
            }
        }
        const int64_t J = mc - 1;  // the last column pair, its odd point wrapped to column 0
        if (!held || !held[i * m + 2 * J]) fr[2 * J] += value(J, J);
        if (!held || !held[i * m + 2 * J + 1]) fr[2 * J + 1] += value(J, 0);
    }
}

}  // namespace

double StencilMultigrid::bytes_per_point() {
    // fine: 5 floats, the held copy and the dirty marks; coarse levels (1/3 of the points in all):
    // 13 coefficients and 5 vectors as floats, the dirty and special marks; the changed list (1/16
    // of int64)
    return 5 * 4.0 + 2.0 + (kStored + 5) * 4.0 / 3.0 + 2.0 / 3.0 + 8.0 / 16.0;
}

StencilMultigrid::StencilMultigrid(int64_t m) : held_(static_cast<std::size_t>(m * m)) {
    for (int64_t s = m; s >= kCoarsest; s /= 2) {
        Level L;
        const auto mm = static_cast<std::size_t>(s * s);
        L.m = s;
        if (s < m) L.c = AlignedBuffer<float>(mm * kStored);
        L.x = AlignedBuffer<float>(mm);
        L.b = AlignedBuffer<float>(mm);
        L.r = AlignedBuffer<float>(mm);
        L.t = AlignedBuffer<float>(mm);
        L.dinv = AlignedBuffer<float>(mm);
        L.dirty = AlignedBuffer<unsigned char>(mm);
        if (s < m) L.special = AlignedBuffer<unsigned char>(mm);
        lv_.push_back(std::move(L));
    }
    changed_.reserve(static_cast<std::size_t>(m * m / 16 + 1));
}

void StencilMultigrid::apply_fine(const float *x, float *y, const float *b, const float *dinv, Mode mode) const {
    fine_rows(lv_[0].m, held_.data(), x, y, b, dinv, mode);
}

void StencilMultigrid::apply_coarse(const Level &lv, const float *x, float *y, const float *b, const float *dinv,
                                    Mode mode) const {
    coarse_rows(lv.m, lv.c.data(), x, y, b, dinv, mode);
}

void StencilMultigrid::apply_mode(int l, const float *x, float *y, Mode mode) {
    Level &L = lv_[static_cast<std::size_t>(l)];
    if (l == 0) apply_fine(x, y, L.b.data(), L.dinv.data(), mode);
    else apply_coarse(L, x, y, L.b.data(), L.dinv.data(), mode);
}

void StencilMultigrid::restrict_to(int l, const float *f, float *c) const {
    restrict_rows(lv_[static_cast<std::size_t>(l)].m, f, c);
}

void StencilMultigrid::prolong_add(int l, const float *c, float *f) const {
    prolong_rows(lv_[static_cast<std::size_t>(l)].m, c, f, l == 0 ? held_.data() : nullptr);
}

// x <- x + D^-1 (b - A x), `sweeps` times, each one pass into t, then swapped
void StencilMultigrid::jacobi(int l, int sweeps) {
    Level &L = lv_[static_cast<std::size_t>(l)];
    for (int s = 0; s < sweeps; s++) {
        apply_mode(l, L.x.data(), L.t.data(), kJacobi);
        std::swap(L.x, L.t);
    }
}

// Chebyshev smoothing of degree kDegree for D^-1 A on [kLow, 1] (Saad's three-term recurrence,
// theta and delta the interval's centre and half width), the direction in t, the residual in r.
// from_zero: x and t hold D^-1 b / theta, the first iterate from x = 0 and its direction
// (first_scale: written with b, no pass of their own); else x is the current iterate.
void StencilMultigrid::chebyshev(int l, bool from_zero) {
    Level &L = lv_[static_cast<std::size_t>(l)];
    const auto mm = static_cast<std::size_t>(L.m * L.m);
    float *x = L.x.data(), *d = L.t.data(), *r = L.r.data();
    const float *dinv = L.dinv.data();
    const double theta = 0.5 * (1.0 + kLow), delta = 0.5 * (1.0 - kLow), sigma = theta / delta;
    double rho = 1.0 / sigma;
    if (!from_zero) {
        apply_mode(l, x, r, kResidual);
        const float c = static_cast<float>(1.0 / theta);
        for (std::size_t p = 0; p < mm; p++) {
            d[p] = c * dinv[p] * r[p];
            x[p] += d[p];
        }
    }
    for (int i = 1; i < kDegree; i++) {
        apply_mode(l, x, r, kResidual);
        const double next = 1.0 / (2.0 * sigma - rho);
        const float c1 = static_cast<float>(next * rho), c2 = static_cast<float>(2.0 * next / delta);
        for (std::size_t p = 0; p < mm; p++) {
            d[p] = c1 * d[p] + c2 * dinv[p] * r[p];
            x[p] += d[p];
        }
        rho = next;
    }
}

float StencilMultigrid::first_scale() { return static_cast<float>(2.0 / (1.0 + kLow)); }

// One V-cycle for level l's right-hand side b from x = 0 (started: x = t = D^-1 b / theta already),
// into L.x: the smoother, the residual restricted, the next grid's cycle, its correction
// prolonged, the smoother; on the coarsest grid kCoarsestSweeps l1-Jacobi sweeps.
void StencilMultigrid::cycle(int l, bool started) {
    Level &L = lv_[static_cast<std::size_t>(l)];
    const auto mm = static_cast<std::size_t>(L.m * L.m);
    float *x = L.x.data();
    const float *b = L.b.data(), *dinv = L.dinv.data();
    if (l + 1 == static_cast<int>(lv_.size())) {
        for (std::size_t p = 0; p < mm; p++) x[p] = dinv[p] * b[p];
        jacobi(l, kCoarsestSweeps - 1);
        return;
    }
    if (!started) {
        const float c = first_scale();
        float *d = L.t.data();
        for (std::size_t p = 0; p < mm; p++) d[p] = x[p] = c * dinv[p] * b[p];
    }
    chebyshev(l, true);
    apply_mode(l, L.x.data(), L.r.data(), kResidual);
    Level &next = lv_[static_cast<std::size_t>(l) + 1];
    restrict_to(l, L.r.data(), next.b.data());
    cycle(l + 1);
    prolong_add(l, next.x.data(), L.x.data());
    chebyshev(l, false);
}

// the operator's entry on level l between point (y, x) and its neighbour (y + dy, x + dx)
double StencilMultigrid::entry(int l, int64_t y, int64_t x, int dy, int dx) const {
    const Level &L = lv_[static_cast<std::size_t>(l)];
    const int64_t m = L.m, p = y * m + x;
    if (l > 0)
        return forward(dy, dx) ? L.c.data()[plane(dy, dx) * m * m + p]
                               : L.c.data()[plane(-dy, -dx) * m * m + wrap(y + dy, m) * m + wrap(x + dx, m)];
    const double v = kL2[dy + 2][dx + 2];
    const unsigned char *held = held_.data();
    return (v == 0.0 || held[p] || held[wrap(y + dy, m) * m + wrap(x + dx, m)]) ? 0.0 : v;
}

// the fine grid's Jacobi weight at (y, x): 1 / sum_j |A_pj|, 0 where the point is held
void StencilMultigrid::fine_weight(int64_t y, int64_t x) {
    double s = 0.0;
    for (int dy = -2; dy <= 2; dy++)
        for (int dx = -2; dx <= 2; dx++) s += std::fabs(entry(0, y, x, dy, dx));
    lv_[0].dinv.data()[y * lv_[0].m + x] = static_cast<float>(s > 0.0 ? 1.0 / s : 0.0);
}

namespace {
// The terms of a coarse row P^T A P (coarse_row): the fine points 2Y + a (a = -1, 0, 1, weights
// 1/2, 1, 1/2 in each direction), their neighbours j = 2Y + a + d (d = -2..2) spread to the coarse
// points (j +- 1) / 2 or j / 2 (weights 1/2 or 1): offsets -2..2.  Grouped by source, the pair
// (fine point, offset), in the order (a, b, dy, dx), and within it by (ky, kx); a term's weight is
// a product of powers of 2 (exact: the same bits as multiplying them into the entry one by one).
struct GalerkinTerm {
    unsigned char target;  // the coarse offset's (oy + 2) * 5 + ox + 2
    float weight;
};
constexpr int kSources = 9 * 25;  // ((a + 1) * 3 + b + 1) * 25 + (dy + 2) * 5 + dx + 2
struct GalerkinTerms {
    GalerkinTerm t[kSources * 4];
    int first[kSources + 1];  // source k's terms: t[first[k]] .. t[first[k + 1] - 1]
    // the free sheet's fine operator (L^2 between free points) in coarse form: exact, since every
    // term is an integer times a power of 2 >= 1/16 and the sums stay below 2^48
    double free_fine[kCoefficients];
    GalerkinTerms() : t(), first(), free_fine() {
        int count = 0;
        for (int a = -1; a <= 1; a++)
            for (int b = -1; b <= 1; b++) {
                const double wi = (a != 0 ? 0.5 : 1.0) * (b != 0 ? 0.5 : 1.0);
                for (int dy = -2; dy <= 2; dy++)
                    for (int dx = -2; dx <= 2; dx++) {
                        first[((a + 1) * 3 + b + 1) * 25 + (dy + 2) * 5 + dx + 2] = count;
                        const Spread &sy = kSpread[a + dy + 3], &sx = kSpread[b + dx + 3];
                        for (int ky = 0; ky < sy.count; ky++)
                            for (int kx = 0; kx < sx.count; kx++) {
                                const int target = (sy.to[ky] + 2) * 5 + sx.to[kx] + 2;
                                const double w = wi * sy.weight * sx.weight;
                                t[count++] = {static_cast<unsigned char>(target), static_cast<float>(w)};
                                free_fine[target] += kL2[dy + 2][dx + 2] * w;
                            }
                    }
            }
        first[kSources] = count;
    }
};
const GalerkinTerms kGalerkin;

}  // namespace

// Whether row (Y, X) of level l + 1 reads only entries of the free sheet's operator: no point of
// level l within 3 of (2Y, 2X) (the fine points 2Y + a and their neighbours) is held (l = 0) or a
// row other than that operator's (l > 0).
bool StencilMultigrid::pristine_window(int l, int64_t Y, int64_t X) const {
    const Level &L = lv_[static_cast<std::size_t>(l)];
    const int64_t m = L.m;
    const unsigned char *flag = l == 0 ? held_.data() : L.special.data();
    for (int dy = -3; dy <= 3; dy++) {
        const unsigned char *row = flag + wrap(2 * Y + dy, m) * m;
        for (int dx = -3; dx <= 3; dx++)
            if (row[wrap(2 * X + dx, m)]) return false;
    }
    return true;
}

// row (Y, X) of level l + 1's operator, P^T A_l P, and its weight.  From the fine grid: the free
// sheet's row less the terms of the pairs with a held point (exact, as kGalerkin.free_fine is:
// the same value as the sum of the free pairs' terms).  From a coarse grid: kGalerkin's terms of
// the entries, summed in their order.  A row whose window is pristine is the free sheet's row of
// its level, computed once (the same function of the same entries: the same bits) and copied.
void StencilMultigrid::coarse_row(int l, int64_t Y, int64_t X) {
    const int64_t m = lv_[static_cast<std::size_t>(l)].m, mc = m / 2, mmc = mc * mc, p = Y * mc + X;
    Level &next = lv_[static_cast<std::size_t>(l) + 1];
    const bool pristine = pristine_window(l, Y, X);
    if (pristine && next.has_free_row) {
        for (int k = 0; k < kStored; k++) next.c.data()[k * mmc + p] = next.free_row[k];
        next.dinv.data()[p] = next.free_row[kStored];
        next.special.data()[p] = 0;
        return;
    }
    double acc[kCoefficients];
    if (l == 0) {
        unsigned char w[7][7];  // the held set within 3 of (2Y, 2X)
        for (int dy = -3; dy <= 3; dy++) {
            const unsigned char *row = held_.data() + wrap(2 * Y + dy, m) * m;
            for (int dx = -3; dx <= 3; dx++) w[dy + 3][dx + 3] = row[wrap(2 * X + dx, m)];
        }
        for (int k = 0; k < kCoefficients; k++) acc[k] = kGalerkin.free_fine[k];
        if (!pristine)
            for (int a = -1; a <= 1; a++)
                for (int b = -1; b <= 1; b++)
                    for (int dy = -2; dy <= 2; dy++)
                        for (int dx = -2; dx <= 2; dx++) {
                            const double v = kL2[dy + 2][dx + 2];
                            if (v == 0.0 || !(w[a + 3][b + 3] | w[a + dy + 3][b + dx + 3])) continue;
                            const int source = ((a + 1) * 3 + b + 1) * 25 + (dy + 2) * 5 + dx + 2;
                            for (int k = kGalerkin.first[source]; k < kGalerkin.first[source + 1]; k++)
                                acc[kGalerkin.t[k].target] -= v * static_cast<double>(kGalerkin.t[k].weight);
                        }
    } else {
        double v[kSources];
        for (int a = -1; a <= 1; a++)
            for (int b = -1; b <= 1; b++) {
                const int64_t y = wrap(2 * Y + a, m), x = wrap(2 * X + b, m);
                double *vp = v + ((a + 1) * 3 + b + 1) * 25;
                for (int dy = -2; dy <= 2; dy++)
                    for (int dx = -2; dx <= 2; dx++) vp[(dy + 2) * 5 + dx + 2] = entry(l, y, x, dy, dx);
            }
        for (int k = 0; k < kCoefficients; k++) acc[k] = 0.0;
        for (int source = 0; source < kSources; source++)
            for (int k = kGalerkin.first[source]; k < kGalerkin.first[source + 1]; k++)
                acc[kGalerkin.t[k].target] += v[source] * static_cast<double>(kGalerkin.t[k].weight);
    }
    double s = 0.0;
    for (int k = 0; k < kCoefficients; k++) {
        const int dy = k / 5 - 2, dx = k % 5 - 2;
        if (forward(dy, dx)) next.c.data()[plane(dy, dx) * mmc + p] = static_cast<float>(acc[k]);
        s += std::fabs(acc[k]);
    }
    next.dinv.data()[p] = static_cast<float>(s > 0.0 ? 1.0 / s : 0.0);
    next.special.data()[p] = pristine ? 0 : 1;
    if (pristine) {
        for (int k = 0; k < kStored; k++) next.free_row[k] = next.c.data()[k * mmc + p];
        next.free_row[kStored] = next.dinv.data()[p];
        next.has_free_row = true;
    }
}

void StencilMultigrid::assemble() {
    const int64_t m = lv_[0].m;
    for (int64_t y = 0; y < m; y++)
        for (int64_t x = 0; x < m; x++) fine_weight(y, x);
    for (std::size_t l = 0; l + 1 < lv_.size(); l++)
        for (int64_t Y = 0; Y < lv_[l + 1].m; Y++)
            for (int64_t X = 0; X < lv_[l + 1].m; X++) coarse_row(static_cast<int>(l), Y, X);
}

// After the held set changed at the points changed_: the rows that depend on them, level by level.
// A fine row depends on the held set within 2 points; row I of level l + 1 on the rows of level l
// within one point of 2I.
void StencilMultigrid::update() {
    const int64_t m = lv_[0].m;
    unsigned char *dirty0 = lv_[0].dirty.data();
    for (const int64_t p : changed_) {
        const int64_t y = p / m, x = p % m;
        for (int dy = -2; dy <= 2; dy++)
            for (int dx = -2; dx <= 2; dx++) dirty0[wrap(y + dy, m) * m + wrap(x + dx, m)] = 1;
    }
    for (std::size_t l = 0; l < lv_.size(); l++) {
        const int64_t ml = lv_[l].m;
        unsigned char *dirty = lv_[l].dirty.data();
        for (int64_t y = 0; y < ml; y++)
            for (int64_t x = 0; x < ml; x++) {
                if (!dirty[y * ml + x]) continue;
                dirty[y * ml + x] = 0;
                if (l == 0) fine_weight(y, x);
                else coarse_row(static_cast<int>(l) - 1, y, x);
                if (l + 1 == lv_.size()) continue;
                const int64_t mc = ml / 2;  // the rows of level l + 1 with |2I - (y, x)| <= 1
                unsigned char *next = lv_[l + 1].dirty.data();
                for (int64_t Y = y / 2 - 1; Y <= (y + 1) / 2 + 1; Y++)
                    for (int64_t X = x / 2 - 1; X <= (x + 1) / 2 + 1; X++)
                        if (std::abs(2 * Y - y) <= 1 && std::abs(2 * X - x) <= 1) next[wrap(Y, mc) * mc + wrap(X, mc)] = 1;
            }
    }
}

void StencilMultigrid::follow(const unsigned char *held) {
    const int64_t mm = lv_[0].m * lv_[0].m;
    const int64_t limit = mm / 16;  // beyond it a whole assembly is cheaper than the updates
    unsigned char *own = held_.data();
    changed_.clear();
    bool many = !assembled_;
    for (int64_t p = 0; p < mm; p++) {
        const unsigned char now = held[p] ? 1 : 0;
        if (now == own[p]) continue;
        own[p] = now;
        if (many) continue;
        if (static_cast<int64_t>(changed_.size()) == limit) many = true;
        else changed_.push_back(p);
    }
    if (many) assemble();
    else if (!changed_.empty()) update();
    assembled_ = true;
}

double StencilMultigrid::apply_inverse(const double *b, double scale, double *x, int64_t block) {
    Level &L = lv_[0];
    const int64_t mm = L.m * L.m;
    float *fb = L.b.data(), *fx0 = L.x.data(), *fd0 = L.t.data();
    const float *dinv = L.dinv.data();
    const float first = first_scale();
    for (int64_t p = 0; p < mm; p++) {  // b to floats and the smoother's first iterate in one pass
        fb[p] = static_cast<float>(b[p]);
        fd0[p] = fx0[p] = first * dinv[p] * fb[p];
    }
    cycle(0, true);
    const float *fx = L.x.data();
    const double inv = 1.0 / scale;
    double total = 0.0;
    for (int64_t p0 = 0; p0 < mm; p0 += block) {
        const int64_t p1 = p0 + block < mm ? p0 + block : mm;
        double t = 0.0;
        for (int64_t p = p0; p < p1; p++) {
            x[p] = inv * static_cast<double>(fx[p]);
            t += b[p] * x[p];
        }
        double acc = 0.0;  // a block's partial starts at 0 and takes its sum (parallel_sums)
        acc += t;
        total += acc;
    }
    return total;
}

}  // namespace gfmd
