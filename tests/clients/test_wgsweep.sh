#!/bin/bash
# wgsweep end to end: outputs exist and parse, threads, paired chains and
# (when given) MPI ranks give byte-identical CSVs to the serial run, Ctrl-C
# leaves partial results readable, --at views, usage errors.
# usage: test_wgsweep.sh WGSWEEP [MPIEXEC]
set -u
sweep=$1
mpiexec=${2:-}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
. "$(dirname "$0")/../wait.sh" # stop
fail=0
check() { if eval "$2"; then echo "$1 ok"; else echo "$1 FAIL"; fail=1; fi; }

common="--from 1.17 --to 1.22 --points 6 --transient 200 --quiet --no-png"
"$sweep" $common --threads 1 --values xi_p=0.08,0.10 --out "$dir/s1" >/dev/null
check "serial run writes csv/md/json" \
  '[ -s "$dir/s1.csv" ] && [ -s "$dir/s1.md" ] && [ -s "$dir/s1.json" ] && [ -s "$dir/s1-poincare.csv" ]'
check "csv has 4 chains x 6 points" '[ $(($(wc -l < "$dir/s1.csv") - 1)) -eq 24 ]'
check "json parses" 'python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert len(d[\"groups\"])==2" "$dir/s1.json"'
check "table finds the doubling at 1.19-1.20" 'grep -q "period doubling | 1.1950 (1.1900-1.2000)" "$dir/s1.md"'

"$sweep" --from 1.17 --to 1.22 --points 3 --transient 100 --threads 1 --values xi_p=0.08,0.10 --out "$dir/w" 2>"$dir/w.err" >/dev/null
check "the last line names every file written" 'grep -q "; wrote $dir/w.csv, $dir/w-poincare.csv, $dir/w.md, $dir/w.json, $dir/w-xi_p-0.08.png, $dir/w-xi_p-0.1.png\$" "$dir/w.err" && [ -s "$dir/w-xi_p-0.1.png" ]'

# The files written by two threads at once: the same bytes (the JSON and
# the Markdown but for the thread count and wall time), listed in order.
"$sweep" --from 1.17 --to 1.22 --points 3 --transient 100 --threads 2 --values xi_p=0.08,0.10 --out "$dir/w2" 2>"$dir/w2.err" >/dev/null
check "two threads write the files: same bytes, listed in order" \
  'grep -q "; wrote $dir/w2.csv, $dir/w2-poincare.csv, $dir/w2.md, $dir/w2.json, $dir/w2-xi_p-0.08.png, $dir/w2-xi_p-0.1.png\$" "$dir/w2.err" &&
   for f in .csv -poincare.csv -xi_p-0.08.png -xi_p-0.1.png; do cmp -s "$dir/w$f" "$dir/w2$f" || exit 1; done &&
   cmp -s <(sed "s/\"wall_s\":[0-9.]*,\"threads\":1,//" "$dir/w.json") <(sed "s/\"wall_s\":[0-9.]*,\"threads\":2,//" "$dir/w2.json") &&
   [ "$(diff "$dir/w.md" "$dir/w2.md" | grep -c "^[<>]")" -eq 4 ]'
# Diverged points (the printed form's modes grow by design: at omega 0.1 and
# 0.2 on table3) are not measurements: their rows hold the value and
# "diverged", nothing else (they read no_impact, impacts 0, min_xn 0, which
# the min x_n line drew as a dip to 0), and --table-from reads them back.
scenes=${WG_SCENE_PATH:-$(dirname "$0")/../../scenes}
sed 's/^model = consistent/model = printed/' "${scenes%%:*}/table3.ini" >"$dir/printed.ini"
"$sweep" --scene "$dir/printed.ini" --from 0.1 --to 0.3 --points 3 --dir up --quiet --no-png \
    --out "$dir/pr" >/dev/null 2>&1
check "diverged points: value and regime only" \
  '[ "$(grep -c "^up,[01],0\.[12],diverged,,,,,,,,,,,,,,,,,,,,,,,,,,,,,\$" "$dir/pr.csv")" -eq 2 ] &&
   grep -q "\"value\":0.1,\"regime\":\"diverged\",\"period\":null" "$dir/pr.json"'
"$sweep" --table-from "$dir/pr.csv" --out "$dir/pr2" >/dev/null 2>&1
check "--table-from reads diverged rows back: the same table" \
  'cmp -s <(sed 1,6d "$dir/pr.md") <(sed 1,6d "$dir/pr2.md")'
# An --out whose directory is missing: refused before the sweep runs.
"$sweep" --from 1.17 --to 1.22 --points 3 --transient 100 --out "$dir/none/w" >"$dir/od.out" 2>"$dir/od.err"
rc=$?
check "--out in a missing directory: exit 2 before any point, the reason said" \
  '[ $rc -eq 2 ] && grep -q "^wgsweep: --out .$dir/none/w.: cannot write in $dir/none: No such file or directory (the directory must exist and be writable)\$" "$dir/od.err" && ! grep -q points "$dir/od.err"'
# A file that cannot be written after the sweep (a directory in its way):
# exit 1, each failed file said, the others written and listed.
mkdir -p "$dir/blk/b.json" "$dir/blk/b-xi_p-0.1.png" "$dir/blk/a-at-omega-1.2-phase.png"
"$sweep" --from 1.17 --to 1.22 --points 3 --transient 100 --values xi_p=0.08,0.10 --out "$dir/blk/b" >/dev/null 2>"$dir/blk.err"
rc=$?
check "a blocked JSON and figure: exit 1, both said, the rest listed" \
  '[ $rc -eq 1 ] && grep -q "^wgsweep: cannot write $dir/blk/b.json: Is a directory; cannot write $dir/blk/b-xi_p-0.1.png: " "$dir/blk.err" && grep -q "; wrote $dir/blk/b.csv, $dir/blk/b-poincare.csv, $dir/blk/b.md, $dir/blk/b-xi_p-0.08.png\$" "$dir/blk.err"'
"$sweep" --at 1.2 --at-periods 100 --out "$dir/blk/a" >"$dir/blka.out" 2>"$dir/blka.err"
rc=$?
check "--at with its phase portrait blocked: exit 1, only what was written listed" \
  '[ $rc -eq 1 ] && grep -q "^files       $dir/blk/a-at-omega-1.2-trace.csv, $dir/blk/a-at-omega-1.2-poincare.png, $dir/blk/a-at-omega-1.2-trace.png\$" "$dir/blka.out" && grep -q "cannot write $dir/blk/a-at-omega-1.2-phase.png" "$dir/blka.err"'
# A period-1 point's Poincare map (its sections agree to ~1e-15) hung
# drawing its axes' ticks.
timeout 60 "$sweep" --at 0.5 --at-periods 200 --out "$dir/p1" >"$dir/p1.out"
rc=$?
check "--at 0.5 (period 1): ends, its Poincare map drawn" '[ $rc -eq 0 ] && grep -q "regime      P1" "$dir/p1.out" && [ -s "$dir/p1-at-omega-0.5-poincare.png" ]'
# its report on a standard output that takes nothing: said, exit 1 (it was 0)
"$sweep" --at 0.5 --at-periods 50 --out "$dir/pf" >/dev/full 2>"$dir/pf.err"
rc=$?
check "--at with stdout /dev/full: exit 1, said once" \
  '[ $rc -eq 1 ] && [ "$(grep -c "writing the standard output failed" "$dir/pf.err")" -eq 1 ]'

"$sweep" $common --threads 2 --values xi_p=0.08,0.10 --out "$dir/s2" >/dev/null
check "threads: identical csv" 'cmp -s "$dir/s1.csv" "$dir/s2.csv" && cmp -s "$dir/s1-poincare.csv" "$dir/s2-poincare.csv"'
"$sweep" $common --threads 1 --pair 1 --values xi_p=0.08,0.10 --out "$dir/p1" >/dev/null
check "--pair 1 (one chain at a time) against the default 8 (the four chains batched, a run a vector lane, with AVX2 or AVX-512): identical csv" \
  'cmp -s "$dir/s1.csv" "$dir/p1.csv" && cmp -s "$dir/s1-poincare.csv" "$dir/p1-poincare.csv"'
"$sweep" $common --threads 1 --pair 2 --values xi_p=0.08,0.10 --out "$dir/p2" >/dev/null
check "--pair 2 (two chains' runs paired): identical csv" \
  'cmp -s "$dir/s1.csv" "$dir/p2.csv" && cmp -s "$dir/s1-poincare.csv" "$dir/p2-poincare.csv"'
check "the JSON and the Markdown record --pair" \
  'grep -q "\"threads\":1,\"pair\":1," "$dir/p1.json" && grep -q "\"threads\":1,\"pair\":8," "$dir/s1.json" && grep -q "on 1 thread, one chain at a time on each thread" "$dir/p1.md" && grep -q "on 1 thread, up to 8 chains at once" "$dir/s1.md"'
"$sweep" --pair 9 --values xi_p=0.08 >/dev/null 2>"$dir/pair.err"
rc=$?
check "--pair 9 refused: exit 2 and what is allowed" '[ $rc -eq 2 ] && grep -q "^wgsweep: --pair: need 1..8, got .9.$" "$dir/pair.err"'

# options that contradict each other or leave the parameter's range:
# refused before any point (exit 2), once, with what is wrong and allowed.
# Each ran before: --to 11 until the chain reached it (exit 1, the files
# marked complete), --values/--map of the swept parameter losing their
# values, --values beside --map dropped, an empty value skipped.
refuse() { # EXPECTED-TEXT ARGS...
  local want=$1 rc
  shift
  "$sweep" "$@" --quiet --out "$dir/refused" >/dev/null 2>"$dir/ref.err"
  rc=$?
  check "refused: $*" '[ $rc -eq 2 ] && [ "$(grep -c "^wgsweep:" "$dir/ref.err")" -eq 1 ] && grep -q -- "$want" "$dir/ref.err" && ! ls "$dir"/refused* >/dev/null 2>&1'
}
refuse "^wgsweep: --to: omega = 11 out of range \[0.01, 10\]" --from 9 --to 11 --points 2
refuse "^wgsweep: --from: b = -1 out of range \[0, 100\]" --param b --from -1 --to 1
refuse "^wgsweep: --at: omega = 11 out of range" --at 11
refuse "^wgsweep: --map omega: the parameter swept (--param omega)" --map omega=0.5:1:2
refuse "^wgsweep: --values omega: the parameter swept" --values omega=1,2
refuse "^wgsweep: --values and --map: give one" --values xi_p=0.1 --map k_a=0.1:0.2:2
refuse "an empty value" --values xi_p=0.1,,0.2
refuse "xi_p = 5 out of range \[0, 2\]" --values xi_p=5
refuse "xi_p = -1 out of range \[0, 2\]" --map xi_p=-1:0.1:2
refuse "M, the rows, need 1..100000" --map xi_p=0.1:0.2:0
refuse "need 1..1e7" --at 1 --at-periods 99999999
refuse "^wgsweep: --step 5: more than the range 0.2" --from 1 --to 1.2 --step 5
# a direction cosine cannot vary alone (a1^2 + a2^2 + a3^2 = 1 broke at every
# point: "chain 0 stopped", exit 1, and a1.csv/.md/.png written with no point)
refuse "^wgsweep: --param 'a1': a direction cosine of the line of action, tied to the other two by a1^2 + a2^2 + a3^2 = 1" --param a1 --from 0.2 --to 0.3 --points 3
refuse "^wgsweep: --values 'a2': a direction cosine .*; set a1, a2 and a3 together (--set or the scene) and vary another parameter" --values a2=0.3
refuse "^wgsweep: --map 'a3': a direction cosine" --map a3=0.8:0.9:2
# tolerances in their ranges (the library's, wg_sweep_opts_check): a floor
# or factor of 1e300 made the period-2 points of 1.0-1.4 period 1, exit 0
refuse "^wgsweep: --tol-floor: need a period tolerance floor (states in b_c) in \[1e-13, 0.0001\], got 1e+300" --from 1 --to 1.4 --points 5 --dir up --tol-floor 1e300
refuse "^wgsweep: --tol-floor: .*\[1e-13, 0.0001\], got 1e-300" --from 1 --to 1.4 --points 5 --tol-floor 1e-300
refuse "^wgsweep: --tol-factor: need a factor on the one-period error in \[1, 1000\], got 1e+300" --from 1 --to 1.4 --points 5 --tol-factor 1e300
refuse "^wgsweep: --lle-tol: need an |LLE| threshold per mesh period in \[0.0001, 0.1\], got 1e+300" --lle-tol 1e300
refuse "^wgsweep: --tol-floor: .*got nan" --at 1.2 --tol-floor nan
check "--help gives the tolerances' ranges" \
  '"$sweep" --help | grep -q "(default 1e-9; 1e-13 to 0.0001: states in b_c" && "$sweep" --help | grep -q "(default 10; 1 to 1000)"'
# the grid is the one asked for, or refused (before: --step won over --points
# silently, 0.07 became 0.0706, equal ends ran the same point three times)
refuse "^wgsweep: --step 0.07: the range 2.4 (--from 0.1 --to 2.5) is 34.29 steps of it, not a whole number; give --step 0.0705882 (35 points) or 0.0685714 (36 points)" --step 0.07
refuse "^wgsweep: --points 5 and --step 0.1: give one" --points 5 --step 0.1
refuse "^wgsweep: --from and --to are both 1: no range to sweep (--at 1 analyses" --from 1 --to 1 --points 3
# a range given downwards, and one point over a range: refused (they ran,
# exit 0, the range swapped to 1 .. 2 and --from alone, over any files of
# the same PREFIX); --dir chooses the direction, --points 1 takes equal ends
refuse "^wgsweep: --from 2 --to 1: --from must be below --to (give the range's lower end as --from; --dir up, down or both chooses which way it is swept)$" --from 2 --to 1 --points 3
refuse "^wgsweep: --from 2.5 --to 0.1: --from must be below --to" --dir down --from 2.5 --to 0.1 --step 0.1
refuse "^wgsweep: --from 1.3788001 --to 1.3788: --from must be below --to" --from 1.3788001 --to 1.3788 --points 3
refuse "^wgsweep: --points 1: a range (--from 1 --to 2) needs 2 points or more, its two ends at least (one point: --from V --to V --points 1, or --at V)$" --from 1 --to 2 --points 1
echo "an earlier run" >"$dir/keep.csv"
"$sweep" --from 1.2 --to 1.1 --points 2 --transient 10 --quiet --no-png --out "$dir/keep" >/dev/null 2>"$dir/keep.err"
rc=$?
check "--from above --to: exit 2, an earlier PREFIX.csv kept, nothing written" \
  '[ $rc -eq 2 ] && [ "$(cat "$dir/keep.csv")" = "an earlier run" ] && [ "$(ls "$dir"/keep* | wc -l)" -eq 2 ]'
"$sweep" --from 1.1 --to 1.1 --points 1 --transient 10 --quiet --no-png --no-json --out "$dir/one" >/dev/null 2>&1
rc=$?
check "one point (--from 1.1 --to 1.1 --points 1): exit 0, a row each way" \
  '[ $rc -eq 0 ] && [ "$(cut -d, -f1-3 "$dir/one.csv" | tail -n +2 | tr "\n" " ")" = "up,0,1.1 down,0,1.1 " ]'
"$sweep" --from 1 --to 1.2 --step 0.0666667 --dir up --no-png --no-json --quiet --out "$dir/st" >/dev/null 2>&1
check "--step as a refusal suggests it (6 digits): 4 points, the last 1.2" '[ "$(tail -1 "$dir/st.csv" | cut -d, -f2,3)" = "3,1.2" ]'

# --out names files: a directory, '', '-' or a name leaving the suffixes
# no room under NAME_MAX are refused first (they wrote runs/.csv, hidden;
# --poincare.csv; or failed after the sweep with "File name too long")
for o in "$dir/" "" "-" "$dir/$(printf 'y%.0s' $(seq 1 230))"; do
  "$sweep" --from 1 --to 1.1 --points 2 --out "$o" >/dev/null 2>"$dir/ref.err"
  rc=$?
  check "--out '${o:0:40}': refused before the sweep" \
    '[ $rc -eq 2 ] && [ "$(grep -c "^wgsweep: --out" "$dir/ref.err")" -eq 1 ] && ! ls "$dir"/.csv "$dir"/y* ./--poincare.csv >/dev/null 2>&1'
done

# digits as given: two --at points 1e-8 apart have their own files and
# say their own omega; a zoomed table shows the grid's digits
"$sweep" --at 1.37880005 --at-periods 20 --no-png --out "$dir/z" >"$dir/z1.txt" &&
"$sweep" --at 1.37880006 --at-periods 20 --no-png --out "$dir/z" >"$dir/z2.txt"
check "--at 1.37880005 and 1.37880006: their own files and omega" \
  '[ -f "$dir/z-at-omega-1.37880005-trace.csv" ] && [ -f "$dir/z-at-omega-1.37880006-trace.csv" ] && grep -q "omega = 1.37880006$" "$dir/z2.txt"'
"$sweep" --from 1.3788 --to 1.3788001 --points 3 --transient 50 --quiet --no-png --out "$dir/zoom"
check "a 5e-8 grid: the table's brackets tell its points apart" \
  'grep -q "1.378800000, 1.378800100\|1.378800000-1.378800100" "$dir/zoom.md"'

if [ -n "$mpiexec" ]; then
  "$mpiexec" --allow-run-as-root --oversubscribe -np 2 "$sweep" ${common/--quiet/} --threads 1 \
      --values xi_p=0.08,0.10 --out "$dir/m2" >/dev/null 2>"$dir/mpi.err"
  check "mpi -np 2: identical csv" 'cmp -s "$dir/s1.csv" "$dir/m2.csv" && cmp -s "$dir/s1-poincare.csv" "$dir/m2-poincare.csv"'
  # one progress bar for the whole run (rank 0's, counting both ranks' points)
  check "mpi -np 2: one progress bar over both ranks" \
    'grep "points, " "$dir/mpi.err" | tail -1 | grep -q " 24/24 points" && ! grep -q "/12 points" "$dir/mpi.err" && [ $(grep -c "100% 24/24 points" "$dir/mpi.err") -eq 1 ]'
  # more ranks than chains: the ranks dealt none wait for the others (they
  # crashed in wg_chains_run with no chains)
  "$mpiexec" --allow-run-as-root --oversubscribe -np 6 "$sweep" $common --threads 1 \
      --values xi_p=0.08,0.10 --out "$dir/m6" >/dev/null 2>"$dir/mpi6.err"
  rc=$?
  check "mpi -np 6 on 4 chains: exit 0, identical csv" \
    '[ $rc -eq 0 ] && cmp -s "$dir/s1.csv" "$dir/m6.csv" && cmp -s "$dir/s1-poincare.csv" "$dir/m6-poincare.csv"'
  # a rank that refuses what rank 0 accepts (here its own --set; on a
  # cluster, a host without the scene): every rank stops, exit 2, said once
  # (rank 0 waited for it forever)
  timeout 60 "$mpiexec" --allow-run-as-root --oversubscribe -np 1 "$sweep" $common --threads 1 \
      --values xi_p=0.08 --out "$dir/mr" : -np 1 "$sweep" $common --threads 1 --values xi_p=0.08 \
      --out "$dir/mr" --set nope=1 >/dev/null 2>"$dir/mr.err"
  rc=$?
  check "mpi: one rank refusing stops them all, exit 2, said once" \
    '[ $rc -eq 2 ] && [ $(grep -c "^wgsweep: another MPI rank refused the run" "$dir/mr.err") -eq 1 ] && ! [ -e "$dir/mr.csv" ]'
  # every rank parses the same arguments: one refusal and one --help, by rank 0
  "$mpiexec" --allow-run-as-root --oversubscribe -np 3 "$sweep" --pair 9 >/dev/null 2>"$dir/mpi9.err"
  rc=$?
  check "mpi -np 3, --pair 9: exit 2, refused once" \
    '[ $rc -eq 2 ] && [ $(grep -c "^wgsweep: --pair: need 1..8, got .9.$" "$dir/mpi9.err") -eq 1 ]'
  "$mpiexec" --allow-run-as-root --oversubscribe -np 3 "$sweep" --help >"$dir/mpih.out" 2>"$dir/mpih.err"
  rc=$?
  check "mpi -np 3, --help: exit 0, printed once" \
    '[ $rc -eq 0 ] && [ $(grep -c "^usage: wgsweep" "$dir/mpih.out") -eq 1 ] && ! [ -s "$dir/mpih.err" ]'
fi

"$sweep" --from 1.17 --to 1.22 --points 6 --transient 200 --quiet --no-png --dir up --verify-steps --out "$dir/v" >/dev/null
check "--verify-steps: 2N check columns and summary" 'grep -q "6 of 6 attractors keep" "$dir/v.md" && [ $(cut -d, -f19 "$dir/v.csv" | grep -c periodic) -eq 6 ]'

"$sweep" --table-from "$dir/s1.csv" --out "$dir/re" >/dev/null
check "--table-from recomputes the same doubling" 'grep -q "period doubling | 1.1950 (1.1900-1.2000)" "$dir/re.md" && grep -q "recomputed from" "$dir/re.md"'

# a sweep without --values has no group column: one group, its own table
# (each row was read as a group of its own, each table "(none found)")
"$sweep" --table-from "$dir/v.csv" --out "$dir/rv" >/dev/null
check "--table-from a sweep without --values: one table, the sweep's doublings" \
  '[ "$(grep -c "^| transition" "$dir/rv.md")" -eq 1 ] && [ "$(grep "^| period doubling" "$dir/rv.md")" = "$(grep "^| period doubling" "$dir/v.md")" ] && grep -q "^| period doubling | 1.1950" "$dir/rv.md"'

# a sweep of b itself: grazing is min x_n against each point's own b (at
# omega 1.2 the orbit impacts at every b; the table once reported "grazing:
# impacts end" where min x_n passed the scene's b = 1); the figure draws.
"$sweep" --param b --from 0 --to 1.5 --points 4 --set omega=1.2 --transient 100 --quiet --out "$dir/pb" >/dev/null
check "--param b: no grazing in the table (min x_n stays under the swept b), the figure written" \
  '! grep -q "^| grazing" "$dir/pb.md" && grep -q "^| transition" "$dir/pb.md" && [ -s "$dir/pb.png" ]'

# a points file read back is verified first: a torn header (said as such), a torn row, a
# header alone, a foreign regime name and a row of too few fields are each
# refused with the line at fault (a torn header once gave an empty table)
head -c 150 "$dir/v.csv" >"$dir/t1.csv"
head -c 700 "$dir/v.csv" >"$dir/t2.csv"
head -1 "$dir/v.csv" >"$dir/t3.csv"
sed 's/periodic/periodik/' "$dir/v.csv" >"$dir/t4.csv"
{ head -2 "$dir/v.csv"; echo "up,1,1.2"; } >"$dir/t5.csv"
awk -F, -v OFS=, 'NR == 2 { $5 = -7 } 1' "$dir/v.csv" >"$dir/t6.csv"   # a period no run writes
awk -F, -v OFS=, 'NR == 2 { $15 = -3 } 1' "$dir/v.csv" >"$dir/t7.csv"  # N = -3
# a NUL inside a row (it was reported as "the line is cut short"), a row of
# 5,000 characters (the same)
{ head -2 "$dir/v.csv"; printf 'up,1,\0001.2\n'; sed -n '4,$p' "$dir/v.csv"; } >"$dir/t8.csv"
{ head -2 "$dir/v.csv"; head -c 5000 /dev/zero | tr '\0' 7; echo; } >"$dir/t9.csv"
printf 'dir,index,omega\nup,0,1\n' >"$dir/t10.csv"   # a whole header, not wgsweep's
# what a points CSV can hold (each was tabled: groups of nan or 1e999, an up
# grid out of order giving brackets like 1.2000 (1.4000-1.0000), omega =
# 1e308, garbage in the index or Floquet columns, a down sweep increasing)
awk -F, -v OFS=, 'NR == 2 { $1 = "nan" } 1' "$dir/s1.csv" >"$dir/t11.csv"
awk -F, -v OFS=, 'NR == 3 { $1 = "1e999" } 1' "$dir/s1.csv" >"$dir/t12.csv"
awk -F, -v OFS=, 'NR == 3 { $3 = 1.0 } 1' "$dir/v.csv" >"$dir/t13.csv"
awk -F, -v OFS=, 'NR == 2 { $3 = "1e308" } 1' "$dir/v.csv" >"$dir/t14.csv"
awk -F, -v OFS=, 'NR == 2 { $2 = "abc" } 1' "$dir/v.csv" >"$dir/t15.csv"
awk -F, -v OFS=, 'NR == 2 { $16 = "zzz" } 1' "$dir/v.csv" >"$dir/t16.csv"
sed 's/^up,/down,/' "$dir/v.csv" >"$dir/t17.csv"
awk -F, -v OFS=, 'NR == 2 { $5 = "+1" } 1' "$dir/v.csv" >"$dir/t18.csv"
# 65 groups: one more than --values takes ("too many groups" gave no limit)
awk -F, -v OFS=, 'NR == 1 { print; next } NR == 2 { for (k = 1; k <= 65; k++) { $1 = k / 100; print } }' \
  "$dir/s1.csv" >"$dir/t19.csv"
# the group column is the swept parameter itself (wgsweep refuses --values omega=...)
sed '1s/^xi_p,/omega,/' "$dir/s1.csv" >"$dir/t20.csv"
i=0
for want in ":1: the line is cut short" ":3: the line is cut short" ": no points after the header" \
            ":2: regime 'periodik' is not what wgsweep writes there: need a regime name" \
            ":3: 3 fields, the header has" \
            ":2: period '-7' is not what wgsweep writes there: need a whole number 0..32" \
            ":2: steps_per_period '-3' is not what wgsweep writes there: need a whole number 8..65536" \
            ":3: a NUL byte: not a text file" ":3: longer than 4094 characters" \
            ":1: not a wgsweep points CSV header" \
            ":2: group value 'nan': need a finite value of xi_p in its range (xi_p = nan out of range \\[0, 2\\])" \
            ":3: group value '1e999': need a finite value of xi_p in its range (xi_p = inf out of range" \
            ":3: omega 1 after 1.17 in the up sweep: need values strictly increasing, as wgsweep writes them" \
            ":2: omega '1e308': need a finite value in its range (omega = 1e+308 out of range \\[0.01, 10\\])" \
            ":2: index 'abc': need 0 (each direction's rows numbered 0, 1, 2, ... in the order" \
            ":2: floquet1_re 'zzz' is not what wgsweep writes there: need a finite number, or empty" \
            ":3: omega 1.18 after 1.17 in the down sweep: need values strictly decreasing" \
            ":2: period '+1' is not what wgsweep writes there" \
            ":66: too many groups: at most 64 values of xi_p (as --values takes)" \
            ":1: not a wgsweep points CSV header"; do
  i=$((i + 1))
  "$sweep" --table-from "$dir/t$i.csv" --out "$dir/tt$i" >/dev/null 2>"$dir/tt.err"; rc=$?
  check "--table-from a damaged file ($i): exit 2, '$want'" \
    '[ $rc -eq 2 ] && grep -q -- "^wgsweep: $dir/t$i.csv$want" "$dir/tt.err" && [ "$(wc -l <"$dir/tt.err")" -eq 1 ] && ! [ -e "$dir/tt$i.md" ]'
done

# a FIFO or a directory is not a points file: refused at once (a FIFO
# blocked the open until a writer came; timeout ends it if it still would)
mkfifo "$dir/fifo.csv"
timeout 20 "$sweep" --table-from "$dir/fifo.csv" --out "$dir/tf" >/dev/null 2>"$dir/tf.err"; rc=$?
check "--table-from a FIFO: exit 2 at once, 'is a FIFO, not a regular file'" \
  '[ $rc -eq 2 ] && grep -q "^wgsweep: points file $dir/fifo.csv is a FIFO, not a regular file" "$dir/tf.err"'
"$sweep" --table-from "$dir" --out "$dir/td" >/dev/null 2>"$dir/td.err"; rc=$?
check "--table-from a directory: exit 2, 'is a directory'" \
  '[ $rc -eq 2 ] && grep -q "is a directory, not a regular file" "$dir/td.err"'

# Ctrl-C: a long sweep interrupted after a second
"$sweep" --from 0.6 --to 1.0 --points 400 --threads 1 --quiet --out "$dir/int" >/dev/null 2>&1 &
pid=$!
sleep 1.5
stop $pid INT; rc=$exit_status
check "interrupt exits 130" '[ "$rc" = 130 ]'
check "interrupt leaves partial results" \
  'grep -q "\"partial\":true" "$dir/int.json" && [ $(wc -l < "$dir/int.csv") -gt 1 ] && [ $(wc -l < "$dir/int.csv") -lt 800 ] && grep -q PARTIAL "$dir/int.md" && [ -s "$dir/int.png" ]'

# A stop signal during --at (which has no points to stop after) ends it at
# once; it used to be caught and ignored until the point was done (here:
# 1e7 periods). SIGTERM: a script's background job ignores SIGINT.
"$sweep" --at 0.85 --at-periods 10000000 --out "$dir/atint" >/dev/null 2>&1 &
pid=$!
sleep 1
stop $pid TERM; rc=$exit_status
check "SIGTERM during --at: ended at once by the signal" '[ "$rc" = 143 ]'

"$sweep" --at 0.85 --at-periods 200 --out "$dir/at" > "$dir/at.txt"
check "--at summary and views" 'grep -q "regime      P1" "$dir/at.txt" && grep -q floquet "$dir/at.txt" && [ -s "$dir/at-at-omega-0.85-phase.png" ] && [ -s "$dir/at-at-omega-0.85-poincare.png" ] && [ -s "$dir/at-at-omega-0.85-trace.csv" ]'
check "--at names every file, none with '='" 'grep -q "^files       $dir/at-at-omega-0.85-trace.csv, $dir/at-at-omega-0.85-phase.png, $dir/at-at-omega-0.85-poincare.png, $dir/at-at-omega-0.85-trace.png\$" "$dir/at.txt" && ! ls "$dir" | grep -q ='

"$sweep" --map xi_p=0.08:0.12:2 --from 1.18 --to 1.21 --points 3 --transient 150 --quiet --out "$dir/map"
check "2-D map csv and pngs" '[ $(wc -l < "$dir/map-map.csv") -eq 7 ] && [ -s "$dir/map-map.png" ] && [ -s "$dir/map-map-motion.png" ]'

# Figures (issue 12 item 12): captions, axes with symbols and units, regime
# and Lyapunov exponent, in SVG (its <title>/<desc>) and PDF (its Title).
"$sweep" --at 1.2 --at-periods 200 --format svg --set f_e=0.1 --out "$dir/fa" > "$dir/fa.txt"
svg=$dir/fa-at-omega-1.2
check "--format svg: the files named" 'grep -q "^files .*$svg-phase.svg, $svg-poincare.svg, $svg-trace.svg\$" "$dir/fa.txt"'
check "svg caption: scene, xi_p, what was set, N, transient, recorded" \
  'grep -q "^<desc>scene table3, ξ_p = 0.08, N = 256 steps per mesh period, transient 300 periods (+ up to 3 x 300 while no period is found), 128 periods recorded\$" "$svg-phase.svg" && grep -q "^set away from the scene: ω = 1.2 (scene: 1), f_e = 0.1 (scene: 0.092442)\$" "$svg-phase.svg"'
"$sweep" --at 1.2 --at-periods 200 --format svg --settle 24 --out "$dir/fs" > /dev/null
check "svg caption with --settle 24: the early stop said" \
  'grep -q "^<desc>scene table3, ξ_p = 0.08, N = 256 steps per mesh period, transient 300 periods or fewer, ending once settled over 24 (+ up to 3 x 300 while no period is found), 128 periods recorded\$" "$dir/fs-at-omega-1.2-phase.svg"'
check "svg phase portrait and Poincare map: regime and Lyapunov exponent" \
  'for v in phase poincare; do grep -q "^P2 (periodic), single_sided, λ = -0\.[0-9]* per mesh period\$" "$svg-$v.svg" || exit 1; done'
check "svg axes: x_n in b_c and um, x_n in b_c omega_n and m/s" \
  'grep -q "^x axis: x_n  (b_c)\$" "$svg-poincare.svg" && grep -q "^x axis, second scale: x_n  (µm)\$" "$svg-poincare.svg" && grep -q "^y axis: x_n. = dx_n/dτ  (b_c ω_n)\$" "$svg-poincare.svg" && grep -q "^y axis, second scale: x_n.  (m/s)</desc>\$" "$svg-poincare.svg"'
check "svg time trace: physical time, mesh periods on top" \
  'grep -q "<title>table3, ω = 1.2: time trace, 20 mesh periods (T = 0.1641 ms)</title>" "$svg-trace.svg" && grep -q "^x axis: t from the first traced period  (ms)\$" "$svg-trace.svg" && grep -q "^x axis, second scale: mesh periods\$" "$svg-trace.svg"'
check "svg is drawn (glyphs and paths), not only described" '[ $(grep -c "<use xlink:href=\"#glyph" "$svg-phase.svg") -gt 200 ]'
"$sweep" --from 1.17 --to 1.22 --points 4 --transient 100 --quiet --format pdf --no-json --out "$dir/fp"
hex() { printf %s "$1" | iconv -f UTF-8 -t UTF-16BE | od -An -tx1 | tr -d ' \n' | tr a-f A-F; }
check "--format pdf: a PDF with its title" \
  '[ "$(head -c 5 "$dir/fp.pdf")" = "%PDF-" ] && grep -a -q "/Title <FEFF$(hex "table3: bifurcation diagram in ω")>" "$dir/fp.pdf"'
check "pdf subject: caption, shading, both axes with Hz and um" \
  'grep -a -q "/Subject <FEFF$(hex "scene table3, ξ_p = 0.08, N = 256 steps per mesh period")" "$dir/fp.pdf" && grep -a -q "$(hex "background: regime of the up sweep")" "$dir/fp.pdf" && grep -a -q "$(hex "x axis, second scale: mesh frequency  (Hz)")" "$dir/fp.pdf" && grep -a -q "$(hex "y axis, second scale: x_n  (µm)")" "$dir/fp.pdf"'
"$sweep" --from 1.17 --to 1.22 --points 4 --transient 100 --quiet --format svg --no-json --dir down --values xi_p=0.1 --out "$dir/fd"
check "down sweep only: its shading named, xi_p listed as set" \
  'grep -q "^background: regime of the down sweep" "$dir/fd-xi_p-0.1.svg" && grep -q "^scene table3, ξ_p = 0.1, .*set away from the scene: ξ_p (scene: 0.08)\$\|^set away from the scene: ξ_p (scene: 0.08)\$" "$dir/fd-xi_p-0.1.svg"'
"$sweep" --format gif >/dev/null 2>"$dir/fmt.err"; rc=$?
check "--format gif: usage error" '[ $rc -eq 2 ] && grep -q "png, svg or pdf" "$dir/fmt.err"'

"$sweep" --param nope >/dev/null 2>&1; rc=$?
check "unknown parameter exits 2" '[ $rc -eq 2 ]'
"$sweep" --param j1 >/dev/null 2>"$dir/j1.err"; rc=$?
check "--param j1 (body data) exits 2, saying why" '[ $rc -eq 2 ] && grep -q "body data" "$dir/j1.err"'
"$sweep" --map z1=1:3:3 >/dev/null 2>&1; rc=$?
check "--map over body data exits 2" '[ $rc -eq 2 ]'
"$sweep" --values xi_p=9 >/dev/null 2>&1; rc=$?
check "out-of-range value exits 2" '[ $rc -eq 2 ]'
exit $fail
