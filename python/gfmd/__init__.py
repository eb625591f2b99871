"""gfmd from Python: Green's function molecular dynamics for the contact of a rigid rough substrate
and an elastic half-space or thin layer, over the library's stable C ABI (ctypes, numpy; no
compiled extension).

    import gfmd
    with gfmd.Simulation(256, 256, 256.0, 256.0) as sim:
        sim.generate_selfaffine(0.8, 32.0, 4.0, 1.0, seed=1)
        sim.set_green(gfmd.LAYER_FLUID, 4.0)
        sim.set_pressure(0.02)
        steps = sim.relax()
        print(sim.contact_area, sim.mean_gap)

Fields are numpy arrays of shape (ny, nx), x fastest, the C layout of the library.  The library is
found through load_library(path), GFMD_LIBRARY, the source tree's build folder, or the system
loader (docs/python.md).
"""
from __future__ import annotations

import ctypes
import os
import sys
from typing import Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import _constants, _library

try:
    from ._version import __version__  # written by the pip build (setup.py)
except ImportError:  # the source tree: the project's version
    import re as _re
    from pathlib import Path as _Path

    _cmake = _Path(__file__).resolve().parents[2] / "CMakeLists.txt"
    _m = _re.search(r"project\(gfmd VERSION ([0-9.]+)", _cmake.read_text()) if _cmake.exists() else None
    __version__ = _m.group(1) if _m else "unknown"

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
PathLike = Union[str, "os.PathLike[str]"]

_VALUES, _STATUS_TEXT = _constants.read()
globals().update(_VALUES)  # every GFMD_* constant of the C header, under its C name
HALFSPACE = _VALUES["GFMD_GREEN_HALFSPACE"]
LAYER_FLUID = _VALUES["GFMD_GREEN_LAYER_FLUID"]
LAYER_BONDED = _VALUES["GFMD_GREEN_LAYER_BONDED"]
PERIODIC = _VALUES["GFMD_BOUNDARY_PERIODIC"]
FREE = _VALUES["GFMD_BOUNDARY_FREE"]
UNIFORM = _VALUES["GFMD_DIST_UNIFORM"]
GAUSSIAN = _VALUES["GFMD_DIST_GAUSSIAN"]
VERLET = _VALUES["GFMD_SOLVER_VERLET"]
FIRE = _VALUES["GFMD_SOLVER_FIRE"]
MASS_WEIGHTED_FIRE = _VALUES["GFMD_SOLVER_MASS_WEIGHTED_FIRE"]
APPROACH_THEN_FIRE = _VALUES["GFMD_SOLVER_APPROACH_THEN_FIRE"]
FIRE_MASS = MASS_WEIGHTED_FIRE  # deprecated names of the two
MASS_FIRE = APPROACH_THEN_FIRE
CG = _VALUES["GFMD_SOLVER_CG"]
NEWTON = _VALUES["GFMD_SOLVER_NEWTON"]
AUTO = _VALUES["GFMD_SOLVER_AUTO"]
ESTIMATE = _VALUES["GFMD_PLANNER_ESTIMATE"]
MEASURE = _VALUES["GFMD_PLANNER_MEASURE"]
PATIENT = _VALUES["GFMD_PLANNER_PATIENT"]
DEFAULT_TOL = _VALUES["GFMD_DEFAULT_TOL"]
_PATCH = {name: _VALUES["GFMD_PATCH_" + name.upper()] for name in
          ("points", "area", "edges", "perimeter", "centroid_x", "centroid_y", "load")}


# ------------------------------------------------------------------ errors
class Error(Exception):
    """A failed library call: .status (GFMD_ERR_*), .message (the library's own words)."""

    def __init__(self, status, message):
        self.status, self.message = status, message
        super().__init__(f"{_STATUS_TEXT.get(status, 'unknown status')}: {message}" if message else
                         _STATUS_TEXT.get(status, "unknown status"))


class NullError(Error, ValueError): pass
class InvalidArgument(Error, ValueError): pass
class BadEnum(Error, ValueError): pass
class StateError(Error): pass
class OutOfMemory(Error, MemoryError): pass
class RangeError(Error, ArithmeticError): pass
class Truncated(Error): pass
class InternalError(Error): pass
class FileError(Error, OSError): pass
class FormatError(Error): pass
class VersionError(Error): pass
class Diverged(Error):
    """The dynamics diverged; the state of the call's start was restored."""


class NotConverged(Error):
    """relax() reached max_steps: .steps were made and kept; another relax() continues."""

    def __init__(self, status, message, steps=0):
        super().__init__(status, message)
        self.steps = steps


_CLASSES = {
    "GFMD_ERR_NULL": NullError, "GFMD_ERR_INVALID_ARG": InvalidArgument, "GFMD_ERR_BAD_ENUM": BadEnum,
    "GFMD_ERR_STATE": StateError, "GFMD_ERR_NOMEM": OutOfMemory, "GFMD_ERR_NOT_CONVERGED": NotConverged,
    "GFMD_ERR_DIVERGED": Diverged, "GFMD_ERR_RANGE": RangeError, "GFMD_ERR_TRUNCATED": Truncated,
    "GFMD_ERR_INTERNAL": InternalError, "GFMD_ERR_IO": FileError, "GFMD_ERR_FORMAT": FormatError,
    "GFMD_ERR_VERSION": VersionError,
}
_BY_STATUS = {_VALUES[name]: cls for name, cls in _CLASSES.items()}


def _raise(status, message):
    raise _BY_STATUS.get(status, Error)(status, message)


# ------------------------------------------------------------------ the library
_lib = None


def load_library(path: Optional[PathLike] = None) -> ctypes.CDLL:
    """Load libgfmd (from path, if given) and return the ctypes handle; done at first use otherwise."""
    global _lib
    if _lib is None or path is not None:
        _lib = _library.load(path)
    return _lib


def _c():
    return _lib if _lib is not None else load_library()


_mpi_lib = None


def _cm():
    """libgfmd_mpi, loaded at the first distributed Simulation (mpi4py must have initialized MPI)."""
    global _mpi_lib
    if _mpi_lib is None:
        _mpi_lib = _library.load_mpi()
    return _mpi_lib


def version() -> str:
    """The library's version string."""
    return _c().gfmd_version().decode()


def green_factor(kind: int, t: float, nu: float = 0.0) -> float:
    """f(t) of a body (HALFSPACE, LAYER_FLUID, LAYER_BONDED) at t = q w."""
    f = ctypes.c_double()
    st = _c().gfmd_green_factor(int(kind), float(t), float(nu), ctypes.byref(f))
    if st:
        _raise(st, f"green_factor(kind={kind}, t={t}, nu={nu})")
    return f.value


def least_squares(a: npt.ArrayLike, b: npt.ArrayLike) -> Tuple[FloatArray, float]:
    """x minimizing ||a x - b|| (a: m x n, full rank) and the residual sum of squares, by LAPACKE."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    if a.ndim != 2 or b.shape != (a.shape[0],):
        raise InvalidArgument(_VALUES["GFMD_ERR_INVALID_ARG"], "a must be m x n and b of length m")
    m, n = a.shape
    col = np.asfortranarray(a)  # the library takes a column-major A
    x = np.empty(n)
    rss = ctypes.c_double()
    st = _c().gfmd_least_squares(m, n, col.ctypes.data_as(_library.c_double_p),
                                 np.ascontiguousarray(b).ctypes.data_as(_library.c_double_p),
                                 x.ctypes.data_as(_library.c_double_p), ctypes.byref(rss))
    if st:
        _raise(st, "least_squares")
    return x, rss.value


def label_patches(mask: npt.ArrayLike, connectivity: int = 4, periodic: bool = True) -> Tuple[IntArray, int]:
    """Connected-component labels of a boolean (ny, nx) mask: (labels, count), labels an int64
    array, 0 outside the set and 1..count inside, numbered in the order of each patch's first point
    (x fastest); connectivity 4 (edge neighbours) or 8 (and the diagonal ones); periodic wraps the
    grid around (a patch across the border is one patch)."""
    m = np.ascontiguousarray(np.asarray(mask) != 0, dtype=np.int32)
    if m.ndim != 2:
        raise InvalidArgument(_VALUES["GFMD_ERR_INVALID_ARG"], f"mask must be 2-dimensional, got shape {m.shape}")
    ny, nx = m.shape
    labels = np.empty((ny, nx), dtype=np.int64)
    n = ctypes.c_int64()
    st = _c().gfmd_label_patches(nx, ny, m.ctypes.data_as(_library.c_int32_p), int(connectivity), 1 if periodic else 0,
                                 labels.ctypes.data_as(_library.c_int64_p), ctypes.byref(n))
    if st:
        _raise(st, f"label_patches(connectivity={connectivity})")
    return labels, n.value


class ContactPatches:
    """The contact patches of a Simulation's configuration (Simulation.contact_patches()): .labels
    (ny, nx) int64 (0 out of contact, 1..count), .count, and per patch in label order: .points,
    .area, .edges (the lattice perimeter, in edges), .perimeter (edges' length times pi/4),
    .centroid ((count, 2): x, y in the cell, periodic mean), .load (the force the patch carries)."""

    def __init__(self, sim: "Simulation", connectivity: int) -> None:
        self.connectivity = connectivity
        self.labels = np.empty(sim.shape, dtype=np.int64)
        n = ctypes.c_int64()
        sim._call("gfmd_get_contact_patches", int(connectivity), self.labels.ctypes.data_as(_library.c_int64_p),
                  ctypes.byref(n))
        self.count = n.value
        values = {}
        for name, code in _PATCH.items():
            v = np.empty(max(self.count, 1))
            sim._call("gfmd_get_patch_property", int(connectivity), code, self.count,
                      v.ctypes.data_as(_library.c_double_p), ctypes.byref(n))
            values[name] = v[:self.count]
        self.points, self.area, self.edges = values["points"], values["area"], values["edges"]
        self.perimeter, self.load = values["perimeter"], values["load"]
        self.centroid = np.column_stack([values["centroid_x"], values["centroid_y"]])

    @property
    def mean_area(self) -> float:
        """The mean patch area (0 without patches)."""
        return float(self.area.mean()) if self.count else 0.0

    def size_histogram(self, bins: int = 10) -> Tuple[FloatArray, IntArray]:
        """(edges, counts): the number of patches by area in `bins` logarithmic bins from the
        smallest patch's area to the largest's (counts sum to .count)."""
        if self.count == 0:
            return np.array([]), np.array([], dtype=np.int64)
        lo, hi = self.area.min(), self.area.max()
        edges = np.geomspace(lo, hi if hi > lo else lo * 2.0, int(bins) + 1)
        counts, _ = np.histogram(self.area, bins=edges)
        return edges, counts

    def perimeter_area_exponent(self) -> float:
        """The exponent D/2 of perimeter ~ area^(D/2) fitted by least squares (ln P against ln A) over
        the patches of more than one point; NaN with fewer than two such sizes."""
        keep = self.points > 1
        if np.unique(self.area[keep]).size < 2:
            return float("nan")
        a = np.column_stack([np.ones(keep.sum()), np.log(self.area[keep])])
        x, _ = least_squares(a, np.log(self.perimeter[keep]))
        return float(x[1])


def import_wisdom(path: PathLike) -> None:
    st = _c().gfmd_import_wisdom(os.fsencode(path))
    if st:
        _raise(st, f"cannot import FFTW wisdom from {path}")


def export_wisdom(path: PathLike) -> None:
    st = _c().gfmd_export_wisdom(os.fsencode(path))
    if st:
        _raise(st, f"cannot export FFTW wisdom to {path}")


def load(path: PathLike, comm=None) -> "Simulation":
    """A Simulation restored from a checkpoint written by save() (or by C, Fortran); with an
    mpi4py communicator, distributed over its ranks (any number: collective)."""
    out = ctypes.c_void_p()
    msg = ctypes.create_string_buffer(512)
    lib = _c() if comm is None else _cm()
    if comm is None:
        st = lib.gfmd_sim_load(os.fsencode(path), ctypes.byref(out), msg, len(msg))
    else:
        st = lib.gfmd_sim_load_mpi_f(comm.py2f(), os.fsencode(path), ctypes.byref(out), msg, len(msg))
    if st:
        _raise(st, msg.value.decode(errors="replace"))
    return Simulation._adopt(out, lib)



# ------------------------------------------------------------------ measured topographies
_FORMATS = {"auto": 0, "matrix": 1, "xyz": 2, "gsf": 3, "sdf_text": 4, "sdf_binary": 5, "npy": 6, "x3p": 7}
_FILLS = {"nearest": _VALUES["GFMD_FILL_NEAREST"], "laplace": _VALUES["GFMD_FILL_LAPLACE"]}
_TRENDS = {"height": _VALUES["GFMD_DETREND_HEIGHT"], "plane": _VALUES["GFMD_DETREND_PLANE"],
           "curvature": _VALUES["GFMD_DETREND_CURVATURE"]}
_WINDOWS = {None: _VALUES["GFMD_WINDOW_NONE"], "none": _VALUES["GFMD_WINDOW_NONE"],
            "hann": _VALUES["GFMD_WINDOW_HANN"]}


def _choice(table, value, what):
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        return int(value)
    try:
        return table[value if value is None else str(value).lower()]
    except KeyError:
        raise BadEnum(_VALUES["GFMD_ERR_BAD_ENUM"], f"unknown {what} {value!r}; one of {sorted(k for k in table if k)}") from None


class Topography:
    """A measured (or given) topography: heights (ny, nx), NaN at missing points, on a rectangle
    physical_size = (lx, ly), lengths in `unit` metres (the unit asked for when reading).

    Read one with read_topography(); make one from an array with Topography.from_heights()."""

    def __init__(self, handle, unit: float) -> None:
        self._h = handle
        self._lib = _c()
        self.unit = float(unit)

    @classmethod
    def from_heights(cls, h: npt.ArrayLike, physical_size: Tuple[float, float], unit: float = 1.0) -> "Topography":
        """A topography of the array h (ny, nx), NaN at missing points, on physical_size (lx, ly)."""
        a = np.ascontiguousarray(np.asarray(h, dtype=np.float64))
        if a.ndim != 2:
            raise InvalidArgument(_VALUES["GFMD_ERR_INVALID_ARG"], f"heights must be 2-D (ny, nx), got shape {a.shape}")
        out = ctypes.c_void_p()
        st = _c().gfmd_topo_from_heights(a.shape[1], a.shape[0], float(physical_size[0]), float(physical_size[1]),
                                         a.ctypes.data_as(_library.c_double_p), ctypes.byref(out))
        if st:
            _raise(st, f"cannot make a topography of a {a.shape} array on {physical_size}")
        return cls(out, unit)

    def close(self) -> None:
        if getattr(self, "_h", None) and self._h.value:
            self._lib.gfmd_topo_destroy(ctypes.byref(self._h))

    def __del__(self):
        self.close()

    def __enter__(self) -> "Topography":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _check(self, st: int, what: str) -> None:
        if st:
            msg = ctypes.create_string_buffer(512)
            self._lib.gfmd_topo_last_error(self._h, msg, len(msg))
            _raise(st, f"{what}: {msg.value.decode(errors='replace')}")

    def _grid(self):
        nx, ny, lx, ly = ctypes.c_int64(), ctypes.c_int64(), ctypes.c_double(), ctypes.c_double()
        self._check(self._lib.gfmd_topo_get_grid(self._h, ctypes.byref(nx), ctypes.byref(ny), ctypes.byref(lx),
                                                 ctypes.byref(ly)), "get_grid")
        return nx.value, ny.value, lx.value, ly.value

    def _info(self):
        f, u, m = ctypes.c_int32(), ctypes.c_int32(), ctypes.c_int64()
        self._check(self._lib.gfmd_topo_get_info(self._h, ctypes.byref(f), ctypes.byref(u), ctypes.byref(m)), "get_info")
        return f.value, bool(u.value), m.value

    @property
    def shape(self) -> Tuple[int, int]:
        """(ny, nx)."""
        nx, ny, _, _ = self._grid()
        return (ny, nx)

    @property
    def physical_size(self) -> Tuple[float, float]:
        """(lx, ly) in `unit`; settable (a file without units has a spacing of 1)."""
        return self._grid()[2:]

    @physical_size.setter
    def physical_size(self, size: Tuple[float, float]) -> None:
        self._check(self._lib.gfmd_topo_set_physical_size(self._h, float(size[0]), float(size[1])), "physical_size")

    @property
    def format(self) -> str:
        """The file format read ("auto": made from an array)."""
        f = self._info()[0]
        return next(k for k, v in _FORMATS.items() if v == f)

    @property
    def has_units(self) -> bool:
        """Whether the file gave physical units (converted to `unit`) or its numbers were kept."""
        return self._info()[1]

    @property
    def missing(self) -> int:
        """The number of missing (NaN) points."""
        return self._info()[2]

    @property
    def heights(self) -> FloatArray:
        """A copy of the heights (ny, nx), NaN at missing points."""
        out = np.empty(self.shape)
        self._check(self._lib.gfmd_topo_get_heights(self._h, out.ctypes.data_as(_library.c_double_p)), "heights")
        return out

    def fill_missing(self, method: Union[str, int] = "laplace") -> None:
        """Fill the missing points: "laplace" (harmonic interpolation) or "nearest"."""
        self._check(self._lib.gfmd_topo_fill_missing(self._h, _choice(_FILLS, method, "fill method")), "fill_missing")

    def detrend(self, mode: Union[str, int] = "plane") -> None:
        """Subtract the least-squares "height" (mean), "plane" or "curvature" (second order)."""
        self._check(self._lib.gfmd_topo_detrend(self._h, _choice(_TRENDS, mode, "detrend mode")), "detrend")

    def resample(self, shape: Tuple[int, int]) -> None:
        """Resample onto shape (ny, nx) by Keys' cubic convolution, the samples' extent kept."""
        self._check(self._lib.gfmd_topo_resample(self._h, int(shape[1]), int(shape[0])), "resample")

    def psd(self, nbins: int = 32, window: Optional[str] = None) -> Tuple[FloatArray, FloatArray, IntArray]:
        """(q, C, count): the radially averaged PSD over nbins log-spaced bins of |q| (gfmd.h's
        gfmd_topo_psd: sum count C (2 pi)^2 / (lx ly) = the variance); window None or "hann"."""
        q, c, n = np.empty(int(nbins)), np.empty(int(nbins)), np.empty(int(nbins), dtype=np.int64)
        self._check(self._lib.gfmd_topo_psd(self._h, _choice(_WINDOWS, window, "window"), int(nbins),
                                            q.ctypes.data_as(_library.c_double_p), c.ctypes.data_as(_library.c_double_p),
                                            n.ctypes.data_as(_library.c_int64_p)), "psd")
        return q, c, n

    def profile_psd(self, window: Optional[str] = None) -> Tuple[FloatArray, FloatArray]:
        """(q, C1): the profiles' PSD along x, averaged over the rows (gfmd_topo_profile_psd)."""
        m = self.shape[1] // 2 + 1
        q, c, n = np.empty(m), np.empty(m), ctypes.c_int64()
        self._check(self._lib.gfmd_topo_profile_psd(self._h, _choice(_WINDOWS, window, "window"), m,
                                                    q.ctypes.data_as(_library.c_double_p),
                                                    c.ctypes.data_as(_library.c_double_p), ctypes.byref(n)), "profile_psd")
        return q, c

    def moments(self, window: Optional[str] = None) -> Tuple[float, float, float]:
        """(rms height, rms slope, rms curvature) from every mode of the spectrum."""
        h, s, k = ctypes.c_double(), ctypes.c_double(), ctypes.c_double()
        self._check(self._lib.gfmd_topo_moments(self._h, _choice(_WINDOWS, window, "window"), ctypes.byref(h),
                                                ctypes.byref(s), ctypes.byref(k)), "moments")
        return h.value, s.value, k.value

    def persson_contact_area(self, sigma0: float, kind: int = HALFSPACE, width: float = 0.0, nu: float = 0.0,
                             e_star: float = 1.0, window: Optional[str] = None) -> float:
        """Persson's A/A0 at sigma0 from this topography's spectrum, on a body (gfmd.h)."""
        a, v = ctypes.c_double(), ctypes.c_double()
        self._check(self._lib.gfmd_topo_persson_contact_area(self._h, _choice(_WINDOWS, window, "window"), int(kind),
                                                             float(width), float(nu), float(e_star), float(sigma0),
                                                             ctypes.byref(a), ctypes.byref(v)), "persson_contact_area")
        return a.value

    def persson_mean_gap(self, sigma0: float, kind: int = HALFSPACE, width: float = 0.0, nu: float = 0.0,
                         e_star: float = 1.0, window: Optional[str] = None, gamma: float = 0.45) -> float:
        """Persson's mean gap at sigma0 > 0 from this topography's spectrum, on a body (Yang &
        Persson 2008; gamma their elastic-energy factor; gfmd_topo_persson_mean_gap)."""
        u = ctypes.c_double()
        self._check(self._lib.gfmd_topo_persson_mean_gap(self._h, _choice(_WINDOWS, window, "window"), int(kind),
                                                         float(width), float(nu), float(e_star), float(sigma0),
                                                         float(gamma), ctypes.byref(u)), "persson_mean_gap")
        return u.value


def x3p_supported() -> bool:
    """Whether this build of the library reads x3p files (built with libzip and libxml2)."""
    return bool(_c().gfmd_topo_format_supported(_FORMATS["x3p"]))


def read_topography(path: PathLike, unit: float = 1.0, format: Union[str, int] = "auto") -> Topography:
    """Read a topography file (text matrix, x y z, .gsf, .sdf text or binary, .npy; detected from
    the content), lengths converted to `unit` metres (1e-6: micrometres) where the file has units."""
    out = ctypes.c_void_p()
    msg = ctypes.create_string_buffer(512)
    st = _c().gfmd_topo_read(os.fsencode(path), _choice(_FORMATS, format, "format"), float(unit), ctypes.byref(out),
                             msg, len(msg))
    if st:
        _raise(st, msg.value.decode(errors="replace"))
    return Topography(out, unit)

# ------------------------------------------------------------------ the simulation
class Simulation:
    """One GFMD simulation (owns one C handle): nx x ny points on a periodic lx x ly cell.

    threads (0 = the library's default) and planner (ESTIMATE, MEASURE, PATIENT) are fixed before
    the first FFT plan.  Free it with close() or a with-block; garbage collection frees it too."""

    def __init__(self, nx: int, ny: int, lx: float, ly: float, threads: int = 0, planner: Optional[int] = None,
                 comm=None) -> None:
        self._h = ctypes.c_void_p()
        plan = MEASURE if planner is None else int(planner)
        if comm is None:
            self._lib = _c()
            st = self._lib.gfmd_sim_create_ex(int(nx), int(ny), float(lx), float(ly), int(threads), plan,
                                              ctypes.byref(self._h))
        else:  # an mpi4py communicator: the grid distributed over its ranks (libgfmd_mpi)
            self._lib = _cm()
            st = self._lib.gfmd_sim_create_mpi_f(comm.py2f(), int(nx), int(ny), float(lx), float(ly), plan,
                                                 ctypes.byref(self._h))
        if st:
            _raise(st, f"cannot create a {nx} x {ny} simulation on {lx} x {ly}")
        self._shape = (int(ny), int(nx))
        self._distributed = comm is not None
        if comm is not None and threads:
            self.set_threads(threads)

    @classmethod
    def from_topography(cls, topo: "Topography", threads: int = 0, planner: Optional[int] = None,
                        boundary: Optional[int] = None) -> "Simulation":
        """A simulation whose grid, cell and substrate are the topography's (its missing points
        filled first: StateError otherwise).  boundary: PERIODIC (the default) or FREE, the scan
        as the whole region of a half-space (a measured, non-periodic scan; see set_boundary)."""
        if topo.missing:
            raise StateError(_VALUES["GFMD_ERR_STATE"],
                             f"{topo.missing} missing points: call fill_missing() on the topography first")
        ny, nx = topo.shape
        lx, ly = topo.physical_size
        sim = cls(nx, ny, lx, ly, threads=threads, planner=planner)
        if boundary is not None:
            sim.set_boundary(boundary)
        sim.set_heights(topo.heights)
        return sim

    @classmethod
    def _adopt(cls, handle, lib=None):
        self = cls.__new__(cls)
        self._h = handle
        self._lib = lib if lib is not None else _c()
        self._distributed = lib is not None and lib is _mpi_lib
        nx, ny = ctypes.c_int64(), ctypes.c_int64()
        self._lib.gfmd_get_grid(handle, ctypes.byref(nx), ctypes.byref(ny), None, None)
        self._shape = (ny.value, nx.value)
        return self

    # lifetime
    def close(self) -> None:
        """Free the C handle (idempotent); the object is unusable afterwards."""
        if getattr(self, "_h", None) and self._h.value:
            self._lib.gfmd_sim_destroy(ctypes.byref(self._h))

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown: nothing left to report to
            pass

    def __enter__(self) -> "Simulation":
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def _handle(self):
        if not self._h.value:
            raise StateError(_VALUES["GFMD_ERR_STATE"], "this Simulation was closed")
        return self._h

    def _call(self, name, *args):
        st = getattr(self._lib, name)(self._handle(), *args)
        if st:
            _raise(st, self.last_error())
        return st

    def last_error(self) -> str:
        """The library's message of the last failed call on this handle."""
        need = ctypes.c_int64()
        self._lib.gfmd_last_error_length(self._handle(), ctypes.byref(need))
        buf = ctypes.create_string_buffer(max(int(need.value), 1))
        self._lib.gfmd_last_error(self._handle(), buf, len(buf))
        return buf.value.decode(errors="replace")

    def clone(self) -> "Simulation":
        """An independent copy in the same state."""
        out = ctypes.c_void_p()
        self._call("gfmd_sim_clone", ctypes.byref(out))
        return Simulation._adopt(out, self._lib)

    def save(self, path: PathLike) -> None:
        """Write the complete state to a checkpoint file (gfmd.load reads it back)."""
        self._call("gfmd_sim_save", os.fsencode(path))

    @property
    def shape(self) -> Tuple[int, int]:
        """(ny, nx), the shape of every field."""
        return self._shape

    @property
    def grid(self) -> Tuple[int, int, float, float]:
        """(nx, ny, lx, ly)."""
        nx, ny, lx, ly = ctypes.c_int64(), ctypes.c_int64(), ctypes.c_double(), ctypes.c_double()
        self._call("gfmd_get_grid", ctypes.byref(nx), ctypes.byref(ny), ctypes.byref(lx), ctypes.byref(ly))
        return nx.value, ny.value, lx.value, ly.value

    # the body and the substrate
    def set_modulus(self, e_star: float) -> None:
        """The contact modulus E* (> 0)."""
        self._call("gfmd_set_modulus", float(e_star))

    def set_green(self, kind: int, width: float = 0.0) -> None:
        """The body: HALFSPACE, LAYER_FLUID (a layer of this width on a fluid foundation) or LAYER_BONDED."""
        self._call("gfmd_set_green", int(kind), float(width))

    def set_boundary(self, boundary: int) -> None:
        """PERIODIC (the default: the grid is a periodic cell) or FREE: the grid is the whole region
        of a half-space whose surface beyond it carries no load (zero padding to 2nx x 2ny); the
        load sigma0 is then the total force sigma0 lx ly, the fields and A/A0 the region's.  Keeps
        the parameters and the substrate, puts the body flat at rest (gfmd_set_boundary)."""
        self._call("gfmd_set_boundary", int(boundary))

    @property
    def boundary(self) -> int:
        """PERIODIC or FREE."""
        k = ctypes.c_int32()
        self._call("gfmd_get_boundary", ctypes.byref(k))
        return k.value

    def set_poisson(self, nu: float) -> None:
        """Poisson's ratio (the bonded layer needs it)."""
        self._call("gfmd_set_poisson", float(nu))

    def _field_in(self, h: npt.ArrayLike, what: str = "heights") -> FloatArray:
        """h as the (ny, nx) C-contiguous float64 array the library reads: h itself if it is one
        (no copy), else one copy made by numpy (any array-like: lists, other dtypes, strides,
        Fortran order, read-only arrays, memoryviews)."""
        try:
            a = np.asarray(h, dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise InvalidArgument(_VALUES["GFMD_ERR_INVALID_ARG"], f"{what}: not convertible to float64: {e}") from None
        if a.shape != self._shape:
            raise InvalidArgument(_VALUES["GFMD_ERR_INVALID_ARG"],
                                  f"{what} must have shape {self._shape} (ny, nx), got {a.shape}")
        return np.ascontiguousarray(a)

    def set_heights(self, h: npt.ArrayLike) -> None:
        """The substrate from any (ny, nx) array-like (a C-contiguous float64 array is read in place,
        anything else converted once)."""
        a = self._field_in(h)
        self._call("gfmd_set_heights", a.ctypes.data_as(_library.c_double_p))

    def generate_selfaffine(self, hurst: float, lambda_r: float, lambda_s: float, rms_gradient: float, seed: int,
                            distribution: Optional[int] = None) -> None:
        """A self-affine substrate (the seed paper's Sec. 2.3); the same seed gives C's surface."""
        self._call("gfmd_generate_selfaffine", float(hurst), float(lambda_r), float(lambda_s), float(rms_gradient),
                   int(seed) & 0xFFFFFFFFFFFFFFFF, UNIFORM if distribution is None else int(distribution))

    # load and dynamics
    def set_pressure(self, sigma0: float) -> None:
        """Pressure control: the external pressure sigma0 >= 0 pushes the body onto the substrate."""
        self._call("gfmd_set_pressure", float(sigma0))

    def set_adhesion(self, gamma0: float, rho: float) -> None:
        """Adhesion: the stress (gamma0/rho) exp(-gap/rho) pulls the body down (gamma0 = 0: none)."""
        self._call("gfmd_set_adhesion", float(gamma0), float(rho))

    def set_mean_displacement(self, d: float) -> None:
        """Displacement control: mean(z) = d; the mean pressure follows (set_pressure returns)."""
        self._call("gfmd_set_mean_displacement", float(d))

    @property
    def mean_displacement(self) -> float:
        """mean(z), under either control."""
        return self._scalar("gfmd_get_mean_displacement")

    @property
    def mean_pressure(self) -> float:
        """The mean pressure the body carries: sigma0, or the balancing one under displacement control."""
        return self._scalar("gfmd_get_mean_pressure")

    def set_timestep(self, dt: float) -> None:
        """The time step of the dynamics (0: automatic)."""
        self._call("gfmd_set_timestep", float(dt))

    def set_damping(self, eta: float) -> None:
        """The damping of the damped dynamics (0: automatic)."""
        self._call("gfmd_set_damping", float(eta))

    def set_solver(self, solver: int) -> None:
        """The relaxation method: AUTO (the default), FIRE, CG, MASS_WEIGHTED_FIRE, APPROACH_THEN_FIRE, NEWTON, VERLET."""
        self._call("gfmd_set_solver", int(solver))

    @property
    def solver(self) -> int:
        """The solver that steps now (GFMD_SOLVER_AUTO resolved)."""
        k = ctypes.c_int32()
        self._call("gfmd_get_solver", ctypes.byref(k))
        return k.value

    def set_threads(self, n: int) -> None:
        """Threads of this handle's loops and transforms (0: the default)."""
        self._call("gfmd_set_threads", int(n))

    @property
    def threads(self) -> int:
        """The threads this handle uses."""
        t = ctypes.c_int32()
        self._call("gfmd_get_threads", ctypes.byref(t))
        return t.value

    def set_fft_planner(self, planner: int) -> None:
        """FFTW planner rigour: ESTIMATE, MEASURE (the default) or PATIENT; replans."""
        self._call("gfmd_set_fft_planner", int(planner))

    @property
    def dynamics(self) -> Tuple[float, float]:
        """(dt, eta) in effect."""
        dt, eta = ctypes.c_double(), ctypes.c_double()
        self._call("gfmd_get_dynamics", ctypes.byref(dt), ctypes.byref(eta))
        return dt.value, eta.value

    def step(self, n: int = 1) -> None:
        """Exactly n steps of the solver, continuing its trajectory."""
        self._call("gfmd_step", int(n))

    def restart_solver(self) -> None:
        """Restart the solver's adaptive state (as a change of the energy landscape does)."""
        self._call("gfmd_restart_solver")

    def reset(self) -> None:
        """The body flat at the highest substrate point, at rest (the load kept)."""
        self._call("gfmd_reset")

    def relax_multilevel(self, levels: int, tol: float = 0.0, max_steps: int = 10_000_000) -> Tuple[int, int]:
        """relax() from a start made on grids coarsened levels - 1 times by 2 (gfmd_relax_multilevel);
        returns (steps on this grid, steps on the coarser grids).  Raises like relax()."""
        taken, below = ctypes.c_int64(), ctypes.c_int64()
        st = self._lib.gfmd_relax_multilevel(self._handle(), float(tol), int(max_steps), int(levels),
                                         ctypes.byref(taken), ctypes.byref(below))
        if st == _VALUES["GFMD_ERR_NOT_CONVERGED"]:
            raise NotConverged(st, f"not converged after {taken.value} steps: residual {self.residual:.3e}",
                               steps=taken.value)
        if st != 0:
            _raise(st, self.last_error())
        return taken.value, below.value

    def relax(self, tol: float = 0.0, max_steps: int = 10_000_000, progress: Union[bool, int] = False) -> int:
        """Step until the residual is <= tol (0: DEFAULT_TOL); returns the steps taken.

        Raises NotConverged (with .steps) when max_steps are reached: the progress is kept and
        another relax() continues the same trajectory.  progress=True (or a number of steps) prints
        steps, residual and A/A0 every 1000 (or that many) steps; relaxing in chunks costs no extra
        steps, since every call continues where the last one stopped."""
        every = 1000 if progress is True else int(progress or 0)
        total, target = 0, int(max_steps)
        while True:
            chunk = min(every, target - total) if every > 0 else target - total
            taken = ctypes.c_int64()
            st = self._lib.gfmd_relax(self._handle(), float(tol), int(chunk), ctypes.byref(taken))
            total += taken.value
            if st == 0:
                if every > 0:
                    print(f"gfmd: converged after {total} steps, residual {self.residual:.3e}, "
                          f"A/A0 {self.contact_area:.5f}", file=sys.stderr)
                return total
            if st != _VALUES["GFMD_ERR_NOT_CONVERGED"] or total >= target:
                message = self.last_error()
                if st == _VALUES["GFMD_ERR_NOT_CONVERGED"]:
                    raise NotConverged(st, f"not converged after {total} steps: residual {self.residual:.3e}",
                                       steps=total)
                _raise(st, message)
            if every > 0:
                print(f"gfmd: {total} steps, residual {self.residual:.3e}, A/A0 {self.contact_area:.5f}",
                      file=sys.stderr)

    # observables
    def _scalar(self, name):
        x = ctypes.c_double()
        self._call(name, ctypes.byref(x))
        return x.value

    @property
    def contact_area(self) -> float:
        """A/A0, the fraction of points in contact."""
        return self._scalar("gfmd_get_contact_area")

    @property
    def mean_gap(self) -> float:
        """The mean gap <z - h> over the cell."""
        return self._scalar("gfmd_get_mean_gap")

    @property
    def residual(self) -> float:
        """The relative residual of the constrained problem at the current configuration."""
        return self._scalar("gfmd_get_residual")

    def _energies(self):
        el, ad = ctypes.c_double(), ctypes.c_double()
        self._call("gfmd_get_energies", ctypes.byref(el), ctypes.byref(ad))
        return el.value, ad.value

    @property
    def elastic_energy(self) -> float:
        """U_el = (A/2) sum_q |u(q)|^2 / G(q) of the whole cell."""
        return self._energies()[0]

    @property
    def adhesive_energy(self) -> float:
        """U_ad = integral of gamma0 exp(-gap/rho) dA over the cell (energy gained, >= 0)."""
        return self._energies()[1]

    @staticmethod
    def _out_buffer(out, shape):
        """out, checked to be a writeable C-contiguous float64 array of shape, or a fresh one."""
        if out is None:
            return np.empty(shape)
        if not (isinstance(out, np.ndarray) and out.dtype == np.float64 and out.shape == shape
                and out.flags.c_contiguous and out.flags.writeable):
            raise InvalidArgument(_VALUES["GFMD_ERR_INVALID_ARG"],
                                  f"out must be a writeable C-contiguous float64 array of shape {shape}, got "
                                  f"{getattr(out, 'dtype', type(out).__name__)} {getattr(out, 'shape', '')}")
        return out

    def _field_out(self, name: str, out: Optional[FloatArray] = None) -> FloatArray:
        out = self._out_buffer(out, self._shape)
        self._call(name, out.ctypes.data_as(_library.c_double_p))
        return out

    def gap(self, out: Optional[FloatArray] = None) -> FloatArray:
        """The (ny, nx) array of z - h: a fresh one, or written into out (and returned)."""
        return self._field_out("gfmd_get_gap", out)

    def surface(self, out: Optional[FloatArray] = None) -> FloatArray:
        """The (ny, nx) array of the elastic surface z (fresh, or into out)."""
        return self._field_out("gfmd_get_surface", out)

    def pressure(self, out: Optional[FloatArray] = None) -> FloatArray:
        """The (ny, nx) array of the pressure the substrate exerts, contact minus adhesion (fresh, or into out)."""
        return self._field_out("gfmd_get_pressure", out)

    def heights(self, out: Optional[FloatArray] = None) -> FloatArray:
        """The (ny, nx) array of the substrate heights (fresh, or into out)."""
        return self._field_out("gfmd_get_heights", out)

    def persson_variance(self) -> float:
        """Persson's full-contact pressure variance V = sum_q |h(q)|^2 / G(q)^2 for this substrate and body."""
        return self._scalar("gfmd_persson_variance")

    def persson_contact_area(self, sigma0: float) -> float:
        """Persson's A/A0 for this substrate and body at the load sigma0."""
        a = ctypes.c_double()
        self._call("gfmd_persson_contact_area", float(sigma0), ctypes.byref(a))
        return a.value

    # a grid distributed over MPI ranks (comm=...): this rank's slab of rows, the names of gfmd_mpi.h
    @property
    def ranks(self) -> int:
        """The number of MPI ranks the grid is distributed over (1 for a serial Simulation)."""
        if not self._distributed:
            return 1
        r = ctypes.c_int32()
        self._call("gfmd_mpi_get_ranks", ctypes.byref(r))
        return r.value

    def _mpi(self):
        if not self._distributed:
            raise StateError(_VALUES["GFMD_ERR_STATE"], "the local-slab calls need a Simulation made with comm=")

    @property
    def local_grid(self) -> Tuple[int, int]:
        """(local_ny, y0): this rank owns rows y0 .. y0 + local_ny - 1 (a distributed Simulation)."""
        self._mpi()
        rows, y0 = ctypes.c_int64(), ctypes.c_int64()
        self._call("gfmd_mpi_get_local_grid", ctypes.byref(rows), ctypes.byref(y0))
        return rows.value, y0.value

    def _local_shape(self):
        return (self.local_grid[0], self._shape[1])

    def set_local_heights(self, h: npt.ArrayLike) -> None:
        """This rank's rows of the substrate, any (local_ny, nx) array-like.  Collective."""
        self._mpi()
        shape = self._local_shape()
        a = np.ascontiguousarray(np.asarray(h, dtype=np.float64))
        if a.shape != shape:
            raise InvalidArgument(_VALUES["GFMD_ERR_INVALID_ARG"], f"local heights must have shape {shape}, got {a.shape}")
        self._call("gfmd_mpi_set_local_heights", a.ctypes.data_as(_library.c_double_p), shape[1])

    def _local_out(self, name, out):
        self._mpi()
        out = self._out_buffer(out, self._local_shape())
        self._call(name, out.ctypes.data_as(_library.c_double_p), self._shape[1])
        return out

    def local_heights(self, out: Optional[FloatArray] = None) -> FloatArray:
        """This rank's rows of the substrate, (local_ny, nx)."""
        return self._local_out("gfmd_mpi_get_local_heights", out)

    def local_surface(self, out: Optional[FloatArray] = None) -> FloatArray:
        """This rank's rows of the surface z, (local_ny, nx)."""
        return self._local_out("gfmd_mpi_get_local_surface", out)

    def local_gap(self, out: Optional[FloatArray] = None) -> FloatArray:
        """This rank's rows of the gap z - h, (local_ny, nx)."""
        return self._local_out("gfmd_mpi_get_local_gap", out)

    def local_pressure(self, out: Optional[FloatArray] = None) -> FloatArray:
        """This rank's rows of the pressure, (local_ny, nx)."""
        return self._local_out("gfmd_mpi_get_local_pressure", out)

    def local_contact_patches(self, connectivity: int = 4) -> Tuple[IntArray, int]:
        """(this rank's rows of the patch labels (local_ny, nx), the number of patches).  Collective."""
        self._mpi()
        labels = np.empty(self._local_shape(), dtype=np.int64)
        n = ctypes.c_int64()
        self._call("gfmd_mpi_get_local_contact_patches", int(connectivity),
                   labels.ctypes.data_as(_library.c_int64_p), self._shape[1], ctypes.byref(n))
        return labels, n.value

    # plasticity
    def set_hardness(self, hardness: float) -> None:
        """Perfect plasticity at the hardness H (math.inf: none, the default; docs/model.md)."""
        self._call("gfmd_set_hardness", float(hardness))

    @property
    def hardness(self) -> float:
        """The hardness H of plasticity (math.inf: none)."""
        return self._scalar("gfmd_get_hardness")

    @property
    def plasticity(self) -> Tuple[float, float]:
        """(plastic area fraction, plastic volume): the points yielding now, the volume lost."""
        a, v = ctypes.c_double(), ctypes.c_double()
        self._call("gfmd_get_plasticity", ctypes.byref(a), ctypes.byref(v))
        return a.value, v.value

    # how the contact is made
    def contact_patches(self, connectivity: int = 4) -> ContactPatches:
        """The contact patches, a ContactPatches (labels, count, per-patch areas, perimeters, ...)."""
        return ContactPatches(self, connectivity)

    def pressure_histogram(self, bins: int = 50, range: Optional[Tuple[float, float]] = None
                           ) -> Tuple[FloatArray, FloatArray, FloatArray]:
        """(edges, fraction, mean): the contact points binned by pressure in `bins` equal bins over
        `range` (default: the contact's own); fraction sums to A/A0, (fraction * mean).sum() is the
        mean contact pressure (sigma0 at equilibrium without adhesion); fraction / width is P(p)."""
        r = np.array([0.0, 0.0] if range is None else [float(range[0]), float(range[1])])
        fraction, mean = np.empty(int(bins)), np.empty(int(bins))
        self._call("gfmd_get_pressure_histogram", int(bins), r.ctypes.data_as(_library.c_double_p),
                   fraction.ctypes.data_as(_library.c_double_p), mean.ctypes.data_as(_library.c_double_p))
        return np.linspace(r[0], r[1], int(bins) + 1), fraction, mean

    def persson_pressure_distribution(self, p: npt.ArrayLike, sigma0: float) -> FloatArray:
        """Persson's P(p) at the load sigma0 at the pressures p (an array of the same shape)."""
        q = np.ascontiguousarray(p, dtype=np.float64)
        out = np.empty_like(q)
        self._call("gfmd_persson_pressure_distribution", float(sigma0), q.size, q.ctypes.data_as(_library.c_double_p),
                   out.ctypes.data_as(_library.c_double_p))
        return out

    def persson_load(self, rel_area: float) -> float:
        """The load at which Persson's A/A0 is rel_area (the inverse of persson_contact_area)."""
        s = ctypes.c_double()
        self._call("gfmd_persson_load", float(rel_area), ctypes.byref(s))
        return s.value
