#!/usr/bin/env python3
"""A points CSV whose classification is the step-halving check's: each row's
regime, period and motion replaced by its check2n_regime, check2n_period and
check2n_motion (written by `wgsweep --verify-steps`), so that
`wgsweep --table-from` gives the transitions table of the 2N analysis.

usage: use_2n.py table3.csv > table3-2N-points.csv
"""
import csv
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
if not rows or 'check2n_regime' not in rows[0]:
    sys.exit('use_2n.py: %s has no check2n_* columns (run wgsweep with --verify-steps)' % sys.argv[1])
out = csv.DictWriter(sys.stdout, fieldnames=list(rows[0].keys()), lineterminator='\n')
out.writeheader()
for r in rows:
    if r['check2n_regime'] == '':
        sys.exit('use_2n.py: row %s was not checked' % r['index'])
    for k in ('regime', 'period', 'motion'):
        r[k] = r['check2n_' + k]
    out.writerow(r)
