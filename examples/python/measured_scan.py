#!/usr/bin/env python3
"""A measured scan, from the instrument's file to the contact.  A self-affine surface (H = 0.8,
spacing 0.1 um) is given what a real scan has -- a tilt, a bow, instrument noise, dropouts (missing
points) -- and written as an ISO 25178-71 binary file (int16 counts of 0.2 nm, -32768 where a point
is missing), the way a profilometer exports it.  It is read back in micrometres, its missing points
filled (Laplace) and its tilt and bow removed (second order); its power spectrum (Hann window)
is plotted against the generator's C(q); the contact is solved with free boundaries (the scan is
the whole region of a half-space, nothing beyond it is loaded) and, beside it, on the scan taken as
a periodic cell; Persson's A/A0 and mean gap from the measured spectrum are set beside both; and the free
contact's gap and pressure are drawn.  The demo (scripts/demo.sh) writes it beside the paper's figures.

    PYTHONPATH=python python3 examples/python/measured_scan.py [--n 256] [--out .]
"""
import argparse
import os
import struct
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import gfmd  # noqa: E402

H, SPACING, ZSCALE = 0.8, 1e-7, 2e-10  # Hurst exponent; 100 nm between points; 0.2 nm a count


def write_sdf(path, counts, xscale, yscale, zscale):
    """An ISO 25178-71 binary surface data file of int16 counts (ny, nx)."""
    ny, nx = counts.shape
    header = (b"bISO-1.0" + b"gfmd demo " + b"071220261200" * 2 + struct.pack("<HH", nx, ny)
              + struct.pack("<dddd", xscale, yscale, zscale, zscale) + bytes([0, 5, 0]))
    assert len(header) == 81
    with open(path, "wb") as f:
        f.write(header + counts.astype("<i2").tobytes())


def theory_psd(q, qr, qs, g):
    """The generator's C(q): flat below q_r, q^-2(1+H) to q_s, 0 above, scaled to rms slope g
    (g^2 = integral d^2q q^2 C(q), done here numerically)."""
    shape = lambda k: np.where(k < qr, 1.0, np.where(k <= qs, (k / qr) ** (-2 * (1 + H)), 0.0))  # noqa: E731
    k = np.linspace(qs * 1e-9, qs, 200001)
    c0 = g * g / np.trapz(2 * np.pi * k ** 3 * shape(k), k)
    return c0 * shape(q)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--out", default=".")
    args = ap.parse_args()
    n, um = args.n, 1e-6
    lam_r, lam_s, g = n / 4 * SPACING, 4 * SPACING, 0.5

    # the true surface (in metres) and the scan an instrument would make of it
    with gfmd.Simulation(n, n, n * SPACING, n * SPACING, planner=gfmd.ESTIMATE) as s:
        s.generate_selfaffine(H, lam_r, lam_s, g, seed=11)
        true = s.heights()
    rng = np.random.default_rng(3)
    y, x = np.mgrid[0:n, 0:n] * SPACING
    scan = true + 0.03 * x - 0.01 * y + 2e3 * ((x - x.mean()) ** 2 + (y - y.mean()) ** 2)  # tilt, bow
    scan += rng.normal(scale=2e-9, size=scan.shape)  # instrument noise, 2 nm
    counts = np.round((scan - scan.mean()) / ZSCALE)
    assert np.abs(counts).max() < 32767, "the scan's range exceeds int16 counts"
    holes = np.zeros_like(scan, dtype=bool)
    for cx, cy, r in rng.uniform([0, 0, 1], [n, n, n / 40], size=(6, 3)):
        holes |= (np.mgrid[0:n, 0:n][1] - cx) ** 2 + (np.mgrid[0:n, 0:n][0] - cy) ** 2 < r * r
    holes[:, n // 3] = True  # a dropped column
    counts[holes] = -32768
    path = os.path.join(args.out, "measured_scan.sdf")
    write_sdf(path, counts, SPACING, SPACING, ZSCALE)

    # read back in micrometres, fill, detrend
    t = gfmd.read_topography(path, unit=um)
    raw = t.heights
    print(f"read {path}: format {t.format}, {t.shape[1]} x {t.shape[0]} points, "
          f"{t.physical_size[0]:.2f} x {t.physical_size[1]:.2f} um, {t.missing} missing")
    t.fill_missing("laplace")
    t.detrend("curvature")
    q, c, count = t.psd(40, window="hann")
    rms_h, rms_slope, rms_curv = t.moments(window="hann")
    truth = gfmd.Topography.from_heights(true / um, (n * SPACING / um,) * 2)
    print(f"rms height {rms_h:.4f} um (true {truth.moments()[0]:.4f}), rms slope {rms_slope:.3f} "
          f"(true {g}), rms curvature {rms_curv:.2f} /um")

    # the contact on the scan: the load at which Persson's theory of the measured spectrum gives
    # A/A0 = 0.05 (bisection on the load), solved with free boundaries and as a periodic cell
    lo, hi = 0.0, 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if t.persson_contact_area(mid, window="hann") < 0.05 else (lo, mid)
    sigma0 = 0.5 * (lo + hi)
    measured = t.persson_contact_area(sigma0, window="hann")
    sim = gfmd.Simulation.from_topography(t, planner=gfmd.ESTIMATE, boundary=gfmd.FREE)
    sim.set_pressure(sigma0)
    sim.relax()
    with gfmd.Simulation.from_topography(t, planner=gfmd.ESTIMATE) as cell:
        cell.set_pressure(sigma0)
        cell.relax()
        periodic, periodic_gap = cell.contact_area, cell.mean_gap
    print(f"sigma0 = {sigma0:.4g} E*: A/A0 with free boundaries {sim.contact_area:.4f}, as a periodic cell "
          f"{periodic:.4f}; Persson from the measured spectrum {measured:.4f}")
    print(f"mean gap with free boundaries {sim.mean_gap:.4f} um, as a periodic cell {periodic_gap:.4f} um; "
          f"Persson from the measured spectrum {t.persson_mean_gap(sigma0, window='hann'):.4f} um")

    fig, ax = plt.subplots(2, 2, figsize=(10.5, 9))
    extent = (0, t.physical_size[0], 0, t.physical_size[1])
    im = ax[0, 0].imshow(np.ma.masked_invalid(raw), origin="lower", extent=extent, cmap="viridis")
    ax[0, 0].set_title(f"(a) the scan as read ({int(np.isnan(raw).sum())} missing)")
    fig.colorbar(im, ax=ax[0, 0], label="height (um)")
    keep = count > 0
    ax[0, 1].loglog(q[keep], c[keep], "o", ms=4, label="measured scan (filled, detrended, Hann)")
    qq = np.geomspace(q[keep].min(), q[keep].max(), 400)
    ax[0, 1].loglog(qq, theory_psd(qq * 1e6, 2 * np.pi / lam_r, 2 * np.pi / lam_s, g) * 1e24,
                    "k-", lw=1, label="the generator's C(q)")
    tq, tc, tn = truth.psd(40)
    real = (tn > 0) & (tc > 1e-12 * tc.max())  # above q_s the true surface has rounding only
    ax[0, 1].loglog(tq[real], tc[real], "x", ms=4, color="0.5", label="true surface (periodic)")
    ax[0, 1].set_ylim(c[keep].min() / 10, c[keep].max() * 10)
    ax[0, 1].set_xlabel("q (1/um)")
    ax[0, 1].set_ylabel("C(q) (um^4)")
    ax[0, 1].set_title("(b) radially averaged power spectrum")
    ax[0, 1].legend(fontsize=8)
    gap = sim.gap()
    im = ax[1, 0].imshow(gap, origin="lower", extent=extent, cmap="Blues")
    ax[1, 0].imshow(np.ma.masked_where(gap > 0, np.ones_like(gap)), origin="lower", extent=extent, cmap="autumn",
                    interpolation="nearest")
    ax[1, 0].set_title(f"(c) gap (red: contact), free boundaries, A/A0 = {sim.contact_area:.3f}")
    fig.colorbar(im, ax=ax[1, 0], label="gap (um)")
    im = ax[1, 1].imshow(sim.pressure() / sigma0, origin="lower", extent=extent, cmap="magma")
    ax[1, 1].set_title(f"(d) pressure / sigma0 (Persson's A/A0 {measured:.3f})")
    fig.colorbar(im, ax=ax[1, 1])
    for a in (ax[0, 0], ax[1, 0], ax[1, 1]):
        a.set_xlabel("x (um)")
        a.set_ylabel("y (um)")
    fig.tight_layout()
    out = os.path.join(args.out, "measured_scan.png")
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
