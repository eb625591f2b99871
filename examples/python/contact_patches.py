#!/usr/bin/env python3
"""How the contact is made: patches, pressures and plastic flow.  One substrate; a half-space and
a thin sheet on a fluid foundation (W = w/lambda_s = 0.125) at the same A/A0.  Top row: the contact
patches coloured by label (the sheet's contact splits into many more, smaller patches, counted),
and the patch-size distributions of both.  Bottom row: the contact-pressure distributions against
Persson's P(p), and the half-space loaded and unloaded at a hardness H (the plastic area while
loading, the contact area on both ways: unloading keeps the flattened tops).  The demo
(scripts/demo.sh) writes it beside the paper's figures.

    PYTHONPATH=python python3 examples/python/contact_patches.py [--n 256] [--W 0.125] [--out .]
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
    return s


def at_area(s, target, load):
    """The load at which s has the contact area target (secant steps in log-log from load)."""
    for _ in range(10):
        s.set_pressure(load)
        s.relax()
        if abs(s.contact_area / target - 1.0) < 0.02:
            break
        load *= target / s.contact_area
    return load


def label_colours(count, seed=1):
    """A colour per label, shuffled so that neighbouring labels differ; label 0 white."""
    rng = np.random.default_rng(seed)
    colours = plt.get_cmap("tab20")(np.arange(max(count, 1)) % 20)
    rng.shuffle(colours)
    return ListedColormap(np.vstack([[1.0, 1.0, 1.0, 1.0], colours]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--W", type=float, default=0.125, help="the sheet's w / lambda_s")
    ap.add_argument("--seed", type=int, default=2016)
    ap.add_argument("--out", default=".")
    args = ap.parse_args()
    n, W = args.n, args.W

    half, sheet = body(n, 0.0, args.seed), body(n, W * LAMBDA_S, args.seed)
    sigma0 = 0.025  # A/A0 about 5 % on the half-space
    half.set_pressure(sigma0)
    half.relax()
    target = half.contact_area
    sheet_load = at_area(sheet, target, sigma0 / 4)
    rows = []
    for name, s, load in (("half-space", half, sigma0), (f"sheet W = {W:g}", sheet, sheet_load)):
        p = s.contact_patches(4)
        edges, fraction, mean = s.pressure_histogram(40)
        rows.append({"name": name, "load": load, "area": s.contact_area, "patches": p, "edges": edges,
                     "density": fraction / np.diff(edges), "persson": s.persson_pressure_distribution(
                         0.5 * (edges[1:] + edges[:-1]), load)})
        print(f"{name:18s} sigma0/E* = {load:.3e}  A/A0 = {s.contact_area:.4f}  patches {p.count:5d}  "
              f"mean patch area {p.mean_area:7.2f} a^2  perimeter ~ area^{p.perimeter_area_exponent():.2f}")
    sheet.close()

    # the half-space loaded to 3 sigma0 and back at a hardness of 0.4 E* (a few times its mean
    # contact pressure g E* / 2): the flattened tops stay in contact on the way down
    half.set_hardness(0.4)
    loads = sigma0 * np.array([0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 2.0, 1.0, 0.5])
    path = []
    for load in loads:
        half.set_pressure(load)
        half.relax()
        plastic, volume = half.plasticity
        path.append((load, half.contact_area, plastic, volume))
    path = np.array(path)
    print(f"hardness 0.4 E*: at 3 sigma0 plastic area {path[5, 2]:.4f}, volume {path[5, 3]:.2f} a^3; "
          f"back at 0.5 sigma0 A/A0 {path[-1, 1]:.4f} against {path[0, 1]:.4f} on the way up")
    half.close()

    fig, axes = plt.subplots(2, 3, figsize=(14.5, 9.0))
    for col, r in enumerate(rows):
        ax = axes[0, col]
        labels = r["patches"].labels
        ax.imshow(labels, origin="lower", cmap=label_colours(r["patches"].count), extent=(0, n, 0, n),
                  interpolation="nearest", vmin=0, vmax=max(r["patches"].count, 1))
        ax.set_title(f"{r['name']}: {r['patches'].count} patches\nA/A0 = {r['area']:.3f}, "
                     rf"$\sigma_0/E^*$ = {r['load']:.2e}")
        ax.set_xlabel("x / a")
        ax.set_ylabel("y / a")
    ax = axes[0, 2]
    for r in rows:
        edges, counts = r["patches"].size_histogram(12)
        centres = np.sqrt(edges[1:] * edges[:-1])
        ax.loglog(centres[counts > 0], counts[counts > 0] / np.diff(edges)[counts > 0], "o-", label=r["name"])
    ax.set_xlabel(r"patch area / $a^2$")
    ax.set_ylabel("patches per unit area (log bins)")
    ax.set_title("patch-size distribution")
    ax.legend()
    for col, r in enumerate(rows):
        ax = axes[1, col]
        centres = 0.5 * (r["edges"][1:] + r["edges"][:-1])
        ax.bar(centres, r["density"], width=np.diff(r["edges"]), color="0.7", label="simulation")
        ax.plot(centres, r["persson"], "r-", label="Persson P(p)")
        ax.set_xlabel(r"contact pressure $p / E^*$")
        ax.set_ylabel("P(p)")
        ax.set_title(f"{r['name']}: pressure distribution")
        ax.legend()
    ax = axes[1, 2]
    up, down = slice(0, 6), slice(5, None)
    ax.plot(path[up, 0], path[up, 1], "o-", color="C0", label="A/A0 loading")
    ax.plot(path[down, 0], path[down, 1], "s--", color="C0", label="A/A0 unloading")
    ax.plot(path[up, 0], path[up, 2], "^-", color="C3", label="plastic area (loading)")
    ax.set_xlabel(r"$\sigma_0 / E^*$")
    ax.set_ylabel("area fraction")
    ax.set_title("half-space at hardness H = 0.4 E*")
    ax.legend()
    fig.suptitle(f"How the contact is made ({n}$^2$, H = 0.8, $\\lambda_s$ = 4a, g = 1)")
    fig.tight_layout()
    out = os.path.join(args.out, "contact_patches.png")
    fig.savefig(out, dpi=100)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
