#!/usr/bin/env python3
"""A measurement, not a solver of the library: what would FIRE's steps do if its update were fused
with the force completion?

The library's FIRE step (src/solvers/fire.cpp, src/kernels.cpp) is an FFT pair and two passes over
the grid: the force completion (the residual and FIRE's sums: power F.v, |F|^2, |v|^2) and then
the update (the step, the mixing and the wall), which needs those sums first.  One pass doing both
would save about a third of the passes' bytes (docs/performance.md, *Against the targets*, the
per-step row) -- but its update of a point could only use the sums of the step before: FIRE would
decide its step, its mixing and an uphill restart one step late.  This program counts the steps
of both forms, FIRE as the library does it (the same control constants, the same update and wall,
the same criterion) in numpy, on the same loads, and the library's own FIRE beside them; the
forms are fire()'s: exact (the library's order), lagged (every decision one step late), undo,
mixlag (only the mixing's |F| and F.v one step late) and optimistic (what a fused pass can do:
the step assumed downhill with mixlag's mixing, redone from its rebuilt state when the sums say
uphill).

What it found (2026-11-28, night; docs/performance.md, *What was tried*): FIRE decided one step
late takes about 1.5x the steps on the half-space and a thick layer, and 7-12x on a thin sheet;
the optimistic form keeps the thick bodies' steps within a few per cent, but on the thin sheets
the mixing's normalisation by the last step's |F| alone costs 6-11x.  A fused pass saves a third
of the passes, about a tenth of a step: not built.

Loads (the study's substrate, H = 0.8, lambda_s = 4a, lambda_r = n a / 8, seed 1, E* = 1): a
half-space and a layer W = 1 from flat, a thin sheet's continuing load, and the same sheet with
adhesion; the body is two_level_prototype's Sheet.  --check asserts that the numpy FIRE takes the library's steps within 10 % (the same
algorithm; numpy's transforms round differently from FFTW's) and that every form reaches the
library's contact count within 0.5 % (a few points at the tolerance).  The library's handles plan
with FFTW_ESTIMATE, so that the equilibria numpy's runs start from have the same bits in every
run (FFTW_MEASURE may pick other plans; the late forms' counts move with the last bits).  Needs
python3-numpy, python3-scipy (through two_level_prototype) and the built library (GFMD_LIBRARY
or build/).

  python3 bench/lagged_fire_prototype.py [--n 256] [--tol 1e-6] [--check]
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import gfmd  # noqa: E402
from two_level_prototype import Sheet, converged  # noqa: E402  (this directory is on sys.path)

# FIRE's control as src/solvers/fire_control.hpp has it
FORMS = ("exact", "lagged", "undo", "mixlag", "optimistic")
DT_MAX, DT_START, INC, DEC, ALPHA0, ALPHA_DEC, DELAY = 1.3, 0.5, 1.1, 0.5, 0.1, 0.99, 5


class Body(Sheet):
    """two_level_prototype's Sheet (the study's substrate, k(q) per point; W = 0 a half-space) on one
    thread with FFTW_ESTIMATE plans, relaxed by the library's FIRE, and FIRE's time step."""

    def __init__(self, n, W, gamma0=0.0, rho=1.0):
        super().__init__(n, W, gamma0, rho, threads=1, planner=gfmd.ESTIMATE)
        self.sim.set_solver(gfmd.FIRE)
        self.dt = 1.0 / np.sqrt(self.k.max() + (gamma0 / rho ** 2 if gamma0 > 0 else 0.0))

    def forces(self, z, v, sigma):
        """The completion: the force, the projected force r (in contact only pulling away counts)
        and FIRE's sums (power r.v, |r|^2, |v|^2)."""
        f, _ = self.gradient(z, sigma)
        f = -f
        contact = z <= self.h
        r = np.where(contact, np.maximum(f, 0.0), f)
        return f, r, ((r * v).sum(), (r * r).sum(), (v * v).sum())

    def converged(self, r, sigma, tol):
        return converged(r, sigma, self.gamma0, self.rho, tol)


def fire(body, z, sigma, tol, form="exact", max_steps=300000):
    """FIRE from z at rest to the criterion; returns (steps, z).  The update is fire_update's.

    exact       the library's order.
    lagged      every decision from the previous evaluation's sums (its step, mixing and uphill
                restart one step late), and one evaluation more at the end.
    undo        lagged, and an uphill restart steps back over the step it came too late for too
                (1.5 steps, not FIRE's half step).
    mixlag      the library's order, but the mixing's |v + dt F| / |F| from |v|^2 (known before
                the pass: the last update wrote v) and the previous evaluation's F.v and |F|^2:
                all that a fused pass lacks if it assumes the step downhill, whose step and alpha
                follow from the count of downhill steps alone.
    optimistic  what a fused pass can do: the step taken as mixlag's downhill one; if the sums
                then say uphill, the step redone from the state rebuilt from the pass's own output
                (z - dt v, and v from the mixing) -- exact but at the points the pass clamped to
                the wall, whose state it overwrote: taken as at rest on the wall; and one
                evaluation more at the end, as lagged."""
    lagged = form in ("lagged", "undo")
    dt, alpha, positive = DT_START * body.dt, ALPHA0, 0
    v = np.zeros_like(z)
    h = body.h
    steps, last = 0, None
    while steps < max_steps:
        f, r, sums = body.forces(z, v, sigma)
        if body.converged(r, sigma, tol):
            # a fused pass has moved the surface past the state it certified: one evaluation more
            return steps + (1 if form in ("lagged", "undo", "optimistic") and steps > 0 else 0), z
        fi = np.where(z <= h, np.maximum(f, 0.0), f)
        v2 = sums[2]  # |v|^2 of the state before the step: known to every form
        power, f2 = (last if lagged and last is not None else sums)[:2]
        mix_power, mix_f2 = (last if form != "exact" and last is not None else sums)[:2]
        last = sums
        dt_used = dt
        # FireControl::control; the downhill branch's step and alpha do not need the sums' values
        down_dt = min(dt * INC, DT_MAX * body.dt) if positive + 1 > DELAY else dt
        down_alpha = alpha * ALPHA_DEC if positive + 1 > DELAY else alpha
        uphill = not power > 0.0
        if not uphill:
            positive += 1
            dt, alpha = down_dt, down_alpha
        else:
            positive = 0
            dt *= DEC
            alpha = ALPHA0
        keep = 1.0 - alpha
        if form == "optimistic" and uphill:
            # the downhill pass ran first and clamped these points: their z and v are lost
            vd = (1.0 - down_alpha) * (v + down_dt * fi)
            vd2 = v2 + 2.0 * down_dt * mix_power + down_dt ** 2 * mix_f2
            vd = vd + down_alpha * np.sqrt(max(vd2, 0.0) / mix_f2) * fi if mix_f2 > 0.0 else vd
            lost = z + down_dt * vd < h
            z = np.where(lost, h, z)
            v = np.where(lost, 0.0, v)
        vn2 = 0.0 if uphill else v2 + 2.0 * dt * mix_power + dt * dt * mix_f2
        mix = alpha * np.sqrt(max(vn2, 0.0) / mix_f2) if mix_f2 > 0.0 else 0.0
        back = (1.5 * dt_used if form == "undo" else 0.5 * dt) if uphill else 0.0
        vi = (0.0 if uphill else v) + dt * fi
        vi = keep * vi + mix * fi
        zn = z - back * v + dt * vi
        hit = zn < h
        v = np.where(hit, 0.0, vi)
        z = np.where(hit, h, zn)
        steps += 1
    raise RuntimeError("FIRE did not converge")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--check", action="store_true")
    args = ap.parse_args()
    # (name, W, gamma0, the load before (None: from flat), the load)
    loads = [("half-space from flat", 0.0, 0.0, None, 0.05),
             ("W = 1 from flat", 1.0, 0.0, None, 0.05),
             ("W = 0.088 continuing", 0.088, 0.0, 1e-4, 1.6e-4),
             ("W = 0.088 adhesive continuing", 0.088, 5e-4, 2e-5, 3.5e-5)]
    print(f"n = {args.n}, tol {args.tol:g}: FIRE's steps, the library's and numpy's, in the library's "
          f"order (exact) and in the fused order (lagged)")
    failed = []
    for name, W, gamma0, before, sigma in loads:
        body = Body(args.n, W, gamma0)
        if before is not None:
            body.sim.set_pressure(before)
            body.sim.relax(tol=args.tol)
        z0 = body.sim.surface().copy()
        body.sim.set_pressure(sigma)
        lib_steps = body.sim.relax(tol=args.tol)
        contacts = body.sim.contact_area * args.n ** 2
        row = [f"{name:30s} library {lib_steps:6d}"]
        counts = {}
        for form in FORMS:
            steps, z = fire(body, z0.copy(), sigma, args.tol, form)
            c = int(np.count_nonzero(z <= body.h))
            counts[form] = steps
            row.append(f"{form} {steps:6d} ({c} contacts)")
            if abs(c - contacts) > 0.005 * contacts + 2:
                failed.append(f"{name}: {c} contacts against the library's {contacts:.0f}")
        row.append("/exact " + " ".join(f"{k} {counts[k] / counts['exact']:.2f}" for k in counts if k != "exact"))
        print("  ".join(row), flush=True)
        if abs(counts['exact'] - lib_steps) > 0.1 * lib_steps:
            failed.append(f"{name}: numpy's exact FIRE {counts['exact']} steps against the library's {lib_steps}")
    if args.check:
        if failed:
            print("\n".join(failed))
            sys.exit(1)
        print(f"checked: {len(loads)} loads, numpy's FIRE at the library's steps and every form at its contact count")


if __name__ == "__main__":
    main()
