#!/usr/bin/env python3
"""same_numbers.py A B [TOL] - A and B say the same: the same text between
their numbers, and each number within TOL (default 1e-9) of the other,
absolutely or relative to it. For generated files whose last digits may
move with the machine's libm (glibc picks its sin/cos by CPU features).
Prints the largest difference; exit 0 when the same, 1 when not."""
import re
import sys

NUM = re.compile(r'[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|nan|inf', re.I)


def split(path):
    text = open(path, encoding='utf-8').read()
    return NUM.split(text), [float(x) for x in NUM.findall(text)]


def main():
    a, b = sys.argv[1], sys.argv[2]
    tol = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-9
    (ta, na), (tb, nb) = split(a), split(b)
    if ta != tb or len(na) != len(nb):
        print(f'{b}: the text differs from {a}')
        return 1
    worst = 0.0
    for x, y in zip(na, nb):
        if x == y or (x != x and y != y):
            continue
        d = abs(x - y)
        if d > tol and d > tol * max(abs(x), abs(y)):
            print(f'{b}: {y!r} against {x!r}')
            return 1
        worst = max(worst, d)
    print(f'{b}: {len(na)} numbers, largest difference {worst:.1e}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
