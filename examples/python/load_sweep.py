#!/usr/bin/env python3
"""A load sweep from Python: a self-affine substrate pressed by a half-space at rising loads, each
load relaxed from the last equilibrium; A/A0 against the load beside Persson's theory, and the
contact map at the highest load.  What a new user copies first.

    PYTHONPATH=python python3 examples/python/load_sweep.py [--n 256] [--out .]
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import gfmd  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=256, help="grid points per side (spacing a = 1)")
    ap.add_argument("--out", default=".", help="folder for load_sweep.png and contact_map.png")
    args = ap.parse_args()
    n = args.n
    loads = np.geomspace(2e-3, 8e-2, 8)  # sigma0 / E*, with E* = 1 and rms gradient g = 1

    with gfmd.Simulation(n, n, float(n), float(n)) as sim:
        # H = 0.8, lambda_r = n/4, lambda_s = 4a, rms gradient 1, seed 1
        sim.generate_selfaffine(0.8, n / 4, 4.0, 1.0, seed=1)
        areas, persson = [], []
        for sigma0 in loads:
            sim.set_pressure(sigma0)
            steps = sim.relax()
            areas.append(sim.contact_area)
            persson.append(sim.persson_contact_area(sigma0))
            print(f"sigma0/E* = {sigma0:.3e}  A/A0 = {areas[-1]:.5f}  Persson {persson[-1]:.5f}  "
                  f"mean gap {sim.mean_gap:.4f}  ({steps} steps)")
        gap, pressure = sim.gap(), sim.pressure()

    fine = np.geomspace(loads[0] / 2, loads[-1] * 2, 60)
    with gfmd.Simulation(n, n, float(n), float(n)) as theory:
        theory.generate_selfaffine(0.8, n / 4, 4.0, 1.0, seed=1)
        curve = [theory.persson_contact_area(s) for s in fine]
    kappa = np.polyfit(loads[:4], areas[:4], 1)[0]

    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    ax.loglog(loads, areas, "o", color="tab:blue", label=f"GFMD, half-space ({n}$^2$)")
    ax.loglog(fine, curve, "-", color="tab:orange", label="Persson's theory")
    ax.loglog(fine, 2.0 * fine, ":", color="grey", label=r"$A/A_0 = 2\,\sigma_0/(E^* g)$")
    ax.set_xlabel(r"load $\sigma_0 / (E^* g)$")
    ax.set_ylabel(r"relative contact area $A/A_0$")
    ax.set_title(f"kappa = {kappa:.2f} (small loads)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "load_sweep.png"), dpi=120)

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.4))
    im = axes[0].imshow(gap, origin="lower", cmap="viridis", extent=(0, n, 0, n))
    contact = np.ma.masked_where(gap > 0.0, np.ones_like(gap))  # only the points in contact
    axes[0].imshow(contact, origin="lower", cmap=ListedColormap(["red"]), extent=(0, n, 0, n))
    axes[0].set_title(f"gap (red: contact, A/A0 = {areas[-1]:.3f})")
    fig.colorbar(im, ax=axes[0], label="gap / a")
    im = axes[1].imshow(np.log10(np.maximum(pressure, 1e-6)), origin="lower", cmap="magma", extent=(0, n, 0, n))
    axes[1].set_title(r"contact pressure, $\log_{10}(p/E^*)$")
    fig.colorbar(im, ax=axes[1], label=r"$\log_{10}(p/E^*)$")
    for ax in axes:
        ax.set_xlabel("x / a")
        ax.set_ylabel("y / a")
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "contact_map.png"), dpi=120)
    print(f"wrote {os.path.join(args.out, 'load_sweep.png')} and {os.path.join(args.out, 'contact_map.png')}")


if __name__ == "__main__":
    main()
