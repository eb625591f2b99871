"""The Python side of the Python-over-MPI check (tests/mpi/python_mpi.cmake), under mpiexec: the
problem of tests/mpi/mpi_surface.c through gfmd.Simulation(..., comm=MPI.COMM_WORLD), its local
slabs gathered with mpi4py and written in the same layout, for a byte-for-byte comparison."""
import sys

import numpy as np
from mpi4py import MPI

import gfmd

NX, NY = 48, 40
comm = MPI.COMM_WORLD
with gfmd.Simulation(NX, NY, float(NX), float(NY), planner=gfmd.ESTIMATE, comm=comm) as s:
    s.generate_selfaffine(0.8, 16.0, 4.0, 1.0, seed=7)
    s.set_green(gfmd.LAYER_FLUID, 4.0)
    s.set_pressure(0.03)
    s.step(60)
    rows, y0 = s.local_grid
    z = s.local_surface()
    labels, patches = s.local_contact_patches(8)
    assert z.shape == (rows, NX) and labels.shape == (rows, NX) and s.ranks == comm.size
    area = s.contact_area
    parts = comm.gather((y0, z, labels), root=0)
    try:
        s.surface()  # whole-grid: refused on several ranks, as in C
        assert comm.size == 1
    except gfmd.StateError:
        assert comm.size > 1
if comm.rank == 0:
    parts.sort(key=lambda p: p[0])
    surface = np.concatenate([p[1] for p in parts])
    lab = np.concatenate([p[2] for p in parts])
    with open(sys.argv[1], "wb") as f:
        f.write(surface.astype(np.float64).tobytes())
        f.write(lab.astype(np.int64).tobytes())
        f.write(np.float64(area).tobytes())
        f.write(np.int64(patches).tobytes())
