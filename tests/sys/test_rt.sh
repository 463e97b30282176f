#!/bin/sh
# test_rt.sh WORMGEARD - the rt_priority key (--rt-priority): every thread
# of the daemon, LCM's receive thread included (it inherits the policy),
# runs SCHED_FIFO at that priority; without the privilege (user nobody,
# RLIMIT_RTPRIO 0) the daemon warns once, says what is needed, and runs on
# the normal scheduler; a value out of [0, 99] is a configuration error
# (exit 2) that names the range. Host-local (netns.sh, a ttl=0 URL).
# Exit 77 (skipped) when not root: both runs need to choose their user.
D=$1
[ "$(id -u)" = 0 ] || { echo "SKIP: needs root"; exit 77; }
tmp=$(mktemp -d) || exit 1
chmod 777 "$tmp"
pid=
trap '[ -n "$pid" ] && kill -KILL $pid 2>/dev/null; rm -rf "$tmp"' EXIT
url="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0"
fail() { echo "FAIL: $*"; for f in "$tmp"/*.log; do echo "--- $f"; cat "$f"; done; exit 1; }
. "$(dirname "$0")/../wait.sh" # wait_until

# start NAME [command prefix...]: the daemon with --rt-priority 10, its
# threads' scheduling classes and priorities once it runs, then SIGTERM
run() {
    name=$1; shift
    "$@" "$D" --url "$url" --prefix RT_ --state-dir "$tmp" --rt-priority 10 >"$tmp/$name.log" 2>&1 &
    pid=$!
    wait_until 5 grep -q "info: ready:" "$tmp/$name.log" 2>/dev/null
    sleep 0.5
    ps -L -o tid=,cls=,rtprio= -p $pid >"$tmp/$name.threads"
    kill -TERM $pid
    wait $pid
    rc=$?
    pid=
    echo "$name: exit $rc; threads (tid class priority):"
    cat "$tmp/$name.threads"
    [ $rc -eq 0 ] || fail "$name: exit $rc after SIGTERM"
}

run root
[ "$(wc -l <"$tmp/root.threads")" -ge 2 ] || fail "root: expected LCM's receive thread besides the main one"
awk '$2 != "FF" || $3 != 10 { bad++ } END { exit bad > 0 }' "$tmp/root.threads" ||
    fail "root: a thread not SCHED_FIFO 10"
grep -q "rt_priority 10: every thread runs SCHED_FIFO" "$tmp/root.log" || fail "root: no info line"
echo "ok root: every thread SCHED_FIFO 10"

run nobody prlimit --rtprio=0:0 setpriv --reuid=65534 --regid=65534 --clear-groups --inh-caps=-all
awk '$2 != "TS" { bad++ } END { exit bad > 0 }' "$tmp/nobody.threads" || fail "nobody: a thread not SCHED_OTHER"
n=$(grep -c "rt_priority 10: SCHED_FIFO refused: .*CAP_SYS_NICE.*running on the normal scheduler" "$tmp/nobody.log")
[ "$n" -eq 1 ] || fail "nobody: $n warnings, want exactly 1"
echo "ok nobody: one warning, the normal scheduler, a clean exit"

out=$("$D" --rt-priority 100 --check-config 2>&1)
rc=$?
echo "--rt-priority 100: exit $rc: $out"
[ $rc -eq 2 ] || fail "out of range: exit $rc, want 2"
echo "$out" | grep -q "rt_priority: '100' must be an integer in \[0, 99\]" || fail "out of range: message"
echo "ok"
