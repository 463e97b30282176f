#!/bin/sh
# test_readme_bench.sh SRC - the README's benchmark command ("Performance":
# `bash tools/bench.sh`), run as written on a copy of the source tree as a
# user has it (no build directories, no .git), so that build-bench and the
# outputs do not stay behind. The command is read from README.md and must
# equal the one below: when the README changes, this test changes with it.
# Nothing here passes or fails on a time: the test asserts that every
# benchmark ran to its end and printed the figures the README quotes (each
# of issue 13's targets with its verdict, the sweeps' rows with the same
# study bytes in every run, the daemon's CPU share and latencies with every
# command accepted, the work-precision ratios and plots, the 10^9-step run
# with no bad section and the same mean x_n before and after), and prints
# the summary. Run through netns.sh. Takes ~4-5 min on 2 cores.
src=$1
. "$(dirname "$0")/readme.sh" # readme_block, readme_expect, readme_tree
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

readme_block "$src/README.md" \
    '## Performance (details and every table: [`docs/performance.md`](docs/performance.md))' \
    >"$tmp/block"
echo 'bash tools/bench.sh' >"$tmp/want"
readme_expect "$tmp/block" "$tmp/want" "benchmark command"

# The command starts with tools/setup.sh, which here, in a network namespace,
# can install nothing: what it would install must be there already (a tree
# pulled since setup.sh last ran may lack the benchmarks' packages).
bash "$src/tools/setup.sh" --check >"$tmp/setup" ||
    fail "$(cat "$tmp/setup"): run tools/setup.sh (as root) first"

# web/node_modules comes along (mtimes kept), so that tools/setup.sh finds
# the dashboard's packages installed and needs no registry.
readme_tree "$src" "$tmp/src" || fail "could not copy the source tree"
cd "$tmp/src" || exit 1
unset WG_SCENE_PATH # as a user runs it

start=$(date +%s)
sh -c "$(cat "$tmp/block")" >"$tmp/out" 2>&1
rc=$?
echo "bench.sh: $(($(date +%s) - start)) s, exit $rc"
[ $rc -eq 0 ] || { tail -40 "$tmp/out"; fail "bash tools/bench.sh exited $rc"; }
sed -n '/^== summary/,$p' "$tmp/out"

status=0
check() { if eval "$2"; then echo "$1 ok"; else echo "FAIL: $1"; status=1; fi; }
# each benchmark's own output (build-bench/bench/NAME.txt), not the summary
# that repeats its lines: has NAME REGEX, count NAME REGEX
has() { grep -Eq -- "$2" "build-bench/bench/$1.txt"; }
count() { grep -Ec -- "$2" "build-bench/bench/$1.txt"; }
num='[0-9]+(\.[0-9]+)?'
for f in step scenes pair sweeps daemon wp long summary; do
    check "build-bench/bench/$f.txt kept" '[ -s build-bench/bench/$f.txt ]'
done
check "the summary names each of the seven benchmarks' commands" \
    '[ $(grep -c "^-- " build-bench/bench/summary.txt) -eq 7 ]'
check "item 1: each step ratio with its target and verdict" \
    'has step "^issue 13, item 1 .*: table3 \(no impact\) ${num}x \(target 1\.5x: (met|missed)\); table3 \(impacting\) ${num}x \(target 2\.0x: (met|missed)\); torsional ${num}x \(target 1\.3x: (met|missed)\)$"'
check "the step against GSL's rk4, each of the 7 scenes" \
    '[ $(count step "^\| (table3 \(|lowfreq|realistic|torsional).*\*\*${num}x\*\*") -eq 7 ]'
check "the per-scene step table, 9 rows" \
    '[ $(count scenes "^\| [a-z0-9 ()]+ \| $num \| rk4(-event)? \| .* \| $num \| $num \| $num \|$") -eq 9 ]'
check "one run, paired, batched: no impact and impacting" \
    '[ $(count pair "^runs, omega .* alone $num, paired $num, batched $num ns/step") -eq 2 ]'
check "item 2: the study, 1,446 points, against 2.0 s" \
    'has sweeps "^\| study, 1446 points \(default --pair\) \| .* \| $num s \| 2\.0 s \| \*\*${num}×\*\* \|$"'
check "item 2: the 201-row map, 48,441 points, against 60 s" \
    'has sweeps "^\| map, 201 rows, 48441 points \| .* \| $num s \| 60 s \| \*\*${num}×\*\* \|$"'
check "the study's CSVs the same bytes in every run" 'has sweeps "^study CSVs .*: same bytes$"'
check "item 3: the daemon's CPU share" 'has daemon "^CPU share over 10 s: $num% of one core"'
check "item 3: set xi_p -> ACK, every command accepted" \
    'has daemon "^command->ACK latency \(set xi_p, 500 of 500 accepted\): p50 $num us, p99 $num us"'
check "work precision against rk8pd at 1e-6 and 1e-9, in each of the 3 cases" \
    '[ $(count wp "^rk4-event / GSL rk8pd time at equal error .*1e-06: \*\*$num\*\*; 1e-09: \*\*$num\*\*") -eq 3 ]'
for c in linear impact chaos; do
    check "the $c work-precision plot is a PNG" \
        '[ "$(head -c 8 build-bench/bench/wp_$c.png | od -An -tx1 | tr -d " \n")" = 89504e470d0a1a0a ]'
done
check "the 10^9-step run: every step taken, no bad section" \
    'has long "^1000000000 steps in $num s wall" && has long "sections with a bad state: 0,"'
check "the 10^9-step run: the same mean x_n before and after" \
    'has long "^mean x_n .*\(diff 0\.00e\+00\)$"'
# memory flat: the anonymous memory (heap, stack) grows by at most 16 kB (4
# pages) over 10^9 steps; the peak RSS also counts code pages the kernel maps
# in as they run (one CI run: 128 kB more, with nothing allocated)
rss=$(sed -n 's/^anonymous memory (RssAnon) \([0-9]*\) kB before, \([0-9]*\) kB after$/\1 \2/p' \
    build-bench/bench/long.txt)
check "the 10^9-step run: memory flat ($rss kB)" \
    '[ -n "$rss" ] && [ $(echo $rss | awk "{print \$2 - \$1}") -le 16 ]'
exit $status
