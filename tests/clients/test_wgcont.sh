#!/bin/bash
# wgcont end to end: the branch and bifurcation CSVs (header type,PARAM),
# the period doubling of table3 located and switched onto, a figure in each
# format (with its Hz and µm scales), another parameter than omega, Ctrl-C writing what is done, usage
# errors, and wgsweep --exact adding its "exact (continuation)" column.
# usage: test_wgcont.sh WGCONT WGSWEEP
set -u
cont=$1
sweep=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
. "$(dirname "$0")/../wait.sh" # wait_until, stop
fail=0
check() { if eval "$2"; then echo "$1 ok"; else echo "$1 FAIL"; fail=1; fi; }
magic() { head -c "$2" "$1" | od -An -c | tr -d ' \n'; }

"$cont" --from 1.18 --to 1.22 --sweep-points 5 --out "$dir/pd" 2>"$dir/pd.err"
check "run exits 0 and writes csv/csv/png" \
  '[ -s "$dir/pd-branch.csv" ] && [ -s "$dir/pd-bifurcations.csv" ] && [ "$(magic "$dir/pd.png" 4)" = "211PNG" ]'
check "bifurcations header begins type,omega, then the state and the multiplier" \
  'head -1 "$dir/pd-bifurcations.csv" | grep -q "^type,omega,x1,y1,z1,x2,y2,z2,s,dx1,.*,ds,mu_re,mu_im,mu_abs,mu_arg,"'
check "period doubling located at 1.19765" \
  'awk -F, "\$1==\"period_doubling\" && \$2>1.19765 && \$2<1.19766" "$dir/pd-bifurcations.csv" | grep -q .'
check "branch csv: period-1 and switched period-2 points, stable and unstable" \
  'cut -d, -f4 "$dir/pd-branch.csv" | sort -u | tr "\n" " " | grep -q "^1 2 period" && cut -d, -f5 "$dir/pd-branch.csv" | sort -u | tr "\n" " " | grep -q "^0 1 "'
check "progress on stderr names the doubling" 'grep -q "period_doubling at omega = 1.1976546" "$dir/pd.err"'

"$cont" --from 1.18 --to 1.22 --sweep-points 0 --format svg --quiet --out "$dir/f" &&
"$cont" --from 1.18 --to 1.22 --sweep-points 0 --format pdf --quiet --out "$dir/f"
check "--format svg and pdf" 'grep -q "<svg" "$dir/f.svg" && [ "$(magic "$dir/f.pdf" 4)" = "%PDF" ]'
check "the figure's second scales: mesh frequency in Hz under omega, x_n in µm" \
  'grep -q "^x axis, second scale: mesh frequency  (Hz)\$" "$dir/f.svg" && grep -q "^y axis, second scale: x_n  (µm)" "$dir/f.svg"'

"$cont" --set omega=1.2 --param xi_p --from 0.1 --to 0.07 --sweep-points 0 --quiet --out "$dir/xi"
check "--param xi_p: header and a period doubling in xi_p" \
  'head -1 "$dir/xi-bifurcations.csv" | grep -q "^type,xi_p," && grep -q "^period_doubling,0.0" "$dir/xi-bifurcations.csv"'

# Ctrl-C: a long run interrupted once it has 50 branch points (its progress
# line says so; at most 120 s, however slow the build or busy the machine)
"$cont" --from 0.1 --to 2.5 --sweep-points 241 --out "$dir/int" 2>"$dir/int.err" &
pid=$!
wait_until 120 grep -q "point 50 at" "$dir/int.err"
stop $pid INT; rc=$exit_status
check "Ctrl-C: exit 130 and partial csv + figure" \
  '[ "$rc" = 130 ] && [ $(wc -l < "$dir/int-branch.csv") -gt 2 ] && [ -s "$dir/int.png" ]'

# A stop during the transient before the first point: it used to run on
# to the transient's end (1e7 periods here: 80 s in a Release build); now
# it ends within a few periods, exit 130, the files written without points.
"$cont" --from 0.5 --to 0.6 --transient 10000000 --sweep-points 0 --out "$dir/tr" 2>"$dir/tr.err" &
pid=$!
sleep 1
stop $pid TERM; rc=$exit_status
check "SIGTERM during the transient: exit 130 at once, the files written with no points" \
  '[ "$rc" = 130 ] && [ $(wc -l < "$dir/tr-branch.csv") -eq 1 ] && [ -s "$dir/tr.png" ] && grep -q "^wgcont: 0 points" "$dir/tr.err"'

"$cont" >/dev/null 2>&1; r1=$?
"$cont" --from 0.5 >/dev/null 2>&1; r2=$?
"$cont" --from 0.5 --to 0.6 --format gif >/dev/null 2>&1; r3=$?
"$cont" --from 0.5 --to 0.6 --param nope >/dev/null 2>&1; r4=$?
"$cont" --from 0.5 --to 0.6 --period 3 --sweep-points 0 --quiet --out "$dir/p3" 2>"$dir/p3.err"; r5=$?
"$cont" --from 10 --to 20 --param z2 >/dev/null 2>"$dir/z2.err"; r6=$?
check "usage errors exit 2" '[ $r1 -eq 2 ] && [ $r2 -eq 2 ] && [ $r3 -eq 2 ] && [ $r4 -eq 2 ]'
check "--param z2 (body data): exit 2, one refusal saying it does not change the motion" \
  '[ $r6 -eq 2 ] && grep -q "^wgcont: --param .z2.: body data, .*does not change the motion" "$dir/z2.err" && [ "$(grep -c "^wgcont:" "$dir/z2.err")" -eq 1 ]'
"$cont" --from 0.3 --to 0.35 --param a2 --out "$dir/a2" >/dev/null 2>"$dir/a2.err"; r7=$?
check "--param a2 (a direction cosine): exit 2, one refusal saying why and what to vary, nothing written" \
  '[ $r7 -eq 2 ] && grep -q "^wgcont: --param .a2.: a direction cosine of the line of action, tied to the other two by a1^2 + a2^2 + a3^2 = 1" "$dir/a2.err" && [ "$(grep -c "^wgcont:" "$dir/a2.err")" -eq 1 ] && ! ls "$dir"/a2-* >/dev/null 2>&1'
"$cont" --from 0.5 --to 0.6 --out "$dir/none/c" >/dev/null 2>"$dir/od.err"; r8=$?
check "--out in a missing directory: exit 2 before the continuation, the reason said" \
  '[ $r8 -eq 2 ] && grep -q "^wgcont: --out .$dir/none/c.: cannot write in $dir/none: No such file or directory" "$dir/od.err" && ! grep -q omega "$dir/od.err"'
# the range and step refused as usage errors naming the option (they were
# exit 1: "start omega = 1 must lie in [1, 1] (from != to)", "ds_min"); the
# conditions are the library's (wg_cont_check), the option names wgcont's
for a in "--from 1 --to 1|--from and --to: need a range" "--from 0.5 --to 0.6 --start 2|--start: need a value in \[0.5, 0.6\] (the range), got 2" \
         "--from 0.5 --to 0.6 --max-step 1e-9|--max-step: need at least 1e-07 (the smallest step the continuation halves to), got 1e-09" "--from 0.5 --to 11|--to: omega = 11 out of range" \
         "--from 1 --to 1.05 --tol 1e300|--tol: need a residual (states in b_c) in \[1e-13, 1e-06\], got 1e+300" \
         "--from 1 --to 1.05 --tol 1e-300|--tol: need a residual (states in b_c) in \[1e-13, 1e-06\], got 1e-300" \
         "--from 1 --to 1.05 --loc-tol 1e300|--loc-tol: need a bracket (parameter units) in \[1e-13, 1e-05\], got 1e+300"; do
  "$cont" ${a%%|*} --out "$dir/rg" >/dev/null 2>"$dir/rg.err"; rc=$?
  check "refused: ${a%%|*}" '[ $rc -eq 2 ] && [ "$(grep -c "^wgcont:" "$dir/rg.err")" -eq 1 ] && grep -q "^wgcont: ${a#*|}" "$dir/rg.err" && ! ls "$dir"/rg* 2>/dev/null | grep -v rg.err'
done
check "--help gives the tolerances' ranges" '"$cont" --help | grep -q "(default 1e-10; 1e-13 to 1e-06"'
"$cont" --from 0.5 --to 0.6 --out "$dir/" >/dev/null 2>"$dir/os.err"; r10=$?
check "--out ending in /: exit 2, a file name prefix asked for" \
  '[ $r10 -eq 2 ] && grep -q "^wgcont: --out .*need a file name prefix" "$dir/os.err" && ! [ -e "$dir/.png" ]'
check "a period-3 start on a period-1 attractor: exit 1, the period named" \
  '[ $r5 -eq 1 ] && grep -q "has period 1, not 3" "$dir/p3.err"'

"$sweep" --from 1.17 --to 1.22 --points 6 --transient 200 --quiet --no-png --no-json \
    --exact "$dir/pd-bifurcations.csv" --out "$dir/sw" >/dev/null
check "wgsweep --exact: the column and the located doubling" \
  'grep -q "| exact (continuation) |" "$dir/sw.md" && grep "period doubling | 1.1950" "$dir/sw.md" | grep -q "1.1976546 (period_doubling P1)"'
# docs/analysis.md's "From a sweep to exact points", step 3: the table of a
# sweep without --values recomputed with the located points (every row of
# such a CSV was read as a group of its own: "1 file(s) for 6 group(s)")
"$sweep" --table-from "$dir/sw.csv" --exact "$dir/pd-bifurcations.csv" --out "$dir/swt" >/dev/null 2>"$dir/swt.err"; r9=$?
check "wgsweep --table-from a plain sweep's CSV --exact: its table with the located doubling" \
  '[ $r9 -eq 0 ] && grep "period doubling | 1.1950" "$dir/swt.md" | grep -q "1.1976546 (period_doubling P1)"'
# a bifurcations file cut inside its last row is refused (its value, cut
# to 1.19, was read as a located doubling)
head -c $(($(wc -c <"$dir/pd-bifurcations.csv") - 40)) "$dir/pd-bifurcations.csv" >"$dir/cut.csv"
"$sweep" --table-from "$dir/sw.csv" --exact "$dir/cut.csv" --out "$dir/swc" >/dev/null 2>"$dir/swc.err"; r11=$?
check "wgsweep --exact with a torn bifurcations file: exit 2, the line cut short said" \
  '[ $r11 -eq 2 ] && grep -q "cut.csv:[0-9]*: the line is cut short" "$dir/swc.err"'
# a NUL byte in a row is said as such (it read as "the line is cut short")
{ head -1 "$dir/pd-bifurcations.csv"; printf 'period_doubling,1.19\0007\n'; } >"$dir/nul.csv"
"$sweep" --table-from "$dir/sw.csv" --exact "$dir/nul.csv" --out "$dir/swn" >/dev/null 2>"$dir/swn.err"; r12=$?
check "wgsweep --exact with a NUL in a bifurcations row: exit 2, 'nul.csv:2: a NUL byte'" \
  '[ $r12 -eq 2 ] && grep -q "nul.csv:2: a NUL byte: not a text file" "$dir/swn.err"'
# a row that is not what wgcont writes is refused (a kind's fields, a period
# of -99999999999, a bracket NOTANUMBER were tabled as 'grazing P-1215752191')
{ head -1 "$dir/pd-bifurcations.csv"; echo "period_doubling,1.17$(printf ',0%.0s' $(seq 2 19)),GARBAGE,zz,nowhere,weird,sideways,NOTANUMBER"; } >"$dir/bad.csv"
{ head -2 "$dir/pd-bifurcations.csv" | tail -1 | awk -F, -v OFS=, '{ $21 = -99999999999 } 1'; } >"$dir/bad2row.csv"
{ head -1 "$dir/pd-bifurcations.csv"; cat "$dir/bad2row.csv"; } >"$dir/bad2.csv"
for b in bad bad2; do
  "$sweep" --table-from "$dir/sw.csv" --exact "$dir/$b.csv" --out "$dir/sw$b" >/dev/null 2>"$dir/sw$b.err"; rb=$?
  check "wgsweep --exact with a row wgcont does not write ($b): exit 2, the line said" \
    '[ $rb -eq 2 ] && grep -q "$b.csv:2: not a bifurcation row" "$dir/sw$b.err"'
done
# what wgcont writes, exactly: its header once (a second period column was
# read, a header with no state taken), the value in the parameter's range
# (1e308 was tabled), a period as %d writes it (" 1" and "+1" were taken)
{ sed '1s/$/,period/; 2s/$/,1/' "$dir/pd-bifurcations.csv" | head -2; } >"$dir/dup.csv"
printf 'type,omega\n' >"$dir/hdr.csv"
awk -F, -v OFS=, 'NR == 2 { $2 = "1e308" } NR <= 2' "$dir/pd-bifurcations.csv" >"$dir/huge.csv"
awk -F, -v OFS=, 'NR == 2 { $21 = "+1" } NR <= 2' "$dir/pd-bifurcations.csv" >"$dir/plus.csv"
awk -F, -v OFS=, 'NR == 2 { $21 = " 1" } NR <= 2' "$dir/pd-bifurcations.csv" >"$dir/space.csv"
for b in "dup|:1: not a bifurcations CSV header of wgcont" "hdr|:1: not a bifurcations CSV header" \
         "huge|:2: not a bifurcation row as wgcont writes it (need the parameter's value, finite and in its range)" \
         "plus|:2: not a bifurcation row as wgcont writes it (need a period 1..32 as %d writes it)" \
         "space|:2: not a bifurcation row as wgcont writes it (need a period 1..32"; do
  f=${b%%|*}
  "$sweep" --table-from "$dir/sw.csv" --exact "$dir/$f.csv" --out "$dir/sx$f" >/dev/null 2>"$dir/sx.err"; rb=$?
  check "wgsweep --exact $f.csv: exit 2, once, '${b#*|}'" \
    '[ $rb -eq 2 ] && [ "$(wc -l <"$dir/sx.err")" -eq 1 ] && grep -q -- "^wgsweep: --exact: $dir/$f.csv${b#*|}" "$dir/sx.err" && ! [ -e "$dir/sx$f.md" ]'
done
# a header alone is what wgcont writes where it locates nothing: taken
head -1 "$dir/pd-bifurcations.csv" >"$dir/none.csv"
"$sweep" --table-from "$dir/sw.csv" --exact "$dir/none.csv" --out "$dir/sxn" >/dev/null 2>&1; rb=$?
check "wgsweep --exact with wgcont's header alone (nothing located): exit 0, the column empty" \
  '[ $rb -eq 0 ] && grep "^| period doubling" "$dir/sxn.md" | grep -q "| - |$"'
mkfifo "$dir/bifs.fifo"
timeout 20 "$sweep" --table-from "$dir/sw.csv" --exact "$dir/bifs.fifo" --out "$dir/swf" >/dev/null 2>"$dir/swf.err"; r12=$?
check "wgsweep --exact with a FIFO: exit 2 at once (the open blocked), 'is a FIFO'" \
  '[ $r12 -eq 2 ] && grep -q "bifurcations file $dir/bifs.fifo is a FIFO, not a regular file" "$dir/swf.err"'
"$sweep" --from 1.17 --to 1.22 --points 6 --quiet --no-png --values xi_p=0.08,0.1 \
    --exact "$dir/pd-bifurcations.csv" --out "$dir/sw2" >/dev/null 2>&1; r6=$?
"$sweep" --from 1.17 --to 1.22 --points 6 --quiet --no-png --param xi_p \
    --exact "$dir/pd-bifurcations.csv" --out "$dir/sw3" >/dev/null 2>&1; r7=$?
check "wgsweep --exact: one file per group, same parameter" '[ $r6 -eq 2 ] && [ $r7 -eq 2 ]'
exit $fail
