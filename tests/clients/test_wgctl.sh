#!/bin/sh
# test_wgctl.sh WORMGEARD WGCTL - what a new user reads from wgctl: units
# ("-" for dimensionless, the physical equivalent beside), `get NAME...`,
# and the question to ask when no daemon answers. Run through netns.sh
# (host-local URL only).
D=$1 C=$2
code=0
tmp=$(mktemp -d) || exit 1
pid=
cleanup() { [ -n "$pid" ] && kill -KILL "$pid" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
export WORMGEAR_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0" WORMGEAR_PREFIX=UCTL_

fail() { echo "FAIL: $*"; code=1; }
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
# ---- get NAME: names are checked before any message is sent
expect 2 "$C" get nosuch
has err "get: 'nosuch' is not a parameter (wgctl params lists them)"
# ---- no daemon: the question names the URL and the prefix
expect 1 "$C" --timeout 0.3 get omega
has err "no answer within 0.3 s: is wormgeard running on $WORMGEAR_URL with prefix UCTL_?"
expect 1 "$C" --timeout 0.3 status
has err "is wormgeard running on $WORMGEAR_URL with prefix UCTL_?"

# ---- a daemon: get with units
"$D" --rate 0.01 --state-dir "$tmp" >"$tmp/d.out" 2>&1 &
pid=$!
i=0
until "$C" --timeout 0.5 status >/dev/null 2>&1 || [ $i -ge 20 ]; do i=$((i + 1)); done
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
kill -TERM "$pid"; wait "$pid"; pid=
exit $code
