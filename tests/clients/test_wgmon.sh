#!/bin/sh
# test_wgmon.sh WORMGEARD WGMON WGCTL - the live monitor headless (--once,
# --frames) and interactive under tmux (draws, resizes, quits on q): usage
# errors, no daemon, a regime change after `wgctl set`, a daemon restart.
# Run through netns.sh (host-local URL only).
D=$1 M=$2 C=$3
code=0
tmp=$(mktemp -d) || exit 1
pid=
sock=wgmon-test-$$
cleanup() {
    [ -n "$pid" ] && kill -KILL "$pid" 2>/dev/null
    command -v tmux >/dev/null && tmux -L "$sock" kill-server 2>/dev/null
    rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; code=1; }
expect() {
    want=$1; shift
    "$@" >"$tmp/out" 2>"$tmp/err"; got=$?
    [ "$got" -eq "$want" ] || fail "$* -> exit $got, want $want: $(cat "$tmp/out" "$tmp/err")"
}
has() { grep -q -- "$2" "$tmp/$1" || fail "$1 lacks '$2': $(cat "$tmp/$1")"; }
export WORMGEAR_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0" WORMGEAR_PREFIX=MONT_
start() {
    "$D" --rate 0.01 --set omega=0.7 --state-dir "$tmp" >>"$tmp/d.out" 2>&1 &
    pid=$!
}

# ---- usage
expect 0 "$M" --help
for o in --url --prefix --window --fps --tol --once --frames --timeout --size --plain; do
    has out "$o"
done
has out "default 4; \[0.2, 30\]"
expect 2 "$M" --fps 99
has err "--fps '99': frames per second in \[0.2, 30\]"
expect 2 "$M" --size 10x10
has err "COLSxROWS"
expect 2 "$M" --bogus
has err "unknown option"
# ---- no daemon: --once waits --timeout, then exits 1
expect 1 "$M" --once --timeout 0.5
has out "waiting for MONT_STATUS"

# ---- a running daemon: one frame
start
expect 0 "$M" --once --size 100x30 --window 3
cat "$tmp/out"
has out "daemon  table3  realtime x0.01  running  ok"
has out "params  omega 0.7 xi_p 0.08"
has out "motion  daemon: single_sided"
has out "Poincare section"
has out "msgs    STATUS"
# ---- the regime change: omega 0.7 (impacts) -> 0.5 (no impact)
"$C" set omega=0.5 >/dev/null || fail "wgctl set"
sleep 2.5
expect 0 "$M" --once --size 100x30 --window 1
has out "params  omega 0.5 "
has out "last 1 s: no_impact, 0 impacts/period"
has out "local: period-1"

# ---- a daemon restart while watching: shows as a seq reset, keeps going
"$M" --frames 14 --fps 4 --size 100x20 >"$tmp/frames" 2>&1 &
mpid=$!
sleep 1
kill -TERM $pid; wait $pid
sleep 0.5
start
wait $mpid || fail "wgmon --frames exit $?"
grep -q "restarted x1" "$tmp/frames" || fail "no restart shown: $(grep '^daemon' "$tmp/frames")"
[ "$(grep -c '^wormgear monitor' "$tmp/frames")" -eq 14 ] || fail "not 14 frames"

# ---- interactive, in a tmux pane: draws, follows a resize, quits on q
if command -v tmux >/dev/null; then
    tmux -L "$sock" -f /dev/null new-session -d -x 120 -y 40 \
        "$M --fps 10; echo \$? >$tmp/rc" || fail "tmux new-session"
    sleep 2
    tmux -L "$sock" capture-pane -p >"$tmp/pane1"
    has pane1 "wormgear monitor"
    has pane1 "x_n trace .*Poincare section"   # side by side at 120 columns
    has pane1 "q: quit"
    tmux -L "$sock" resize-window -x 80 -y 40 2>/dev/null || tmux -L "$sock" refresh-client -C 80,40
    sleep 1
    tmux -L "$sock" capture-pane -p >"$tmp/pane2"
    has pane2 "^Poincare section"              # stacked at 80 columns
    awk 'length > 80 { exit 1 }' "$tmp/pane2" || fail "lines wider than 80 after resize"
    tmux -L "$sock" send-keys q
    i=0
    while [ ! -s "$tmp/rc" ] && [ $i -lt 30 ]; do sleep 0.1; i=$((i + 1)); done
    [ "$(cat "$tmp/rc" 2>/dev/null)" = 0 ] || fail "q did not quit with 0: $(cat "$tmp/rc" 2>/dev/null)"
else
    echo "tmux not installed: interactive checks skipped"
fi
kill -TERM $pid; wait $pid; pid=
exit $code
