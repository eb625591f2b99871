"""The package as a user installs it: `pip install --no-build-isolation ./python` into a fresh venv
(offline: Debian's setuptools and numpy through --system-site-packages) builds the library with
CMake (in the suite's build tree, GFMD_BUILD_DIR) and installs it beside the modules; from a folder outside the tree, with neither GFMD_LIBRARY
nor PYTHONPATH, the installed package imports, finds its own library, reports its version, carries
its type-hint marker, and relaxes a contact to the same numbers as the package of the source tree."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

import gfmd

ROOT = Path(__file__).resolve().parents[2]

PROBE = """
import json, gfmd, importlib.resources as r
s = gfmd.Simulation(32, 32, 32.0, 32.0, planner=gfmd.ESTIMATE)
s.generate_selfaffine(0.8, 16.0, 4.0, 1.0, seed=3)
s.set_pressure(0.05)
steps = s.relax(tol=1e-10)
print(json.dumps({"version": gfmd.__version__, "library": gfmd._c()._name, "file": gfmd.__file__,
                  "typed": (r.files("gfmd") / "py.typed").is_file(), "steps": steps,
                  "area": s.contact_area, "gap": s.mean_gap, "help": gfmd.Simulation.relax.__doc__}))
"""


def test_pip_install_into_a_venv(tmp_path):
    venv = tmp_path / "venv"
    made = subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], capture_output=True,
                          text=True)
    if made.returncode != 0 and "ensurepip" in made.stdout + made.stderr:
        pytest.fail("python3-venv is missing (scripts/test.sh installs it): " + made.stdout + made.stderr)
    assert made.returncode == 0, made.stdout + made.stderr
    env = {k: v for k, v in os.environ.items() if k not in ("GFMD_LIBRARY", "PYTHONPATH")}
    # the build tree the suite runs on (its library already built: `cmake --build` checks it and
    # copies it) rather than a second compilation in a scratch tree, which takes 26 s on 2 cores
    build = Path(gfmd._c()._name).resolve().parent
    if (build / "CMakeCache.txt").exists():
        env["GFMD_BUILD_DIR"] = str(build)
    pip = subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "--no-build-isolation", "--no-index",
                          "--quiet", str(ROOT / "python")], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert pip.returncode == 0, pip.stdout + pip.stderr
    run = subprocess.run([str(venv / "bin" / "python"), "-c", PROBE], capture_output=True, text=True, env=env,
                         cwd=tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    import json
    got = json.loads(run.stdout)
    assert got["version"] == gfmd.__version__ == gfmd.version()
    assert got["file"].startswith(str(venv)) and got["library"].startswith(str(venv)), got
    assert got["typed"] and got["help"]  # the marker of the type hints, and help() has text
    # the same problem through the source tree's package and library
    with gfmd.Simulation(32, 32, 32.0, 32.0, planner=gfmd.ESTIMATE) as s:
        s.generate_selfaffine(0.8, 16.0, 4.0, 1.0, seed=3)
        s.set_pressure(0.05)
        steps = s.relax(tol=1e-10)
        assert got["steps"] == steps
        assert abs(got["area"] - s.contact_area) <= 1e-12 and abs(got["gap"] - s.mean_gap) <= 1e-12 * s.mean_gap
