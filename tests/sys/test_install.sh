#!/bin/sh
# test_install.sh CMAKE SRC BUILD - `cmake --install` to a temporary prefix:
# the files land where the README says, the installed unit names this
# prefix's paths and passes `systemd-analyze verify`; then the install is
# moved elsewhere and, with the source tree hidden (a tmpfs mounted over it
# in a private mount namespace), the installed wgsim finds its scenes, the
# installed wormgeard checks the installed config and runs, wgctl talks to
# it, SIGTERM stops it with 0. Run through netns.sh (host-local LCM).
cmake=$1 src=$2 build=$3
tmp=$(mktemp -d) || exit 1
pid=
cleanup() { [ -n "$pid" ] && kill -KILL "$pid" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }

"$cmake" --install "$build" --prefix "$tmp/p" >"$tmp/install.log" 2>&1 ||
    { cat "$tmp/install.log"; fail "cmake --install"; exit 1; }
for f in bin/wgsim bin/wgsweep bin/wgctl bin/wgmon bin/wgrig bin/wglog bin/wgspy \
         sbin/wormgeard etc/wormgear/wormgeard.conf lib/systemd/system/wormgeard.service \
         share/wormgear/scenes/table3.ini share/wormgear/scenes/torsional.ini \
         share/doc/wormgear/daemon.md share/doc/wormgear/PROTOCOL.md; do
    [ -e "$tmp/p/$f" ] || fail "not installed: $f"
done
unit=$tmp/p/lib/systemd/system/wormgeard.service
grep -q "^ExecStart=$tmp/p/sbin/wormgeard --config $tmp/p/etc/wormgear/wormgeard.conf\$" "$unit" ||
    fail "unit ExecStart: $(grep ExecStart "$unit")"
grep -q "^ConfigurationDirectory=" "$unit" && fail "ConfigurationDirectory= names /etc for a config in $tmp/p/etc"
grep -q "Documentation=file:$tmp/p/share/doc/wormgear/daemon.md" "$unit" || fail "unit Documentation="
if grep -nE '@WG_|(^|[= ])/(usr|etc)/' "$unit"; then fail "unit names paths outside the prefix"; fi
# the example configuration names every key --help lists (it said it did
# and lacked six: scope_hz, contacts, bearing_every, state_decimation,
# foreground, verbose)
conf=$tmp/p/etc/wormgear/wormgeard.conf
keys=$("$tmp/p/sbin/wormgeard" --help | sed -n 's/^  --\([a-z][a-z-]*\) .*/\1/p' | tr - _)
[ "$(echo "$keys" | wc -w)" -ge 25 ] || fail "--help lists only: $keys"
for k in $keys; do
    grep -q "^;\{0,1\}$k = " "$conf" || fail "the example $conf lacks the key $k"
done
if command -v systemd-analyze >/dev/null 2>&1; then
    (cd "$tmp" && systemd-analyze verify "$unit") || fail "systemd-analyze verify $unit"
fi

# Moved, with the source tree out of sight.
mv "$tmp/p" "$tmp/q"
url="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0"
cat >"$tmp/run.sh" <<EOF
set -u
q=$tmp/q
unset WG_SCENE_PATH
[ -e "$src/CMakeLists.txt" ] && { echo "FAIL: the source tree is still visible"; exit 1; }
\$q/bin/wgsim --periods 3 --transient 0 >$tmp/wgsim.out 2>&1 || { cat $tmp/wgsim.out; echo "FAIL: installed wgsim"; exit 1; }
grep -q "scene       table3" $tmp/wgsim.out || { cat $tmp/wgsim.out; echo "FAIL: wgsim summary"; exit 1; }
# wgspy finds the socket filter it preloads under lcm-spy beside itself
f=\$(\$q/bin/wgspy --print-filter) && [ -f "\$f" ] && case \$f in \$q/*) ;; *) false;; esac ||
    { echo "FAIL: installed wgspy --print-filter: \$f"; exit 1; }
\$q/bin/wgsim --scene nope >$tmp/nope.out 2>&1
grep -q "scenes there: lowfreq, realistic, table3, table3-physical, torsional" $tmp/nope.out ||
    { cat $tmp/nope.out; echo "FAIL: scene-not-found lists the installed scenes"; exit 1; }
\$q/sbin/wormgeard --config \$q/etc/wormgear/wormgeard.conf --check-config >$tmp/check.out 2>&1 ||
    { cat $tmp/check.out; echo "FAIL: installed wormgeard --check-config"; exit 1; }
\$q/sbin/wormgeard --config \$q/etc/wormgear/wormgeard.conf --url '$url' --state-dir $tmp/state \
    --rate 0.05 2>$tmp/daemon.log &
d=\$!
ok=1
for i in 1 2 3 4 5 6 7 8 9 10; do
    \$q/bin/wgctl --url '$url' status >$tmp/status.out 2>&1 && { ok=0; break; }
done
[ \$ok = 0 ] || { cat $tmp/status.out $tmp/daemon.log; echo "FAIL: wgctl status against the installed daemon"; }
grep -q "scene table3" $tmp/status.out || { cat $tmp/status.out; echo "FAIL: status shows the scene"; ok=1; }
kill -TERM \$d; wait \$d; rc=\$?
[ \$rc = 0 ] || { echo "FAIL: installed wormgeard exited \$rc on SIGTERM"; ok=1; }
exit \$ok
EOF
if unshare -m true 2>/dev/null; then
    unshare -m sh -c "mount -t tmpfs none '$src' && sh '$tmp/run.sh'" || fail "the moved install, source tree hidden"
else
    echo "note: no mount namespace here; the moved install runs with the source tree visible"
    sh -c "sed 's/^\[ -e .*still visible.*//' '$tmp/run.sh' | sh" ||
        fail "the moved install"
fi
[ $status = 0 ] && echo "ok: installed, moved and run without the source tree"
exit $status
