#!/bin/sh
# test_wgrig.sh WORMGEARD WGRIG WGSWEEP WGCTL WGSPOOF - a live stepwise sweep of the real
# daemon (fast mode) against the offline sweep of the same scene, N and grid:
# the same regime, period, motion, impacts and x_n extremes at omega = 0.5
# and 1.7 both ways and 1.5 down (points whose attractor does not depend on
# the phase at which the daemon applies the step: 0.7, 0.9, 1.1, 1.3 and 1.5
# up have coexisting orbits or long transients, and land on either); the outputs exist; the
# CONTACT impacts equal the POINCARE statistics; a ramp (beside a hostile
# sender whose PARAMS the rig ignores) and the value put back after it, also
# when stopped mid-ramp; refusals (every point refused: no outputs written,
# an earlier run's stay; some refused: their rows hold no values); usage.
# Run through netns.sh (host-local URL only).
D=$1 R=$2 S=$3 C=$4 SPOOF=$5
code=0
tmp=$(mktemp -d) || exit 1
pid=
cleanup() { [ -n "$pid" ] && kill -KILL "$pid" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; code=1; }
. "$(dirname "$0")/../wait.sh" # wait_until, stop

expect() {
    want=$1; shift
    "$@" >"$tmp/out" 2>"$tmp/err"; got=$?
    [ "$got" -eq "$want" ] || fail "$* -> exit $got, want $want: $(tail -5 "$tmp/out" "$tmp/err")"
}
has() { grep -q -- "$2" "$tmp/$1" || fail "$1 lacks '$2': $(tail -5 "$tmp/$1")"; }
export WORMGEAR_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0" WORMGEAR_PREFIX=RIGT_

# ---- usage
expect 0 "$R" --help
for o in --url --prefix --param --from --points --dir --settle --record --extend --ramp --bins \
         --tol --no-lle --fast --keep --out --timeout --stall --retries --quiet; do
    has out "$o"
done
expect 2 "$R" --from 0.5
has err "^wgrig: --to is required (the range of the sweep)"
expect 2 "$R" --from 0.5 --to 20
has err "omega = 20 out of range \[0.01, 10\]"
expect 2 "$R" --from 2 --to 1 --out "$tmp/swapped"
has err "^wgrig: --from 2 --to 1: --from must be below --to (give the range's lower end as --from; --dir up, down or both"
expect 2 "$R" --from 0.5 --to 1 --dir sideways
has err "\-\-dir 'sideways': one of up, down, both"
expect 2 "$R" --param nosuch --from 0 --to 1
has err "\-\-param 'nosuch'"
# a tolerance in the library's range, as wgsweep's (1e300 was taken)
expect 2 "$R" --from 0.5 --to 1 --tol 1e300
has err "^wgrig: --tol '1e300': a tolerance in \[1e-13, 0.0001\]"
expect 1 "$R" --from 0.5 --to 1 --timeout 0.2 --retries 0 --out "$tmp/none"
has err "no ACK"

# ---- live vs offline
"$D" --mode realtime --rate 0.01 --set omega=0.5 --state-dir "$tmp" >"$tmp/d.out" 2>&1 &
pid=$!
sleep 0.5
expect 0 "$R" --from 0.5 --to 1.7 --points 7 --fast --out "$tmp/live"
cat "$tmp/err"
expect 0 "$S" --from 0.5 --to 1.7 --points 7 --steps-per-period 128 --threads 1 --quiet \
    --no-png --no-json --out "$tmp/off"
for f in live.csv live-poincare.csv live.json live.md live.png live-sections.csv \
         live-impacts.csv live-impacts.png; do
    [ -s "$tmp/$f" ] || fail "no $f"
done
# dir,index,omega,regime,period,converged,motion,impacts,min_xn,max_xn
for wd in 0.5/up 0.5/down 1.5/down 1.7/up 1.7/down; do
    w=${wd%/*} d=${wd#*/}
    {
        a=$(awk -F, -v w=$w -v d=$d '$1 == d && $3 == w { print $4, $5, $7, $8 }' "$tmp/live.csv")
        b=$(awk -F, -v w=$w -v d=$d '$1 == d && $3 == w { print $4, $5, $7, $8 }' "$tmp/off.csv")
        echo "omega $w $d: live [$a] offline [$b]"
        [ -n "$a" ] && [ "$a" = "$b" ] || fail "omega $w $d: live [$a] != offline [$b]"
        awk -F, -v w=$w -v d=$d 'NR == FNR { if ($1 == d && $3 == w) { m = $9; M = $10 }; next }
            $1 == d && $3 == w { dm = $9 - m; dM = $10 - M; if (dm < 0) dm = -dm; if (dM < 0) dM = -dM
                                 exit !(dm < 1e-6 && dM < 1e-6) }' "$tmp/live.csv" "$tmp/off.csv" ||
            fail "omega $w $d: x_n extremes differ by more than 1e-6"
        # each bearing's impacts per period (from POINCARE's period statistics)
        la=$(awk -F, -v w=$w -v d=$d 'NR == 1 { for (i = 1; i <= NF; i++) if ($i ~ /^[xyz][12]_impacts_per_period$/) c[++n] = i; next }
            $1 == d && $3 == w { for (k = 1; k <= n; k++) printf "%s ", $c[k] }' "$tmp/live.csv")
        lb=$(awk -F, -v w=$w -v d=$d 'NR == 1 { for (i = 1; i <= NF; i++) if ($i ~ /^[xyz][12]_impacts_per_period$/) c[++n] = i; next }
            $1 == d && $3 == w { for (k = 1; k <= n; k++) printf "%s ", $c[k] }' "$tmp/off.csv")
        echo "omega $w $d: bearing impacts per period [$la]"
        [ -n "$la" ] && [ "$la" = "$lb" ] || fail "omega $w $d: bearing impacts live [$la] != offline [$lb]"
    }
done
# impacts per period: CONTACT events agree with the POINCARE statistics
# (an empty CONTACT column: messages lost inside that window, said so, not compared)
awk -F, 'NR > 1 && $6 > 0 && $5 != "" { d = $4 - $5; if (d < 0) d = -d; if (d > 1e-9) bad++ } END { exit bad > 0 }' \
    "$tmp/live-impacts.csv" || fail "CONTACT and POINCARE impacts differ: $(cat "$tmp/live-impacts.csv")"
expect 0 "$C" status
has out "mode realtime (rate 0.01)"       # --fast restored the mode
has out "^omega     0\.5$"                  # and the original omega (no --keep)

# ---- partly refused: k1x 5050 and 10000 cross the RK4 limit at N = 128
# and omega 0.5 (ESTABILITY); 100 is measured. A refused point's rows have its value, regime
# none and nothing else (they read "none,0,0,no_impact,0,nan,..,0.000e+00"),
# its progress line says so, and the .md lists it.
expect 0 "$R" --param k1x --from 100 --to 10000 --points 3 --settle 20 --record 64 --extend 0 \
    --no-lle --fast --out "$tmp/part"
has err "set k1x=5050 refused (ESTABILITY)"
has err "up k1x=5050 refused, not measured"
has err "4 skipped (refused)"
for d in up down; do
    for v in 5050 10000; do
        row=$(awk -F, -v d=$d -v v=$v '$1 == d && $3 == v' "$tmp/part.csv")
        case $row in "$d,"[0-9]",$v,none"*) ;; *) fail "part.csv: no row for $d $v: $row" ;; esac
        rest=$(printf '%s' "${row#*,none}" | tr -d ,)
        [ -z "$rest" ] || fail "part.csv: refused $d $v has values: $row"
        row=$(awk -F, -v d=$d -v v=$v '$1 == d && $3 == v' "$tmp/part-impacts.csv")
        [ "${row#*,$v,}" = ",,0,,none," ] || fail "part-impacts.csv: refused $d $v: $row"
    done
    awk -F, -v d=$d '$1 == d && $3 == 100 && $4 == "periodic" && $7 == "no_impact" { ok = 1 }
        END { exit !ok }' "$tmp/part.csv" || fail "part.csv: 100 $d not measured: $(cat "$tmp/part.csv")"
done
has_md() { grep -qF -- "$1" "$tmp/part.md" || fail "part.md lacks '$1'"; }
has_md "Not measured in the up sweep (refused by the daemon; the run's messages say why; their rows have regime none and no other value): k1x = 5050.0000, 10000.0000"
has_md "Not measured in the down sweep"
grep -q '"value":5050,"regime":"none","period":null' "$tmp/part.json" || fail "part.json: refused point not null"

# ---- stopped mid-sweep (SIGTERM: a script's background job ignores SIGINT):
# exit 130, partial outputs, and the daemon put back, its mode and omega
# (it was left in fast mode at the sweep's value: the restore was skipped)
"$C" set omega=0.5 >/dev/null
"$R" --from 0.6 --to 2.0 --points 40 --settle 3000 --fast --out "$tmp/stop" 2>"$tmp/stop.err" &
rpid=$!
wait_until 20 grep -q "up omega" "$tmp/stop.err"
stop $rpid TERM; rc=$exit_status
[ "$rc" = 130 ] || fail "SIGTERM mid-sweep: exit $rc, want 130: $(tail -3 "$tmp/stop.err")"
grep -q "stopped; putting the daemon back" "$tmp/stop.err" || fail "no 'putting the daemon back': $(tail -3 "$tmp/stop.err")"
grep -q "no ACK after" "$tmp/stop.err" && fail "a false 'no ACK' after the stop: $(grep 'no ACK' "$tmp/stop.err")"
[ -s "$tmp/stop.csv" ] || fail "no partial stop.csv"
expect 0 "$C" status
has out "mode realtime (rate 0.01)"
has out "^omega     0\.5$"

# ---- a terminal that takes nothing (Ctrl-S in wgrig's tmux pane, sent
# before its first line): its messages blocked its loop in write(), and the
# sweep stood still, the daemon left in fast mode at one value, until
# Ctrl-Q. Now the sweep runs to its end while the terminal is stopped: the
# outputs are written and the daemon put back; the summary waits for the
# terminal, and after Ctrl-Q it is there and wgrig exits 0.
if command -v tmux >/dev/null; then
    sock=wgrig-stop-$$
    tmux -L "$sock" -f /dev/null new-session -d -x 150 -y 10 \
        "sh -c 'echo \$\$ >$tmp/ttypid; exec $R --from 0.5 --to 0.8 --points 4 --dir up --fast --out $tmp/tty'; echo \$? >$tmp/ttyrc; sleep 60"
    tmux -L "$sock" send-keys C-s
    if wait_until 60 test -s "$tmp/tty.md"; then
        echo "stopped terminal: the sweep ended and wrote its outputs"
        [ -s "$tmp/ttyrc" ] && fail "stopped terminal: wgrig ended before its summary was written"
        expect 0 "$C" status
        has out "mode realtime (rate 0.01)"
        has out "^omega     0\.5$"
    else
        fail "stopped terminal: the sweep did not run on (no outputs in 60 s)"
    fi
    tmux -L "$sock" send-keys C-q
    wait_until 10 test -s "$tmp/ttyrc"
    [ "$(cat "$tmp/ttyrc" 2>/dev/null)" = 0 ] || fail "stopped terminal: exit '$(cat "$tmp/ttyrc" 2>/dev/null)' after Ctrl-Q, want 0"
    tmux -L "$sock" capture-pane -p >"$tmp/pane" 2>/dev/null
    grep -q "wgrig: 4/4 points" "$tmp/pane" || fail "stopped terminal: no summary after Ctrl-Q: $(cat "$tmp/pane")"
    [ -s "$tmp/ttyrc" ] || kill -KILL "$(cat "$tmp/ttypid")" 2>/dev/null
    tmux -L "$sock" kill-server 2>/dev/null
else
    echo "tmux not installed: the stopped-terminal check skipped"
fi

# ---- a ramp up and down, 1 s of simulated time each way (physical real time),
# with a hostile sender on the same channels (tests/clients/wgspoof.c): its
# PARAMS (scale NaN, N = 0, unknown model, a NaN value) are ignored, said
# so, and the ramp is what it is without it
"$SPOOF" "$WORMGEAR_URL" RIGT_ 30 params >"$tmp/spoof.out" 2>&1 &
spid=$!
expect 0 "$R" --from 0.5 --to 1.0 --ramp 0.5s --bins 6 --fast --out "$tmp/ramp"
kill "$spid" 2>/dev/null; wait "$spid" 2>/dev/null
has err "ignored a PARAMS message no daemon sends (its scale is not positive and finite)"
has err "12/12 points"
[ "$(grep -c '^up' "$tmp/ramp.csv")" -eq 6 ] || fail "ramp: not 6 up bins"
awk -F, '$1 == "up" && $3 == 0.5 && $7 == "no_impact" { ok = 1 } END { exit !ok }' "$tmp/ramp.csv" ||
    fail "ramp: omega 0.5 not no_impact: $(cat "$tmp/ramp.csv")"
awk -F, '$1 == "up" && $3 == 0.9 && $7 == "single_sided" { ok = 1 } END { exit !ok }' "$tmp/ramp.csv" ||
    fail "ramp: omega 0.9 not single_sided: $(cat "$tmp/ramp.csv")"
# what the ramp did, in the .md (and the figures' captions: clients.test_plot),
# not a transient and record per point that it never ran
grep -q "ramp ω 0.5 → 1 and back over 0.5 s simulated each way (≈ [0-9]* mesh periods), \
every section binned onto 6 values" "$tmp/ramp.md" || fail "ramp.md: $(sed -n 5p "$tmp/ramp.md")"
grep -q "transient" "$tmp/ramp.md" &&
    fail "ramp.md claims a transient: $(grep transient "$tmp/ramp.md")"
# the JSON too: its options say the ramp ("run"), no transient or record
grep -q '"run":"ramp ω 0.5 → 1 and back over 0.5 s simulated each way' "$tmp/ramp.json" ||
    fail "ramp.json: no run: $(grep options "$tmp/ramp.json")"
grep -q '"transient"\|"record"' "$tmp/ramp.json" &&
    fail "ramp.json claims a transient or record: $(grep options "$tmp/ramp.json")"

# the value put back after a ramp (no --keep), from 0.8, neither end: the
# ramps left it at their end (0.5 after both ways, 1.0 after one up). The
# mode first: the spoofer's STATUS (rate 1) is what the unsigned rig
# restored above (it cannot tell the daemon's STATUS from a forged one)
"$C" mode realtime 0.01 >/dev/null
"$C" set omega=0.8 >/dev/null
expect 0 "$R" --from 0.5 --to 1.0 --ramp 0.5s --bins 6 --fast --out "$tmp/ramp2"
expect 0 "$C" status
has out "mode realtime (rate 0.01)"
has out "^omega     0\.8$"
expect 0 "$R" --from 0.5 --to 1.0 --ramp 0.5s --bins 6 --dir up --fast --out "$tmp/ramp2"
expect 0 "$C" status
has out "^omega     0\.8$"
# a long ramp stopped while it runs: exit 130, the ramp cancelled by the
# restore, omega and the mode put back
ramping() { "$C" status 2>/dev/null | grep -q "^ramp "; }
"$R" --from 0.5 --to 1.0 --ramp 60s --bins 6 --dir up --fast --out "$tmp/rstop" \
    2>"$tmp/rstop.err" &
rpid=$!
wait_until 30 ramping || fail "long ramp: the daemon never ramped: $(tail -3 "$tmp/rstop.err")"
stop $rpid TERM; rc=$exit_status
[ "$rc" = 130 ] || fail "SIGTERM mid-ramp: exit $rc, want 130: $(tail -3 "$tmp/rstop.err")"
expect 0 "$C" status
has out "mode realtime (rate 0.01)"
has out "^omega     0\.8$"
grep -q "^ramp " "$tmp/out" && fail "SIGTERM mid-ramp: the ramp still runs: $(cat "$tmp/out")"

kill -TERM $pid; wait $pid; pid=

# ---- refusals: a monitor-only daemon refuses every set (ESTATE)
"$D" --accept-commands=no --rate 0.01 --state-dir "$tmp" >"$tmp/d2.out" 2>&1 &
pid=$!
sleep 0.5
# every point refused, so none measured: nothing written, an earlier run's
# outputs under the same prefix stay as they were (they were overwritten
# with rows of "none,0,0,no_impact,0,nan", a .md with settings and wall time)
for f in "$tmp"/live.* "$tmp"/live-*; do cp "$f" "$tmp/ref${f#"$tmp"/live}"; done
(cd "$tmp" && cksum ref.* ref-* >refsum)
expect 1 "$R" --from 0.5 --to 0.6 --points 2 --dir up --retries 1 --out "$tmp/ref"
has err "refused (ESTATE)"
has err "2 skipped (refused)"
has err ", 3 refusals,"   # one a point and the restore: commands off is not "not now", not retried
has err "no point measured: no outputs written"
has err "; outputs none$"
(cd "$tmp" && cksum ref.* ref-* | cmp -s - refsum) ||
    fail "refused run: the earlier ref.* changed: $(cd "$tmp" && cksum ref.* ref-* | diff - refsum)"
[ -e "$tmp/ref-sections.csv.part" ] && fail "refused run: ref-sections.csv.part left behind"
kill -TERM $pid; wait $pid; pid=
exit $code
