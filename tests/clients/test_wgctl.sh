#!/bin/sh
# test_wgctl.sh WORMGEARD WGCTL WGSPOOF - what a new user reads from wgctl:
# units ("-" for dimensionless, the physical equivalent beside), `get
# NAME...`, and the question to ask when no daemon answers; and `status`
# from a hostile sender (tests/clients/wgspoof.c): its strings' escapes
# never reach the terminal, and --json stays JSON. Run through netns.sh
# (host-local URL only).
D=$1 C=$2 SPOOF=$3
code=0
tmp=$(mktemp -d) || exit 1
pid=
cleanup() { [ -n "$pid" ] && kill -KILL "$pid" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
export WORMGEAR_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0" WORMGEAR_PREFIX=UCTL_

fail() { echo "FAIL: $*"; code=1; }
. "$(dirname "$0")/../wait.sh" # wait_until
expect() {
    want=$1; shift
    "$@" >"$tmp/out" 2>"$tmp/err"; got=$?
    [ "$got" -eq "$want" ] || fail "$* -> exit $got, want $want: $(cat "$tmp/out" "$tmp/err")"
}
has() { grep -q -- "$2" "$tmp/$1" || fail "$1 lacks '$2': $(cat "$tmp/$1")"; }
hasnt() { grep -q -- "$2" "$tmp/$1" && fail "$1 has '$2': $(grep -- "$2" "$tmp/$1")"; }

# ---- params needs no daemon: a dash for dimensionless, the physical rule
expect 0 "$C" params
has out "^omega -    \[0.01, 10\] "
has out "physical: Hz = omega omega_n / 2 pi"
has out "^b     -    .*physical: µm = b b_c"
has out "^phi1  rad "
hasnt out " 1 \[0"
# a range as shown is accepted: 2 pi rounded inwards (it read 6.28319 > 2 pi)
has out "^phi1  rad  \[-6.28318, 6.28318\] "
# ---- refused before sending: a prefix the daemon would not take, an empty
# URL, an infinite duration (each was sent, or failed inside LCM); with
# --json the refusal is an object on stdout too
expect 2 "$C" --prefix 'a b' status
has err "^wgctl: --prefix 'a b': need \[A-Za-z0-9_.-\], at most 40 characters"
expect 2 "$C" --prefix "$(printf 'p%.0s' $(seq 1 100))" status
expect 2 "$C" --url= status
has err "^wgctl: --url '': need an LCM URL"
expect 2 "$C" ramp omega 1 --over infs
has err "^wgctl: --over 'infs': a positive duration"
expect 2 "$C" --json ramp omega 1 --over infs
has out '^{"accepted":false,"code":"EUSAGE","message":"usage error (see stderr)"}$'
# a duration given without --over, or NAME=TO: the command line to type (it
# said only "--over DURATION is required")
expect 2 "$C" ramp omega 1 2 30s
has err "^wgctl: ramp: '30s' is a duration: give it with --over (wgctl ramp omega 1 2 --over 30s)"
expect 2 "$C" ramp omega=1.3 5s
has err "(wgctl ramp omega 1.3 --over 5s)"
expect 2 "$C" ramp omega=1.3 --over 5s
has err "^wgctl: ramp: expected NAME \[FROM\] TO --over DURATION, with spaces (got 'omega=1.3')"
# an unknown command lists the known ones; help is --help
expect 2 "$C" snapshot
has err "^wgctl: unknown command 'snapshot' (one of: set, ramp, step, tick, save, restore, mode, pause, resume, reset, get, status, contacts, params, keygen)"
expect 0 "$C" help
has out "^usage: wgctl"
# ---- get NAME: names are checked before any message is sent
expect 2 "$C" get nosuch
has err "get: 'nosuch' is not a parameter (wgctl params lists them)"
# ---- no daemon: the question names the URL and the prefix
expect 1 "$C" --timeout 0.3 get omega
has err "no answer within 0.3 s: is wormgeard running on $WORMGEAR_URL with prefix UCTL_?"
expect 1 "$C" --timeout 0.3 status
has err "is wormgeard running on $WORMGEAR_URL with prefix UCTL_?"
# a command longer than one datagram holds: not sent, and said why (the daemon's socket
# filter drops fragments: it would go unanswered)
for len in 65400 100000; do
    expect 1 "$C" --timeout 0.3 save "$(head -c $len /dev/zero | tr '\0' n)"
    has err "^wgctl: save not sent: the message is [0-9]* bytes with its channel UCTL_CMD, over the 65499 one datagram holds"
done
# --json: the object carries the same question (it said only "no ACK within 0.3 s")
expect 1 "$C" --json --timeout 0.3 get omega
has out '^{"accepted":false,"code":"ETIMEDOUT","message":"no ACK within 0.3 s: is wormgeard running on .* with prefix UCTL_?'
python3 -c 'import json, sys; json.load(open(sys.argv[1]))' "$tmp/out" || fail "--json timeout: not JSON: $(cat "$tmp/out")"

# ---- a daemon: get with units
"$D" --rate 0.01 --state-dir "$tmp" >"$tmp/d.out" 2>&1 &
pid=$!
wait_until 10 "$C" --timeout 0.5 status >/dev/null 2>&1 || fail "no daemon: $(cat "$tmp/d.out")"
expect 0 "$C" get
has out "^scale omega_n = 31901 rad/s, b_c = 100 µm"
has out "^  omega = 1 *-    5077.2 Hz$"
has out "^  b     = 1 *-    100 µm$"
has out "^  xi_p  = 0.08 *-    "
has out "^  phi1  = 1.613 *rad  92.4181 deg$"
has out "^  mu1   = 2.7442 *-    0.716056 kg$"
has out "^  k1x   = 21.198 *-    1.5447.e+10 N/m$"
has out "^  a1    = 0.24724948462317603 -$"
has out "^  z2    = 37 *-$"
has out "^  rho1  = 220 *-    22 mm$"
has out "^  j1    = 0.18221 *-    0.0001732[0-9]* kg m^2$"
# no unit column reads "1" any more
hasnt out "= [^ ]* *1$"
[ "$(grep -c '^  [a-z_0-9]* *= ' "$tmp/out")" -eq 35 ] || fail "get: not 35 parameter lines"
expect 0 "$C" get omega b_j
[ "$(wc -l <"$tmp/out")" -eq 2 ] || fail "get omega b_j: not two lines: $(cat "$tmp/out")"
has out "^  omega = 1 "
has out "^  b_j   = 1 .*100 µm"
expect 0 "$C" --json get omega
has out '"params":{"omega":1},"physical":{"omega":{"value":5077.20'
has out '"length_m":0.0001'
# a ramp of xi_p: status says a ramp runs, not that omega is ramping
expect 0 "$C" ramp xi_p 0.2 --over 1000s
ramping() { "$C" status >"$tmp/st" 2>&1 && grep -q "^ramp " "$tmp/st"; }
wait_until 20 ramping
has st "^ramp      a parameter is ramping (wgctl get names it)$"
hasnt st "(ramping)"
kill -TERM "$pid"; wait "$pid"; pid=

# ---- status from a hostile sender: STATUS strings with markup, quotes,
# ESC, BEL, a C1 CSI and a byte that is not UTF-8
"$SPOOF" "$WORMGEAR_URL" UCTS_ 4 >"$tmp/spoof.out" 2>&1 &
spid=$!
expect 0 "$C" --prefix UCTS_ status
cp "$tmp/out" "$tmp/human"
expect 0 "$C" --prefix UCTS_ --json status
cp "$tmp/out" "$tmp/json"
kill "$spid" 2>/dev/null; wait "$spid" 2>/dev/null
has human '^scene spoof, mode realtime .*health ok: <img src=x onerror="window.wgPwned=1"> ?\[2J?\]0;pwned? ?31m ?$'
has human "regime <b id=wgpwn>P9</b>?\[31m$"
has human '^messages  5 not published; commands '
has human '^ticks     7 lost on the way (gaps in their seq)$'
has human '^ticks     3 refused; the last: <img src=x onerror="window.wgPwned=2"> ?\[2J?\]0;pwned?$'
for f in human json; do
    LC_ALL=C grep -q "$(printf '[\033\007\377]')" "$tmp/$f" && fail "status ($f): an escape or a non-UTF-8 byte printed"
    LC_ALL=C grep -q "$(printf '\302\233')" "$tmp/$f" && fail "status ($f): a C1 CSI printed"
done
python3 -c 'import json, sys; s = json.load(open(sys.argv[1])); assert s["regime"] == "<b id=wgpwn>P9</b>?[31m", s["regime"]; assert s["fault"].startswith("<img src=x onerror=\"window"), s["fault"]; assert s["ticks_lost"] == 7 and s["msgs_dropped"] == 5; assert s["ticks_refused"] == 3 and s["tick_refusal"].startswith("<img src=x onerror=\"window.wgPwned=2"), s' "$tmp/json" ||
    fail "status --json: not JSON, or the strings changed: $(cat "$tmp/json")"
exit $code
