"""Contact patches, the pressure distribution and plasticity from Python: hand-made sets whose
patches are known, a flood fill written here as a second labelling algorithm, the handle's patches
against its own observables, the histogram's totals, and a punch pressed until it all yields."""
import os
import subprocess
import sys
from collections import deque
from pathlib import Path

import numpy as np
import pytest

import gfmd


def flood_fill(mask, connectivity, periodic):
    """Labels by breadth-first search, numbered in the order of each patch's first point (x fastest)."""
    ny, nx = mask.shape
    labels = np.zeros((ny, nx), dtype=np.int64)
    steps = [(1, 0), (-1, 0), (0, 1), (0, -1)]
    if connectivity == 8:
        steps += [(1, 1), (-1, 1), (1, -1), (-1, -1)]
    count = 0
    for y in range(ny):
        for x in range(nx):
            if not mask[y, x] or labels[y, x]:
                continue
            count += 1
            labels[y, x] = count
            todo = deque([(y, x)])
            while todo:
                cy, cx = todo.popleft()
                for dx, dy in steps:
                    jy, jx = cy + dy, cx + dx
                    if periodic:
                        jy, jx = jy % ny, jx % nx
                    elif not (0 <= jy < ny and 0 <= jx < nx):
                        continue
                    if mask[jy, jx] and not labels[jy, jx]:
                        labels[jy, jx] = count
                        todo.append((jy, jx))
    return labels, count


def test_hand_made_sets():
    ny, nx = 32, 40
    y, x = np.mgrid[0:ny, 0:nx]
    dx, dy = np.where(x < nx // 2, x, x - nx), np.where(y < ny // 2, y, y - ny)
    ring = (np.hypot(dx, dy) >= 5) & (np.hypot(dx, dy) <= 8)  # around the corner
    assert gfmd.label_patches(ring, 4)[1] == 1
    assert gfmd.label_patches(ring, 8, periodic=False)[1] == 4
    board = (np.add.outer(np.arange(6), np.arange(8)) % 2) == 0
    labels, n = gfmd.label_patches(board, 4)
    assert n == 24 and labels[0, 0] == 1 and labels[0, 2] == 2 and labels[0, 1] == 0
    labels, n = gfmd.label_patches(board, 8)
    assert n == 1 and np.array_equal(labels == 1, board)
    assert gfmd.label_patches(np.zeros((4, 4)), 4)[1] == 0
    with pytest.raises(gfmd.InvalidArgument):
        gfmd.label_patches(board, 6)
    with pytest.raises(gfmd.InvalidArgument):
        gfmd.label_patches(np.zeros(5), 4)


@pytest.mark.parametrize("connectivity", [4, 8])
@pytest.mark.parametrize("periodic", [True, False])
def test_random_sets_against_a_flood_fill(connectivity, periodic):
    rng = np.random.default_rng(3)
    for density in (0.3, 0.55, 0.8):
        mask = rng.random((23, 31)) < density
        labels, n = gfmd.label_patches(mask, connectivity, periodic)
        expected, m = flood_fill(mask, connectivity, periodic)
        assert n == m and np.array_equal(labels, expected)


def rough(sigma0, hardness=None):
    sim = gfmd.Simulation(64, 64, 64.0, 64.0, planner=gfmd.ESTIMATE)
    sim.generate_selfaffine(0.8, 32.0, 4.0, 1.0, seed=9)
    if hardness is not None:
        sim.set_hardness(hardness)
    sim.set_pressure(sigma0)
    sim.relax(tol=1e-10)
    return sim


def test_patches_and_histogram_of_a_rough_contact():
    with rough(0.03) as sim:
        p = sim.contact_patches(8)
        assert p.labels.shape == (64, 64) and p.count > 3
        assert np.array_equal(p.labels, gfmd.label_patches(sim.gap() <= 0, 8)[0])
        # areas sum to A/A0 (integers times 1: exact), loads to sigma0 A0 within the residual 1e-10
        assert p.area.sum() == sim.contact_area * 64 * 64
        assert abs(p.load.sum() / (0.03 * 64 * 64) - 1) < 1e-8
        assert p.centroid.shape == (p.count, 2)
        assert np.all((p.centroid >= 0) & (p.centroid < 64))
        assert np.allclose(p.perimeter, np.pi / 4 * p.edges)  # unit spacing
        edges, counts = p.size_histogram(5)
        assert counts.sum() == p.count and edges.size == 6
        assert sim.contact_patches(4).count >= p.count
        edges, fraction, mean = sim.pressure_histogram(30)
        assert abs(fraction.sum() - sim.contact_area) < 1e-14
        assert abs((fraction * mean).sum() / 0.03 - 1) < 1e-8
        assert edges[-1] == sim.pressure().max()
        pp = np.linspace(0, 1, 5)
        d = sim.persson_pressure_distribution(pp, 0.03)
        assert d.shape == pp.shape and d[0] == 0.0 and np.all(d[1:] >= 0)


def test_punch_pressed_until_all_yields():
    n, hard = 64, 0.05
    h = np.full((n, n), -5.0)
    h[28:36, 28:36] = 0.0
    with gfmd.Simulation(n, n, float(n), float(n), planner=gfmd.ESTIMATE) as sim:
        sim.set_heights(h)
        sim.set_hardness(hard)
        assert sim.hardness == hard and sim.solver == gfmd.FIRE
        sim.set_mean_displacement(-1.5)
        sim.relax(tol=1e-10)
        plastic, volume = sim.plasticity
        assert sim.contact_area == plastic == 64 / n**2
        assert abs(sim.mean_pressure / (hard * sim.contact_area) - 1) < 1e-8
        assert abs((h - sim.heights()).sum() - volume) < 1e-12 * volume
        assert sim.pressure().max() == hard
        with pytest.raises(gfmd.StateError):
            sim.set_solver(gfmd.CG)
        with pytest.raises(gfmd.InvalidArgument):
            sim.set_hardness(float("nan"))


def test_demo_panel_runs(tmp_path):
    """examples/python/contact_patches.py (the demo's panel) in a small mode: the sheet's contact at
    the half-space's A/A0 splits into more patches, and unloading at a hardness keeps more contact
    than loading had at the same load."""
    script = Path(__file__).resolve().parents[2] / "examples" / "python" / "contact_patches.py"
    out = subprocess.run([sys.executable, str(script), "--n", "64", "--out", str(tmp_path)],
                         env=dict(os.environ, MPLBACKEND="Agg"), capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
    assert (tmp_path / "contact_patches.png").stat().st_size > 1000
    counts = [int(line.split("patches")[1].split()[0]) for line in out.stdout.splitlines() if " patches " in line]
    assert len(counts) == 2 and counts[1] > counts[0]
    cycle = [line for line in out.stdout.splitlines() if line.startswith("hardness")][0]
    back, up = (float(x.split()[0]) for x in cycle.split("A/A0 ")[1].split(" against "))
    assert back > up
