#!/usr/bin/env bash
# tools/bench.sh - measure, in one run on this machine, every figure of the
# README's "Performance" section. Installs what the benchmarks need
# (tools/setup.sh: GSL and SUNDIALS are the step's and the work-precision
# comparisons), builds build-bench (Release, -DWG_BUILD_BENCH=ON), then runs:
#   bench_gsl 1000000 5       the step against its dependency-chain bound and
#                             against GSL's rk4 (issue 13, item 1)
#   bench_step 1000000 5      the step per scene, and what skipping costs
#   bench_pair_* 300000 3     one run, two paired, a batch (the widest set
#                             this CPU runs)
#   sweep_bench.sh 3 map      the study and the 201-row map (item 2)
#   wgd_bench 10 500          the daemon at physical real time: CPU share,
#                             command -> ACK latency (item 3; in a private
#                             network namespace, tests/netns.sh)
#   bench_wp DIR 5            work precision against GSL and CVODE (its
#                             PNGs in build-bench/bench/)
#   bench_long 1e9            the 10^9-step run
# Each prints its own tables (kept in build-bench/bench/*.txt); a summary of
# the lines the README quotes ends the run, each under the command that gave
# it (kept in build-bench/bench/summary.txt). Figures only: nothing passes
# or fails on a time; the exit status is non-zero only if a step fails.
# Run as root on Debian 12; ~5 min on 2 cores once tools/setup.sh's
# packages are installed (a fresh machine first installs all of them: the
# project's, not only the benchmarks').
# Keep the machine otherwise quiet: the figures are wall and CPU times.
# No arguments (--help: this text).
set -euo pipefail
. "$(dirname "$0")/args.sh"
args_none bench.sh "$@"
cd "$(dirname "$0")/.."
bash tools/setup.sh
b=build-bench
out=$b/bench
echo "== build $b (Release, -DWG_BUILD_BENCH=ON)"
cmake -S . -B "$b" -DCMAKE_BUILD_TYPE=Release -DWG_BUILD_BENCH=ON -DWG_SANITIZE=OFF -DWG_MPI=OFF \
    >/dev/null
cmake --build "$b" -j"$(nproc)" >/dev/null
mkdir -p "$out"
export WG_SCENE_PATH=$PWD/scenes
bin=$b/tests/bench
wide=sse2
grep -qw avx2 /proc/cpuinfo && wide=avx2
grep -qw avx512f /proc/cpuinfo && wide=avx512

# run NAME COMMAND...: the command's output on the terminal and in
# $out/NAME.txt, the command itself in cmd[NAME]; a failing command ends
# the run.
declare -A cmd
run() {
    local name=$1; shift
    cmd[$name]="$*"
    echo
    echo "== $name: $*"
    if ! "$@" 2>&1 | tee "$out/$name.txt"; then
        echo "bench.sh: $name failed: $*" >&2
        exit 1
    fi
}
head="commit $(git describe --always --dirty 2>/dev/null || echo '(no git)'), $(date -u +%F),"
head+=" $(nproc) CPUs: $(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1),"
head+=" load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "$head"
run step "$bin/bench_gsl" 1000000 5
run scenes "$bin/bench_step" 1000000 5
run pair "$bin/bench_pair_$wide" 300000 3
run sweeps bash tests/bench/sweep_bench.sh "$b" 3 map
run daemon sh tests/netns.sh "$bin/wgd_bench" "$b/daemon/wormgeard" 10 500
run wp "$bin/bench_wp" "$out" 5
run long "$bin/bench_long" 1e9

# pick NAME REGEX: NAME's command, and the lines of its output the README
# quotes
pick() {
    echo "-- ${cmd[$1]}"
    grep -E "$2" "$out/$1.txt" || { echo "bench.sh: no '$2' in $out/$1.txt" >&2; exit 1; }
}
summary() {
    echo "== summary: $head"
    pick step '^\||^issue 13, item 1'
    pick scenes '^\|'
    pick pair '^runs, omega'
    pick sweeps '^\||^study CSVs|^pairing'
    pick daemon '^CPU share|^command->ACK'
    pick wp '^## \(|^rk4-event / GSL rk8pd'
    pick long 'steps in .* s wall|bad state|^mean x_n|^tau |^anonymous memory'
    echo "(load at the end $(cut -d' ' -f1-3 /proc/loadavg); every table: $out/*.txt;" \
        "work-precision plots: $out/wp_*.png)"
}
echo
summary | tee "$out/summary.txt"
