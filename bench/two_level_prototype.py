#!/usr/bin/env python3
"""A measurement, not a solver of the library: does a coarse space at the contacts' spacing cut the
preconditioned CG's iterations on a thin sheet held by its contacts?

The library's preconditioned surface CG (src/solvers/cg.cpp) and its mass-weighted FIRE
(src/solvers/fire_mass.cpp) precondition with the masked inverse P M^-1 P, M = max(k(q), k_c):
the principal block of M^-1 on the free points, not the inverse of the stiffness's block on them.
What it misses are the long waves between the points the wall holds.  This program adds to it a
coarse correction on bilinear hats of a grid coarsened c times, masked to the free points, in the
balancing form

    B r = Q r + (I - Q K) P M^-1 P (I - K Q) r,   Q = Z (Z^T K Z)^-1 Z^T,

with Z^T K Z read off K by probing (one FFT pair for every S-th hat in each direction at once, S^2
pairs) and its system solved exactly or by a few Jacobi-preconditioned CG iterations, and counts:

  --fixed   the held set of the library's equilibrium at sigma0 fixed: CG iterations to 1e-8 of
            the right-hand side (a uniform load on the free points and a random one) with P M^-1 P
            and with B (flexible CG when the coarse solve is inexact);
  --newton  a continuing load sigma0 -> sigma1 from the library's equilibrium at sigma0 by an
            active-set Newton method (the held set fixed per Newton step, its linear problem
            solved by CG to a tenth of its residual, a backtracking step clipped at the wall),
            FFT pairs counted, against the library's own steps on the same load (with --gamma0
            the CG runs on K plus the adhesive law's negative curvature, stopped where p.Ap <= 0);
  --fire    the same load by FIRE on the preconditioned force (a = P M^-1 P F, or a = B F with the
            coarse operator rebuilt when the held set changes), also with adhesion.
  --by-residual  the library's own steps on that load to residuals 1e-3, 1e-4, ... --tol (each
            call continuing the trajectory; checked against one call: the same steps and surface).
  --stencil DEG  with --newton: the second method's CG preconditioned not by the coarse space but
            by the exact inverse of a real-space stencil's block on the free points, the stencil
            L^2 times a polynomial of degree DEG in L (L the 5-point -Laplacian) fitted to k(q);
            --stencil-rtol R: that block solved only to R (how well a multigrid solve must do);
            --stencil-mg NU: by one multigrid V(NU,NU)-cycle (Galerkin coarse operators that see
            the held set, damped Jacobi smoothing).

What it found (2026-11-28): the coarse space cuts the iterations and steps several-fold, with a
coarse operator that follows the held set at every change; probed, that costs S^2 FFT pairs per
change and eats the gain; --rebuild F (the operator kept until the held count moved by F) makes
FIRE diverge; --drop F (the operator kept, the hats the held set changed in dropped from it,
whose block stays exact) is stable but loses most of the gain: the coarse space is needed exactly
where the held set moves; --assembly R --sharp (K's real-space kernel cut sharply) leaves CG
unconverged.  --assembly R (the kernel times a Gaussian window) works as well as the probed
operator and costs no FFT pair: each entry reads the free set near its two hats only, so it can
follow the held set point by point.  The deflation forms with one FFT pair fewer per step
(--form def1, def2) did worse than the balancing one.

Measured again that evening at the library's own criterion (--tol; before, the methods here
stopped at max |F| <= 1e-8 E* g, about the library's default 1e-6, while the library was run to
1e-8): at the study's tolerance 1e-6 the default took 333, 260 and 1064 steps on the three
continuing loads (not 424, 340 and 1173), two-level FIRE 114, 126 and 431 — 2.1-2.9x fewer; the
default's mass-weighted step costs about 3 FFT pairs (gfmd_bench, 2048²), the two-level step 4
pairs, two coarse solves of about 0.9 pair each (bench/coarse_solve_timing) and its passes: about
0.9-1.3x the default's speed, not the 1.9x the study's thin sheets need (the Newton method with
the coarse space 1.1-1.5x without adhesion, 0.93x with it, --newton --gamma0).  The
cheaper forms do not rescue it: --form additive (Q + P M^-1 P, no extra pair) cuts nothing, with
P M^-1 P's floor raised to the coarse grid's waves (--smoother-floor) neither (in FIRE 573 steps);
--form adef2 (the balancing form's CG started from Q b, one solve an iteration) needs the Galerkin
coarse operator of K, and the windowed one is not: no convergence with the exact coarse solve.

The library and every method stop at the library's criterion (rms residual relative to sigma +
gamma0/rho, --tol, 1e-8 unless given, tighter than the default so that the equilibria can be
compared: max |z - z_library| printed).  Needs python3-numpy and python3-scipy (apt) and the built
library (GFMD_LIBRARY or build/).  docs/performance.md, *What was tried*, quotes its figures.

  python3 bench/two_level_prototype.py --fixed  [--n 256] [--W 0.088] [--sigma0 1e-4] [--c 4]
  python3 bench/two_level_prototype.py --newton [--n 256] [--W 0.088] [--sigma0 1e-4 --sigma1 1.6e-4]
  python3 bench/two_level_prototype.py --fire --assembly 8 [--gamma0 5e-4 --sigma0 2e-5 --sigma1 3.5e-5]
"""
import argparse
import os
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import gfmd  # noqa: E402

TOL = [1e-8]  # --tol: the library's criterion (rms residual / (sigma + gamma0/rho)) for every method
CHECKS = []  # (what, value, bound) of every solution, for --check
FLOOR_Q = [0.0]  # --smoother-floor F: P M^-1 P floored at k(q) for q <= F pi / c
FORM = ["balancing"]  # --form: how the coarse correction and P M^-1 P combine


def converged(residual, sigma, gamma, rho, tol=None):
    """gfmd_get_residual's criterion: the rms over all points of the net stress that is not the
    wall's, divided by sigma + gamma0/rho + 1e-8 E* (docs/model.md), <= tol (--tol unless given)."""
    return np.sqrt(np.mean(residual ** 2)) <= (TOL[0] if tol is None else tol) * (abs(sigma) + gamma / rho + 1e-8)


class Sheet:
    """The study's substrate (H = 0.8, lambda_s = 4a, lambda_r = n a / 8, g = 1, seed 1) under a
    layer of width w = 4 W a on a fluid foundation (W = 0: a half-space), E* = 1, a = 1, and its
    stiffness in numpy; the handle's threads and FFT planner as gfmd.Simulation's."""

    def __init__(self, n, W, gamma0=0.0, rho=1.0, threads=0, planner=None):
        self.n, self.w = n, 4.0 * W
        self.sim = gfmd.Simulation(n, n, float(n), float(n), threads=threads, planner=planner)
        self.sim.set_modulus(1.0)
        if W > 0:
            self.sim.set_green(gfmd.LAYER_FLUID, self.w)
        self.sim.generate_selfaffine(0.8, n / 8.0, 4.0, 1.0, 1)
        self.h = self.sim.heights()
        self.gamma0, self.rho = gamma0, rho
        if gamma0 > 0:
            self.sim.set_adhesion(gamma0, rho)
        self.qx, self.qy = np.meshgrid(2 * np.pi * np.fft.rfftfreq(n), 2 * np.pi * np.fft.fftfreq(n))
        self.q = np.hypot(self.qx, self.qy)
        f = np.ones_like(self.q)
        for i, t in np.ndenumerate(self.q * self.w):
            if t > 0:
                f[i] = gfmd.green_factor(gfmd.LAYER_FLUID, t)
        self.k = np.where(self.q > 0, self.q / (2 * f), 0.0)
        self.pairs = self.solves = 0

    def relax(self, sigma0):
        self.sim.set_pressure(sigma0)
        steps = self.sim.relax(tol=TOL[0])
        return steps, self.sim.surface().copy()

    def truncated(self, radius, sharp=False):
        """K's real-space kernel within |dx|, |dy| <= radius, as a sparse matrix (no FFT pair: an
        assembly a solver could update point by point as the held set changes)."""
        if getattr(self, "_trunc", (None,))[0] != (radius, sharp):
            n = self.n
            kr = np.fft.irfft2(self.k, s=(n, n))
            idx = np.r_[0:radius + 1, n - radius:n]
            if sharp:
                # cut sharply, K's zero sum (k(0) = 0) kept by the centre: the long waves get a
                # stiffness of either sign from the kernel's slowly decaying, alternating tail
                # along the axes (the kink of k(q) at the zone boundary), and the CG fails
                w = kr[np.ix_(idx, idx)].copy()
                w[0, 0] -= w.sum()
            else:
                # times a Gaussian window of width radius / 4: the symbol is k(q) averaged over a
                # width of about 4 / radius (a Gaussian has a positive transform, so the operator
                # stays positive), stiffer than K at the longest waves, which the contacts pin
                d = np.where(idx > n // 2, idx - n, idx).astype(float)
                dx, dy = np.meshgrid(d, d, indexing="ij")
                w = kr[np.ix_(idx, idx)] * np.exp(-(dx ** 2 + dy ** 2) / (2 * (radius / 4.0) ** 2))
            kr[:] = 0.0
            kr[np.ix_(idx, idx)] = w
            shift = [sp.csr_matrix(np.roll(np.eye(n), d, axis=1)) for d in range(-radius, radius + 1)]
            T = sp.csr_matrix((n * n, n * n))
            for i, dx in enumerate(range(-radius, radius + 1)):
                for j, dy in enumerate(range(-radius, radius + 1)):
                    T = T + kr[dx % n, dy % n] * sp.kron(shift[i], shift[j], format="csr")
            self._trunc = ((radius, sharp), T.tocsr())
        return self._trunc[1]

    def K(self, x):
        self.pairs += 1
        return np.fft.irfft2(np.fft.rfft2(x) * self.k, s=x.shape)

    def gradient(self, u, sigma):
        """The energy's gradient K u + sigma + (gamma0/rho) w and the adhesive weight w =
        exp(-(u - h)/rho) (None without adhesion); one FFT pair."""
        g = self.K(u) + sigma
        if self.gamma0 <= 0:
            return g, None
        w = np.exp(-(u - self.h) / self.rho)
        return g + (self.gamma0 / self.rho) * w, w

    def energy(self, u, sigma):  # not counted: a solver gets it from the transforms it does anyway
        adhesive = -self.gamma0 * np.exp(-(u - self.h) / self.rho).sum() if self.gamma0 > 0 else 0.0
        return 0.5 * (u * np.fft.irfft2(np.fft.rfft2(u) * self.k, s=u.shape)).sum() + sigma * u.sum() + adhesive

    def masked_inverse(self, free, floor_q=0.0):
        """P M^-1 P with the library's floor k_c (src/solvers/cg.cpp: q_c = min(0.5 q_spacing, 1/w),
        at dense contacts no lower than 0.5 q_spacing / 5)."""
        phi = 1.0 - free.mean()
        qc2 = 0.25 * 4 * np.pi * phi
        cap2 = 1.0 / self.w ** 2
        if phi >= 0.05:
            cap2 = max(cap2, qc2 / 25)
        kmin = self.k[self.q > 0].min()
        kc = max(self.k[self.q ** 2 <= min(qc2, cap2)].max(), kmin)
        if floor_q > 0:  # --smoother-floor: the fine part left the short waves only
            kc = max(kc, self.k[self.q <= floor_q].max())
        m = np.maximum(self.k, kc)
        m[0, 0] = kc

        def apply(r):
            self.pairs += 1
            return free * np.fft.irfft2(np.fft.rfft2(free * r) / m, s=r.shape)
        return apply


def stencil_matrix(sheet, deg):
    """A real-space stencil S ~ K for --stencil: L^2 (c0 + c1 L + ... + c_deg L^deg), L the
    periodic 5-point -Laplacian (symbol lam = 4 - 2 cos qx - 2 cos qy), the c fitted to k(q) / lam^2
    by least squares in the relative error over the modes (a thin sheet's k is w^3 q^4 / 12 at
    long waves, lam^2 -> q^4); a stencil 2 deg + 5 points wide.  Returns S and the range of its
    symbol over k(q), q != 0 (CG's count depends on that ratio's spread, not on its scale)."""
    n = sheet.n
    e = np.ones(n)
    D = sp.diags([-e[:-1], 2 * e, -e[:-1]], [-1, 0, 1], format="lil")
    D[0, n - 1] = D[n - 1, 0] = -1
    I1 = sp.identity(n, format="csr")
    L = (sp.kron(D.tocsr(), I1) + sp.kron(I1, D.tocsr())).tocsr()
    lam = (4 - 2 * np.cos(sheet.qx) - 2 * np.cos(sheet.qy))[sheet.q > 0]
    y = sheet.k[sheet.q > 0] / lam ** 2
    A = np.array([lam ** a for a in range(deg + 1)]).T
    c, *_ = np.linalg.lstsq(A / y[:, None], np.ones_like(y), rcond=None)
    ratio = (A @ c) / y
    poly, power = c[0] * sp.identity(n * n, format="csr"), sp.identity(n * n, format="csr")
    for a in range(1, deg + 1):
        power = (power @ L).tocsr()
        poly = poly + c[a] * power
    return (L @ L @ poly).tocsc(), (ratio.min(), ratio.max())


MG_SWEEPS = [0]  # --stencil-mg NU: one V(NU, NU)-cycle instead of the exact solve


def multigrid(n, idx, a_ff, nu):
    """One V(nu, nu)-cycle for the free block a_ff as an operator b -> x: Galerkin coarse operators
    P^T A P with bilinear prolongation from grids coarsened 2, 4, ... times (the fine grid's rows
    of held points left out, so that the coarse operators see the held set), coarse points whose
    hats hold no free point dropped, down to 16^2 or less and an exact solve there; damped Jacobi
    smoothing (4 / (3 lambda_max) of D^-1 A by 20 power iterations).  Built once per held set."""
    def prolong_1d(m):  # m/2 -> m points, periodic: 1 at even points, 1/2 to the odd neighbours
        rows, cols, vals = [], [], []
        for i in range(m):
            if i % 2 == 0:
                rows.append(i), cols.append(i // 2), vals.append(1.0)
            else:
                for j in ((i - 1) // 2, ((i + 1) // 2) % (m // 2)):
                    rows.append(i), cols.append(j), vals.append(0.5)
        return sp.csr_matrix((vals, (rows, cols)), shape=(m, m // 2))

    levels, keep, m, a = [], idx, n, a_ff
    while True:
        d = a.diagonal()
        x = np.random.default_rng(5).standard_normal(a.shape[0])
        for _ in range(20):
            x = (a @ x) / d
            lam = np.linalg.norm(x)
            x /= lam
        level = {"a": a, "dinv": 1.0 / d, "omega": 4.0 / (3.0 * lam)}
        levels.append(level)
        if m <= 16 or m % 2:
            level["solve"] = spl.factorized(a.tocsc())
            break
        p1 = prolong_1d(m)
        p_full = sp.kron(p1, p1, format="csr")[keep]
        a_c = (p_full.T @ a @ p_full).tocsr()
        alive = np.flatnonzero(a_c.diagonal() > 0)
        level["p"] = p_full[:, alive].tocsr()
        a = a_c[alive][:, alive].tocsr()
        keep = alive
        m //= 2

    def cycle(k, b):
        lv = levels[k]
        if "solve" in lv:
            return lv["solve"](b)
        a, dinv, w = lv["a"], lv["dinv"], lv["omega"]
        x = w * dinv * b
        for _ in range(nu - 1):
            x += w * dinv * (b - a @ x)
        x += lv["p"] @ cycle(k + 1, lv["p"].T @ (b - a @ x))
        for _ in range(nu):
            x += w * dinv * (b - a @ x)
        return x
    return lambda b: cycle(0, b)


def stencil_inverse(sheet, free, deg, rtol=0.0):
    """--stencil: r -> S_FF^-1 r on the free points, the inverse of the stencil's free block (the
    sheet bending between the points the wall holds, which they hold at rest), by a sparse LU
    factorization per held set -- the ideal a multigrid solve would approximate; or, with rtol
    (--stencil-rtol), inexactly: Jacobi-preconditioned CG on S_FF to that relative residual, to
    see how well a multigrid solve must do.  Solves counted."""
    if getattr(sheet, "_stencil", (None,))[0] != deg:
        sheet._stencil = (deg,) + stencil_matrix(sheet, deg)
    S = sheet._stencil[1]
    idx = np.flatnonzero(free.ravel())
    s_ff = S[idx][:, idx]
    if rtol > 0:
        s_ff = s_ff.tocsr()
        d = s_ff.diagonal()

        def solve(b):
            x, r = np.zeros_like(b), b.copy()
            y = r / d
            p, ry, b0 = y.copy(), r @ y, np.sqrt(b @ b)
            for _ in range(100 * len(b)):  # CG ends in len(b) steps in exact arithmetic
                if np.sqrt(r @ r) <= rtol * b0:
                    break
                sp_ = s_ff @ p
                a = ry / (p @ sp_)
                x += a * p
                r -= a * sp_
                y = r / d
                ry, ry_old = r @ y, ry
                p = y + (ry / ry_old) * p
            else:
                raise RuntimeError("the stencil's Jacobi-CG did not converge")
            return x
    elif MG_SWEEPS[0] > 0:
        solve = multigrid(sheet.n, idx, s_ff.tocsr(), MG_SWEEPS[0])
    else:
        solve = spl.factorized(s_ff.tocsc())

    def apply(r):
        sheet.solves += 1
        x = np.zeros(r.size)
        x[idx] = solve(r.ravel()[idx])
        return x.reshape(r.shape)
    return apply


def coarse_space(sheet, free, c, S, coarse_its, assembly=0, sharp=False):
    """Q and the balancing preconditioner B for the held set ~free; S^2 probes counted as pairs."""
    n = sheet.n
    nc = n // c
    t = np.arange(n)
    hat = np.zeros((nc, n))
    for j in range(nc):
        d = (t - j * c + n / 2) % n - n / 2
        hat[j] = np.maximum(0.0, 1.0 - np.abs(d) / c)
    hat = sp.csr_matrix(hat)
    full = sp.kron(hat, hat).tocsr()
    Z = (full @ sp.diags(free.ravel().astype(float))).tocsr()
    if assembly > 0:
        return finish(sheet, free, Z, Z @ sheet.truncated(assembly, sharp) @ Z.T, coarse_its, n, nc, full)
    R = S // 2
    rows, cols, vals = [], [], []
    for cx in range(S):
        for cy in range(S):
            idx = (np.arange(cx, nc, S)[:, None] * nc + np.arange(cy, nc, S)[None, :]).ravel()
            probe = np.asarray(Z[idx].sum(axis=0)).reshape(n, n)
            seen = Z @ (free * sheet.K(probe)).ravel()
            for j in idx:
                j0, j1 = divmod(int(j), nc)
                for di in range(-R, R + 1):
                    for dj in range(-R, R + 1):
                        rows.append(((j0 + di) % nc) * nc + (j1 + dj) % nc)
                        cols.append(j)
                        vals.append(seen[rows[-1]])
    return finish(sheet, free, Z, sp.csr_matrix((vals, (rows, cols)), shape=(nc * nc, nc * nc)),
                  coarse_its, n, nc, full)


def finish(sheet, free, Z, A, coarse_its, n, nc, support=None):
    A = (0.5 * (A + A.T)).tocsr()
    d = A.diagonal()
    A = (A + sp.diags((d <= 0).astype(float))).tocsr()  # a hat with no free point: a unit row
    dinv = 1.0 / A.diagonal()
    lu = spl.splu(A.tocsc()) if coarse_its == 0 else None

    def solve(v, keep=None):
        sheet.solves += 1
        if lu is not None and keep is None:
            return lu.solve(v)
        x, r = np.zeros_like(v), v.copy()
        y = dinv * r
        p, ry = y.copy(), r @ y
        for _ in range(coarse_its):
            Ap = A @ p if keep is None else keep * (A @ p)
            a = ry / (p @ Ap)
            x += a * p
            r -= a * Ap
            y = dinv * r
            ry, ry_old = r @ y, ry
            p = y + (ry / ry_old) * p
        return x

    def galerkin(x, f):  # Q x = f Z^T A^-1 Z f x
        return f * (Z.T @ solve(Z @ (f * x).ravel())).reshape(n, n)

    def B(r, now=None, keep=None):
        # now: the free set of the current step when the coarse operator is older (--rebuild);
        # Q is then masked to it (symmetric), the fine part follows it.  keep (--drop): the hats
        # whose support the held set has not changed in since the build; their block of A is
        # exact for the current held set (A[I, J] reads the free set on the supports of I and J
        # only), and Q the exact Galerkin correction on them
        f = free if now is None else now
        masked = sheet.masked_inverse(f, FLOOR_Q[0])

        def Q(x):
            if keep is not None:
                return (Z.T @ (keep * solve(keep * (Z @ x.ravel()), keep))).reshape(n, n)
            return galerkin(x, f)
        qr = Q(r)
        if FORM[0] == "additive":  # Q + P M^-1 P: symmetric, no FFT pair beyond P M^-1 P's
            return qr + masked(r)
        if FORM[0] == "def2":  # (I - QK) P M^-1 P + Q: one FFT pair fewer, not symmetric
            u = masked(r)
            return qr + u - Q(f * sheet.K(u))
        u = masked(r - f * sheet.K(qr))
        if FORM[0] == "def1":  # P M^-1 P (I - KQ) + Q: one FFT pair fewer, not symmetric
            return qr + u
        return qr + u - Q(f * sheet.K(u))
    B.support = support
    B.Q = lambda x: galerkin(x, free)
    B.masked = sheet.masked_inverse(free, FLOOR_Q[0])
    return B, nc


def cg(sheet, free, B, b, rtol, maxit=5000, flexible=False, diag=None, x0=None):
    """(Flexible) preconditioned CG on the free block of K (+ diag, the adhesive law's curvature,
    negative: where p.Ap <= 0 it stops as Steihaug's, with the iterate so far, or with the
    preconditioned right-hand side at the first iteration) from x0 (0 unless given); returns
    iterations and x."""
    if FORM[0] == "adef2" and hasattr(B, "Q"):
        return cg_deflated(sheet, free, B, b, rtol, maxit)
    if x0 is None:
        x, r = np.zeros_like(b), b.copy()
    else:
        x, r = x0, b - free * sheet.K(x0)
    y = B(r)
    p, ry = y.copy(), (r * y).sum()
    b0 = np.sqrt((b * b).sum())
    for it in range(1, maxit + 1):
        Kp = free * (sheet.K(p) if diag is None else sheet.K(p) + diag * p)
        pKp = (p * Kp).sum()
        if pKp <= 0:
            return it, (x if it > 1 else p)
        a = ry / pKp
        x += a * p
        r_old = r.copy() if flexible else None
        r -= a * Kp
        if np.sqrt((r * r).sum()) < rtol * b0:
            return it, x
        y = B(r)
        beta = (((r - r_old) * y).sum() if flexible else (r * y).sum()) / ry
        ry = (r * y).sum()
        p = y + beta * p
    return maxit, x


def cg_deflated(sheet, free, B, b, rtol, maxit):
    """The balancing preconditioner's CG with one coarse solve and 3 FFT pairs an iteration
    instead of two and 4 (A-DEF2 of Tang, Nabben, Vuik & Erlangga, J. Sci. Comput. 39, 340 (2009)): started
    from x0 = Q b, the residual stays orthogonal to the hats (Z^T r = 0, exactly with an exact
    coarse solve), so B r = Q r + (I - QK) P M^-1 P (I - KQ) r loses its first solve and its
    first product: y = (I - QK) P M^-1 P r, one solve; flexible CG for the inexact solves."""
    Q, masked = B.Q, B.masked

    def prec(v):
        u = masked(v)
        return u - Q(free * sheet.K(u))
    return cg(sheet, free, prec, b, rtol, maxit, flexible=True, x0=Q(b))


def fixed(args):
    sheet = Sheet(args.n, args.W)
    steps, z = sheet.relax(args.sigma0)
    free = (z - sheet.h) > 0
    print(f"n = {args.n}, W = {args.W}, sigma0 = {args.sigma0:g}: A/A0 = {1 - free.mean():.4f} "
          f"(library: {steps} steps from flat); CG iterations to 1e-8 of the right-hand side")
    rhs = {"uniform": free * 1.0, "random": free * np.random.default_rng(3).standard_normal(z.shape)}
    def run(B, b, flexible=False):
        its, x = cg(sheet, free, B, b, 1e-8, flexible=flexible)
        # the residual recomputed from x, not CG's recurrence: 1e-8 and what CG's updates may
        # have drifted in 5000 iterations at most (a few hundred roundings of 1e-16 per term)
        CHECKS.append(("residual", np.linalg.norm(free * sheet.K(x) - b) / np.linalg.norm(b), 1e-7))
        return its
    line = "  P M^-1 P:" + "".join(f"  {name} {run(sheet.masked_inverse(free), b)}" for name, b in rhs.items())
    print(line)
    for c in args.c:
        for its in args.coarse_its:
            sheet.pairs = 0
            B, nc = coarse_space(sheet, free, c, args.probes, its, args.assembly, args.sharp)
            probes = sheet.pairs
            solve = "exact" if its == 0 else f"{its} Jacobi-CG its"
            if args.assembly:
                solve += f", {assembly_name(args)}"
            sheet.solves = 0
            counts = "".join(f"  {name} {run(B, b, its > 0)}" for name, b in rhs.items())
            counts += f" ({sheet.solves} coarse solves{', ' + args.form if args.form != 'balancing' else ''})"
            print(f"  two-level, c = {c} ({nc}^2 coarse, {probes} probes), coarse solve {solve}:{counts}")


def newton(args, sheet, z, sigma1, two_level):
    """Active-set Newton for the continuing load; returns (steps, CG its, pairs, probes, z)."""
    h, u = sheet.h, z.copy()
    sheet.pairs = 0
    probes = cg_its = steps = 0
    gamma, rho = sheet.gamma0, sheet.rho
    while True:
        g, w = sheet.gradient(u, sigma1)
        diag = None if w is None else -(gamma / rho ** 2) * w  # the adhesive law's curvature
        at_wall = (u - h) <= 0
        free = ~(at_wall & (g >= 0))
        if converged(np.where(at_wall, np.minimum(g, 0), g), sigma1, gamma, rho) or steps >= 200:
            return steps, cg_its, sheet.pairs, probes, u
        steps += 1
        if two_level and args.stencil >= 0:
            B = stencil_inverse(sheet, free, args.stencil, args.stencil_rtol)
        elif two_level:
            before = sheet.pairs
            B, _ = coarse_space(sheet, free, args.c[0], args.probes, args.coarse_its[0], args.assembly,
                                    args.sharp)
            probes += sheet.pairs - before
        else:
            B = sheet.masked_inverse(free)
        its, d = cg(sheet, free, B, -(free * g), 0.1, maxit=500, flexible=two_level, diag=diag)
        cg_its += its
        e0, alpha = sheet.energy(u, sigma1), 1.0
        while True:
            trial = np.maximum(h, u + alpha * d)
            if sheet.energy(trial, sigma1) <= e0 + 1e-4 * (g * (trial - u)).sum() or alpha < 1e-6:
                break
            alpha *= 0.5
        u = trial


def fire(args, sheet, z, sigma1, two_level):
    """Preconditioned FIRE (FIRE 2.0's constants, semi-implicit Euler, a point that reaches the
    wall stops) on a continuing load, with a = P M^-1 P F or a = B F; the coarse space is rebuilt
    whenever the held set changes (with --rebuild F only once the held count has moved by more
    than F).  Returns (steps, pairs, probes, rebuilds, z).  The same dynamics and constants for
    both preconditioners; this is not the library's mass-weighted FIRE (whose step follows its
    masses), so compare the two rows with each other, and either with the library only roughly."""
    h, u = sheet.h, z.copy()
    v = np.zeros_like(u)
    sheet.pairs = 0
    probes = rebuilds = steps = 0
    dt, dt_max, alpha, since = 0.5, 1.0, 0.25, 0
    built_on, built_set, B = -1, None, None
    gamma, rho = args.gamma0, args.rho
    while steps < args.max_steps:
        g, _ = sheet.gradient(u, sigma1)
        force = -g
        at_wall = (u - h) <= 0
        held = at_wall & (force < 0)
        force[held] = 0.0
        if converged(force, sigma1, gamma, rho):
            break
        free = ~held
        count = int(held.sum())
        keep = None
        if args.drop > 0 and B is not None and two_level:
            # the hats whose support holds a point the held set changed at since the build
            touched = (B.support @ (held != built_set).ravel().astype(float)) > 0
            keep = (~touched).astype(float)
            changed = touched.mean() > args.drop
        else:
            changed = (not np.array_equal(held, built_set)) if args.rebuild == 0 else \
                abs(count - built_on) > args.rebuild * max(built_on, 1)
        if B is None or changed:
            built_set, keep = held.copy(), None
            if two_level:
                before = sheet.pairs
                B, _ = coarse_space(sheet, free, args.c[0], args.probes, args.coarse_its[0], args.assembly,
                                    args.sharp)
                probes += sheet.pairs - before
            built_on, rebuilds = count, rebuilds + 1
        if not two_level:
            B = sheet.masked_inverse(free)  # the floor follows the held set, as the library's
        a = B(force, free, keep) if two_level else B(force)
        steps += 1
        v[held] = 0.0
        if (force * v).sum() > 0:
            since += 1
            if since > 5:
                dt, alpha = min(1.1 * dt, dt_max), 0.99 * alpha
        else:
            since, dt, alpha = 0, 0.5 * dt, 0.25
            u -= 0.5 * dt * v
            v[:] = 0.0
        v += dt * a
        va, aa = np.sqrt((v * v).sum()), np.sqrt((a * a).sum())
        if aa > 0:
            v = (1 - alpha) * v + alpha * (va / aa) * a
        u = u + dt * v
        stop = u < h
        u[stop], v[stop] = h[stop], 0.0
    return steps, sheet.pairs, probes, rebuilds, u


def check_equilibrium(u, z_library, h):
    """Both methods against the library's equilibrium: the same contact set (the count), and the
    surface within 1e-3 a (all three are stopped at the same --tol; at 1e-6 the sheets' softest
    modes turn that into displacements of up to 1.6e-4 a in the runs logged, at 1e-8 up to 2.5e-6 a)."""
    CHECKS.append(("contacts", abs(int(np.sum(u - h <= 0)) - int(np.sum(z_library - h <= 0))), 0))
    CHECKS.append(("surface", np.abs(u - z_library).max(), 1e-3))


def assembly_name(args):
    if args.assembly:
        return f"kernel {'cut at' if args.sharp else 'windowed to'} {args.assembly}"
    return f"{args.probes}^2 probes"


def continuing(args):
    sheet = Sheet(args.n, args.W, args.gamma0, args.rho)
    _, z0 = sheet.relax(args.sigma0)
    steps, z1 = sheet.relax(args.sigma1)
    adhesion = f", gamma0 = {args.gamma0:g}, rho = {args.rho:g}," if args.gamma0 > 0 or args.fire else ","
    print(f"n = {args.n}, W = {args.W}{adhesion} sigma0 {args.sigma0:g} -> {args.sigma1:g}: library {steps} "
          f"steps (solver {sheet.sim.solver}), A/A0 = {np.mean(z1 - sheet.h <= 0):.6f}")
    for two_level in (False, True):
        name = (f"two-level c = {args.c[0]}, {assembly_name(args)}, coarse {args.coarse_its[0]} its"
                if two_level else "P M^-1 P")
        if two_level and args.stencil >= 0:
            sheet._stencil = (args.stencil,) + stencil_matrix(sheet, args.stencil)
            lo, hi = sheet._stencil[2]
            solved = (f"to {args.stencil_rtol:g} by Jacobi-CG" if args.stencil_rtol > 0 else
                      f"by one V({args.stencil_mg},{args.stencil_mg})-cycle" if args.stencil_mg > 0 else "exactly")
            name = (f"stencil L^2 poly(L) of degree {args.stencil} (its symbol {lo:.2f}-{hi:.2f} of k(q)), "
                    f"its free block solved {solved}")
        if two_level and args.form != "balancing":
            name += f", {args.form}"
        sheet.solves = 0
        if args.fire:
            n_steps, pairs, probes, rebuilds, u = fire(args, sheet, z0, args.sigma1, two_level)
            what = (f"FIRE, {name}: {n_steps} steps, {pairs} FFT pairs ({probes} of them probes, "
                    f"{rebuilds} held sets)")
        else:
            n_steps, its, pairs, probes, u = newton(args, sheet, z0, args.sigma1, two_level)
            what = (f"Newton, {name}: {n_steps} Newton steps, {its} CG its, {pairs} FFT pairs "
                    f"({probes} of them probes)")
        if two_level:
            what += f", {sheet.solves} {'stencil' if args.stencil >= 0 else 'coarse'} solves"
        check_equilibrium(u, z1, sheet.h)
        print(f"  {what}, A/A0 = {np.mean(u - sheet.h <= 0):.6f}, "
              f"max |z - z_library| = {np.abs(u - z1).max():.1e}", flush=True)


def by_residual(args):
    """The library's default on the load sigma0 -> sigma1, relaxed to 1e-3, then each decade down
    to --tol, each call continuing the same trajectory: where a continuing load spends its steps.
    Checked against one call to --tol on a second handle: the same steps, the same surface."""
    tols = [10.0 ** -k for k in range(3, 20) if 10.0 ** -k > args.tol * 1.001] + [args.tol]
    runs = []
    for staged in (True, False):
        sheet = Sheet(args.n, args.W, args.gamma0, args.rho)
        sheet.relax(args.sigma0)
        sheet.sim.set_pressure(args.sigma1)
        steps = [sheet.sim.relax(tol=t) for t in (tols if staged else tols[-1:])]
        runs.append((np.cumsum(steps), sheet.sim.surface().copy(), sheet))
    (staged, z, sheet), (whole, z1, _) = runs
    adhesion = f", gamma0 = {args.gamma0:g}, rho = {args.rho:g}," if args.gamma0 > 0 else ","
    print(f"n = {args.n}, W = {args.W}{adhesion} sigma0 {args.sigma0:g} -> {args.sigma1:g} (solver "
          f"{sheet.sim.solver}), steps to residuals " + ", ".join(f"{t:g}" for t in tols) + ": " +
          " ".join(str(k) for k in staged) + f" (one call to {tols[-1]:g}: {whole[-1]})")
    CHECKS.append(("staged steps", abs(int(staged[-1]) - int(whole[-1])), 0))
    CHECKS.append(("staged surface", np.abs(z - z1).max(), 0.0))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--fixed", action="store_true")
    p.add_argument("--newton", action="store_true")
    p.add_argument("--fire", action="store_true", help="--newton by preconditioned FIRE instead")
    p.add_argument("--by-residual", action="store_true",
                   help="the library's steps on the load, relaxed to 1e-3, then decade by decade to --tol")
    p.add_argument("--gamma0", type=float, default=0.0, help="adhesion (--newton, --fire)")
    p.add_argument("--rho", type=float, default=1.0)
    p.add_argument("--max-steps", type=int, default=20000)
    p.add_argument("--rebuild", type=float, default=0.0,
                   help="--fire: the held count's relative change that rebuilds (0: every change)")
    p.add_argument("--assembly", type=int, default=0,
                   help="0: the coarse operator probed (S^2 FFT pairs); R > 0: summed from K's "
                        "real-space kernel times a Gaussian window of width R/4 cut at R (no FFT pair)")
    p.add_argument("--sharp", action="store_true", help="--assembly: the kernel cut sharply, no window")
    p.add_argument("--drop", type=float, default=0.0,
                   help="--fire: keep the coarse operator, drop the hats whose support the held set "
                        "changed in, rebuild once more than this fraction of them is dropped")
    p.add_argument("--form", choices=("balancing", "def1", "def2", "additive", "adef2"), default="balancing",
                   help="the two-level preconditioner: balancing (symmetric, 3 FFT pairs), or the "
                        "deflation forms def1 / def2 (2 pairs, not symmetric), or additive Q + P M^-1 P "
                        "(symmetric, 1 pair: P M^-1 P's own)")
    p.add_argument("--smoother-floor", type=float, default=0.0,
                   help="F > 0: the two-level runs' P M^-1 P floored at k(q) for q <= F pi / c, so that "
                        "it leaves the long waves to the coarse space (for --form additive)")
    p.add_argument("--check", action="store_true",
                   help="fail unless every CG solution has its residual and every load the library's "
                        "contact count and surface (the divergent forms excepted: do not --check them)")
    p.add_argument("--tol", type=float, default=1e-8,
                   help="relative residual (the library's criterion) for the library and every method")
    p.add_argument("--stencil", type=int, default=-1, metavar="DEG",
                   help="--newton: the second method's CG preconditioned by the exact inverse of a "
                        "real-space stencil's free block, L^2 times a polynomial of degree DEG in L")
    p.add_argument("--stencil-rtol", type=float, default=0.0, metavar="R",
                   help="--stencil: the free block solved inexactly, to R by Jacobi-preconditioned CG")
    p.add_argument("--stencil-mg", type=int, default=0, metavar="NU",
                   help="--stencil: the free block solved by one multigrid V(NU,NU)-cycle (Galerkin, Jacobi)")
    p.add_argument("--n", type=int, default=256)
    p.add_argument("--W", type=float, default=0.088)
    p.add_argument("--sigma0", type=float, default=1e-4)
    p.add_argument("--sigma1", type=float, default=1.6e-4)
    p.add_argument("--c", type=lambda s: [int(x) for x in s.split(",")], default=[4])
    p.add_argument("--probes", type=int, default=4, help="S: S^2 probes, coarse stencil (S+1)^2")
    p.add_argument("--coarse-its", type=lambda s: [int(x) for x in s.split(",")], default=[5],
                   help="Jacobi-CG iterations of the coarse solve, 0: exact")
    args = p.parse_args()
    FORM[0] = args.form
    TOL[0] = args.tol
    MG_SWEEPS[0] = args.stencil_mg
    FLOOR_Q[0] = args.smoother_floor * np.pi / args.c[0]
    if args.stencil >= 0 and (not args.newton or args.fire):
        sys.exit("--stencil is a preconditioner of --newton's CG")
    if args.n % (max(args.c) * args.probes):
        sys.exit("n must be a multiple of c times the probes' stride")
    if args.fixed:
        fixed(args)
    if args.by_residual:
        by_residual(args)
    if args.gamma0 > 0 and args.fixed:
        sys.exit("adhesion: --newton or --fire only")
    if args.newton or args.fire:
        continuing(args)
    if not (args.fixed or args.newton or args.fire or args.by_residual):
        p.print_help()
    bad = [(what, value, bound) for what, value, bound in CHECKS if not value <= bound]
    if args.check and bad:
        sys.exit("disagree: " + ", ".join(f"{w} {v:.2e} > {b:.0e}" for w, v, b in bad))
    if args.check:
        print(f"checked: {len(CHECKS)} solutions' residuals, contact counts and surfaces within bounds")


if __name__ == "__main__":
    main()
