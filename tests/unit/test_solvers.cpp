// The library's internal paths that honest inputs of the C API reach only by rounding, or that it
// reads without returning, driven from the inside (the library's own objects linked in):
//
// 1. The substrate's shortest wave (observables.cpp, read by the automatic choice's adhesive rule)
//    against substrates whose answer is known (check_shortest_wave).
// 2. The surface CG's safety net (src/solvers/cg.cpp, SurfaceCg::sufficient_decrease): a step the
//    wall stopped must lower the energy by Armijo's rule; if no backtrack does, the step is undone
//    (z from the scratch, bit for bit) and the next direction is the projected force itself, along
//    which a small enough step always descends.  The test injects the failure: the solver is
//    handed the forces of the current surface with an elastic energy lowered by far more than any
//    step can change it, so that every trial step, each evaluated from the surface it produces,
//    looks as if it had raised the energy.  Then:
//     - the surface is the start's, bit for bit, and the solver's state says "steepest next";
//     - with the true forces the next step's direction is the projected force, bit for bit (zero
//       where the wall holds the body), its step was checked (points reached the wall) and
//       accepted, and the energy U_el + sigma0 A mean(z), evaluated afresh, fell.
//    A library without the undo leaves the surface moved; one that forgets the steepest direction
//    takes the preconditioned one (M^-1 F, not F) and keeps its state at 0 or 1.
// 3. The masked select of the Newton method and its multigrid cycle (src/solvers/free_part.hpp),
//    which stands for `held ? 0 : v` so that their loops vectorize: at a free point every bit of
//    v kept (-0, infinities, a NaN's payload, the smallest subnormal), at a held one +0, in float
//    and double (check_free_part).
// 4. The cycle's inverse and the dot b.x it sums as it writes x: the grid's sum_points bits
//    (check_inverse_dot).
// 5. The cycle's coarse operators against a Galerkin product P^T A P the test forms itself (P the
//    bilinear prolongation evaluated from its formula, A the fine L^2 between free points, then
//    the stored coarse operator one level down), for held sets with wide free regions (where the
//    library copies the free sheet's row) and dense ones; and a held set reached by small changes
//    (rows recomputed where they reach) against one assembled whole, bit for bit
//    (check_coarse_operators).
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

#include "constants.hpp"
#include "fft_grid.hpp"
#include "fields.hpp"
#include "forces.hpp"
#include "green.hpp"
#include "observables.hpp"
#include "params.hpp"
#include "solvers/cg.hpp"
#include "solvers/free_part.hpp"
#include "solvers/stencil_mg.hpp"
#include "substrate.hpp"

namespace {

int failures = 0;

void expect(bool ok, const char *what) {
    std::printf("%s %s\n", ok ? "ok  " : "FAIL", what);
    if (!ok) ++failures;
}

template <class T>
bool same_bits(T a, T b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

// The energy the surface CG minimizes under pressure control: U_el + sigma0 A mean(z).
double energy(const gfmd::FftGrid &grid, const gfmd::Params &p, const gfmd::ForceState &fs, const double *z) {
    double sum = 0.0;
    for (int64_t i = 0; i < grid.real_size(); ++i) sum += z[i];
    return fs.u_el + p.sigma0 * grid.area_per_point() * sum;
}

// The substrate's shortest wave (observables.cpp, read by the automatic choice's adhesive rule)
// against substrates whose answer is known: two cosines (their larger wave vector, to the
// bisection's 1e-4 of the corner), a flat substrate and a white-noise one (the grid's corner, or
// within 2 % of it: a random field's slope variance grows towards the corner).
void check_shortest_wave() {
    using namespace gfmd;
    const int64_t nx = 96, ny = 64;
    const double lx = 96.0, ly = 128.0;  // unequal spacings
    FftGrid grid(nx, ny, lx, ly, 1, GFMD_PLANNER_ESTIMATE);
    Fields fields(grid);
    const double two_pi = 2.0 * kPi, corner = shortest_wave_q(grid);
    double *h = fields.h.data();
    const double q1 = two_pi * 5.0 / lx, q2 = two_pi * 9.0 / ly;  // the larger: q2 = 0.442
    for (int64_t y = 0; y < ny; ++y)
        for (int64_t x = 0; x < nx; ++x)
            h[y * nx + x] = std::cos(q1 * static_cast<double>(x) * lx / nx) +
                            0.3 * std::sin(q2 * static_cast<double>(y) * ly / ny);
    const double q = substrate_shortest_wave(grid, fields);
    std::printf("     two cosines: %.6f against %.6f (corner %.4f)\n", q, std::max(q1, q2), corner);
    expect(q >= std::max(q1, q2) && q <= std::max(q1, q2) + 1e-4 * corner + 1e-12,
           "the shortest wave of two cosines is the larger wave vector");
    std::fill(h, h + nx * ny, -1.0);
    expect(substrate_shortest_wave(grid, fields) == corner, "a flat substrate's is the grid's corner");
    uint64_t state = 12345;
    for (int64_t i = 0; i < nx * ny; ++i) {  // white noise, a portable generator (xorshift64)
        state ^= state << 13, state ^= state >> 7, state ^= state << 17;
        h[i] = static_cast<double>(state >> 11) * 0x1.0p-53;
    }
    const double noise = substrate_shortest_wave(grid, fields);
    std::printf("     white noise: %.6f (corner %.4f)\n", noise, corner);
    expect(noise > 0.98 * corner && noise <= corner, "white noise's is within 2 % of the corner");

    // Generated self-affine substrates (the rule reads 2 sqrt(2) q_s capped at the corner, and
    // on lambda_s = 4a must give the corner's answer): q_s = 2 pi/lambda_s to within 1e-3 below
    // (the tail above 1e-4 of the slope variance: less than 1e-3 of q_s wide for H = 0.3 ... 1)
    // and at most the bisection's 1e-4 of the corner above, 128^2, lambda_r = 4 lambda_s.
    FftGrid square(128, 128, 128.0, 128.0, 1, GFMD_PLANNER_ESTIMATE);
    Fields sq(square);
    const double sq_corner = shortest_wave_q(square);
    bool close = true;
    for (const double lambda_s : {2.0, 4.0, 8.0})
        for (const double hurst : {0.3, 0.8, 1.0}) {
            const SelfAffineParams p{hurst, 4.0 * lambda_s, lambda_s, 1.0, 7, GFMD_DIST_UNIFORM};
            generate_selfaffine(square, p, sq.work.data(), sq.h.data());
            const double qs = two_pi / lambda_s, got = substrate_shortest_wave(square, sq);
            if (!(got >= (1.0 - 1e-3) * qs && got <= qs + 1e-4 * sq_corner)) {
                std::printf("     lambda_s = %g, H = %g: %.6f against q_s = %.6f\n", lambda_s, hurst, got, qs);
                close = false;
            }
        }
    expect(close, "a generated substrate's is its q_s = 2 pi/lambda_s (lambda_s = 2, 4, 8 a; H = 0.3, 0.8, 1)");
}

void check_cg_safety_net() {
    using namespace gfmd;
    // A thin sheet on a fluid foundation at a low load, flat at the highest peak: the
    // preconditioned CG's first step pushes the soft sheet down onto the substrate, where the wall
    // stops points, so the step is checked (the case the check was built for, cg.cpp).
    const int64_t n = 64;
    FftGrid grid(n, n, static_cast<double>(n), static_cast<double>(n), 1, GFMD_PLANNER_ESTIMATE);
    Params p;
    p.kind = GFMD_GREEN_LAYER_FLUID;
    p.width = 2.0;
    p.sigma0 = 1e-4;
    p.solver = GFMD_SOLVER_CG;
    const Body body = make_body(grid, p.kind, p.width, p.e_star, p.nu);
    Fields fields(grid);
    const double two_pi = 2.0 * kPi;
    for (int64_t y = 0; y < n; ++y)
        for (int64_t x = 0; x < n; ++x) {
            const double sx = two_pi * static_cast<double>(x) / static_cast<double>(n);
            const double sy = two_pi * static_cast<double>(y) / static_cast<double>(n);
            fields.h.data()[y * n + x] = std::cos(sx) * std::cos(2.0 * sy) + 0.3 * std::sin(3.0 * sx + sy) - 1.3;
        }
    fields.put_flat_at_rest(grid);
    const Dynamics d = dynamics_for(p, body);
    ConjugateGradient cg(grid);
    cg.restart(d);

    const std::size_t points = static_cast<std::size_t>(grid.real_size());
    const double *z = fields.z.data(), *h = fields.h.data(), *f = fields.f.data(), *t = fields.v.data();
    ForceState fs = evaluate_forces(grid, p, body, fields);
    const std::vector<double> z0(z, z + points), f0(f, f + points);
    const double e0 = energy(grid, p, fs, z);

    // 1. Every trial step rejected: lower the reference energy by a hundred times the energy's size
    // (the check's rounding slack is 1e-12 of it, so no trial step can pass).
    ForceState lie = fs;
    lie.u_el -= 100.0 * (std::fabs(e0) + 1.0);
    {
        StepContext c{grid, p, body, d, lie, fields};
        cg.advance(c);
    }
    bool undone = true;
    for (std::size_t i = 0; i < points; ++i) undone = undone && same_bits(z[i], z0[i]);
    expect(undone, "a step no backtrack rescues is undone: z is the start's, bit for bit");
    expect(cg.state()[1] == 2.0, "the solver's state then says: the next direction is the force");

    // 2. The true forces of the unchanged surface, and the next step.
    fs = evaluate_forces(grid, p, body, fields);
    bool same_forces = true;
    for (std::size_t i = 0; i < points; ++i) same_forces = same_forces && same_bits(f[i], f0[i]);
    expect(same_forces, "the forces of the restored surface are the start's");
    {
        StepContext c{grid, p, body, d, fs, fields};
        cg.advance(c);
    }
    // the direction: the projected force (t = F where the body may move, 0 where the wall holds it)
    bool along_force = true;
    int64_t held = 0, landed = 0;
    for (std::size_t i = 0; i < points; ++i) {
        const bool wall = z0[i] <= h[i] && f0[i] <= 0.0;
        held += wall ? 1 : 0;
        along_force = along_force && same_bits(t[i], wall ? 0.0 : f0[i]);
        landed += (z0[i] > h[i] && z[i] == h[i]) ? 1 : 0;
    }
    std::printf("     %" PRId64 " points held at the start, %" PRId64 " landed on the wall in the step\n", held, landed);
    expect(along_force, "the step after it goes along the projected force, bit for bit");
    expect(landed > 0, "the wall stopped points in that step (it was checked)");
    expect(cg.state()[1] != 2.0, "the checked steepest step was accepted");
    const ForceState after = evaluate_forces(grid, p, body, fields);
    const double e1 = energy(grid, p, after, z);
    std::printf("     energy %.17g -> %.17g\n", e0, e1);
    // Armijo's rule asks for a decrease of at least 1e-4 of the first-order prediction; strictly
    // lower is what a caller relies on (the check's rounding slack, 1e-12 of the energy, is far
    // below the decrease of a first step from flat).
    expect(e1 < e0, "and the energy fell");
}

template <class T>
void check_free_part_of(const char *type) {
    const T values[] = {T(1.5), T(-2.25), T(0), -T(0), std::numeric_limits<T>::infinity(),
                        -std::numeric_limits<T>::infinity(), std::numeric_limits<T>::quiet_NaN(),
                        -std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::denorm_min(),
                        std::numeric_limits<T>::max(), std::numeric_limits<T>::lowest()};
    bool kept = true, zeroed = true;
    for (const T v : values) {
        kept = kept && same_bits(gfmd::free_part(v, 0), v);
        zeroed = zeroed && same_bits(gfmd::free_part(v, 1), T(0));
    }
    char what[96];
    std::snprintf(what, sizeof what, "free_part<%s>: a free point's value bit for bit", type);
    expect(kept, what);
    std::snprintf(what, sizeof what, "free_part<%s>: +0 at a held point", type);
    expect(zeroed, what);
}

void check_free_part() {
    check_free_part_of<float>("float");
    check_free_part_of<double>("double");
}

// The cycle's inverse returns b.x summed as it writes x (newton.cpp's preconditioner): the same bits
// as the grid's own sum_points over the points, which the Newton method summed before.  256^2 on
// two threads: four blocks of kBlock points, handed to two threads in either order; a held set of
// a tenth of the points (b 0 there, as the method keeps it) and a right-hand side of mixed signs.
void check_inverse_dot() {
    using namespace gfmd;
    const int64_t n = 256, points = n * n;
    FftGrid grid(n, n, static_cast<double>(n), static_cast<double>(n), 2, GFMD_PLANNER_ESTIMATE);
    std::vector<unsigned char> held(static_cast<std::size_t>(points));
    std::vector<double> b(static_cast<std::size_t>(points)), x(b.size());
    uint64_t state = 12345;
    const auto next = [&] {  // a 64-bit LCG's top 53 bits in [0, 1)
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(state >> 11) * 0x1.0p-53;
    };
    for (int64_t i = 0; i < points; ++i) {
        held[i] = next() < 0.1 ? 1 : 0;
        const double v = next() - 0.5;
        b[i] = held[i] ? 0.0 : v;
    }
    StencilMultigrid mg(n);
    mg.follow(held.data());
    const double fused = mg.apply_inverse(b.data(), 3.0, x.data(), kBlock);
    const double apart = grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
        double t = 0.0;
        for (int64_t i = i0; i < i1; ++i) t += b[i] * x[i];
        acc[0] += t;
    })[0];
    expect(fused > 0.0 && same_bits(fused, apart), "the cycle's b.x is sum_points' b.x bit for bit (4 blocks, 2 threads)");
}

// The bilinear prolongation's weight between fine index r and coarse index R on a periodic line
// of m fine points: 1 at r = 2R, 1/2 at r = 2R +- 1, else 0.
double hat(int64_t r, int64_t R, int64_t m) {
    int64_t d = ((r - 2 * R) % m + m) % m;
    if (d > m / 2) d -= m;
    return d == 0 ? 1.0 : (d == 1 || d == -1) ? 0.5 : 0.0;
}

// Level l + 1's entry (Y, X) -> (Y + oy, X + ox) as sum P(r, I) A_l(r, r') P(r', I + O) over the
// fine points r around 2I and their neighbours r' (A_l read from the multigrid one level down:
// l = 0 the fine stencil on the free points, else the stored operator).
double galerkin(const gfmd::StencilMultigrid &mg, int l, int64_t m, int64_t Y, int64_t X, int oy, int ox) {
    const int64_t mc = m / 2;
    double s = 0.0;
    for (int64_t ry = 2 * Y - 1; ry <= 2 * Y + 1; ++ry)
        for (int64_t rx = 2 * X - 1; rx <= 2 * X + 1; ++rx) {
            const double pi = hat(ry, Y, m) * hat(rx, X, m);
            const int64_t y = (ry + m) % m, x = (rx + m) % m;
            for (int dy = -2; dy <= 2; ++dy)
                for (int dx = -2; dx <= 2; ++dx) {
                    const double pj = hat(ry + dy, (Y + oy + mc) % mc, m) * hat(rx + dx, (X + ox + mc) % mc, m);
                    if (pj != 0.0) s += pi * mg.operator_entry(l, y, x, dy, dx) * pj;
                }
        }
    return s;
}

// The largest difference between the multigrid's coarse entries and galerkin()'s, relative to
// the largest entry of each level, over every level below the fine grid.
double galerkin_error(const gfmd::StencilMultigrid &mg, int64_t n) {
    double worst = 0.0;
    int64_t m = n;
    for (int l = 0; l + 1 < mg.levels(); ++l, m /= 2) {
        const int64_t mc = m / 2;
        double top = 0.0, diff = 0.0;
        for (int64_t Y = 0; Y < mc; ++Y)
            for (int64_t X = 0; X < mc; ++X)
                for (int oy = -2; oy <= 2; ++oy)
                    for (int ox = -2; ox <= 2; ++ox) {
                        const double want = galerkin(mg, l, m, Y, X, oy, ox);
                        top = std::max(top, std::fabs(want));
                        diff = std::max(diff, std::fabs(want - mg.operator_entry(l + 1, Y, X, oy, ox)));
                    }
        worst = std::max(worst, top > 0.0 ? diff / top : diff);
    }
    return worst;
}

void check_coarse_operators() {
    using namespace gfmd;
    const int64_t n = 64, points = n * n;
    uint64_t state = 777;
    const auto next = [&] {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(state >> 11) * 0x1.0p-53;
    };
    // a few discs (wide free regions between them) and a held set of a quarter of the points
    std::vector<unsigned char> discs(static_cast<std::size_t>(points)), dense(discs.size());
    for (int k = 0; k < 6; ++k) {
        const double cy = next() * n, cx = next() * n, r = 1.0 + 3.0 * next();
        for (int64_t y = 0; y < n; ++y)
            for (int64_t x = 0; x < n; ++x) {
                const double ddy = std::remainder(y - cy, static_cast<double>(n)), ddx = std::remainder(x - cx, static_cast<double>(n));
                if (ddy * ddy + ddx * ddx <= r * r) discs[y * n + x] = 1;
            }
    }
    for (auto &h : dense) h = next() < 0.25 ? 1 : 0;
    char what[160];
    // the fine level's and coarse levels' products: exact at the first level (integers times
    // powers of 2), then float entries (relative rounding 6e-8 each, 25 x 9 terms of one sign
    // at most): 1e-6 of the level's largest entry
    for (const auto *held : {&discs, &dense}) {
        StencilMultigrid mg(n);
        mg.follow(held->data());
        const double err = galerkin_error(mg, n);
        std::snprintf(what, sizeof what, "coarse operators = the test's P^T A P (%s held set): %.1e of the largest entry",
                      held == &discs ? "discs" : "dense", err);
        expect(err < 1e-6, what);
    }
    // the discs grown a point at a time (the rows they reach recomputed) against a whole assembly
    // of the last set: every entry and a V-cycle bit for bit
    StencilMultigrid grown(n);
    std::vector<unsigned char> held = discs;
    grown.follow(held.data());
    for (int k = 0; k < 40; ++k) {
        held[static_cast<std::size_t>(next() * static_cast<double>(points))] ^= 1;
        grown.follow(held.data());
    }
    StencilMultigrid whole(n);
    whole.follow(held.data());
    bool same = true;
    int64_t m = n;
    for (int l = 0; l < whole.levels(); ++l, m /= 2)
        for (int64_t y = 0; y < m; ++y)
            for (int64_t x = 0; x < m; ++x)
                for (int dy = -2; dy <= 2; ++dy)
                    for (int dx = -2; dx <= 2; ++dx)
                        same = same && same_bits(grown.operator_entry(l, y, x, dy, dx), whole.operator_entry(l, y, x, dy, dx));
    expect(same, "40 single-point changes of the held set: every level's entries = a whole assembly's, bit for bit");
    std::vector<double> b(static_cast<std::size_t>(points)), xa(b.size()), xb(b.size());
    for (int64_t i = 0; i < points; ++i) b[i] = held[i] ? 0.0 : next() - 0.5;
    const double da = grown.apply_inverse(b.data(), 2.0, xa.data(), points);
    const double db = whole.apply_inverse(b.data(), 2.0, xb.data(), points);
    expect(same_bits(da, db) && std::memcmp(xa.data(), xb.data(), xa.size() * sizeof(double)) == 0,
           "... and their V-cycles, bit for bit");
    expect(galerkin_error(grown, n) < 1e-6, "... and = the test's P^T A P");
}

}  // namespace

int main() {
    check_shortest_wave();
    check_cg_safety_net();
    check_free_part();
    check_inverse_dot();
    check_coarse_operators();
    if (failures > 0) {
        std::printf("test_solvers: %d failure(s)\n", failures);
        return 1;
    }
    std::printf("test_solvers: all passed\n");
    return 0;
}
