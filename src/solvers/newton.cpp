#include "newton.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <vector>

#include "../constraint.hpp"
#include "../error.hpp"
#include "../kernels.hpp"
#include "../parallel.hpp"
#include "free_part.hpp"

namespace gfmd {

namespace {
constexpr double kInnerTolerance = 0.1;  // the CG to a tenth of its right-hand side (measured best of 0.01 ... 0.3)
// At most 10 iterations of the inner CG: the held set of the first steps is not yet the
// equilibrium's, and the line search's projection onto the substrate keeps little of an exact
// solve.  From flat (512^2-2048^2, W = 1/16 and 1/4, with and without adhesion) 10 took
// 0.28-0.93x the time of 500 (2048^2, W = 1/16: 36.7 s against 67.0 s; 3, 5, 7, 20, 40 and 80 did
// worse at 512^2).
constexpr int kMaxInner = 10;
constexpr double kArmijo = 1e-4;
constexpr int kMaxHalvings = 20;  // alpha down to 2^-20, about 1e-6 (the measured program's floor)
// With adhesion the CG's iterate stays within max |d| <= radius on the free points (Steihaug's CG):
// the radius starts at kTrustStart rho after a restart, doubles after a full step to its edge,
// and after a shortened step becomes the step taken, but not less than kTrustFloor rho (rho the
// scale on which the adhesive law changes).  Measured (docs/decisions.md, "The active-set Newton
// method"): a floor
// of 1e-3 rho let one point toggling between held and free shrink the region to nothing; a
// region in the 2-norm did worse than none.
constexpr double kTrustStart = 1.0;
constexpr double kTrustFloor = 0.3;

// The coefficients of x^2 (1/2! - x/3! + x^2/4! - ...) = sum over k >= 2 of (-x)^k / k!, to
// k = 17 (for |x| < 0.5 the next term is below 1e-17 of the sum): (-1)^j / (j + 2)!
struct RestSeries {
    double c[16];
    constexpr RestSeries() : c() {
        double f = 2.0;  // (j + 2)!
        for (int j = 0; j < 16; ++j) {
            c[j] = (j % 2 == 0 ? 1.0 : -1.0) / f;
            f *= static_cast<double>(j + 3);
        }
    }
};
constexpr RestSeries kRestSeries;

// A point's adhesive energy beyond first order in a move delta, per unit of gamma0:
// exp(-g1/rho) - e0 + e0 x (>= 0), e0 = exp(-g0/rho) its weight before, g1 = g0 + delta >= 0 the
// gap after, x = delta/rho; for |x| < 0.5 as e0 (exp(-x) - 1 + x) by its series (Horner's rule:
// no division, no cancellation of its terms), and for larger |x| from the gap after, which cannot
// overflow where e0 underflowed: exp(-x) alone could.
// Split in two so that a pass over the points can vectorize the series: rest_series at every
// point (its value for |x| >= 0.5 unused), rest_far where |x| >= 0.5 (rest_near tells which).
inline bool rest_near(double x) { return std::fabs(x) < 0.5; }
inline double rest_series(double e0, double x) {
    double p = kRestSeries.c[15];
    for (int j = 14; j >= 0; --j) p = p * x + kRestSeries.c[j];
    return e0 * (x * x * p);
}
inline double rest_far(double e0, double x, double g1_over_rho) { return std::exp(-g1_over_rho) - e0 + e0 * x; }

// c0 of the stencil c0 L^2 fitted to k(q) in relative error over the modes with a stiffness:
// minimizes sum (c0 y - 1)^2, y = lambda^2 / k, lambda = 4 - 2 cos(qx a) - 2 cos(qy a) the
// 5-point -Laplacian's symbol in units of the spacing a.  A function of the body alone.
double stencil_scale(const FftGrid &grid, const Body &body) {
    const int64_t nxh = grid.nxh();
    const double a = grid.lx() / static_cast<double>(grid.nx());
    const double *stiff = body.stiffness.data();
    const auto s = grid.sum_mode_rows<2>([&](int64_t r0, int64_t r1, double *acc) {
        for (int64_t r = r0; r < r1; ++r) {
            const double cy = 2.0 - 2.0 * std::cos(grid.qy(grid.first_mode_row() + r) * a);
            for (int64_t kx = 0; kx < nxh; ++kx) {
                const double k = stiff[r * nxh + kx], lam = 2.0 - 2.0 * std::cos(grid.qx(kx) * a) + cy;
                if (!(k > 0.0)) continue;
                const double y = lam * lam / k;
                acc[0] += y;
                acc[1] += y * y;
            }
        }
    });
    return s[0] / s[1];
}
}  // namespace

const char *newton_grid_refusal(const FftGrid &grid) {
    if (grid.distributed()) return "the Newton solver runs on one process only";
    if (grid.nx() != grid.ny() || !StencilMultigrid::fits(grid.nx()) || grid.lx() != grid.ly())
        return "the Newton solver needs a square grid of square cells whose side is a power of 2 >= 32";
    return "";
}

const char *newton_refusal(const FftGrid &grid, const Params &p) {
    if (p.kind != GFMD_GREEN_LAYER_FLUID) return "the Newton solver takes a layer on a fluid foundation only";
    if (p.control != kPressureControl) return "the Newton solver takes pressure control only";
    return newton_grid_refusal(grid);
}

double ActiveSetNewton::bytes_per_point() { return 4 * 8.0 + 1.0 + StencilMultigrid::bytes_per_point(); }

ActiveSetNewton::ActiveSetNewton(int64_t side)
    : side_(side),
      r_(static_cast<std::size_t>(side * side)),
      p_(static_cast<std::size_t>(side * side)),
      s_(static_cast<std::size_t>(side * side)),
      e_(static_cast<std::size_t>(side * side)),
      held_(static_cast<std::size_t>(side * side)),
      block_top_(static_cast<std::size_t>(block_count(side * side, kBlock))),
      mg_(side) {}

void ActiveSetNewton::set_state(const std::vector<double> &s) {
    // (a checkpoint of a library before the trust region holds no number: the restarted radius)
    if (s.size() > 1 || (s.size() == 1 && !(std::isfinite(s[0]) && s[0] >= kTrustFloor)))
        fail(GFMD_ERR_FORMAT, "invalid Newton solver state");
    radius_ = s.empty() ? kTrustStart : s[0];
}

void ActiveSetNewton::restart(const Dynamics &) {
    c0_ = 0.0;
    radius_ = kTrustStart;
}

void ActiveSetNewton::advance(StepContext &c) {
    const FftGrid &grid = c.grid;
    double *__restrict z = c.fields.z.data(), *__restrict d = c.fields.v.data();
    const double *__restrict h = c.fields.h.data(), *__restrict f = c.fields.f.data();
    double *__restrict r = r_.data(), *__restrict p = p_.data(), *__restrict s = s_.data(), *__restrict e = e_.data();
    unsigned char *__restrict held = held_.data();
    std::vector<double> &block_top = block_top_;  // one number per kBlock block of points
    std::complex<double> *work = c.fields.work.data();
    const double *stiff = c.body.stiffness.data();
    const int64_t nxh = grid.nxh();
    const double inv_n = 1.0 / static_cast<double>(grid.real_size()), w_last = grid.weight(nxh - 1);
    // With adhesion the energy adds -gamma0 exp(-(z - h)/rho) a point (forces.cpp's units): its
    // curvature -(gamma0/rho^2) e on the free points, e = exp(-(z - h)/rho) of this z (in e_).
    const bool adhesive = c.params.gamma0 > 0.0;
    const double rho = c.params.rho, inv_rho = adhesive ? 1.0 / rho : 0.0;
    const double soft = adhesive ? c.params.gamma0 / (rho * rho) : 0.0, radius = radius_ * rho;

    // the held set and the right-hand side F_F
    const double b2 = grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
        double t = 0.0;
        for (int64_t i = i0; i < i1; ++i) {
            held[i] = held_by_wall(z[i], h[i], f[i]) ? 1 : 0;
            r[i] = held[i] ? 0.0 : f[i];
            d[i] = 0.0;
            t += r[i] * r[i];
        }
        if (adhesive)
            for (int64_t i = i0; i < i1; ++i) e[i] = held[i] ? 0.0 : std::exp(-(z[i] - h[i]) * inv_rho);
        acc[0] += t;
    })[0];
    if (!(b2 > 0.0)) return;  // nothing moves: the caller's test stops
    mg_.follow(held);
    if (!(c0_ > 0.0)) c0_ = stencil_scale(grid, c.body);  // once per restart (a new body restarts the solver)
    const double c0 = c0_;
    // s = M^-1 r, returns r.s (summed as grid.sum_points sums on this serial grid: kBlock blocks)
    const auto precondition = [&] { return mg_.apply_inverse(r, c0, s, kBlock); };
    // the largest t >= 0 with max |d + t sign p| <= radius on the free points (0 if p is 0 there):
    // how far the CG's iterate may go along sign p before it leaves the trust region.  Each free
    // point's limit (radius - d sign x)/|x| computed at every point, the others' masked to
    // +infinity, the minimum in vector lanes (exact in any order).
    const auto block_low = [&](double sign, int64_t i0, int64_t i1) {  // the points [i0, i1)' smallest limit
        const double inf = std::numeric_limits<double>::infinity();
        double low = inf;
#pragma omp simd reduction(min : low)
        for (int64_t i = i0; i < i1; ++i) {
            const double x = sign * p[i], ax = std::fabs(x), t = (radius - std::copysign(1.0, x) * d[i]) / ax;
            low = std::min(low, (held[i] == 0) & (ax != 0.0) ? t : inf);  // no branch: & not &&
        }
        return low;
    };
    const auto edge_of = [](double top) { return std::isfinite(top) ? std::max(-top, 0.0) : 0.0; };
    const auto to_edge = [&](double sign) {
        return edge_of(grid.max_points<1>([&](int64_t i0, int64_t i1, double *m) {
            m[0] = std::max(m[0], -block_low(sign, i0, i1));
        })[0]);
    };
    const auto step_along = [&](double t, double sign) {  // d += t sign p
        grid.for_points([&](int64_t i0, int64_t i1) {
            for (int64_t i = i0; i < i1; ++i) d[i] += t * (sign * p[i]);
        });
    };
    double rs = precondition();
    grid.for_points([&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) p[i] = s[i];
    });
    bool edge = false;  // the iterate stopped at the trust region's edge (with adhesion)
    for (int it = 1; it <= kMaxInner; ++it) {
        // s = K p on the free points (the stiffness scaled by -k/N: the elastic force of p), with
        // adhesion plus the adhesive curvature's -(gamma0/rho^2) e p; p.s and r.p
        grid.forward(p, work);
        grid.for_mode_rows([&](int64_t y0, int64_t y1) { kernels::use().apply_stiffness(work, stiff, y0, y1, nxh, inv_n, w_last); });
        grid.backward(work, s);
        const auto curv = grid.sum_points<2>([&](int64_t i0, int64_t i1, double *acc) {
            double t = 0.0, u = 0.0;
            if (adhesive) {
                for (int64_t i = i0; i < i1; ++i) {
                    s[i] = free_part(-s[i] - soft * e[i] * p[i], held[i]);
                    t += p[i] * s[i];
                    u += r[i] * p[i];
                }
                // to_edge(1)'s part of this block while p and d are in the cache (d does not
                // change before it is read: the same value as to_edge(1) after this pass); the
                // grid is serial (newton_grid_refusal), whose sums hand out blocks of kBlock
                // points from multiples of kBlock
                block_top[i0 / kBlock] = -block_low(1.0, i0, i1);
            } else {
                for (int64_t i = i0; i < i1; ++i) {
                    s[i] = free_part(-s[i], held[i]);
                    t += p[i] * s[i];
                }
            }
            acc[0] += t;
            acc[1] += u;
        });
        const double pkp = curv[0];
        if (!(pkp > 0.0)) {
            if (adhesive) {  // along p, downhill for the model, to the region's edge (Steihaug)
                const double sign = curv[1] >= 0.0 ? 1.0 : -1.0;
                step_along(to_edge(sign), sign);
                edge = true;
            } else if (it == 1) {  // no curvature along p (no contact holds the sheet): the first direction
                grid.for_points([&](int64_t i0, int64_t i1) {
                    for (int64_t i = i0; i < i1; ++i) d[i] = p[i];
                });
            }
            break;
        }
        const double a = rs / pkp;
        if (adhesive) {
            double top = -std::numeric_limits<double>::infinity();  // to_edge(1), from the blocks' parts
            for (const double x : block_top) top = std::max(top, x);
            const double t = edge_of(top);
            if (a > t) {  // the next iterate would leave the region: to its edge
                step_along(t, 1.0);
                edge = true;
                break;
            }
        }
        const double r2 = grid.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {
            double t = 0.0;
            for (int64_t i = i0; i < i1; ++i) {
                d[i] += a * p[i];
                r[i] -= a * s[i];
                t += r[i] * r[i];
            }
            acc[0] += t;
        })[0];
        if (!(r2 >= kInnerTolerance * kInnerTolerance * b2)) break;
        const double rs_new = precondition();
        const double beta = rs_new / rs;
        rs = rs_new;
        grid.for_points([&](int64_t i0, int64_t i1) {
            for (int64_t i = i0; i < i1; ++i) p[i] = s[i] + beta * p[i];
        });
    }

    // The move to max(h, z + alpha d): delta = that - z (in r) and the energy's change
    // -(A/N) F.delta + (A/2N^2) sum_q k |delta(q)|^2 (forces.cpp's units), the factor A/N dropped;
    // with adhesion plus the adhesive law's part beyond the first order, -gamma0 sum of
    // e (exp(-delta/rho) - 1 + delta/rho) (F holds its first order; rest_series, rest_far).
    double alpha = 1.0;
    for (int halving = 0;; ++halving, alpha *= 0.5) {
        const auto m = grid.sum_points<3>([&](int64_t i0, int64_t i1, double *acc) {
            double fd = 0.0, hits = 0.0, rest = 0.0;
            for (int64_t i = i0; i < i1; ++i) {
                const double zn = z[i] + alpha * d[i];
                hits += zn < h[i] ? 1.0 : 0.0;
                r[i] = (zn < h[i] ? h[i] : zn) - z[i];
                fd += f[i] * r[i];
            }
            if (adhesive) {  // the series into s (free after the CG), vectorized; then summed in order
                for (int64_t i = i0; i < i1; ++i) s[i] = rest_series(e[i], r[i] * inv_rho);
                for (int64_t i = i0; i < i1; ++i) {
                    if (r[i] == 0.0) continue;
                    const double x = r[i] * inv_rho;
                    rest += rest_near(x) ? s[i] : rest_far(e[i], x, (z[i] + r[i] - h[i]) * inv_rho);
                }
            }
            acc[0] += fd;
            acc[1] += hits;
            acc[2] += rest;
        });
        // the CG's iterate itself: a decrease of the quadratic energy (with adhesion always tested)
        if (m[1] == 0.0 && halving == 0 && !adhesive) break;
        if (halving == kMaxHalvings) break;  // the smallest step, taken (the next step starts again)
        grid.forward(r, work);
        const double dkd = grid.sum_mode_rows<1>([&](int64_t y0, int64_t y1, double *acc) {
            acc[0] += kernels::use().mode_energy(work, stiff, y0, y1, nxh, w_last);
        })[0];
        const double change = -m[0] + 0.5 * dkd * inv_n - c.params.gamma0 * m[2];
        if (change <= kArmijo * -m[0]) break;
    }
    if (adhesive) {  // the region: doubled after a full step to its edge, else the step taken
        if (alpha == 1.0 && edge) {
            radius_ *= 2.0;
        } else if (alpha < 1.0) {
            const double dmax = grid.max_points<1>([&](int64_t i0, int64_t i1, double *top) {
                for (int64_t i = i0; i < i1; ++i) top[0] = std::max(top[0], std::fabs(d[i]));
            })[0];
            radius_ = std::max(alpha * dmax * inv_rho, kTrustFloor);
        }
    }
    grid.for_points([&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) {
            const double zn = z[i] + alpha * d[i];  // as in the test: a point stopped is at h exactly
            z[i] = zn < h[i] ? h[i] : zn;
            d[i] = 0.0;  // at rest: the velocity field held the direction
        }
    });
}

}  // namespace gfmd
