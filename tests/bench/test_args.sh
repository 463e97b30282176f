#!/bin/sh
# test_args.sh SRC BUILD - every benchmark's command line, as a newcomer
# types it (bench_args.h; the scripts' own checks): --help and -h print the
# usage on standard output and exit 0; a value that is not allowed, an
# unknown option or an operand too many gets one refusal on standard error
# that names what was typed, exit 2, and nothing runs (standard output
# stays empty). The cases that once went wrong: bench_step 0 divided by
# zero, bench_step with 33 repetitions sorted 33 timings in an array of
# 32, bench_gsl --help timed zero steps, and wgd_bench --help exec'd
# "--help" as the daemon and then waited a second for each of 1,500
# unanswered commands: now a daemon that exits ends wgd_bench at once with
# its status. The benchmarks built with -DWG_BUILD_BENCH=ON are checked
# when BUILD has them.
# Run through netns.sh (wgd_bench starts a daemon).
src=$1 build=$2
bin=$build/tests/bench
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
export WG_SCENE_PATH="$src/scenes"
status=0
fail() { echo "FAIL: $*"; status=1; }

# run CMD...: rc, stdout and stderr of CMD (30 s at most) into $rc, $tmp/o, $tmp/e
run() {
    timeout 30 "$@" >"$tmp/o" 2>"$tmp/e"
    rc=$?
}

# help NAME CMD...: CMD --help and CMD -h print "usage: NAME" first, on
# standard output only, and exit 0
help() {
    name=$1
    shift
    for h in --help -h; do
        run "$@" $h
        [ $rc -eq 0 ] || fail "$name $h: exit $rc"
        head -1 "$tmp/o" | grep -q "^usage: $name" || fail "$name $h: no usage line: $(head -3 "$tmp/o")"
        [ -s "$tmp/e" ] && fail "$name $h wrote to standard error: $(cat "$tmp/e")"
    done
}

# refused NAME PATTERN CMD...: exit 2, nothing on standard output, and a
# refusal on standard error that matches PATTERN (grep -E) and says where
# the usage is
refused() {
    name=$1 pat=$2
    shift 2
    run "$@"
    [ $rc -eq 2 ] || fail "$name: '$*' exit $rc, not 2 (refused): $(head -3 "$tmp/e")"
    [ -s "$tmp/o" ] && fail "$name: '$*' ran: $(head -3 "$tmp/o")"
    grep -Eq -- "$pat" "$tmp/e" || fail "$name: '$*': no '$pat' in: $(cat "$tmp/e")"
    grep -q -- "--help" "$tmp/e" || fail "$name: '$*': the refusal does not point to --help"
    [ $status -eq 0 ] && echo "ok: $(echo "$*" | sed "s|$bin/||; s|$build/||g") -> $(head -1 "$tmp/e")"
}

# the operands each benchmark takes: NAME then a refused first operand's name
n=0
for b in bench_step bench_pair_sse2 bench_pair_avx2 bench_pair_avx512 bench_ports bench_mac \
    bench_gsl bench_wp bench_long; do
    [ -x "$bin/$b" ] || continue
    n=$((n + 1))
    help $b "$bin/$b"
    refused $b "unknown option '--bogus'" "$bin/$b" --bogus
    refused $b "unknown option '-x'" "$bin/$b" -x
    case $b in
    bench_ports | bench_mac) refused $b "'1 *': an operand too many \(at most 1\)" "$bin/$b" 1 1 ;;
    *) refused $b "'7': an operand too many \(at most 2\)" "$bin/$b" 1000 1 7 ;;
    esac
done
[ $n -ge 6 ] || fail "only $n benchmarks in $bin"

refused bench_step "STEPS '0': .*1000 to 1e9" "$bin/bench_step" 0
refused bench_step "STEPS 'abc': " "$bin/bench_step" abc
refused bench_step "STEPS '2.5': " "$bin/bench_step" 2.5
refused bench_step "REPS '33': .*1 to 32" "$bin/bench_step" 1000 33
refused bench_step "REPS '0': " "$bin/bench_step" 1000 0
refused bench_pair_sse2 "REPS '65': .*1 to 64" "$bin/bench_pair_sse2" 1000 65
refused bench_pair_sse2 "STEPS '999': " "$bin/bench_pair_sse2" 999
refused bench_ports "REPS '101': .*1 to 100" "$bin/bench_ports" 101
refused bench_mac "REPEATS '-1': " "$bin/bench_mac" -1
if [ -x "$bin/bench_gsl" ]; then
    refused bench_gsl "REPS '32': .*1 to 31" "$bin/bench_gsl" 1000 32
    refused bench_wp "DIR '$tmp/none': No such file" "$bin/bench_wp" "$tmp/none" 1
    refused bench_wp "DIR '$src/README.md': not a directory" "$bin/bench_wp" "$src/README.md"
    refused bench_wp "REPS '16': .*1 to 15" "$bin/bench_wp" "$tmp" 16
    refused bench_long "STEPS '1e13': " "$bin/bench_long" 1e13
    refused bench_long "SCENE: scene 'nosuch' not found" "$bin/bench_long" 1000 nosuch
fi
# a run within the limits still runs (the smallest bench_step, a few seconds)
run "$bin/bench_step" 1000 1
[ $rc -eq 0 ] && grep -q '^| torsional |' "$tmp/o" || fail "bench_step 1000 1: exit $rc: $(head -3 "$tmp/e")"

# wgd_bench: WORMGEARD first, required; the rest goes to the daemon
d=$build/daemon/wormgeard
help wgd_bench "$bin/wgd_bench"
refused wgd_bench "WORMGEARD missing" "$bin/wgd_bench"
refused wgd_bench "WORMGEARD missing" "$bin/wgd_bench" --rt-priority 10
refused wgd_bench "WORMGEARD '$tmp/none': No such file" "$bin/wgd_bench" "$tmp/none"
refused wgd_bench "WORMGEARD '$src/README.md': Permission denied" "$bin/wgd_bench" "$src/README.md"
refused wgd_bench "SECONDS '0': .*1 to 3600" "$bin/wgd_bench" "$d" 0
refused wgd_bench "NCMDS '1e6': .*1 to 100000" "$bin/wgd_bench" "$d" 1 1e6
# a daemon that refuses its options exits 2 at once: wgd_bench says so and
# exits 1 after its 3 s start-up wait, not after 1,500 one-second timeouts
start=$(date +%s)
run "$bin/wgd_bench" "$d" 1 5 --rt-priority 500
took=$(($(date +%s) - start))
[ $rc -eq 1 ] || fail "wgd_bench with a refused daemon option: exit $rc, not 1"
grep -q "rt_priority: '500'" "$tmp/e" || fail "wgd_bench: the daemon's refusal not shown: $(cat "$tmp/e")"
grep -q "^wgd_bench: the daemon exited with status 2" "$tmp/e" || fail "wgd_bench: no word of the daemon's exit: $(cat "$tmp/e")"
[ $took -le 10 ] || fail "wgd_bench took $took s to see its daemon gone"
[ -s "$tmp/o" ] && fail "wgd_bench printed figures without a daemon: $(head -3 "$tmp/o")"
[ $status -eq 0 ] && echo "ok: wgd_bench with a daemon that exits: exit 1 after $took s"

# the scripts
for s in sweep_bench.sh web_bench.sh; do
    for h in --help -h; do
        run bash "$src/tests/bench/$s" $h
        [ $rc -eq 0 ] && head -1 "$tmp/o" | grep -q "^$s " || fail "$s $h: exit $rc: $(head -2 "$tmp/o")"
    done
done
run bash "$src/tests/bench/sweep_bench.sh" "$build" 3 maps
[ $rc -eq 2 ] && grep -q "unknown argument 'maps'" "$tmp/e" || fail "sweep_bench.sh maps: exit $rc"
run sh "$src/tests/bench/web_bench.sh" "$d" "$build/clients/wgweb" 3
[ $rc -eq 2 ] && grep -q "SECONDS '3': .*8 to 3600" "$tmp/e" || fail "web_bench.sh SECONDS 3: exit $rc: $(cat "$tmp/e")"
run sh "$src/tests/bench/web_bench.sh" "$d" "$tmp/none"
[ $rc -eq 2 ] && grep -q "WGWEB '$tmp/none': not an executable" "$tmp/e" || fail "web_bench.sh no wgweb: exit $rc: $(cat "$tmp/e")"
[ $status -eq 0 ] && echo "ok: sweep_bench.sh and web_bench.sh: --help, -h and refusals"
exit $status
