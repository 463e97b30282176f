#!/usr/bin/env python3
"""Step halving for wgcont: the bifurcations of a run at N and of one at 2N
with the tolerances halved, matched by type, period, contact, threshold and
extreme (the nearest value), as a Markdown table.
usage: compare_cont.py A-bifurcations.csv B-bifurcations.csv LABEL_A LABEL_B"""
import csv
import sys


def rows(path):
    with open(path) as f:
        r = csv.reader(f)
        head = next(r)
        param = head[1]
        idx = {k: i for i, k in enumerate(head)}
        out = []
        for row in r:
            key = (row[0], row[idx['period']], row[idx['contact']], row[idx['threshold']],
                   row[idx['extreme']])
            out.append((key, float(row[1]), int(row[idx['branch']]), float(row[idx['mu_re']]),
                        float(row[idx['bracket']])))
        return param, out


def detail(key):
    t, per, contact, thr, ext = key
    if t == 'grazing':
        c = 'b' if contact == 'mesh' else 'b_j'
        return f'P{per}, {ext} {contact} = {thr[0]}{c}'
    return f'P{per}'


def main():
    a_path, b_path, la, lb = sys.argv[1:5]
    param, a = rows(a_path)
    _, b = rows(b_path)
    print(f'| type | orbit | {param} ({la}) | {param} ({lb}) | difference | bracket ({la}) |')
    print('|---|---|---|---|---|---|')
    worst, seen, unmatched = 0.0, set(), []
    for key, v, br, mu, brk in a:
        if (key, round(v, 7)) in seen:  # a body's axes grazing together, or a point met twice
            continue
        seen.add((key, round(v, 7)))
        cand = [w for k, w, *_ in b if k == key]
        if not cand:
            unmatched.append(f'{key[0]} {detail(key)} at {v:.9f}')
            continue
        w = min(cand, key=lambda x: abs(x - v))
        d = abs(w - v)
        if d > 1e-4:
            unmatched.append(f'{key[0]} {detail(key)} at {v:.9f} (nearest at {lb}: {w:.9f})')
            continue
        worst = max(worst, d)
        print(f'| {key[0]} | {detail(key)} | {v:.9f} | {w:.9f} | {d:.1e} | {brk:.1e} |')
    print(f'\nLargest difference of a matched event: {worst:.1e} '
          f'({len(seen) - len(unmatched)} events).')
    if unmatched:
        print(f'\nNot found within 1e-4 in the {lb} run: ' + '; '.join(unmatched) + '.')


if __name__ == '__main__':
    main()
