#!/bin/sh
# test_sweep_bench.sh SRC BUILD - tests/bench/sweep_bench.sh (issue 13's
# sweep figures) works as docs/performance.md tells: on a coarse grid
# (--quick) it prints a row of figures for the study, the study with
# --pair 1, the study with its figures and the map, and finds the CSVs
# the same (and the figures drawn); and given a wgsweep
# whose --pair 1 output differs by one byte, it says so and exits 1.
src=$1 build=$2
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
export WG_SCENE_PATH="$src/scenes"
bash "$src/tests/bench/sweep_bench.sh" "$build" 1 map --quick >"$tmp/out" 2>&1
rc=$?
cat "$tmp/out"
[ $rc -eq 0 ] || { echo "FAIL: sweep_bench.sh exit $rc"; exit 1; }
num='[0-9][0-9]*\.[0-9]*'
grep -q "^| study, 150 points (default --pair) | $num ($num) | $num s | 2.0 s | \*\*$num×\*\* |$" "$tmp/out" ||
    { echo "FAIL: no study row"; exit 1; }
grep -q "^| study, --pair 1 (one chain at a time a thread) | $num ($num) | $num s |" "$tmp/out" ||
    { echo "FAIL: no --pair 1 row"; exit 1; }
grep -q "^| study with its figures (3 PNGs) | $num ($num) | $num s | 2.0 s | \*\*$num×\*\* |$" "$tmp/out" ||
    { echo "FAIL: no row for the study with its figures"; exit 1; }
grep -q "^| map, 5 rows, 125 points | $num ($num) | $num s | 60 s |" "$tmp/out" ||
    { echo "FAIL: no map row"; exit 1; }
grep -q "^figures: 3 PNGs from 1 run(s) with figures$" "$tmp/out" || { echo "FAIL: no figures"; exit 1; }
grep -q "same bytes$" "$tmp/out" || { echo "FAIL: the CSVs not found the same"; exit 1; }
# A wgsweep whose one-chain-at-a-time CSV differs: the script must say so.
mkdir -p "$tmp/fake/clients"
cat >"$tmp/fake/clients/wgsweep" <<EOS
#!/bin/sh
"$build/clients/wgsweep" "\$@" || exit \$?
case " \$* " in *" --pair 1 "*) ;; *) exit 0 ;; esac
while [ \$# -gt 1 ] && [ "\$1" != --out ]; do shift; done
echo >>"\$2.csv"
EOS
chmod +x "$tmp/fake/clients/wgsweep"
bash "$src/tests/bench/sweep_bench.sh" "$tmp/fake" 1 --quick >"$tmp/out2" 2>&1
rc=$?
[ $rc -eq 1 ] && grep -q "): differ: study.1.csv pair1.1.csv$" "$tmp/out2" ||
    { cat "$tmp/out2"; echo "FAIL: a differing CSV not reported (exit $rc)"; exit 1; }
echo "ok: the figures' rows, and a differing CSV reported"
