#!/usr/bin/env python3
"""Compare two runs of gfmd_paper body by body, from their logs (the program's whole output).

    python3 apps/paper/compare_runs.py NEW.log OLD.log [--label NAME] [--check FILE]

Prints the per-body table of docs/paper/full.md (steps and seconds of each body and of its first
load in NEW, the steps and seconds of the same body in OLD), then the ratios the text quotes: the
seconds NEW/OLD of the bodies that took the same steps in both runs (within 1 %: another
trajectory is another amount of work), and the whole runs' seconds and steps.  With --check FILE
it also fails (exit 1) unless every line of the table appears in FILE verbatim: docs/paper/full.md
quotes this program's output, and the test paper_compare_runs keeps it so.

Standard library only: it reads the lines `half-space ..., W = w/lambda_s = W` (each body's
heading) and `this body: S steps, T s; its first load ... S1 steps, T1 s` of gfmd_paper's output,
and the last line `total T s, S steps ...`.
"""
import argparse
import re
import sys

BODY = re.compile(r'^(half-space|layer on a fluid foundation)( with adhesion)?, W = w/lambda_s = (\S+)')
THIS = re.compile(r'^this body: (\d+) steps, ([\d.]+) s; its first load \([^)]*\) (\d+) steps, ([\d.]+) s')
TOTAL = re.compile(r'^total ([\d.]+) s, (\d+) steps')


def parse(path):
    """[(body, steps, seconds, first steps, first seconds)] in the log's order, and (seconds, steps)."""
    rows, name, total = [], None, None
    with open(path, encoding='utf-8') as log:
        for line in log:
            m = BODY.match(line)
            if m:
                width = m.group(3)
                name = ('half-space' if width == '0' else 'W = ' + width) + (' (adhesive)' if m.group(2) else '')
                continue
            m = THIS.match(line)
            if m:
                if name is None:
                    sys.exit(f'compare_runs: {path}: a body\'s line before any body\'s heading')
                rows.append((name,) + m.groups())
                name = None
                continue
            m = TOTAL.match(line)
            if m:
                total = (float(m.group(1)), int(m.group(2)))
    if not rows or total is None:
        sys.exit(f'compare_runs: {path}: no bodies or no total line: not a gfmd_paper log')
    return rows, total


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('new')
    ap.add_argument('old')
    ap.add_argument('--label', default='other', help='the old run\'s name in the table\'s head')
    ap.add_argument('--check', metavar='FILE', help='fail unless FILE holds the table verbatim')
    a = ap.parse_args()
    new, new_total = parse(a.new)
    old_rows, old_total = parse(a.old)
    old = {r[0]: r for r in old_rows}
    missing = [r[0] for r in new if r[0] not in old]
    if missing:
        sys.exit('compare_runs: bodies missing from the old run: ' + ', '.join(missing))

    table = [f'| body | steps | seconds | first load: steps | seconds | {a.label} run: steps | seconds |',
             '|---|---|---|---|---|---|---|']
    table += [f'| {r[0]} | {r[1]} | {r[2]} | {r[3]} | {r[4]} | {old[r[0]][1]} | {old[r[0]][2]} |' for r in new]
    print('\n'.join(table))
    print()

    same = [(r[0], float(r[2]) / float(old[r[0]][2])) for r in new
            if abs(int(r[1]) - int(old[r[0]][1])) <= 0.01 * int(old[r[0]][1])]
    other = [r[0] for r in new if r[0] not in dict(same)]
    if same:
        low, high = min(x for _, x in same), max(x for _, x in same)
        print(f'bodies with the same steps in both runs (within 1 %): {len(same)} of {len(new)}, '
              f'their seconds {low:.2f}-{high:.2f}x the old run\'s')
        for body, ratio in same:
            print(f'  {body}: {ratio:.2f}x')
    print('other steps: ' + (', '.join(other) if other else 'none'))
    print(f'whole run: {new_total[0]} s against {old_total[0]} s ({new_total[0] / old_total[0]:.3f}x), '
          f'{new_total[1]} steps against {old_total[1]} ({new_total[1] / old_total[1]:.3f}x)')

    if a.check:
        with open(a.check, encoding='utf-8') as f:
            lines = set(f.read().splitlines())
        absent = [line for line in table if line not in lines]
        if absent:
            print(f'compare_runs: {a.check} does not hold this table; first line missing:\n{absent[0]}')
            return 1
        print(f'compare_runs: {a.check} holds the table')
    return 0


if __name__ == '__main__':
    sys.exit(main())
