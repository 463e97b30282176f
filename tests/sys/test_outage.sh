#!/bin/sh
# test_outage.sh WORMGEARD WGRIG WGCTL - the network goes away for two seconds in
# the middle of a rig sweep (its multicast route deleted, then added back),
# and again as a sweep is stopped:
# the daemon says once in its log that publishing fails and why, runs on,
# says once that it works again and how many messages were lost, and
# counts them on STATUS; wgrig's sweep ends with every point measured, a
# command it could not send said with the reason and sent again after a
# wait (before, six tries failed within a millisecond and the sweep
# stopped, exit 1), a recording the outage broke recorded again; the
# commands that put the daemon back after Ctrl-C wait for the network too.
#
# Runs in a network namespace of its own, through tests/netns.sh --own
# (the route it deletes is that namespace's): skipped (77) where none can
# be made. Never on the host: without --own it refuses to start.
D=$1 R=$2 C=$3
[ "${WG_OWN_NS:-}" = 1 ] ||
    { echo "test_outage.sh deletes a route: run it through tests/netns.sh --own"; exit 2; }
code=0
tmp=$(mktemp -d) || exit 1
dpid= rpid=
cleanup() { for p in $rpid $dpid; do kill -KILL "$p" 2>/dev/null; done; rm -rf "$tmp"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; code=1; }
. "$(dirname "$0")/../wait.sh" # wait_until, wait_exit
export WORMGEAR_URL="udpm://239.255.76.67:7667?ttl=0" WORMGEAR_PREFIX=OUT_
has() { grep -q -- "$2" "$1"; }

"$D" --state-dir "$tmp" >"$tmp/d.log" 2>&1 &
dpid=$!
wait_until 20 has "$tmp/d.log" "ready:" ||
    { fail "the daemon did not start"; cat "$tmp/d.log"; exit 1; }
"$R" --from 1.0 --to 1.2 --points 40 --dir up --fast --no-lle --out "$tmp/rig" \
    >"$tmp/rig.out" 2>"$tmp/rig.err" &
rpid=$!
wait_until 60 has "$tmp/rig.err" " 5/40 " || fail "wgrig did not reach its 5th point"
ip route del 239.0.0.0/8 dev lo
wait_until 10 has "$tmp/d.log" "publishing on LCM fails" ||
    fail "no line in the daemon's log when publishing failed"
sleep 2 # the outage
ip route add 239.0.0.0/8 dev lo
wait_exit "$rpid" 180
rpid=
[ "$exit_status" = 0 ] || fail "wgrig -> exit $exit_status, want 0"
wait_until 10 has "$tmp/d.log" "publishing on LCM works again" ||
    fail "no line in the daemon's log when publishing worked again"
echo "-- the daemon's log"
grep -v 'info: [rsm]' "$tmp/d.log"
echo "-- wgrig"
grep -v '^\[' "$tmp/rig.err"

has "$tmp/d.log" "warning: publishing on LCM fails: Network is unreachable ([0-9]* messages in \
the last second); the simulation runs on" ||
    fail "the failing line lacks the reason"
[ "$(grep -c 'publishing on LCM fails' "$tmp/d.log")" = 1 ] ||
    fail "the failing line more than once"
[ "$(grep -c 'publishing on LCM works again' "$tmp/d.log")" = 1 ] ||
    fail "the works-again line more than once"
lost=$(sed -n 's/.*works again: \([0-9]*\) messages were not published.*/\1/p' "$tmp/d.log")
[ "${lost:-0}" -gt 0 ] || fail "no count of the messages lost: $(grep 'works again' "$tmp/d.log")"
has "$tmp/rig.err" "40/40 points" || fail "wgrig did not measure every point"
[ "$(grep -c '' "$tmp/rig.csv")" -ge 41 ] || fail "rig.csv has fewer than 40 points"
# what the outage hit: a set it could not send (Release, 5 of 5 runs), a
# recording it broke (ASan, 3 of 3), or a settle (it would be skipped
# over: the part after this one hits a send every time)
if has "$tmp/rig.err" "not sent:"; then
    has "$tmp/rig.err" "wgrig: set omega=[0-9.]* not sent: LCM could not send it on OUT_CMD: \
Network is unreachable; trying again in 3 s" ||
        fail "the line of a command not sent lacks its reason"
elif ! grep -q '[1-9][0-9]* recordings re-waited' "$tmp/rig.err"; then
    echo "note: the outage fell in a settle, hitting neither a command nor a recording"
fi

# The outage at a sweep's end, when wgrig must send: Ctrl-C with the route
# gone; its commands that put the daemon back (omega, mode realtime) are
# sent once the route is back (before, they failed at once and left the
# daemon in fast mode at the last point's omega).
"$R" --from 1.0 --to 1.2 --points 40 --dir up --fast --no-lle --out "$tmp/rig2" \
    >"$tmp/rig2.out" 2>"$tmp/rig2.err" &
rpid=$!
wait_until 60 has "$tmp/rig2.err" " 5/40 " || fail "the second wgrig did not reach its 5th point"
ip route del 239.0.0.0/8 dev lo
kill -INT "$rpid"
wait_until 20 has "$tmp/rig2.err" \
    "not sent: LCM could not send it on OUT_CMD: Network is unreachable" ||
    fail "the second wgrig did not say that a command was not sent: $(cat "$tmp/rig2.err")"
ip route add 239.0.0.0/8 dev lo
wait_exit "$rpid" 60
rpid=
[ "$exit_status" = 130 ] || fail "the second wgrig -> exit $exit_status, want 130 (interrupted)"
echo "-- the second wgrig, stopped in the outage"
grep -v '^\[' "$tmp/rig2.err"
"$C" get omega >"$tmp/get" 2>&1 || fail "wgctl get omega -> exit $?: $(cat "$tmp/get")"
has "$tmp/get" "omega = 1  " || fail "omega not put back to 1: $(cat "$tmp/get")"

# the daemon answers, and its STATUS counts what it could not publish
"$C" status >"$tmp/st" 2>&1 || fail "wgctl status -> exit $?: $(cat "$tmp/st")"
has "$tmp/st" "messages  *[0-9]* not published" || fail "STATUS lacks the count: $(cat "$tmp/st")"
has "$tmp/st" "mode realtime" || fail "the daemon not put back to realtime: $(cat "$tmp/st")"
kill -TERM "$dpid"
wait_exit "$dpid" 10
dpid=
[ "$exit_status" = 0 ] || fail "wormgeard -> exit $exit_status on SIGTERM"
[ "$code" = 0 ] && echo "ok: a 2 s outage in a sweep: $lost messages lost, the sweep whole"
exit $code
