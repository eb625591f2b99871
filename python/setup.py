"""Builds the package with the library it needs: `pip install --no-build-isolation ./python`
configures and builds libgfmd from this source tree with CMake (the library only, Release) and puts
it, the constants table and the version beside the package's modules.  GFMD_CMAKE_ARGS adds CMake
arguments; GFMD_BUILD_DIR names a configured build tree of this source to build the library in
instead of a scratch one; the build needs what the library needs (cmake, a C++ compiler, FFTW and LAPACKE:
scripts/setup.sh installs them)."""
import os
import re
import shlex
import shutil
import subprocess
import tempfile
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(gfmd VERSION ([0-9.]+)", text).group(1)


class BuildWithLibrary(build_py):
    def run(self):
        super().run()
        target = Path(self.build_lib) / "gfmd"
        target.mkdir(parents=True, exist_ok=True)
        existing = os.environ.get("GFMD_BUILD_DIR")  # a configured build tree of this source to reuse
        with tempfile.TemporaryDirectory(prefix="gfmd-build-") as scratch:
            build = existing or scratch
            if not existing:
                args = ["-DCMAKE_BUILD_TYPE=Release", "-DGFMD_BUILD_TESTS=OFF", "-DGFMD_BUILD_EXAMPLES=OFF",
                        "-DGFMD_BUILD_FORTRAN=OFF", "-DGFMD_BUILD_BENCHMARK=OFF"]
                args += shlex.split(os.environ.get("GFMD_CMAKE_ARGS", ""))
                subprocess.run(["cmake", "-S", str(ROOT), "-B", build, *args], check=True, stdout=subprocess.DEVNULL)
            subprocess.run(["cmake", "--build", build, "--target", "gfmd", "-j", str(os.cpu_count() or 1)],
                           check=True, stdout=subprocess.DEVNULL)
            built = Path(build) / "libgfmd.so.0"
            shutil.copyfile(built.resolve(), target / "libgfmd.so.0")
        shutil.copyfile(ROOT / "include" / "gfmd" / "constants.tbl", target / "constants.tbl")
        (target / "_version.py").write_text(f'__version__ = "{version()}"\n')


setup(version=version(), cmdclass={"build_py": BuildWithLibrary})
