/* The multigrid V-cycle for a thin sheet's stencil block on the free points, shared by the
 * measurement programs stencil_vcycle_timing.c and stencil_newton.c (not part of the library):
 *   fine grid    the fixed 13-point biharmonic stencil L^2 (L the periodic 5-point -Laplacian) on
 *                the free points, the held points (held[p] = 1) held at zero;
 *   coarse grids Galerkin operators P^T A P (bilinear P), 25 float coefficients a point, down to
 *                16^2, assembled row by row from the finer grid's operator (mg_assemble) and
 *                updated where the held set changed (mg_update);
 *   the cycle    V(nu, nu): Jacobi sweeps (the weights in dinv: l1-Jacobi from mg_assemble, or
 *                the caller's), the residual restricted, the cycle on the next grid, its
 *                correction prolonged; 40 sweeps on the coarsest grid.
 * Sides are powers of 2 (>= 32 on the fine grid). */
#ifndef GFMD_BENCH_STENCIL_MG_H
#define GFMD_BENCH_STENCIL_MG_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define CLONES __attribute__((target_clones("default", "arch=x86-64-v3")))
#else
#define CLONES
#endif

enum { MAXL = 20, NC = 25 }; /* levels; coarse stencil 5 x 5 */
/* the cycle's arithmetic: single precision (a preconditioner's rounding of 1e-7 against the
 * cycle's reduction of 0.8; half the memory traffic of doubles, and the cycle is bound by it) */
typedef float mgreal;
typedef struct {
    int m;                        /* side */
    float *c;                     /* coarse levels: NC coefficients a point, entry (dy + 2) * 5 + dx + 2 */
    mgreal *x, *b, *r, *t, *dinv; /* solution, right-hand side, residual, scratch, Jacobi weights */
} level;
static level lv[MAXL];
static int nl;
static unsigned char *held; /* fine grid: 1 where the wall holds the point */
static int nu = 2;          /* Jacobi sweeps before and after the coarse correction (--nu) */
enum { MG_APPLY, MG_JACOBI, MG_RESIDUAL }; /* y = A x;  y = x + dinv (b - A x);  y = b - A x */

static inline int wrap(int i, int m) { return i & (m - 1); } /* m a power of 2 */

static inline mgreal mg_out(int mode, mgreal x, mgreal ax, mgreal b, mgreal dinv) {
    return mode == MG_APPLY ? ax : mode == MG_RESIDUAL ? b - ax : x + dinv * (b - ax);
}

/* y = A x on level l (A: masked L^2 on the fine grid, the 25-point operator on coarse ones), or a
 * Jacobi sweep or the residual in the same pass (mode; b and dinv unused by MG_APPLY).  Rows in
 * order, the interior of each row in a loop without branches (it vectorizes), its two ends
 * wrapped. */
#define MG_L2(j0, jm2, jm1, jp1, jp2)                                                                  \
    (20 * r0[j0] - 8 * (r0[jm1] + r0[jp1] + rm1[j0] + rp1[j0]) + r0[jm2] + r0[jp2] + rm2[j0] + rp2[j0] + \
     2 * (rm1[jm1] + rm1[jp1] + rp1[jm1] + rp1[jp1]))
CLONES static void apply_fine(int m, const mgreal *x, mgreal *y, const mgreal *b, const mgreal *dinv, int mode) {
    for (int i = 0; i < m; i++) {
        const mgreal *rm2 = x + (size_t)wrap(i - 2, m) * m, *rm1 = x + (size_t)wrap(i - 1, m) * m,
                     *r0 = x + (size_t)i * m, *rp1 = x + (size_t)wrap(i + 1, m) * m,
                     *rp2 = x + (size_t)wrap(i + 2, m) * m;
        const unsigned char *h = held + (size_t)i * m;
        mgreal *yr = y + (size_t)i * m;
        const mgreal *br = b ? b + (size_t)i * m : r0, *dr = dinv ? dinv + (size_t)i * m : r0;
        for (int j = 0; j < m; j++) {
            if (j == 2) j = (m > 4) ? m - 2 : j; /* the interior below */
            const mgreal s = MG_L2(j, wrap(j - 2, m), wrap(j - 1, m), wrap(j + 1, m), wrap(j + 2, m));
            yr[j] = mg_out(mode, r0[j], h[j] ? 0 : s, br[j], dr[j]);
        }
        if (mode == MG_APPLY)
            for (int j = 2; j < m - 2; j++) yr[j] = h[j] ? 0 : MG_L2(j, j - 2, j - 1, j + 1, j + 2);
        else if (mode == MG_RESIDUAL)
            for (int j = 2; j < m - 2; j++) yr[j] = br[j] - (h[j] ? 0 : MG_L2(j, j - 2, j - 1, j + 1, j + 2));
        else
            for (int j = 2; j < m - 2; j++)
                yr[j] = r0[j] + dr[j] * (br[j] - (h[j] ? 0 : MG_L2(j, j - 2, j - 1, j + 1, j + 2)));
    }
}

/* the coarse operator: coefficient k of point p at c[k * m^2 + p] (25 planes, so that the row loop
 * vectorizes), entry k = (dy + 2) * 5 + dx + 2 */
CLONES static void apply_coarse(int m, const float *c, const mgreal *x, mgreal *y, const mgreal *b,
                                const mgreal *dinv, int mode) {
    const size_t mm = (size_t)m * m;
    for (int i = 0; i < m; i++) {
        mgreal *yr = y + (size_t)i * m;
        for (int j = 0; j < m; j++) yr[j] = 0;
        for (int a = -2; a <= 2; a++) {
            const mgreal *row = x + (size_t)wrap(i + a, m) * m;
            for (int e = -2; e <= 2; e++) {
                const float *ck = c + (size_t)((a + 2) * 5 + e + 2) * mm + (size_t)i * m;
                yr[0] += ck[0] * row[wrap(e, m)];
                yr[1] += ck[1] * row[wrap(1 + e, m)];
                for (int j = 2; j < m - 2; j++) yr[j] += ck[j] * row[j + e];
                yr[m - 2] += ck[m - 2] * row[wrap(m - 2 + e, m)];
                yr[m - 1] += ck[m - 1] * row[wrap(m - 1 + e, m)];
            }
        }
        if (mode != MG_APPLY) {
            const mgreal *xr = x + (size_t)i * m, *br = b + (size_t)i * m, *dr = dinv ? dinv + (size_t)i * m : xr;
            for (int j = 0; j < m; j++) yr[j] = mg_out(mode, xr[j], yr[j], br[j], dr[j]);
        }
    }
}

static void apply_mode(int l, const mgreal *x, mgreal *y, int mode) {
    if (l == 0) apply_fine(lv[l].m, x, y, lv[l].b, lv[l].dinv, mode);
    else apply_coarse(lv[l].m, lv[l].c, x, y, lv[l].b, lv[l].dinv, mode);
}

static inline void apply(int l, const mgreal *x, mgreal *y) { apply_mode(l, x, y, MG_APPLY); }

/* coarse (side m/2) <- P^T fine (side m): bilinear weights 1, 1/2, 1/4 */
CLONES static void restrict_to(int l, const mgreal *f, mgreal *c) {
    const int m = lv[l].m, mc = m / 2;
    for (int I = 0; I < mc; I++)
        for (int J = 0; J < mc; J++) {
            mgreal s = 0;
            for (int a = -1; a <= 1; a++)
                for (int e = -1; e <= 1; e++) {
                    const mgreal wgt = (mgreal)((a ? 0.5 : 1.0) * (e ? 0.5 : 1.0));
                    s += wgt * f[(size_t)wrap(2 * I + a, m) * m + wrap(2 * J + e, m)];
                }
            c[(size_t)I * mc + J] = s;
        }
}

/* fine (side m) += P coarse; on the fine grid the held points stay zero */
CLONES static void prolong_add(int l, const mgreal *c, mgreal *f) {
    const int m = lv[l].m, mc = m / 2;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < m; j++) {
            const size_t p = (size_t)i * m + j;
            if (l == 0 && held[p]) continue;
            const int I0 = i / 2, J0 = j / 2;
            const int I1 = (i % 2) ? wrap(I0 + 1, mc) : I0, J1 = (j % 2) ? wrap(J0 + 1, mc) : J0;
            const mgreal *r0 = c + (size_t)I0 * mc, *r1 = c + (size_t)I1 * mc;
            f[p] += (mgreal)0.25 * (r0[J0] + r0[J1] + r1[J0] + r1[J1]);
        }
}

/* x <- x + D^-1 (b - A x), `sweeps` times, each one pass into t, then swapped */
static void jacobi(int l, int sweeps) {
    for (int s = 0; s < sweeps; s++) {
        apply_mode(l, lv[l].x, lv[l].t, MG_JACOBI);
        mgreal *x = lv[l].x;
        lv[l].x = lv[l].t;
        lv[l].t = x;
    }
}

/* the first sweep from x = 0: x = D^-1 b, no operator to apply (the same bits as a sweep) */
CLONES static void first_sweep(int l) {
    const size_t mm = (size_t)lv[l].m * lv[l].m;
    for (size_t p = 0; p < mm; p++) lv[l].x[p] = lv[l].dinv[p] * lv[l].b[p];
}

/* one V(nu, nu)-cycle for level l's right-hand side b from x = 0; the result in lv[l].x */
static void cycle(int l) {
    first_sweep(l);
    if (l == nl - 1) {
        jacobi(l, 39);
        return;
    }
    jacobi(l, nu - 1);
    apply_mode(l, lv[l].x, lv[l].r, MG_RESIDUAL);
    restrict_to(l, lv[l].r, lv[l + 1].b);
    cycle(l + 1);
    prolong_add(l, lv[l + 1].x, lv[l].x);
    jacobi(l, nu);
}

/* The 13-point L^2 as a 5 x 5 table, entry [dy + 2][dx + 2] */
static const double L2_TABLE[5][5] = {
    {0, 0, 1, 0, 0}, {0, 2, -8, 2, 0}, {1, -8, 20, -8, 1}, {0, 2, -8, 2, 0}, {0, 0, 1, 0, 0}};

/* the operator's entry on level l between point (y, x) and its neighbour (y + dy, x + dx) */
static inline double mg_entry(int l, int y, int x, int dy, int dx) {
    const int m = lv[l].m;
    const size_t p = (size_t)y * m + x;
    if (l > 0) return lv[l].c[(size_t)((dy + 2) * 5 + dx + 2) * m * m + p];
    const double v = L2_TABLE[dy + 2][dx + 2];
    return (v == 0.0 || held[p] || held[(size_t)wrap(y + dy, m) * m + wrap(x + dx, m)]) ? 0.0 : v;
}

/* the fine grid's Jacobi weight at p: 1 / sum_j |A_pj| (l1-Jacobi: a smoother without a
 * damping factor to estimate, stable whatever the held set); 0 where the point is held */
static inline void mg_fine_dinv(int y, int x) {
    const int m = lv[0].m;
    double s = 0.0;
    for (int dy = -2; dy <= 2; dy++)
        for (int dx = -2; dx <= 2; dx++) s += fabs(mg_entry(0, y, x, dy, dx));
    lv[0].dinv[(size_t)y * m + x] = (mgreal)(s > 0 ? 1.0 / s : 0.0);
}

/* a fine point j - 2I = r (-3..3, in one direction) spread to the coarse offsets P gives it: r/2
 * with weight 1 if r is even, (r -+ 1)/2 with weight 1/2 each if odd; indexed by r + 3 */
static const struct {
    int count, to[2];
    double weight;
} SPREAD[7] = {{2, {-2, -1}, 0.5}, {1, {-1, 0}, 1.0}, {2, {-1, 0}, 0.5}, {1, {0, 0}, 1.0},
               {2, {0, 1}, 0.5},   {1, {1, 0}, 1.0},  {2, {1, 2}, 0.5}};

/* row (Y, X) of level l + 1's operator, P^T A_l P, and its l1-Jacobi weight: fine points 2Y + a
 * (a = -1, 0, 1, weights 1/2, 1, 1/2 in each direction), their neighbours j = 2Y + a + d (d =
 * -2..2) spread to the coarse points (j +- 1) / 2 or j / 2 (weights 1/2 or 1): offsets -2..2 */
static void mg_row(int l, int Y, int X) {
    const int m = lv[l].m, mc = m / 2;
    const size_t mmc = (size_t)mc * mc, p = (size_t)Y * mc + X;
    double acc[NC] = {0};
    for (int a = -1; a <= 1; a++)
        for (int b = -1; b <= 1; b++) {
            const double wi = (a ? 0.5 : 1.0) * (b ? 0.5 : 1.0);
            const int y = wrap(2 * Y + a, m), x = wrap(2 * X + b, m);
            for (int dy = -2; dy <= 2; dy++)
                for (int dx = -2; dx <= 2; dx++) {
                    const double v = mg_entry(l, y, x, dy, dx);
                    if (v == 0.0) continue;
                    const int ry = a + dy + 3, rx = b + dx + 3; /* j - 2I + 3, in 0..6 */
                    for (int sy = 0; sy < SPREAD[ry].count; sy++)
                        for (int sx = 0; sx < SPREAD[rx].count; sx++)
                            acc[(SPREAD[ry].to[sy] + 2) * 5 + SPREAD[rx].to[sx] + 2] +=
                                wi * v * SPREAD[ry].weight * SPREAD[rx].weight;
                }
        }
    double s = 0.0;
    for (int k = 0; k < NC; k++) {
        lv[l + 1].c[(size_t)k * mmc + p] = (float)acc[k];
        s += fabs(acc[k]);
    }
    lv[l + 1].dinv[p] = (mgreal)(s > 0 ? 1.0 / s : 0.0);
}

/* every coarse operator and every Jacobi weight for the current held set */
static void mg_assemble(void) {
    const int m = lv[0].m;
    for (int y = 0; y < m; y++)
        for (int x = 0; x < m; x++) mg_fine_dinv(y, x);
    for (int l = 0; l + 1 < nl; l++)
        for (int Y = 0; Y < lv[l + 1].m; Y++)
            for (int X = 0; X < lv[l + 1].m; X++) mg_row(l, Y, X);
}

/* after the held set changed at the `count` fine points `changed`: the rows that depend on them,
 * recomputed level by level (dirty[l]: one byte a point of level l, zero on entry and on return).
 * A fine row depends on held[] within 2 points; row I of level l + 1 on the rows of level l
 * within one point of 2I.  Returns the rows recomputed, summed over the levels. */
static inline size_t mg_update(const size_t *changed, size_t count, unsigned char **dirty) {
    const int m = lv[0].m;
    size_t rows = 0;
    for (size_t k = 0; k < count; k++) {
        const int y = (int)(changed[k] / (size_t)m), x = (int)(changed[k] % (size_t)m);
        for (int dy = -2; dy <= 2; dy++)
            for (int dx = -2; dx <= 2; dx++) dirty[0][(size_t)wrap(y + dy, m) * m + wrap(x + dx, m)] = 1;
    }
    for (int l = 0; l < nl; l++) {
        const int ml = lv[l].m;
        for (int y = 0; y < ml; y++)
            for (int x = 0; x < ml; x++) {
                const size_t p = (size_t)y * ml + x;
                if (!dirty[l][p]) continue;
                dirty[l][p] = 0;
                rows++;
                if (l == 0) mg_fine_dinv(y, x);
                else mg_row(l - 1, y, x);
                if (l + 1 < nl) /* the rows of level l + 1 with |2I - (y, x)| <= 1 */
                    for (int Y = y / 2 - 1; Y <= (y + 1) / 2 + 1; Y++)
                        for (int X = x / 2 - 1; X <= (x + 1) / 2 + 1; X++)
                            if (abs(2 * Y - y) <= 1 && abs(2 * X - x) <= 1)
                                dirty[l + 1][(size_t)wrap(Y, ml / 2) * (ml / 2) + wrap(X, ml / 2)] = 1;
            }
    }
    return rows;
}

/* the levels of an n x n grid, n, n/2, ... down to 16 points a side (at most MAXL): their arrays
 * allocated (the coarse ones' operators too); 0 on success, -1 out of memory (mg_free() then frees
 * what was allocated) */
static inline int mg_alloc(int n) {
    for (int m = n; m >= 16 && nl < MAXL; m /= 2) {
        const size_t mm = (size_t)m * m;
        level *L = &lv[nl++];
        L->m = m;
        L->x = malloc(mm * sizeof(mgreal)), L->b = malloc(mm * sizeof(mgreal)), L->r = malloc(mm * sizeof(mgreal));
        L->t = malloc(mm * sizeof(mgreal)), L->dinv = malloc(mm * sizeof(mgreal));
        L->c = (m < n) ? malloc(mm * NC * sizeof(float)) : NULL;
        if (!L->x || !L->b || !L->r || !L->t || !L->dinv || (m < n && !L->c)) return -1;
    }
    return 0;
}

/* every level's arrays freed (mg_alloc()) */
static inline void mg_free(void) {
    for (int l = 0; l < nl; l++) {
        free(lv[l].x);
        free(lv[l].b);
        free(lv[l].r);
        free(lv[l].t);
        free(lv[l].dinv);
        free(lv[l].c);
    }
    nl = 0;
}

#endif
