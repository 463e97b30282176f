#!/bin/sh
# test_readme.sh SRC - the README's walk-through and install commands, run
# literally from the source tree, and what the README says will be seen.
#
# Walk-through: `bash tools/run.sh` (which builds build/release if needed
# and starts the daemon), wgmon in a tmux pane, the wgctl commands in order;
# after each, the wgmon screen and `wgctl status` are checked against the
# README's sentences. The daemon's, the dashboard's and the analysis
# sections' commands: each runs and does what its section says (a status
# line, the page served, the files written, wgcont's three quoted events).
# Install: `cmake --install build/release --prefix
# /usr/local` with a tmpfs over /usr/local in a private mount namespace, the
# installed daemon checks its installed config; `cpack -G DEB` in
# build/release. The commands are read from README.md and must equal the
# list below: when the README changes, this test changes with it.
# Run through netns.sh: the README's default URL then stays in a private
# network namespace.
src=$1
tmp=$(mktemp -d) || exit 1
sock=wgreadme$$
runpid=
cleanup() {
    [ -n "$runpid" ] && kill -KILL "$runpid" 2>/dev/null
    tmux -L "$sock" kill-server 2>/dev/null
    rm -rf "$tmp"
}
trap cleanup EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }
. "$(dirname "$0")/readme.sh" # readme_block, readme_expect
. "$(dirname "$0")/../wait.sh" # wait_until, wait_gone, stop
cd "$src" || exit 1

readme_block README.md "## A walk-through" >"$tmp/walk"
cat >"$tmp/want" <<'EOF'
bash tools/run.sh
build/release/clients/wgmon
build/release/clients/wgctl set omega=0.5
build/release/clients/wgctl ramp omega 1.5 --over 6s
build/release/clients/wgctl set omega=1.2
build/release/clients/wgctl status
EOF
readme_expect "$tmp/walk" "$tmp/want" "walk-through commands"
line() { sed -n "${1}p" "$tmp/walk"; }

# ---- terminal 1: the daemon (tools/run.sh builds first when needed)
export WG_STATE_DIR="$tmp/state"
sh -c "exec $(line 1)" >"$tmp/run.out" 2>"$tmp/run.err" &
runpid=$!
up_or_ended() { build/release/clients/wgctl --timeout 0.5 status >/dev/null 2>&1 || wait_gone "$runpid"; }
wait_until 600 up_or_ended || { tail "$tmp/run.err"; fail "no daemon after tools/run.sh"; exit 1; }
wait_gone "$runpid" && { cat "$tmp/run.err"; fail "tools/run.sh exited"; exit 1; }

# ---- terminal 2: wgmon in a tmux pane
tmux -L "$sock" -f /dev/null new-session -d -x 120 -y 45 "$(line 2)" || { fail "tmux"; exit 1; }
screen() { tmux -L "$sock" capture-pane -p >"$tmp/screen"; }
shows() { screen; grep -Eq -- "$1" "$tmp/screen"; }
# wait_for PATTERN SECONDS: the pane shows PATTERN (extended regex) in time
wait_for() {
    wait_until "$2" shows "$1" || { fail "wgmon never showed '$1'; last frame:"; cat "$tmp/screen"; }
}

# ---- terminal 3
sh -c "$(line 3)" >"$tmp/out" 2>&1 || fail "$(line 3): $(cat "$tmp/out")"
wait_for "regime +daemon: period-1" 20
wait_for "rtf 1\.0" 5
grep -q "no_impact" "$tmp/screen" || fail "at omega = 0.5: no 'no_impact' on the screen"
# CONTACT messages received since wgmon started (the msgs line)
contacts() { screen; sed -n 's/.* CONTACT \([0-9]*\).*/\1/p' "$tmp/screen" | head -1; }
c1=$(contacts)
sleep 1.5
c2=$(contacts)
[ -n "$c1" ] && [ "$c1" = "$c2" ] || fail "at omega = 0.5 contact events flow ($c1 -> $c2)"

sh -c "$(line 4)" >"$tmp/out" 2>&1 || fail "$(line 4): $(cat "$tmp/out")"
wait_for "daemon: ramping" 5
flowing() { [ "$(contacts)" != "$c2" ]; }
wait_until 8 flowing || fail "no contact events during the ramp"

sh -c "$(line 5)" >"$tmp/out" 2>&1 || fail "$(line 5): $(cat "$tmp/out")"
wait_for "regime +daemon: period-2" 30
wait_for "single_sided, 0\.5 impacts/period" 10
# the scatter holds the last 5 s of sections: two points once the ramp's are out of it.
# Title and points are read from one capture that shows both: tmux can be caught
# mid-frame (a frame is one write, but the pty hands it over in pieces), and one
# CI run read the new frame's "2 cells" above the old frame's ramp points
two_points() { shows "sections in 2 cells" && [ "$(grep -o '@' "$tmp/screen" | wc -l)" -eq 2 ]; }
wait_until 20 two_points || { fail "not 2 cells shown as two '@' in the scatter:"; cat "$tmp/screen"; }

sh -c "$(line 6)" >"$tmp/status" 2>&1 || fail "$(line 6): $(cat "$tmp/status")"
for w in "period-2" "single_sided" "health ok"; do
    grep -q "$w" "$tmp/status" || fail "wgctl status lacks '$w': $(cat "$tmp/status")"
done

# Ctrl-C stops it with 0 (run.sh exec'd the daemon: the signal is its)
tmux -L "$sock" send-keys q
stop "$runpid" INT; rc=$exit_status
runpid=
[ "$rc" = 0 ] || fail "tools/run.sh after Ctrl-C: exit $rc"
grep -q "realtime x1 running ok" "$tmp/run.out" || fail "no status line from run.sh: $(tail -2 "$tmp/run.out")"
# what run.sh does is said (a first build took minutes with no word)
grep -q "^run: building build/release" "$tmp/run.err" && grep -q "^run: starting wormgeard" "$tmp/run.err" ||
    fail "run.sh did not say it builds and starts: $(head -3 "$tmp/run.err")"

# ---- the offline commands that follow (the section's second block), in a
# scratch directory (they write files) that sees the build as build/
readme_block README.md "## A walk-through" 2 >"$tmp/offline"
cat >"$tmp/want" <<'EOF'
build/release/clients/wgsim --set omega=1.2 --poincare -
build/release/clients/wgsweep --out sweep
build/release/clients/wgsweep --at 1.33 --out view
EOF
readme_expect "$tmp/offline" "$tmp/want" "offline commands"
mkdir "$tmp/scratch" && ln -s "$src/build" "$tmp/scratch/build"
(cd "$tmp/scratch" && sh -c "$(sed -n 1p "$tmp/offline")") >"$tmp/pc.csv" 2>"$tmp/err" ||
    fail "$(sed -n 1p "$tmp/offline"): $(cat "$tmp/err")"
head -1 "$tmp/pc.csv" | grep -q "^period,tau,omega,x_n" || fail "wgsim --poincare: $(head -2 "$tmp/pc.csv")"
[ "$(wc -l <"$tmp/pc.csv")" -eq 201 ] || fail "wgsim --poincare: not 200 periods"
(cd "$tmp/scratch" && sh -c "$(sed -n 2p "$tmp/offline")" && sh -c "$(sed -n 3p "$tmp/offline")") \
    >"$tmp/sweep.out" 2>&1 || fail "wgsweep: $(tail -3 "$tmp/sweep.out")"
[ -s "$tmp/scratch/sweep.csv" ] && [ -s "$tmp/scratch/sweep.png" ] ||
    fail "wgsweep --out sweep wrote no sweep.csv and sweep.png: $(ls "$tmp/scratch")"
ls "$tmp/scratch"/view*.png >/dev/null 2>&1 || fail "wgsweep --at 1.33 --out view wrote no PNG"

# ---- wgsim's example: the command and the figures the README gives for it
awk '/^Example \(`build\/release\/clients\/wgsim / { getline n; print $0 " " n }' README.md >"$tmp/ex"
ex=$(sed -n 's/^Example (`\([^`]*\)`): .*/\1/p' "$tmp/ex")
[ "$ex" = "build/release/clients/wgsim --set omega=0.7" ] || fail "wgsim example: '$ex'"
want=$(sed -n 's/.*single-sided impacts, one per period, x_n between \([0-9.]*\) and \([0-9.]*\) (b = 1)\..*/\1 \2/p' "$tmp/ex")
(cd "$tmp/scratch" && sh -c "$ex") >"$tmp/ex.out" 2>&1 || fail "$ex: $(cat "$tmp/ex.out")"
got=$(sed -n 's/^x_n  *min \([0-9.]*\), max \([0-9.]*\) (b = 1)$/\1 \2/p' "$tmp/ex.out" |
      awk '{ printf "%.3f %.3f", $1, $2 }')
[ -n "$want" ] && [ "$got" = "$want" ] || fail "wgsim example: x_n $got, the README says '$want'"
grep -q "^motion  *single_sided (periods: 0 no impact, 200 single-sided" "$tmp/ex.out" &&
    grep -q "^impacts  *1 per period" "$tmp/ex.out" ||
    fail "wgsim example: not single-sided, one impact a period: $(grep -E '^(motion|impacts)' "$tmp/ex.out")"

# ---- the daemon's section: in the foreground, its help, the example config
# checked (its state directory, $STATE_DIRECTORY as systemd would give it,
# is ours)
heading() { grep -m1 "^## $1" README.md; }
readme_block README.md "$(heading 'The daemon:')" >"$tmp/daemon"
cat >"$tmp/want" <<'EOF'
build/release/daemon/wormgeard -F
build/release/daemon/wormgeard --help
build/release/daemon/wormgeard -c systemd/wormgeard.conf --check-config
EOF
readme_expect "$tmp/daemon" "$tmp/want" "daemon commands"
dline() { sed -n "${1}p" "$tmp/daemon"; }
export STATE_DIRECTORY="$tmp/state"
sh -c "exec $(dline 1)" >"$tmp/d.out" 2>"$tmp/d.err" &
runpid=$!
status_line() { grep -q "realtime x1 running ok" "$tmp/d.out" || wait_gone "$runpid"; }
wait_until 30 up_or_ended && wait_until 10 status_line && ! wait_gone "$runpid" ||
    fail "$(dline 1): no daemon answering, or no status line: $(tail -3 "$tmp/d.err")"
sh -c "$(dline 2)" >"$tmp/help" 2>&1 && grep -q -- "--rate" "$tmp/help" ||
    fail "$(dline 2): $(head -3 "$tmp/help")"
sh -c "$(dline 3)" >"$tmp/check" 2>&1 && grep -q "^configuration ok" "$tmp/check" ||
    fail "$(dline 3): $(cat "$tmp/check")"

# ---- the dashboard's section, with that daemon running: the page is served
readme_block README.md "$(heading 'The browser dashboard:')" >"$tmp/web"
echo "build/release/clients/wgweb --allow-commands" >"$tmp/want"
readme_expect "$tmp/web" "$tmp/want" "dashboard command"
sh -c "exec $(cat "$tmp/web")" >"$tmp/web.out" 2>&1 &
webpid=$!
page() {
    python3 -c 'import sys, urllib.request as u
r = u.urlopen("http://127.0.0.1:8765/", timeout=2)
sys.exit(0 if r.status == 200 and b"<html" in r.read().lower() else 1)' 2>/dev/null ||
        wait_gone "$webpid"
}
wait_until 20 page && ! wait_gone "$webpid" ||
    fail "$(cat "$tmp/web"): no page at http://127.0.0.1:8765/: $(tail -3 "$tmp/web.out")"
stop "$webpid" INT
[ "$exit_status" = 0 ] || fail "wgweb after Ctrl-C: exit $exit_status"
stop "$runpid" INT; rc=$exit_status
runpid=
[ "$rc" = 0 ] || fail "$(dline 1) after Ctrl-C: exit $rc"

# ---- the analysis section's two blocks, in the scratch directory: each
# command ends 0 and writes what the section says; wgcont finds the three
# events the section quotes, to the digits quoted
readme_block README.md "$(heading 'Bifurcation analysis:')" >"$tmp/ana"
cat >"$tmp/want" <<'EOF'
build/release/clients/wgsweep --out sweep
build/release/clients/wgsweep --values xi_p=0.08,0.10,0.12 --step 0.0025 --out table3
build/release/clients/wgsweep --param k_a --from 0.1 --to 0.5 --points 81 --set omega=1.3
build/release/clients/wgsweep --map xi_p=0.05:0.15:21 --step 0.01 --out map
build/release/clients/wgsweep --at 1.33 --out view --floquet
EOF
readme_expect "$tmp/ana" "$tmp/want" "analysis commands"
readme_block README.md "$(heading 'Bifurcation analysis:')" 2 >"$tmp/cont"
echo "build/release/clients/wgcont --scene table3 --from 0.1 --to 2.5 --sweep-points 241 --out cont" \
    >"$tmp/want"
readme_expect "$tmp/cont" "$tmp/want" "continuation command"
while read -r c; do
    (cd "$tmp/scratch" && sh -c "$c") >"$tmp/ana.out" 2>&1 || fail "$c: $(tail -3 "$tmp/ana.out")"
done <"$tmp/ana"
# the last, --at 1.33 --floquet, at a chaotic point: says so rather than nothing
grep -q "^floquet  *none: no periodic orbit here (chaotic)" "$tmp/ana.out" ||
    fail "wgsweep --at 1.33 --floquet: no floquet line: $(cat "$tmp/ana.out")"
for f in sweep.csv sweep.png table3.csv table3.md table3-xi_p-0.08.png map-map.csv map-map.png \
    view-at-omega-1.33-phase.png view-at-omega-1.33-poincare.png; do
    [ -s "$tmp/scratch/$f" ] || fail "the analysis commands wrote no $f: $(ls "$tmp/scratch")"
done
grep -q "grazing" "$tmp/scratch/table3.md" || fail "table3.md names no grazing"
(cd "$tmp/scratch" && sh -c "$(cat "$tmp/cont")") >"$tmp/cont.out" 2>&1 ||
    fail "$(cat "$tmp/cont"): $(tail -3 "$tmp/cont.out")"
for e in grazing:0.696787929 fold:0.698336370 period_doubling:1.197654628; do
    kind=${e%%:*} at=${e#*:}
    grep -q "$at" README.md || fail "the README no longer quotes $kind at $at"
    awk -F, -v k="$kind" -v w="$at" '$1 == k && sprintf("%.9f", $2) == w { f = 1 } END { exit !f }' \
        "$tmp/scratch/cont-bifurcations.csv" || fail "wgcont: no $kind at ω = $at"
done

# ---- Install, literally: /usr/local is a tmpfs in a private mount namespace
readme_block README.md "## Install" >"$tmp/inst"
cat >"$tmp/want" <<'EOF'
cmake --install build/release --prefix /usr/local
(cd build/release && cpack -G DEB)
EOF
readme_expect "$tmp/inst" "$tmp/want" "install commands"
if unshare -m true 2>/dev/null; then
    unshare -m sh -c "mount -t tmpfs none /usr/local && $(sed -n 1p "$tmp/inst") >'$tmp/inst.log' 2>&1 &&
        /usr/local/sbin/wormgeard --config /usr/local/etc/wormgear/wormgeard.conf --check-config &&
        /usr/local/bin/wgsim --periods 2 --transient 0 >/dev/null" ||
        { tail -5 "$tmp/inst.log"; fail "$(sed -n 1p "$tmp/inst"), then the installed programs"; }
else
    echo "note: no mount namespace here: the install into /usr/local is not run"
fi
before=$(ls build/release/*.deb 2>/dev/null)
sh -c "$(sed -n 2p "$tmp/inst")" >"$tmp/cpack.log" 2>&1 || { tail -5 "$tmp/cpack.log"; fail "cpack"; }
deb=$(ls build/release/wormgear_*_amd64.deb 2>/dev/null | head -1)
[ -n "$deb" ] && dpkg-deb -c "$deb" 2>/dev/null | grep -q "./usr/sbin/wormgeard" || fail "no .deb with /usr/sbin/wormgeard"
[ -z "$before" ] && rm -f build/release/*.deb

[ $status = 0 ] && echo "ok: the README's walk-through and install commands, literally"
exit $status
