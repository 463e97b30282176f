#!/bin/sh
# test_wait.sh - tests/wait.sh, which the test scripts wait with, run by
# both shells that source it (dash as sh, and bash): wait_until returns as
# soon as its condition holds and gives up after its bound in wall time,
# however long each try takes; wait_exit and stop give the exit status,
# or "timeout" with the process killed.
. "$(dirname "$0")/wait.sh"
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
code=0
fail() { echo "FAIL: $*"; code=1; }
ms() { echo $(($(date +%s%N) / 1000000)); }

t0=$(ms); wait_until 5 true; rc=$? t=$(($(ms) - t0))
[ $rc -eq 0 ] && [ $t -lt 1000 ] || fail "wait_until 5 true: $rc after $t ms, want 0 at once"

(sleep 0.5; touch "$tmp/f") &
t0=$(ms); wait_until 20 test -e "$tmp/f"; rc=$? t=$(($(ms) - t0))
[ $rc -eq 0 ] && [ $t -ge 400 ] && [ $t -lt 10000 ] ||
    fail "a file made after 0.5 s: $rc after $t ms, want 0 once it is there"

t0=$(ms); wait_until 1 false; rc=$? t=$(($(ms) - t0))
[ $rc -eq 1 ] && [ $t -ge 1000 ] && [ $t -lt 10000 ] || fail "wait_until 1 false: $rc after $t ms, want 1 after 1 s"

slow() { sleep 0.7; false; } # a try of 0.7 s: the bound is wall time, not 10 tries
t0=$(ms); wait_until 1 slow; rc=$? t=$(($(ms) - t0))
[ $rc -eq 1 ] && [ $t -ge 1000 ] && [ $t -lt 5000 ] || fail "wait_until 1 slow: $rc after $t ms, want 1 after 1-2 s"

wait_until 1 test "a b" = "a b" || fail "arguments with spaces not passed whole"
out=$(wait_until 1 sh -c 'echo said; exit 1')
[ -n "$out" ] && [ -z "$(printf '%s\n' "$out" | grep -v '^said$')" ] ||
    fail "wait_until wrote something of its own: '$out'"

sh -c 'sleep 0.3; exit 3' &
wait_exit $! 10
[ "$exit_status" = 3 ] || fail "wait_exit of 'exit 3': '$exit_status'"

sleep 30 &
p=$!
t0=$(ms); wait_exit $p 1; t=$(($(ms) - t0))
[ "$exit_status" = timeout ] && [ $t -lt 5000 ] || fail "wait_exit 1 s of sleep 30: '$exit_status' after $t ms"
kill -0 $p 2>/dev/null && fail "wait_exit left the timed-out process running"

sleep 30 &
p=$!
# HUP only once the child is sleep: before its exec it is a copy of this shell,
# whose handlers (bash's, with an EXIT trap) may take the HUP (seen once in CI)
execd() { [ "$(cat /proc/$p/comm 2>/dev/null)" = sleep ]; }
wait_until 5 execd
stop $p HUP
[ "$exit_status" = 129 ] || fail "stop HUP of sleep 30: '$exit_status', want 129"

[ $code -eq 0 ] && echo "ok: wait.sh in $(readlink /proc/$$/exe)"
exit $code
