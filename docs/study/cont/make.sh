#!/bin/sh
# make.sh BUILD - every file of this directory from its command: the table3
# branches at xi_p = 0.08, 0.10, 0.12 (N = 256, with a 241-point up/down
# sweep under the figure), the same at 2N with the tolerances halved and
# (0.08, 0.12) at 4N, the zooms and the torsional scene, steps.md from
# compare_cont.py for each pair, and table3-exact.md. The branch CSVs
# (~0.3 MB each) are removed. Run from this directory:
#   sh make.sh ../../../build/release
set -eu
B=$(cd "$1" && pwd)
export WG_SCENE_PATH="${WG_SCENE_PATH:-$(cd ../../../scenes && pwd)}"
export PATH="$B/clients:$PATH" # table3-exact.md quotes its command as run
cont="wgcont --quiet"
for x in 0.08 0.10 0.12; do
    $cont --scene table3 --set xi_p=$x --from 0.1 --to 2.5 --sweep-points 241 \
        --out table3-xi_p-$x-N256
    $cont --scene table3 --set xi_p=$x --from 0.1 --to 2.5 --sweep-points 0 \
        --steps-per-period 512 --tol 5e-11 --loc-tol 5e-10 --out table3-xi_p-$x-N512
done
for x in 0.08 0.12; do
    $cont --scene table3 --set xi_p=$x --from 0.1 --to 2.5 --sweep-points 0 \
        --steps-per-period 1024 --tol 2.5e-11 --loc-tol 2.5e-10 --out table3-xi_p-$x-N1024
done
$cont --scene table3 --from 0.64 --to 0.80 --sweep-points 161 --out table3-jump
$cont --scene table3 --from 1.15 --to 1.32 --sweep-points 171 --out table3-doubling
$cont --scene torsional --from 0.6 --to 0.9 --sweep-points 121 --out torsional
rm -f ./*-branch.csv ./*-N512.png ./*-N1024.png   # no sweep under those figures

pair() { # pair XI NA NB HOW
    printf '## xi_p = %s: N = %s against N = %s (%s)\n\n' "$1" "$2" "$3" "$4"
    python3 compare_cont.py "table3-xi_p-$1-N$2-bifurcations.csv" \
        "table3-xi_p-$1-N$3-bifurcations.csv" "N = $2" "N = $3"
    echo
}
{
    for x in 0.08 0.10 0.12; do pair $x 256 512 "tolerances halved"; done
    for x in 0.08 0.12; do pair $x 512 1024 "tolerances halved again"; done
} >steps.md

wgsweep --table-from ../table3.csv \
    --exact table3-xi_p-0.08-N256-bifurcations.csv --exact table3-xi_p-0.10-N256-bifurcations.csv \
    --exact table3-xi_p-0.12-N256-bifurcations.csv --out table3-exact
