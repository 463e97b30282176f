#!/usr/bin/env python3
"""Compare two wgsweep points CSVs of the same grid run with different step
sizes (e.g. N = 256 and N = 512 steps per mesh period): per point, is the
classification (regime, period, motion class) the same? Prints Markdown.

usage: compare_steps.py A.csv B.csv [label_a label_b]
"""
import csv
import sys


def label(r):
    if r['regime'] == 'periodic':
        return 'P' + r['period'] if r['period'] != '0' else 'P?'
    return {'quasiperiodic': 'quasi', 'chaotic': 'chaos'}.get(r['regime'], r['regime'])


def load(path):
    rows = list(csv.DictReader(open(path)))
    gcol = [k for k in rows[0].keys()][0]
    group = gcol if gcol != 'dir' else None
    param = [k for k in rows[0].keys()][3 if group else 2]
    out = {}
    for r in rows:
        key = (r[group] if group else '', r['dir'], r[param])
        out[key] = r
    return out, group, param


def main():
    a, group, param = load(sys.argv[1])
    b, _, _ = load(sys.argv[2])
    la = sys.argv[3] if len(sys.argv) > 3 else 'A'
    lb = sys.argv[4] if len(sys.argv) > 4 else 'B'
    keys = sorted(set(a) & set(b), key=lambda k: (k[0], k[1], float(k[2])))
    print(f'| {group or ""} | dir | points | same regime+period | same motion class | '
          f'median / max abs diff of min x_n (both periodic, same period) |')
    print('|---|---|---|---|---|---|')
    diffs = []
    for g in sorted({k[0] for k in keys}):
        for d in ('up', 'down'):
            ks = [k for k in keys if k[0] == g and k[1] == d]
            if not ks:
                continue
            same = sum(label(a[k]) == label(b[k]) for k in ks)
            mot = sum(a[k]['motion'] == b[k]['motion'] for k in ks)
            dv = sorted(abs(float(a[k]['min_xn']) - float(b[k]['min_xn'])) for k in ks
                        if label(a[k]) == label(b[k]) and a[k]['regime'] == 'periodic') or [0]
            print(f'| {g} | {d} | {len(ks)} | {same} | {mot} | '
                  f'{dv[len(dv) // 2]:.1e} / {dv[-1]:.1e} |')
            diffs += [(k, label(a[k]), label(b[k])) for k in ks if label(a[k]) != label(b[k])]
    print()
    print(f'Points whose classification differs ({la} vs {lb}):')
    print()
    if not diffs:
        print('none')
    for k, x, y in diffs:
        print(f'- {group}={k[0]} {k[1]} {param}={k[2]}: {x} vs {y}')


if __name__ == '__main__':
    main()
