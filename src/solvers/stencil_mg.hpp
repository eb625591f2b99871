// The multigrid V-cycle for a thin sheet's stiffness between its contacts, the preconditioner of
// the active-set Newton method (newton.hpp).  A thin sheet's k(q) is nearly local: c0 L^2, the
// 13-point biharmonic stencil (L the periodic 5-point -Laplacian) scaled to fit k(q), stands for it
// within a factor of a few over all modes, and so does its block on the points the wall does not
// hold for the stiffness' block there (docs/decisions.md).  The levels:
//   fine grid    L^2 on the free points, the held points held at zero;
//   coarse grids Galerkin operators P^T A P (bilinear P), 25 coefficients a point (13 stored: the
//                operator is symmetric), down to 16^2,
//                assembled for a held set and then recomputed only in the rows its change reaches
//                (the same bits as a whole assembly: each row is one function of the held set);
//   the cycle    a V-cycle smoothed by Chebyshev's degree-2 polynomial in D^-1 A on [1/16, 1]
//                before and after the coarse correction (D the l1 weights 1 / sum_j |A_ij|,
//                which bound the spectrum by 1 for any held set: no eigenvalue to estimate), the
//                residual restricted, the next grid's cycle, its correction prolonged; 40
//                l1-Jacobi sweeps on the coarsest grid.
// In single precision: a preconditioner's rounding of 1e-7 against a cycle's reduction of 0.8, and
// half the memory traffic of doubles, which bounds the cycle.  Serial (a deterministic order);
// square grids whose side is a power of 2 >= 32.
#ifndef GFMD_SRC_SOLVERS_STENCIL_MG_HPP
#define GFMD_SRC_SOLVERS_STENCIL_MG_HPP

#include <cstdint>
#include <vector>

#include "../buffer.hpp"

namespace gfmd {

class StencilMultigrid {
public:
    // Memory a grid of side m takes, per fine point (about 60 bytes).
    static double bytes_per_point();
    // Whether a square grid of side m can have the cycle: a power of 2 >= 32.
    static bool fits(int64_t m) { return m >= 32 && (m & (m - 1)) == 0; }
    // Throws std::bad_alloc.  m must fit().
    explicit StencilMultigrid(int64_t m);
    // The operators for the held set (held[p] = 1 where the wall holds point p).
    void follow(const unsigned char *held);
    // x = V(b) / scale on the free points, 0 on the held ones (b must be 0 there).  follow() first.
    // Returns b.x, summed as a serial grid's sum_points sums (parallel.hpp): in blocks of `block`
    // points, each in order from 0, the blocks' sums added in order -- the same bits, without a
    // pass of its own over b and x.
    double apply_inverse(const double *b, double scale, double *x, int64_t block);
    // Level l's operator entry between point (y, x) and its neighbour (y + dy, x + dx), |dy|, |dx|
    // <= 2 (level 0: the fine stencil on the free points; the tests compare the coarse ones with a
    // Galerkin product of their own).  follow() first.
    double operator_entry(int l, int64_t y, int64_t x, int dy, int dx) const { return entry(l, y, x, dy, dx); }
    int levels() const { return static_cast<int>(lv_.size()); }

private:
    struct Level {
        int64_t m = 0;
        AlignedBuffer<float> c;                 // coarse levels: 13 planes of m^2, the forward offsets' (plane())
        AlignedBuffer<float> x, b, r, t, dinv;  // solution, right-hand side, residual, scratch, weights
        AlignedBuffer<unsigned char> dirty;     // rows to recompute (update())
        AlignedBuffer<unsigned char> special;   // coarse levels: 1 where the row is not the free sheet's
        float free_row[14] = {};                // the free sheet's row on this level: 13 entries, the weight
        bool has_free_row = false;
    };
    enum Mode { kApply, kJacobi, kResidual };
    void apply_fine(const float *x, float *y, const float *b, const float *dinv, Mode mode) const;
    void apply_coarse(const Level &lv, const float *x, float *y, const float *b, const float *dinv, Mode mode) const;
    void apply_mode(int l, const float *x, float *y, Mode mode);
    void restrict_to(int l, const float *f, float *c) const;
    void prolong_add(int l, const float *c, float *f) const;
    void jacobi(int l, int sweeps);
    void chebyshev(int l, bool from_zero);
    static float first_scale();  // x = first_scale() D^-1 b: the smoother's first iterate from 0
    // started: the caller has made the first sweep x = D^-1 b already
    void cycle(int l, bool started = false);
    double entry(int l, int64_t y, int64_t x, int dy, int dx) const;
    void fine_weight(int64_t y, int64_t x);
    bool pristine_window(int l, int64_t Y, int64_t X) const;
    void coarse_row(int l, int64_t Y, int64_t X);
    void assemble();
    void update();
    std::vector<Level> lv_;
    AlignedBuffer<unsigned char> held_;  // the held set the operators belong to
    std::vector<int64_t> changed_;       // points whose held state changed (capacity: the update's limit)
    bool assembled_ = false;
};

}  // namespace gfmd

#endif
