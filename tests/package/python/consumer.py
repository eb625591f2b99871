"""A user's script on the installed package: PYTHONPATH=<prefix>/share/gfmd/python, no GFMD_LIBRARY,
no LD_LIBRARY_PATH; the package finds <prefix>/lib/libgfmd.so by itself."""
import gfmd

with gfmd.Simulation(32, 32, 32.0, 32.0) as s:
    s.generate_selfaffine(0.8, 16.0, 4.0, 1.0, seed=1)
    s.set_pressure(0.05)
    steps = s.relax()
    assert 0.0 < s.contact_area < 1.0
    print(f"python consumer: gfmd {gfmd.version()}, A/A0 = {s.contact_area:.4f} after {steps} steps")
