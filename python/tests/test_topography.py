"""Topographies from Python: what numpy saves reads back bit for bit (every dtype and order numpy
writes), a Gwyddion text export with units, the spectrum's Parseval sum and numpy's own FFT as a
second computation of C(q), the generator's rms gradient from the moments, and a simulation made
from a topography in one line."""
import numpy as np
import pytest

import gfmd


@pytest.mark.parametrize("dtype", [np.float64, np.float32, np.int16, np.int32, np.uint8, ">f8"])
@pytest.mark.parametrize("order", ["C", "F"])
def test_npy_written_by_numpy_reads_back(tmp_path, dtype, order):
    rng = np.random.default_rng(4)
    h = np.asarray(rng.integers(-100, 100, size=(7, 11)), dtype=dtype, order=order)
    np.save(tmp_path / "h.npy", h)
    t = gfmd.read_topography(tmp_path / "h.npy")
    assert (t.format, t.has_units, t.missing, t.shape) == ("npy", False, 0, (7, 11))
    assert np.array_equal(t.heights, h.astype(np.float64))  # exact: small integers in every dtype
    assert t.physical_size == (11.0, 7.0)  # a spacing of 1: no units in .npy
    t.physical_size = (2.2, 1.4)
    assert t.physical_size == (2.2, 1.4)


def test_nan_points_are_missing_and_filled(tmp_path):
    h = np.add.outer(0.5 * np.arange(9.0), -0.25 * np.arange(12.0))  # linear: harmonic
    h[3:6, 4:8] = np.nan
    np.save(tmp_path / "holes.npy", h)
    t = gfmd.read_topography(tmp_path / "holes.npy")
    assert t.missing == 12
    with pytest.raises(gfmd.StateError, match="missing points"):
        t.psd()
    with pytest.raises(gfmd.StateError, match="fill_missing"):
        gfmd.Simulation.from_topography(t)
    t.fill_missing("laplace")
    full = np.add.outer(0.5 * np.arange(9.0), -0.25 * np.arange(12.0))
    assert np.max(np.abs(t.heights - full)) < 1e-11  # CG to 1e-13 of the boundary values
    with pytest.raises(gfmd.BadEnum, match="unknown fill method 'bilinear'"):
        t.fill_missing("bilinear")


def test_gwyddion_text_export_with_units(tmp_path):
    path = tmp_path / "scan.txt"
    rows = "\n".join(" ".join(f"{v:g}" for v in row) for row in [[1e-9, 2e-9, 3e-9], [4e-9, 5e-9, 6e-9]])
    path.write_text("# Channel: Height\n# Width: 3.000 um\n# Height: 2.000 um\n# Value units: m\n" + rows + "\n")
    t = gfmd.read_topography(path, unit=1e-9)  # nanometres
    assert t.has_units and t.format == "matrix"
    assert t.physical_size == pytest.approx((3000.0, 2000.0), rel=1e-15)
    assert t.heights == pytest.approx(np.array([[1, 2, 3], [4, 5, 6]], dtype=float), rel=1e-15)


def test_psd_against_numpy_fft(tmp_path):
    """C(q) of every bin from numpy's FFT of the same heights: a second computation."""
    rng = np.random.default_rng(7)
    ny, nx, lx, ly = 24, 40, 8.0, 5.0
    h = rng.normal(size=(ny, nx))
    t = gfmd.Topography.from_heights(h, (lx, ly))
    nbins = 12
    q, c, count = t.psd(nbins)
    hq = np.fft.fft2(h - h.mean()) / h.size
    qx = 2 * np.pi * np.fft.fftfreq(nx, d=lx / nx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, d=ly / ny)
    qq = np.hypot(*np.meshgrid(qx, qy)).ravel()
    a2 = (np.abs(hq) ** 2).ravel()
    keep = qq > 0
    qq, a2 = qq[keep], a2[keep]
    edges = np.log(qq.min()) + np.log(qq.max() / qq.min()) * np.arange(nbins + 1) / nbins
    k = np.minimum((nbins * np.log(qq / qq.min()) / np.log(qq.max() / qq.min())).astype(int), nbins - 1)
    for b in range(nbins):
        sel = k == b
        assert count[b] == sel.sum()
        if sel.any():
            assert c[b] == pytest.approx(lx * ly / (2 * np.pi) ** 2 * a2[sel].mean(), rel=1e-12)
            assert q[b] == pytest.approx(qq[sel].mean(), rel=1e-12)
            assert np.exp(edges[b]) * (1 - 1e-12) <= q[b] <= np.exp(edges[b + 1]) * (1 + 1e-12)
    assert (count * c).sum() * (2 * np.pi) ** 2 / (lx * ly) == pytest.approx(h.var(), rel=1e-12)
    qp, c1 = t.profile_psd()
    assert qp[1] == pytest.approx(2 * np.pi / lx)
    w = np.where((np.arange(len(qp)) == 0) | (np.arange(len(qp)) == nx // 2), 1.0, 2.0)
    assert (w * c1).sum() * 2 * np.pi / lx == pytest.approx(h.var(axis=1).mean(), rel=1e-12)


def test_simulation_from_topography_and_persson():
    with gfmd.Simulation(64, 64, 64.0, 64.0, planner=gfmd.ESTIMATE) as s:
        s.generate_selfaffine(0.8, 32.0, 4.0, 0.2, seed=2)
        t = gfmd.Topography.from_heights(s.heights(), (64.0, 64.0))
        assert t.moments()[1] == pytest.approx(0.2, rel=1e-12)  # the generator's rms gradient
        with gfmd.Simulation.from_topography(t, planner=gfmd.ESTIMATE) as r:
            assert np.array_equal(r.heights(), s.heights())
            assert t.persson_contact_area(0.01) == pytest.approx(r.persson_contact_area(0.01), rel=1e-12)


def test_resample_reproduces_a_quadratic():
    ny, nx, lx, ly = 20, 30, 3.0, 2.0
    y, x = np.mgrid[0:ny, 0:nx] * np.array([ly / ny, lx / nx])[:, None, None]
    f = lambda X, Y: 0.5 * X * X - 0.2 * X * Y + Y * Y - X  # noqa: E731
    t = gfmd.Topography.from_heights(f(x, y), (lx, ly))
    t.resample((37, 52))
    sx, sy = (nx - 1) * lx / nx / 51, (ny - 1) * ly / ny / 36
    assert t.shape == (37, 52) and t.physical_size == pytest.approx((52 * sx, 37 * sy), rel=1e-14)
    Y, X = np.mgrid[0:37, 0:52] * np.array([sy, sx])[:, None, None]
    inside = (X >= 2 * lx / nx) & (X <= (nx - 3) * lx / nx) & (Y >= 2 * ly / ny) & (Y <= (ny - 3) * ly / ny)
    assert np.max(np.abs(t.heights - f(X, Y))[inside]) < 1e-12  # Keys' kernel is exact for quadratics


def test_measured_scan_example_runs(tmp_path):
    """examples/python/measured_scan.py (the demo's panel) in a small mode: the SDF file it writes
    reads back with its missing points, and Persson's A/A0 from the measured spectrum is near the
    simulations' with free boundaries and on the periodic cell (the theory's known underestimate at
    small A/A0: within a factor 2)."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    script = Path(__file__).resolve().parents[2] / "examples" / "python" / "measured_scan.py"
    out = subprocess.run([sys.executable, str(script), "--n", "64", "--out", str(tmp_path)],
                         env=dict(os.environ, MPLBACKEND="Agg"), capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
    assert (tmp_path / "measured_scan.png").stat().st_size > 1000
    assert "format sdf_binary" in out.stdout and " missing" in out.stdout
    line = [s for s in out.stdout.splitlines() if s.startswith("sigma0")][0]
    free = float(line.split("free boundaries ")[1].split(",")[0])
    periodic = float(line.split("periodic cell ")[1].split(";")[0])
    persson = float(line.split("measured spectrum ")[1].split(",")[0])
    assert 0.5 < free / persson < 2.0 and 0.5 < periodic / persson < 2.0


def test_free_boundaries_hertz_and_topography():
    """Free boundaries from Python: Hertz's contact radius and central pressure without periodic
    images (Johnson Sec. 4.2; 32^2, a = 8 spacings: the pixel error (spacing/a)^2 / 2 bounds
    them), the region's total force sigma0 lx ly in the pressures, and a topography solved with
    free boundaries in one line."""
    n, radius, a_hertz = 32, 1.0, 0.25
    force = 4.0 * a_hertz ** 3 / (3.0 * radius)
    y, x = (np.mgrid[0:n, 0:n] + 0.5) / n - 0.5
    with gfmd.Simulation(n, n, 1.0, 1.0, planner=gfmd.ESTIMATE) as s:
        s.set_boundary(gfmd.FREE)
        assert s.boundary == gfmd.FREE and s.grid == (n, n, 1.0, 1.0)
        s.set_heights(-(x * x + y * y) / (2 * radius))
        s.set_pressure(force)
        s.relax(tol=1e-9)
        p = s.pressure()
        assert p.shape == (n, n)
        assert p.sum() / n ** 2 == pytest.approx(force, rel=1e-6)
        assert np.sqrt(s.contact_area / np.pi) == pytest.approx(a_hertz, rel=0.5 / 8)
        assert p[n // 2, n // 2] == pytest.approx(3 * force / (2 * np.pi * a_hertz ** 2), rel=0.5 / 64)
        assert -s.mean_displacement == pytest.approx(a_hertz ** 2 / radius, rel=0.5 / 64)  # the approach
        with pytest.raises(gfmd.StateError):
            s.set_green(gfmd.LAYER_FLUID, 1.0)
        t = gfmd.Topography.from_heights(s.heights(), (1.0, 1.0))
    with gfmd.Simulation.from_topography(t, planner=gfmd.ESTIMATE, boundary=gfmd.FREE) as r:
        assert r.boundary == gfmd.FREE and np.array_equal(r.heights(), t.heights)


def test_persson_mean_gap_against_numpy_quadrature():
    """Persson's mean gap u(p) = int_p^inf dp'/p' dU/dp' / A0 evaluated with numpy as the theory
    writes it (numpy's FFT, V(q) over the modes up to |q|, dU/dp summed, Simpson over ln p'),
    against the library's reduction to E1 and a tabulated integral: 1e-9 (both ~1e-12)."""
    from math import erf

    rng = np.random.default_rng(7)
    ny, nx, lx, ly, gamma = 9, 14, 2.0, 1.5, 0.45
    h = rng.normal(size=(ny, nx))
    hq = np.fft.fft2(h) / h.size
    qx = 2 * np.pi * np.fft.fftfreq(nx, lx / nx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, ly / ny)
    q = np.hypot(*np.meshgrid(qx, qy)).ravel()
    a2 = np.abs(hq.ravel()) ** 2
    keep = q > 0
    q, a2 = q[keep], a2[keep]
    k = q / 2  # a half-space, E* = 1
    v = np.array([np.sum(a2[q <= qi] * k[q <= qi] ** 2) for qi in q])
    erf_v = np.vectorize(erf)
    t = gfmd.Topography.from_heights(h, (lx, ly))
    for p in (1e-3, 0.2, 2.0):
        s = np.linspace(0.0, 60.0, 20001)
        pp = p * np.exp(s)[:, None]
        big_p = erf_v(pp / np.sqrt(2 * v))
        du = np.sum(0.5 * a2 * k * (gamma + 3 * (1 - gamma) * big_p ** 2) * np.sqrt(2 / (np.pi * v))
                    * np.exp(-pp ** 2 / (2 * v)), axis=1)
        w = np.ones_like(s)
        w[1:-1:2], w[2:-1:2] = 4, 2
        ref = np.sum(w * du) * (s[1] - s[0]) / 3
        assert t.persson_mean_gap(p, gamma=gamma) == pytest.approx(ref, rel=1e-9)
    with pytest.raises(gfmd.InvalidArgument):
        t.persson_mean_gap(0.0)


def test_x3p_written_with_zipfile_reads_back(tmp_path):
    """An ISO 5436-2 x3p archive written with Python's zipfile (another writer than the C test's
    libzip): float32 heights linked from main.xml, NaN points missing, read back in micrometres
    exactly as the float32 values times the unit conversion; the Python name of the format."""
    import zipfile

    ny, nx = 4, 6
    z = (np.arange(ny * nx, dtype="<f4").reshape(ny, nx) - 7.0) * np.float32(1e-8)
    z[2, 3] = np.nan
    xml = f"""<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2">
 <Record1><Revision>ISO5436 - 2000</Revision><FeatureType>SUR</FeatureType><Axes>
  <CX><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-6</Increment><Offset>0</Offset></CX>
  <CY><AxisType>I</AxisType><DataType>D</DataType><Increment>2e-6</Increment><Offset>0</Offset></CY>
  <CZ><AxisType>A</AxisType><DataType>F</DataType><Increment>1</Increment><Offset>0</Offset></CZ>
 </Axes></Record1>
 <Record3><MatrixDimension><SizeX>{nx}</SizeX><SizeY>{ny}</SizeY><SizeZ>1</SizeZ></MatrixDimension>
  <DataLink><PointDataLink>bin/data.bin</PointDataLink></DataLink></Record3>
</p:ISO5436_2>"""
    path = tmp_path / "scan.x3p"
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as f:
        f.writestr("main.xml", xml)
        f.writestr("bin/data.bin", z.tobytes())
    if not gfmd.x3p_supported():
        with pytest.raises(gfmd.StateError, match="libzip"):
            gfmd.read_topography(path)
        return
    t = gfmd.read_topography(path, unit=1e-6)
    assert (t.format, t.shape, t.has_units, t.missing) == ("x3p", (ny, nx), True, 1)
    assert t.physical_size == pytest.approx((nx * 1e-6 / 1e-6, ny * 2e-6 / 1e-6), rel=1e-15)
    expect = z.astype(np.float64) / 1e-6
    assert np.array_equal(np.isnan(t.heights), np.isnan(expect))
    assert np.array_equal(t.heights[~np.isnan(expect)], expect[~np.isnan(expect)])
