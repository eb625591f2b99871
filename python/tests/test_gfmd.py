"""The Python package against independent answers: the C library's own recorded trajectories
(tests/trajectory/reference.txt, same bits), the analytic sinusoid, numpy's least squares, and
every way a call can fail.  Run: PYTHONPATH=python python3 -m pytest python/tests (GFMD_LIBRARY
selects the library; ctest passes the one it built)."""
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import gfmd

ROOT = Path(__file__).resolve().parents[2]


def fnv1a(z):
    h = 0xCBF29CE484222325
    for byte in np.ascontiguousarray(z, dtype=np.float64).tobytes():
        h = ((h ^ byte) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def test_trajectories_are_those_of_c():
    """The setup of tests/trajectory/record_trajectories.c, driven from Python: every number and the
    hash of z equal the C program's recorded ones, bit for bit."""
    expected = {}
    for line in (ROOT / "tests" / "trajectory" / "reference.txt").read_text().splitlines():
        solver, body, stage, *fields = line.split()
        expected[(solver, body, stage)] = dict(f.split("=") for f in fields)
    solvers = {"verlet": gfmd.VERLET, "fire": gfmd.FIRE, "fire_mass": gfmd.MASS_WEIGHTED_FIRE,
               "mass_fire": gfmd.APPROACH_THEN_FIRE}
    for sname, solver in solvers.items():
        for body in ("halfspace", "fluid_w4", "bonded_w8_adhesive"):
            with gfmd.Simulation(64, 48, 64.0, 48.0, threads=1, planner=gfmd.ESTIMATE) as s:
                s.generate_selfaffine(0.8, 16.0, 4.0, 0.5, 7)
                if body == "fluid_w4":
                    s.set_green(gfmd.LAYER_FLUID, 4.0)
                if body == "bonded_w8_adhesive":
                    s.set_poisson(0.3)
                    s.set_green(gfmd.LAYER_BONDED, 8.0)
                    s.set_adhesion(2e-3, 0.5)
                s.set_pressure(0.03)
                s.set_solver(solver)
                for stage in ("relax", "step50"):
                    steps = s.relax(max_steps=20000) if stage == "relax" else (s.step(50) or 50)
                    ref = expected[(sname, body, stage)]
                    assert steps == int(ref["steps"])
                    assert s.contact_area == float.fromhex(ref["area"])
                    assert s.mean_gap == float.fromhex(ref["gap"])
                    assert s.elastic_energy == float.fromhex(ref["uel"])
                    assert s.adhesive_energy == float.fromhex(ref["uad"])
                    assert f"{fnv1a(s.surface()):016x}" == ref["z"]


def test_sinusoid_full_contact_threshold():
    """h = h0 cos(q x) on a half-space: full contact exactly from p* = h0 q E*/2 on (the elastic
    stress of the mode that the surface must follow); 2 % either side decides."""
    nx, ny, lam, h0 = 64, 8, 64.0, 0.5
    x = np.arange(nx) * lam / nx
    h = np.ascontiguousarray(np.tile(h0 * np.cos(2 * np.pi * x / lam), (ny, 1)))
    p_star = h0 * (2 * np.pi / lam) / 2
    with gfmd.Simulation(nx, ny, lam, float(ny)) as s:
        s.set_heights(h)
        assert np.array_equal(s.heights(), h)  # the layout round trip, (ny, nx)
        s.set_pressure(1.02 * p_star)
        s.relax(tol=1e-10)
        assert s.contact_area == 1.0
        s.set_pressure(0.98 * p_star)
        s.relax(tol=1e-10)
        assert 0.0 < s.contact_area < 1.0
        gap = s.gap()
        assert np.all(gap >= 0.0)
        assert np.ptp(gap, axis=0).max() < 1e-12  # constant along y: the substrate varies along x only


def test_relax_in_chunks_and_not_converged():
    def fresh():
        s = gfmd.Simulation(48, 32, 48.0, 32.0, threads=1, planner=gfmd.ESTIMATE)
        s.generate_selfaffine(0.8, 16.0, 4.0, 0.5, 3)
        s.set_green(gfmd.LAYER_FLUID, 2.0)
        s.set_pressure(0.01)
        return s

    with fresh() as one, fresh() as chunked, fresh() as limited:
        steps = one.relax()
        assert chunked.relax(progress=7) == steps  # printed progress costs no step
        assert np.array_equal(one.surface(), chunked.surface())
        with pytest.raises(gfmd.NotConverged) as info:
            limited.relax(max_steps=5)
        assert info.value.steps == 5 and limited.residual > gfmd.DEFAULT_TOL
        assert limited.relax() + 5 == steps  # continues the same trajectory
        assert np.array_equal(one.surface(), limited.surface())


def test_checkpoint_clone_and_lifetime(tmp_path):
    with gfmd.Simulation(32, 24, 32.0, 24.0, threads=1, planner=gfmd.ESTIMATE) as a:
        a.generate_selfaffine(0.8, 8.0, 4.0, 1.0, 5)
        a.set_pressure(0.05)
        a.step(20)
        a.save(tmp_path / "run.gfmd")
        b = gfmd.load(tmp_path / "run.gfmd")
        c = a.clone()
        for s in (a, b, c):
            s.step(30)
        assert np.array_equal(a.surface(), b.surface())
        assert np.array_equal(a.surface(), c.surface())
        assert b.grid == (32, 24, 32.0, 24.0) and b.shape == (24, 32)
        b.close()
        b.close()  # idempotent
        with pytest.raises(gfmd.StateError):
            b.step(1)
        c.set_pressure(0.0)  # c is independent of a
        assert a.residual != c.residual
    with pytest.raises(gfmd.StateError):
        a.contact_area  # closed by the with-block


def test_every_error_is_an_exception_with_the_library_message(tmp_path):
    with gfmd.Simulation(16, 12, 16.0, 12.0) as s:
        before = (s.contact_area, s.mean_gap, s.surface(), s.pressure())
        good = np.zeros((12, 16))
        for bad in (np.zeros((16, 12)), np.zeros(12 * 16), [[0.0] * 16] * 11, "heights", np.zeros((12, 16, 1))):
            with pytest.raises(gfmd.InvalidArgument):
                s.set_heights(bad)
        nan = good.copy()
        nan[3, 4] = np.nan
        with pytest.raises(gfmd.InvalidArgument, match="height 52"):
            s.set_heights(nan)  # refused by the library, which names the point
        with pytest.raises(gfmd.BadEnum):
            s.set_green(7, 1.0)
        with pytest.raises(gfmd.StateError):
            s.set_green(gfmd.LAYER_BONDED, 1.0)  # Poisson's ratio not set
        with pytest.raises(ValueError):  # InvalidArgument is a ValueError too
            s.set_pressure(float("nan"))
        with pytest.raises(gfmd.InvalidArgument):
            s.generate_selfaffine(0.8, 1e300, 4.0, 1.0, 3)
        with pytest.raises(gfmd.FileError):
            s.save(tmp_path / "no" / "such" / "dir.gfmd")
        after = (s.contact_area, s.mean_gap, s.surface(), s.pressure())
        assert all(np.array_equal(x, y) for x, y in zip(before, after))  # no failure changed the state
    with pytest.raises(gfmd.InvalidArgument):
        gfmd.Simulation(0, 4, 1.0, 1.0)
    with pytest.raises(gfmd.FileError):
        gfmd.load(tmp_path / "missing.gfmd")
    (tmp_path / "junk.gfmd").write_bytes(b"not a checkpoint at all")
    with pytest.raises(gfmd.FormatError):
        gfmd.load(tmp_path / "junk.gfmd")
    with pytest.raises(gfmd.InvalidArgument):
        gfmd.green_factor(gfmd.LAYER_FLUID, -1.0)


def test_theory_and_fits():
    assert gfmd.green_factor(gfmd.HALFSPACE, 2.0) == 1.0
    t = 1e-3  # thin-plate limit f -> 6/t^3
    assert gfmd.green_factor(gfmd.LAYER_FLUID, t) * t**3 / 6 == pytest.approx(1.0, rel=1e-5)
    rng = np.random.default_rng(1)
    a = rng.normal(size=(20, 3))
    b = rng.normal(size=20)
    x, rss = gfmd.least_squares(a, b)
    x_np, rss_np, *_ = np.linalg.lstsq(a, b, rcond=None)
    assert np.allclose(x, x_np, rtol=1e-12, atol=1e-12) and rss == pytest.approx(rss_np[0], rel=1e-10)
    with gfmd.Simulation(64, 64, 64.0, 64.0) as s:
        s.generate_selfaffine(0.8, 32.0, 4.0, 1.0, 2)
        v = s.persson_variance()
        assert s.persson_contact_area(0.05) == pytest.approx(math.erf(0.05 / math.sqrt(2 * v)), rel=1e-14)
        # the inverse: to the last bit of the bisection's x (the load's own rounding, 1e-15)
        assert s.persson_load(s.persson_contact_area(0.05)) == pytest.approx(0.05, rel=1e-13)
        with pytest.raises(gfmd.Error, match="rel_area"):
            s.persson_load(1.0)


def test_constants_are_the_tables():
    values = {}
    for line in (ROOT / "include" / "gfmd" / "constants.tbl").read_text().splitlines():
        parts = [p.strip() for p in line.split("|")]
        if parts[0] == "value":
            values[parts[1]] = int(parts[2])
    assert values and all(getattr(gfmd, k) == v for k, v in values.items())
    assert (gfmd.HALFSPACE, gfmd.LAYER_FLUID, gfmd.LAYER_BONDED) == (0, 1, 2)
    # the deprecated names keep their values (the ABI's): the two mass-weighted methods
    assert gfmd.GFMD_SOLVER_FIRE_MASS == gfmd.FIRE_MASS == gfmd.MASS_WEIGHTED_FIRE == 2
    assert gfmd.GFMD_SOLVER_MASS_FIRE == gfmd.MASS_FIRE == gfmd.APPROACH_THEN_FIRE == 5


def test_missing_library_names_every_place_tried(tmp_path):
    """An installed-like copy of the package (constants table beside it, no build tree) with
    GFMD_LIBRARY pointing nowhere: the error names the paths it tried."""
    pkg = tmp_path / "site" / "gfmd"
    shutil.copytree(ROOT / "python" / "gfmd", pkg)
    shutil.copy(ROOT / "include" / "gfmd" / "constants.tbl", pkg / "constants.tbl")
    env = dict(os.environ, GFMD_LIBRARY="/no/such/libgfmd.so", PYTHONPATH=str(tmp_path / "site"),
               LD_LIBRARY_PATH="")
    code = "import gfmd\ntry:\n    gfmd.version()\nexcept OSError as e:\n    print(e)\n"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, cwd=tmp_path)
    assert "/no/such/libgfmd.so" in out.stdout and "GFMD_LIBRARY" in out.stdout, out.stdout + out.stderr


def test_example_script_runs(tmp_path):
    """examples/python/load_sweep.py in its small mode: a load sweep, Persson's curve, the plots."""
    env = dict(os.environ, MPLBACKEND="Agg")
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "python" / "load_sweep.py"), "--n", "64",
                          "--out", str(tmp_path)], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
    assert (tmp_path / "load_sweep.png").stat().st_size > 1000
    assert (tmp_path / "contact_map.png").stat().st_size > 1000
    rows = [l for l in out.stdout.splitlines() if l.startswith("sigma0")]
    assert len(rows) >= 5


def test_docs_example(tmp_path, monkeypatch):
    """The complete example of docs/python.md, run as written (in a scratch folder)."""
    text = (ROOT / "docs" / "python.md").read_text()
    code = text.split("```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "docs/python.md", "exec"), {})
    assert (tmp_path / "sweep.gfmd").exists()


def test_readme_example():
    """README.md's Python block, run as written."""
    text = (ROOT / "README.md").read_text()
    code = text.split("```python\n", 1)[1].split("```", 1)[0]
    scope = {}
    exec(compile(code, "README.md", "exec"), scope)
    assert scope["steps"] > 0 and scope["gap"].shape == (256, 256) and scope["gap"].min() == 0.0


def test_displacement_control_matches_pressure_control():
    """The position of a pressure-controlled equilibrium, prescribed, gives back its pressure (as the
    C test_displacement checks on more bodies)."""
    with gfmd.Simulation(48, 40, 48.0, 40.0, threads=1, planner=gfmd.ESTIMATE) as p:
        p.generate_selfaffine(0.8, 16.0, 4.0, 0.5, 11)
        p.set_pressure(0.03)
        p.relax(tol=1e-9)
        assert p.mean_pressure == 0.03
        d = p.mean_displacement
        q = p.clone()
        q.reset()
        q.set_mean_displacement(d)
        q.relax(tol=1e-9)
        assert q.mean_displacement == pytest.approx(d, abs=1e-12)
        assert q.mean_pressure == pytest.approx(0.03, rel=1e-6)
        assert np.abs(q.surface() - p.surface()).max() < 1e-6
        with pytest.raises(gfmd.InvalidArgument):
            q.set_mean_displacement(p.heights().mean() - 1.0)
        q.close()


def test_solver_choice():
    """GFMD_SOLVER_AUTO chooses CG for a small half-space, with adhesion too under pressure
    control; under displacement control FIRE with adhesion, where CG and adhesion refuse each other
    with a StateError that changes nothing."""
    with gfmd.Simulation(32, 32, 32.0, 32.0, threads=1, planner=gfmd.ESTIMATE) as s:
        s.generate_selfaffine(0.8, 8.0, 4.0, 1.0, seed=3)
        s.set_pressure(0.05)
        assert s.solver == gfmd.CG
        s.set_adhesion(1e-3, 0.5)
        assert s.solver == gfmd.CG
        s.relax()
        assert 0.0 < s.contact_area < 1.0
        h = s.heights()
        s.set_mean_displacement(h.mean() + 0.5 * h.std())
        assert s.solver == gfmd.FIRE
        with pytest.raises(gfmd.StateError):
            s.set_solver(gfmd.CG)
        assert s.solver == gfmd.FIRE
        s.set_adhesion(0.0, 0.5)
        s.set_solver(gfmd.CG)
        with pytest.raises(gfmd.StateError):
            s.set_adhesion(1e-3, 0.5)
        assert s.solver == gfmd.CG
        s.relax()
        assert 0.0 < s.contact_area < 1.0


def test_newton_solver():
    """GFMD_SOLVER_NEWTON ends where the CG ends on a thin sheet (the same contact set), a body it
    does not take is refused with a StateError that changes nothing, and with adhesion it relaxes
    the same sheet to a larger contact (its trust region; test_adhesion checks those minima)."""
    areas = []
    for solver in (gfmd.NEWTON, gfmd.CG):
        with gfmd.Simulation(64, 64, 64.0, 64.0, threads=1, planner=gfmd.ESTIMATE) as s:
            s.generate_selfaffine(0.8, 16.0, 4.0, 1.0, seed=5)
            s.set_green(gfmd.LAYER_FLUID, 0.35)
            s.set_pressure(2e-5)
            s.set_solver(solver)
            s.relax(tol=1e-10)
            areas.append(s.contact_area)
            if solver == gfmd.NEWTON:
                with pytest.raises(gfmd.StateError):
                    s.set_green(gfmd.HALFSPACE, 0.0)
                assert s.solver == gfmd.NEWTON
                s.set_adhesion(5e-4, 1.0)
                s.relax(tol=1e-10)
                assert s.solver == gfmd.NEWTON
                assert s.contact_area > areas[0]
    assert 0.0 < areas[0] == areas[1] < 1.0


def test_relax_multilevel():
    """A start made on coarser grids ends where a flat start ends (gfmd_relax_multilevel)."""
    results = []
    for levels in (1, 3):
        with gfmd.Simulation(64, 64, 64.0, 64.0, threads=1, planner=gfmd.ESTIMATE) as s:
            s.generate_selfaffine(0.8, 16.0, 4.0, 1.0, seed=5)
            s.set_green(gfmd.LAYER_FLUID, 2.0)
            s.set_pressure(0.002)
            steps, coarse = s.relax_multilevel(levels, tol=1e-10)
            assert (coarse > 0) == (levels > 1)
            results.append((s.contact_area, s.mean_gap))
    assert results[0][0] == results[1][0]
    assert abs(results[0][1] - results[1][1]) <= 1e-6 * results[0][1]
    with gfmd.Simulation(48, 40, 48.0, 40.0, threads=1, planner=gfmd.ESTIMATE) as s:
        with pytest.raises(gfmd.InvalidArgument):
            s.relax_multilevel(5)


def test_array_inputs_as_numpy_takes_them(tmp_path):
    """Every array-like numpy converts, with the right shape: the same substrate bit for bit; a
    C-contiguous float64 array is passed without a copy, anything else converted once; out= fills
    the caller's buffer."""
    ny, nx = 12, 16
    rng = np.random.default_rng(1)
    h = -rng.random((ny, nx))
    with gfmd.Simulation(nx, ny, float(nx), float(ny), planner=gfmd.ESTIMATE) as s:
        assert s._field_in(h) is h  # no copy
        s.set_heights(h)
        ref = s.heights()
        wide = np.zeros((ny, 2 * nx))
        wide[:, ::2] = h
        ro = h.copy()
        ro.setflags(write=False)
        inputs = {"non-contiguous": wide[:, ::2], "Fortran order": np.asfortranarray(h),
                  "transpose of the transpose": h.T.copy().T, "float32": h.astype(np.float32),
                  "integers": np.round(10 * h).astype(np.int64), "list of lists": h.tolist(),
                  "read-only": ro, "memoryview": memoryview(np.ascontiguousarray(h)),
                  "FFT round trip": np.fft.irfft2(np.fft.rfft2(h), s=h.shape)}
        for name, x in inputs.items():
            s.set_heights(x)
            expect = np.asarray(x, dtype=np.float64)
            assert np.array_equal(s.heights(), expect), name
        assert s._field_in(ro) is ro  # read-only but C-contiguous float64: read in place
        s.set_heights(h)
        out = np.full((ny, nx), 7.0)
        assert s.heights(out=out) is out and np.array_equal(out, ref)
        for get in (s.gap, s.surface, s.pressure):
            buf = np.empty((ny, nx))
            assert get(out=buf) is buf and np.array_equal(buf, get())
        for bad in (np.empty((nx, ny)), np.empty((ny, nx), dtype=np.float32), np.empty((ny, 2 * nx))[:, ::2], ro):
            with pytest.raises(gfmd.InvalidArgument):
                s.heights(out=bad)
