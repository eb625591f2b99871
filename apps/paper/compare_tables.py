#!/usr/bin/env python3
"""Compare a run of gfmd_paper with a tracked reference table of the same study.

    python3 apps/paper/compare_tables.py OUT_DIR REFERENCE.csv [--n N]
    python3 apps/paper/compare_tables.py OUT_DIR REFERENCE.csv --write

OUT_DIR is the study's output folder (its fig3_area.csv and fits.csv); REFERENCE.csv holds, for
every body without adhesion and every load, sigma0, A/A0 and the mean gap, then the fits (rows
`fit,<quantity>,<value>`).  The run matches when every body and load is there, the loads are the
same to 1e-9 relative (they are set from Persson's theory of the same substrate: the same
arithmetic), and

- A/A0 within 2/N + 1e-4 A/A0 of it: the solvers stop at a force residual, not at one state, and
  two solvers' equilibria may differ by a contact point or two out of N = n^2 (measured: the
  quick study by FIRE alone against the default's);
- the mean gap within 1e-3 relative (the same residual's effect on the surface, far below the
  gap's own variation from load to load, 10-30 %);
- the fits (kappa, the c(W) and theta exponents) within 1e-2 absolute: least squares over those
  areas and energies; the adhesive bodies enter only through theta, whose energies come from a
  non-convex problem whose minima may differ by a solver's path.

--write makes REFERENCE.csv from OUT_DIR (after a change that moves the physics on purpose; say
why in the commit).  Standard library only.  Exit 0 on a match, 1 otherwise, 2 on bad input.
"""
import argparse
import csv
import sys
from pathlib import Path

FITS = ('kappa_halfspace', 'c_exponent', 'theta_exponent')


def read_run(out):
    rows = {}
    try:
        with open(out / 'fig3_area.csv', newline='', encoding='utf-8') as f:
            for r in csv.DictReader(f):
                rows.setdefault((r['body'], r['W']), []).append(
                    (float(r['sigma0']), float(r['rel_area']), float(r['mean_gap'])))
        with open(out / 'fits.csv', newline='', encoding='utf-8') as f:
            fits = {r['quantity']: float(r['value']) for r in csv.DictReader(f)}
    except (OSError, KeyError, ValueError) as e:
        sys.exit(f'compare_tables: {out}: not a gfmd_paper output folder ({e})')
    return rows, fits


def write(path, rows, fits):
    with open(path, 'w', newline='', encoding='utf-8') as f:
        w = csv.writer(f, lineterminator='\n')
        w.writerow(['body', 'W', 'sigma0', 'rel_area', 'mean_gap'])
        for (body, width), loads in rows.items():
            for s, a, g in loads:
                w.writerow([body, width, f'{s:.10e}', f'{a:.10e}', f'{g:.10e}'])
        for q in FITS:
            w.writerow(['fit', q, f'{fits[q]:.6f}', '', ''])


def read_reference(path):
    rows, fits = {}, {}
    try:
        with open(path, newline='', encoding='utf-8') as f:
            for r in csv.DictReader(f):
                if r['body'] == 'fit':
                    fits[r['W']] = float(r['sigma0'])
                else:
                    rows.setdefault((r['body'], r['W']), []).append(
                        (float(r['sigma0']), float(r['rel_area']), float(r['mean_gap'])))
    except (OSError, KeyError, ValueError) as e:
        sys.exit(f'compare_tables: {path}: not a reference table ({e})')
    if not rows or set(fits) != set(FITS):
        sys.exit(f'compare_tables: {path}: no bodies or not the fits {", ".join(FITS)}')
    return rows, fits


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('out', type=Path)
    ap.add_argument('reference', type=Path)
    ap.add_argument('--n', type=int, default=128, help='the grid side of the run (default 128, --quick)')
    ap.add_argument('--write', action='store_true', help='write REFERENCE.csv from OUT instead')
    a = ap.parse_args()
    if a.n < 1:
        ap.error('--n must be >= 1')
    rows, fits = read_run(a.out)
    if a.write:
        write(a.reference, rows, fits)
        print(f'compare_tables: wrote {a.reference}: {sum(map(len, rows.values()))} loads, {len(FITS)} fits')
        return 0
    ref_rows, ref_fits = read_reference(a.reference)
    points = a.n * a.n
    bad, checked = [], 0
    for key, ref in ref_rows.items():
        got = rows.get(key)
        if got is None or len(got) != len(ref):
            bad.append(f'{key[0]} W = {key[1]}: {len(got or [])} loads, the reference {len(ref)}')
            continue
        for (s, ar, gr), (s0, a0, g0) in zip(got, ref):
            checked += 1
            where = f'{key[0]} W = {key[1]} sigma0 = {s0:.4e}'
            if abs(s - s0) > 1e-9 * abs(s0):
                bad.append(f'{where}: the load is {s:.10e}')
            area_tol = 2.0 / points + 1e-4 * a0
            if abs(ar - a0) > area_tol:
                bad.append(f'{where}: A/A0 {ar:.6e} against {a0:.6e} (tolerance {area_tol:.1e})')
            if abs(gr - g0) > 1e-3 * abs(g0):
                bad.append(f'{where}: mean gap {gr:.6e} against {g0:.6e}')
    for key in rows.keys() - ref_rows.keys():
        bad.append(f'{key[0]} W = {key[1]}: not in the reference')
    for q in FITS:
        checked += 1
        if q not in fits or abs(fits[q] - ref_fits[q]) > 1e-2:
            bad.append(f'fit {q}: {fits.get(q)} against {ref_fits[q]}')
    for line in bad:
        print('compare_tables: ' + line)
    print(f'compare_tables: {checked} loads and fits compared, {len(bad)} mismatches')
    return 0 if not bad else 1


if __name__ == '__main__':
    sys.exit(main())
