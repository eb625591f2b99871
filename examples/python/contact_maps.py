#!/usr/bin/env python3
"""Pictures of the contact: why thin sheets touch more.  One substrate; a half-space and a thin
sheet on a fluid foundation (W = w/lambda_s = 0.125) at the same load, and the sheet again at the
lower load where it has the half-space's contact area.  Top row: the gap with the contact points
in red; bottom row: the contact pressure.  The demo (scripts/demo.sh) writes it beside the
paper's figures.

    PYTHONPATH=python python3 examples/python/contact_maps.py [--n 256] [--W 0.125] [--out .]
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import gfmd  # noqa: E402

LAMBDA_S = 4.0


def body(n, width, seed):
    """A body on the study's substrate: H = 0.8, lambda_s = 4a, lambda_r = n a/2, g = 1."""
    s = gfmd.Simulation(n, n, float(n), float(n))
    s.generate_selfaffine(0.8, n / 2, LAMBDA_S, 1.0, seed=seed)
    if width > 0:
        s.set_green(gfmd.LAYER_FLUID, width)
        s.set_solver(gfmd.MASS_WEIGHTED_FIRE)  # mass weighting: thin sheets relax several times faster
    return s


def state(s, sigma0):
    s.set_pressure(sigma0)
    steps = s.relax()
    return {"sigma0": sigma0, "area": s.contact_area, "gap": s.gap(), "p": s.pressure(), "steps": steps}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--W", type=float, default=0.125, help="the sheet's w / lambda_s")
    ap.add_argument("--seed", type=int, default=2016)
    ap.add_argument("--out", default=".")
    args = ap.parse_args()
    n, W = args.n, args.W

    half = body(n, 0.0, args.seed)
    sigma0 = 0.025  # A/A0 about 5 % on the half-space
    hs = state(half, sigma0)
    sheet = body(n, W * LAMBDA_S, args.seed)
    same_load = state(sheet, sigma0)
    # the sheet's load with the half-space's area: A/A0 grows about linearly with the load, so a
    # few secant steps in log-log (each continuing from the last equilibrium) find it
    target, load, same_area = hs["area"], sigma0 * hs["area"] / same_load["area"], None
    for _ in range(8):
        same_area = state(sheet, load)
        if abs(same_area["area"] / target - 1.0) < 0.02:
            break
        load *= target / same_area["area"]
    half.close()
    sheet.close()

    panels = [("half-space", hs), (f"sheet W = {W:g}, same load", same_load),
              (f"sheet W = {W:g}, same A/A0", same_area)]
    for name, st in panels:
        print(f"{name:30s} sigma0/E* = {st['sigma0']:.3e}  A/A0 = {st['area']:.4f}  ({st['steps']} steps)")
    fig, axes = plt.subplots(2, 3, figsize=(13.5, 8.6))
    red = ListedColormap(["red"])
    for col, (name, st) in enumerate(panels):
        ax = axes[0, col]
        im = ax.imshow(st["gap"], origin="lower", cmap="viridis", extent=(0, n, 0, n), vmin=0.0,
                       vmax=np.percentile(st["gap"], 99.5), interpolation="nearest")
        ax.imshow(np.ma.masked_where(st["gap"] > 0.0, np.ones_like(st["gap"])), origin="lower", cmap=red,
                  extent=(0, n, 0, n), interpolation="nearest")
        ax.set_title(f"{name}\n" + rf"$\sigma_0/E^*$ = {st['sigma0']:.2e}, A/A0 = {st['area']:.3f}")
        fig.colorbar(im, ax=ax, label="gap / a (red: contact; own scale)", shrink=0.85)
        ax = axes[1, col]
        pmax = np.percentile(st["p"][st["p"] > 0], 99) if np.any(st["p"] > 0) else 1.0
        im = ax.imshow(st["p"], origin="lower", cmap="magma", extent=(0, n, 0, n), vmin=0.0, vmax=pmax,
                       interpolation="nearest")
        ax.set_title("contact pressure (own scale)")
        fig.colorbar(im, ax=ax, label=r"$p / E^*$", shrink=0.85)
    for ax in axes.flat:
        ax.set_xlabel("x / a")
        ax.set_ylabel("y / a")
    fig.suptitle(f"One substrate ({n}$^2$, H = 0.8, $\\lambda_s$ = 4a, g = 1): a thin sheet touches more at the same "
                 "load, and at the same area its contact spreads in many small patches")
    fig.tight_layout()
    path = os.path.join(args.out, "contact_maps.png")
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
