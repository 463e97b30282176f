#!/bin/bash
# sweep_bench.sh BUILD [ROUNDS] [map] [--quick] - issue 13's sweep targets,
# measured with BUILD's wgsweep as docs/performance.md runs it (--quiet
# --no-png --settle 24 --threads 2; the CSVs and the JSON are written):
#   the Table-3 study (--values xi_p=0.08,0.10,0.12 --from 0.1 --to 2.5
#   --step 0.01: 6 chains, 1,446 points; target 2.0 s wall), ROUNDS times
#   (default 3), each run followed by the same study one chain at a time a
#   thread (--pair 1: what pairing and batching save, in the same window)
#   and by the study with its figures (the three PNGs wgsweep draws by
#   default, without --no-png: what a user who asks for them waits);
#   with `map`, then the 201-row xi_p map once (--map xi_p=0.05:0.15:201
#   --step 0.01: 48,441 points; target 60 s wall).
# Prints the load average before and after, wall and CPU (user + system)
# of every run, each sweep's median wall time and its ratio to the target,
# and whether every study run wrote the same CSV bytes. Figures only:
# nothing passes or fails on a time; the exit status is 1 only if wgsweep
# fails or two study CSVs differ.
# --quick: a coarse grid (--step 0.1, a 5-row map) to try the script itself
# (ctest sys.sweep_bench); its figures are not the targets'.
# Example: bash tests/bench/sweep_bench.sh build/release 3 map   (~75 s)
# --help (or -h): this text.
. "$(dirname "$0")/../../tools/args.sh"
args_help "$@"
[ $# -ge 1 ] || args_refuse sweep_bench.sh "BUILD missing: BUILD [ROUNDS] [map] [--quick]"
build=$1
shift
rounds=3 map=0 quick=0
for a in "$@"; do
    case $a in
    map) map=1 ;;
    --quick) quick=1 ;;
    [1-9] | [1-9][0-9]) rounds=$a ;;
    -h | --help) args_help --help ;;
    *) args_refuse sweep_bench.sh "unknown argument '$a' (ROUNDS 1..99, map, --quick)" ;;
    esac
done
sweep=$build/clients/wgsweep
[ -x "$sweep" ] || args_refuse sweep_bench.sh "BUILD '$build': no clients/wgsweep in it (build first)"
here=$(cd "$(dirname "$0")" && pwd)
export WG_SCENE_PATH=${WG_SCENE_PATH:-$here/../../scenes}
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT

step=0.01 rows=201
[ $quick = 1 ] && step=0.1 rows=5
study=(--values xi_p=0.08,0.10,0.12 --from 0.1 --to 2.5 --step $step)
common=(--quiet --settle 24 --threads 2)

load() { cut -d' ' -f1-3 /proc/loadavg; }

# run NAME ARGS...: one timed wgsweep run; appends "wall cpu" to $tmp/NAME.t
# and keeps its CSVs as $tmp/NAME.N*.csv.
run() {
    local name=$1 n
    shift
    n=$(($(cat "$tmp/$name.t" 2>/dev/null | wc -l) + 1))
    local TIMEFORMAT='%3R %3U %3S'
    { time "$sweep" "${common[@]}" "$@" --out "$tmp/$name.$n" >"$tmp/out" 2>&1; } 2>"$tmp/time" ||
        { echo "sweep_bench.sh: wgsweep $* failed:"; cat "$tmp/out"; exit 1; }
    awk '{printf "%.2f %.2f\n", $1, $2 + $3}' "$tmp/time" >>"$tmp/$name.t"
}

# wall NAME: the median wall time of NAME's runs.
wall() { cut -d' ' -f1 "$tmp/$1.t" | sort -n | awk '{v[NR] = $1} END {print NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

# same NAME...: did every run of these sweeps write the first one's CSV?
same() {
    local first= f
    for name in "$@"; do
        for f in "$tmp/$name".*.csv; do
            case $f in *-poincare.csv) continue ;; esac
            [ -z "$first" ] && first=$f && continue
            cmp -s "$first" "$f" || { echo "differ: $(basename "$first") $(basename "$f")"; return 1; }
        done
    done
    echo "same bytes"
}

echo "wgsweep: $sweep ($(nproc) CPUs; load before: $(load))"
[ $quick = 1 ] && echo "--quick: a coarse grid; these figures are not the targets'"
for r in $(seq 1 "$rounds"); do
    run study "${study[@]}" --no-png
    run pair1 "${study[@]}" --no-png --pair 1
    run figs "${study[@]}"
done
if [ $map = 1 ]; then
    run map --map xi_p=0.05:0.15:$rows --step $step --no-png
fi
echo "load after: $(load)"
echo
echo "| sweep | runs: wall s (CPU s) | median wall | target | median / target |"
echo "|---|---|---|---|---|"
points() { # the points of NAME's first run
    local f
    for f in "$tmp/$1".1.csv "$tmp/$1".1-map.csv; do
        [ -f "$f" ] && echo $(($(wc -l <"$f") - 1)) && return
    done
}
row() { # name label target
    local runs med
    runs=$(awk '{printf "%s%s (%s)", (NR > 1 ? ", " : ""), $1, $2}' "$tmp/$1.t")
    med=$(wall "$1")
    if [ -n "$3" ]; then
        echo "| $2 | $runs | $med s | $3 s | **$(awk -v m="$med" -v t="$3" 'BEGIN {printf "%.2f", m / t}')×** |"
    else
        echo "| $2 | $runs | $med s | – | – |"
    fi
}
row study "study, $(points study) points (default --pair)" 2.0
row pair1 "study, --pair 1 (one chain at a time a thread)"
row figs "study with its figures (3 PNGs)" 2.0
[ $map = 1 ] && row map "map, $rows rows, $(points map) points" 60
echo
echo "pairing and batching: --pair 1 / default = $(awk -v a="$(wall pair1)" -v b="$(wall study)" 'BEGIN {printf "%.2f", a / b}')× in wall time"
npng=$(ls "$tmp"/figs.*.png 2>/dev/null | wc -l)
echo "figures: $npng PNGs from $rounds run(s) with figures"
[ "$npng" -eq $((3 * rounds)) ] || { echo "sweep_bench.sh: expected 3 PNGs a run"; exit 1; }
printf "study CSVs (every round, both --pair settings, with figures): "
same study pair1 figs || exit 1
