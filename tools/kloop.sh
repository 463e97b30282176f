#!/usr/bin/env bash
# Instructions per pass of the hottest loop (the largest backward jump) in
# the table3 kernel's code, for each instruction set: wg_krun's loop
# (krun_111111: the kernel plus the run's bookkeeping) in the library's
# objects, and bench_pair's bare loop (`one`). With the ns/step of
# bench_step / bench_pair this gives instructions per cycle.
# usage: tools/kloop.sh BUILD_DIR        (needs objdump, python3)
# --help: this text.
set -euo pipefail
. "$(dirname "$0")/args.sh"
args_help "$@"
[ $# -eq 1 ] || args_refuse kloop.sh "BUILD_DIR, one argument, got $#"
[ -d "$1/lib" ] || args_refuse kloop.sh "BUILD_DIR '$1': no lib/ in it (a build directory, e.g. build/release)"
build=$1
count() { # FILE FUNCTION-REGEX
  objdump -d --no-show-raw-insn "$1" | python3 -c '
import re, sys
want = re.compile(sys.argv[1])
ins, on = [], False
for line in sys.stdin:
    m = re.match(r"^[0-9a-f]+ <([^>]+)>:$", line)
    if m:
        if on:
            break
        on = bool(want.fullmatch(m.group(1)))
        continue
    m = re.match(r"\s*([0-9a-f]+):\s+(\S+)\s*(.*)", line)
    if on and m:
        ins.append((int(m.group(1), 16), m.group(2), m.group(3)))
best = None
for a, op, arg in ins:
    t = re.match(r"([0-9a-f]+)", arg)
    if op.startswith("j") and t and int(t.group(1), 16) < a:
        body = [x for x in ins if int(t.group(1), 16) <= x[0] <= a]
        if best is None or len(body) > len(best):
            best = body
if not best:
    sys.exit("no loop")
mem = sum("(%" in x[2] for x in best)
print("%d instructions, %d with a memory operand" % (len(best), mem))
' "$2"
}
echo "| code | instruction set | loop |"
echo "|---|---|---|"
for isa in sse2 avx2 avx512 avx512vl; do
  suffix=$([ $isa = sse2 ] && echo "" || echo "_$isa")
  obj=$(find "$build" -name "wg_kernel$suffix.c.o" | head -1)
  [ -n "$obj" ] && echo "| wg_krun (krun_111111) | $isa | $(count "$obj" 'krun_111111') |"
  bin=$build/tests/bench/bench_pair_$isa
  [ -x "$bin" ] && echo "| bench_pair, bare kernel | $isa | $(count "$bin" 'one(\.\S+)?') |"
done
