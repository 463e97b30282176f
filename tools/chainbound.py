#!/usr/bin/env python3
"""The dependency-chain bound of one RK4 step of the table3 kernels: the
critical path through their dataflow, as lib/kern_tmpl.h writes it (sse2
layout: the six bearings in three 2-wide vectors; the full path, and the
torsional path with only s and s' moving). Every value carries the time it
is ready; an operation's result is ready at max(inputs) + its latency;
steps are chained, each step's output the next one's input, until the time
per step is steady. Prints the time per step and the operations on the
critical path, which tests/bench/bench_gsl.c turns into nanoseconds with
latencies it measures (CHAIN_FULL_*, CHAIN_TORS_*).

usage: tools/chainbound.py [ADD MUL OTHER [HSUM]]   latencies (cycles or ns)
       of an add/sub, a multiply, and a min/max/logic/shuffle; default 3 3 1
       (Zen 2/3); this VM (Zen 5) measured 0.58 0.88 0.58 ns. HSUM (default
       0): what a sum across the bearing lanes (hsumb) costs beyond the
       sse2 layout's, e.g. the cross-lane extracts of a wider layout
       (bench_pair's link, in the same unit, minus its 6 adds); the output
       counts how many of them the critical path passes."""
import sys


class Val:
    __slots__ = ('t', 'path')

    def __init__(self, t, path):
        self.t, self.path = t, path


LAT = {}
CONST = Val(0.0, ())  # loop invariants and table entries: ready at once
KINDS = ('add', 'mul', 'other', 'hsum')


def op(kind, *xs):
    src = max(xs, key=lambda x: x.t)
    return Val(src.t + LAT[kind], src.path + (kind,))


def add(a, b):
    return op('add', a, b)


def mul(a, b):
    return op('mul', a, b)


def hsumb(p):  # (p0 + p1 + p2) lane-wise, then t[0] + t[1]; 'hsum' marks it
    t = add(add(p[0], p[1]), p[2])
    return op('hsum', add(t, op('other', t)))


def dz(x):  # x - max(min(x, c), -c)
    return add(x, op('other', op('other', x, CONST), CONST))


def weight(j, x):  # the RK4 weights 1, 2, 2, 1: GCC -O2 folds x * 1 to x, x * 2 to x + x
    return x if j in (0, 3) else add(x, x)


def full_step(q0, v0, s0, vs0, locked):
    nb = 3
    X0 = add(hsumb([mul(CONST, q0[b]) for b in range(nb)]), s0)
    V0 = add(hsumb([mul(CONST, v0[b]) for b in range(nb)]), vs0)
    X, V, vs, q, v = X0, V0, vs0, list(q0), list(v0)
    sq, sv, ssv, sas = [CONST] * nb, [CONST] * nb, CONST, CONST
    for j in range(4):
        xn, dxn = add(X, CONST), add(V, CONST)  # mesh_force
        g = add(mul(CONST, xn), CONST) if locked else dz(xn)
        F = add(mul(CONST, dxn), mul(CONST, g))
        Fs = op('other', F)  # vsplat
        acc, pb = [], []
        for b in range(nb):  # stage_full
            gb = add(mul(CONST, q[b]), CONST) if locked else dz(q[b])
            base = add(op('other', mul(CONST, v[b])), mul(CONST, gb))
            pb.append(add(mul(CONST, v[b]), mul(CONST, gb)))
            acc.append(add(base, mul(CONST, Fs)))
        dsvs = mul(CONST, vs)
        P = add(add(CONST, dsvs), hsumb(pb))
        as6 = add(add(CONST, F), dsvs)
        cacc = add(P, mul(CONST, F))
        for b in range(nb):
            sq[b] = add(sq[b], weight(j, v[b]))
            sv[b] = add(sv[b], weight(j, acc[b]))
        ssv, sas = add(ssv, weight(j, vs)), add(sas, weight(j, as6))
        if j == 3:
            break
        V, X = add(V0, mul(CONST, cacc)), add(X0, mul(CONST, V))
        for b in range(nb):
            q[b], v[b] = add(q0[b], mul(CONST, v[b])), add(v0[b], mul(CONST, acc[b]))
        vs = add(vs0, mul(CONST, as6))
    return ([add(q0[b], mul(CONST, sq[b])) for b in range(nb)],
            [add(v0[b], mul(CONST, sv[b])) for b in range(nb)],
            add(s0, mul(CONST, ssv)), add(vs0, mul(CONST, sas)))


def tors_step(s, v, locked):
    def rhs(s, v):
        xn, dxn = add(s, CONST), add(v, CONST)
        g = add(mul(CONST, xn), CONST) if locked else dz(xn)
        F = add(mul(CONST, dxn), mul(CONST, g))
        return v, add(add(CONST, F), mul(CONST, v))
    a1, b1 = rhs(s, v)
    a2, b2 = rhs(add(s, mul(CONST, a1)), add(v, mul(CONST, b1)))
    a3, b3 = rhs(add(s, mul(CONST, a2)), add(v, mul(CONST, b2)))
    a4, b4 = rhs(add(s, mul(CONST, a3)), add(v, mul(CONST, b3)))
    return (add(s, mul(CONST, add(add(a1, a4), weight(1, add(a2, a3))))),
            add(v, mul(CONST, add(add(b1, b4), weight(1, add(b2, b3))))))


def bound(lat, torsional, locked, steps=40):
    LAT.clear()
    LAT.update(lat)
    z = Val(0.0, ())
    st = (z, z) if torsional else ([z] * 3, [z] * 3, z, z)
    ends = []
    for _ in range(steps):
        st = tors_step(*st, locked) if torsional else full_step(*st, locked)
        flat = list(st) if torsional else st[0] + st[1] + [st[2], st[3]]
        ends.append(max(flat, key=lambda x: x.t))
    per = (ends[-1].t - ends[-11].t) / 10
    prev = ends[-2].path
    if ends[-1].path[:len(prev)] != prev:
        sys.exit('chainbound: the critical path is not periodic')
    tail = ends[-1].path[len(prev):]
    return per, {k: tail.count(k) for k in KINDS}


def latencies(args):
    """ADD MUL OTHER [HSUM] from the command line (tools/args.sh's rule:
    --help prints the usage, anything else wrong one refusal, exit 2)."""
    if args[:1] in (['--help'], ['-h']):
        print(__doc__)
        sys.exit(0)

    def refuse(what):
        sys.stderr.write('chainbound.py: %s\n(try chainbound.py --help)\n' % what)
        sys.exit(2)
    if len(args) not in (0, 3, 4):
        refuse('ADD MUL OTHER [HSUM] or nothing, got %d arguments' % len(args))
    v = []
    for name, s in zip(('ADD', 'MUL', 'OTHER', 'HSUM'), args):
        try:
            x = float(s)
        except ValueError:
            x = float('nan')
        if not (0 <= x < 1e6) or (name != 'HSUM' and x == 0):
            refuse("%s '%s': a latency, a number > 0 (HSUM >= 0)" % (name, s))
        v.append(x)
    return (v + [0.0])[:4] if v else [3.0, 3.0, 1.0, 0.0]


def main():
    a, m, o, hs = latencies(sys.argv[1:])
    lat = {'add': a, 'mul': m, 'other': o, 'hsum': hs}
    print('latencies: add/sub %g, mul %g, min/max/logic/shuffle %g; hsumb beyond that %g'
          % (a, m, o, hs))
    for torsional in (False, True):
        for locked in (False, True):
            per, comp = bound(lat, torsional, locked)
            print('%-9s %-6s %7.2f per step; critical path: %d add/sub, %d mul, %d other; '
                  'through hsumb %d times'
                  % ('torsional' if torsional else 'full', 'locked' if locked else 'plain',
                     per, comp['add'], comp['mul'], comp['other'], comp['hsum']))


if __name__ == '__main__':
    main()
