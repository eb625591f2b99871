"""Finding and loading libgfmd, and the C prototypes (ctypes) of the functions the package calls."""
import ctypes
import ctypes.util
import os
from pathlib import Path

_HERE = Path(__file__).resolve().parent


def _candidates(explicit=None, name="gfmd", env="GFMD_LIBRARY"):
    """Where to look for lib<name>, in order: an explicit path, the variable env, the package's own
    folder (pip), the source tree's build folder, the folder of an installed package, then the
    system loader."""
    out = [str(explicit)] if explicit else []
    if os.environ.get(env):
        out.append(os.environ[env])
    # installed by pip: the library beside the package's modules
    out.append(str(_HERE / f"lib{name}.so.0"))
    # python/gfmd in the source tree -> build/; <prefix>/share/gfmd/python/gfmd installed -> <prefix>/lib
    for folder in (_HERE.parents[1] / "build", _HERE.parents[3] / "lib", _HERE.parents[3] / "lib64"):
        out.append(str(folder / f"lib{name}.so"))
    found = ctypes.util.find_library(name)
    out.append(found if found else f"lib{name}.so.0")
    return out


def load_mpi():
    """libgfmd_mpi (for handles distributed over MPI ranks), loaded once; OSError as load()."""
    return load(None, _candidates(None, "gfmd_mpi", "GFMD_MPI_LIBRARY"), mpi=True)


def load(explicit=None, candidates=None, mpi=False):
    """The loaded library; OSError naming every place tried if none works."""
    tried = []
    for path in (candidates if candidates is not None else _candidates(explicit)):
        if os.sep in path and not os.path.exists(path):
            tried.append(f"{path} (no such file)")
            continue
        try:
            lib = ctypes.CDLL(path)
        except OSError as e:
            tried.append(f"{path} ({e})")
            continue
        _declare(lib, mpi)
        return lib
    name = "libgfmd_mpi" if mpi else "libgfmd"
    hint = ("configure with -DGFMD_BUILD_MPI=ON and build it, or set GFMD_MPI_LIBRARY" if mpi else
            "build it (cmake --build build) or set GFMD_LIBRARY to the path of libgfmd.so")
    raise OSError(f"gfmd: cannot load {name}; tried:\n  " + "\n  ".join(tried) + "\n" + hint[0].upper() + hint[1:])


c_double_p = ctypes.POINTER(ctypes.c_double)
c_int64_p = ctypes.POINTER(ctypes.c_int64)
c_int32_p = ctypes.POINTER(ctypes.c_int32)
_sim = ctypes.c_void_p
_sim_p = ctypes.POINTER(ctypes.c_void_p)
_i32, _i64, _u64, _dbl, _str = ctypes.c_int32, ctypes.c_int64, ctypes.c_uint64, ctypes.c_double, ctypes.c_char_p

# name: (argument types); every function returns an int32_t status unless listed in _RESTYPE
_PROTOTYPES = {
    "gfmd_last_error": (_sim, ctypes.c_char_p, _i64),
    "gfmd_last_error_length": (_sim, c_int64_p),
    "gfmd_sim_create_ex": (_i64, _i64, _dbl, _dbl, _i32, _i32, _sim_p),
    "gfmd_sim_clone": (_sim, _sim_p),
    "gfmd_sim_destroy": (_sim_p,),
    "gfmd_sim_save": (_sim, _str),
    "gfmd_sim_load": (_str, _sim_p, ctypes.c_char_p, _i64),
    "gfmd_get_grid": (_sim, c_int64_p, c_int64_p, c_double_p, c_double_p),
    "gfmd_set_modulus": (_sim, _dbl),
    "gfmd_set_green": (_sim, _i32, _dbl),
    "gfmd_set_poisson": (_sim, _dbl),
    "gfmd_green_factor": (_i32, _dbl, _dbl, c_double_p),
    "gfmd_set_heights": (_sim, c_double_p),
    "gfmd_get_heights": (_sim, c_double_p),
    "gfmd_generate_selfaffine": (_sim, _dbl, _dbl, _dbl, _dbl, _u64, _i32),
    "gfmd_set_pressure": (_sim, _dbl),
    "gfmd_set_adhesion": (_sim, _dbl, _dbl),
    "gfmd_set_mean_displacement": (_sim, _dbl),
    "gfmd_get_mean_displacement": (_sim, c_double_p),
    "gfmd_get_mean_pressure": (_sim, c_double_p),
    "gfmd_set_timestep": (_sim, _dbl),
    "gfmd_set_damping": (_sim, _dbl),
    "gfmd_set_solver": (_sim, _i32),
    "gfmd_set_threads": (_sim, _i32),
    "gfmd_get_threads": (_sim, c_int32_p),
    "gfmd_get_solver": (_sim, c_int32_p),
    "gfmd_set_boundary": (_sim, _i32),
    "gfmd_get_boundary": (_sim, c_int32_p),
    "gfmd_set_fft_planner": (_sim, _i32),
    "gfmd_import_wisdom": (_str,),
    "gfmd_export_wisdom": (_str,),
    "gfmd_get_dynamics": (_sim, c_double_p, c_double_p),
    "gfmd_step": (_sim, _i64),
    "gfmd_restart_solver": (_sim,),
    "gfmd_relax": (_sim, _dbl, _i64, c_int64_p),
    "gfmd_relax_multilevel": (_sim, _dbl, _i64, _i32, c_int64_p, c_int64_p),
    "gfmd_get_residual": (_sim, c_double_p),
    "gfmd_reset": (_sim,),
    "gfmd_get_contact_area": (_sim, c_double_p),
    "gfmd_get_mean_gap": (_sim, c_double_p),
    "gfmd_get_energies": (_sim, c_double_p, c_double_p),
    "gfmd_get_gap": (_sim, c_double_p),
    "gfmd_get_surface": (_sim, c_double_p),
    "gfmd_get_pressure": (_sim, c_double_p),
    "gfmd_persson_variance": (_sim, c_double_p),
    "gfmd_persson_contact_area": (_sim, _dbl, c_double_p),
    "gfmd_persson_load": (_sim, _dbl, c_double_p),
    "gfmd_least_squares": (_i64, _i64, c_double_p, c_double_p, c_double_p, c_double_p),
    "gfmd_set_hardness": (_sim, _dbl),
    "gfmd_get_hardness": (_sim, c_double_p),
    "gfmd_get_plasticity": (_sim, c_double_p, c_double_p),
    "gfmd_label_patches": (_i64, _i64, c_int32_p, _i32, _i32, c_int64_p, c_int64_p),
    "gfmd_get_contact_patches": (_sim, _i32, c_int64_p, c_int64_p),
    "gfmd_get_patch_property": (_sim, _i32, _i32, _i64, c_double_p, c_int64_p),
    "gfmd_get_pressure_histogram": (_sim, _i64, c_double_p, c_double_p, c_double_p),
    "gfmd_persson_pressure_distribution": (_sim, _dbl, _i64, c_double_p, c_double_p),
    "gfmd_topo_read": (_str, _i32, _dbl, _sim_p, ctypes.c_char_p, _i64),
    "gfmd_topo_from_heights": (_i64, _i64, _dbl, _dbl, c_double_p, _sim_p),
    "gfmd_topo_destroy": (_sim_p,),
    "gfmd_topo_last_error": (_sim, ctypes.c_char_p, _i64),
    "gfmd_topo_get_grid": (_sim, c_int64_p, c_int64_p, c_double_p, c_double_p),
    "gfmd_topo_get_info": (_sim, c_int32_p, c_int32_p, c_int64_p),
    "gfmd_topo_set_physical_size": (_sim, _dbl, _dbl),
    "gfmd_topo_get_heights": (_sim, c_double_p),
    "gfmd_topo_fill_missing": (_sim, _i32),
    "gfmd_topo_detrend": (_sim, _i32),
    "gfmd_topo_resample": (_sim, _i64, _i64),
    "gfmd_topo_psd": (_sim, _i32, _i64, c_double_p, c_double_p, c_int64_p),
    "gfmd_topo_profile_psd": (_sim, _i32, _i64, c_double_p, c_double_p, c_int64_p),
    "gfmd_topo_moments": (_sim, _i32, c_double_p, c_double_p, c_double_p),
    "gfmd_topo_persson_contact_area": (_sim, _i32, _i32, _dbl, _dbl, _dbl, _dbl, c_double_p, c_double_p),
    "gfmd_topo_format_supported": (_i32,),
    "gfmd_topo_persson_mean_gap": (_sim, _i32, _i32, _dbl, _dbl, _dbl, _dbl, _dbl, c_double_p),
    "gfmd_version": (),
    "gfmd_status_string": (_i32,),
}
# libgfmd_mpi's own calls (gfmd_mpi.h), the communicator as its Fortran handle (MPI_Fint)
_MPI_PROTOTYPES = {
    "gfmd_sim_create_mpi_f": (_i32, _i64, _i64, _dbl, _dbl, _i32, _sim_p),
    "gfmd_sim_load_mpi_f": (_i32, _str, _sim_p, ctypes.c_char_p, _i64),
    "gfmd_mpi_get_local_grid": (_sim, c_int64_p, c_int64_p),
    "gfmd_mpi_get_ranks": (_sim, c_int32_p),
    "gfmd_mpi_set_local_heights": (_sim, c_double_p, _i64),
    "gfmd_mpi_get_local_heights": (_sim, c_double_p, _i64),
    "gfmd_mpi_get_local_surface": (_sim, c_double_p, _i64),
    "gfmd_mpi_get_local_gap": (_sim, c_double_p, _i64),
    "gfmd_mpi_get_local_pressure": (_sim, c_double_p, _i64),
    "gfmd_mpi_get_local_contact_patches": (_sim, _i32, c_int64_p, _i64, c_int64_p),
}
_RESTYPE = {"gfmd_sim_destroy": None, "gfmd_topo_destroy": None, "gfmd_version": ctypes.c_char_p, "gfmd_status_string": ctypes.c_char_p}


def _declare(lib, mpi=False):
    table = dict(_PROTOTYPES, **_MPI_PROTOTYPES) if mpi else _PROTOTYPES
    for name, args in table.items():
        fn = getattr(lib, name)
        fn.argtypes = list(args)
        fn.restype = _RESTYPE.get(name, _i32)
