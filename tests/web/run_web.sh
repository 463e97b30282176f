#!/bin/sh
# run_web.sh TEST WORMGEARD WGWEB JSDIR OUTDIR - run web/test/TEST.mjs
# against a real daemon and two wgweb bridges (one with --allow-commands,
# one read-only), all host-local (run through netns.sh; HTTP and WebSocket
# on 127.0.0.1, LCM on a ttl=0 URL). Exit 77 (skipped) without node or
# web/node_modules, or without chromium for the browser test. wgweb must
# exit 0 on SIGTERM with nothing on stderr from the sanitizers.
# TEST-keyed runs TEST with a new key: the daemon (and the one the test
# restarts) with --command-key-file, both bridges with $WORMGEAR_KEY_FILE,
# so every command they send is signed and every message they forward
# checked.
T=$1 D=$2 W=$3 JS=$4 OUT=$5
keyed=
case $T in *-keyed) T=${T%-keyed} keyed=1;; esac
node=${WG_NODE:-$(command -v node)}
if [ ! -x "$node" ]; then echo "SKIP: node not found"; exit 77; fi
if [ ! -d "$JS/../node_modules/@foxglove/ws-protocol" ]; then
    echo "SKIP: web/node_modules missing: run 'npm ci' in web/ (tools/setup.sh does)"; exit 77
fi
if [ "$T" = browser ] && [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ]; then
    echo "SKIP: chromium not found (Debian package chromium)"; exit 77
fi
tmp=$(mktemp -d) || exit 1
dpid= wpid= rpid=
cleanup() {
    for p in $wpid $rpid $dpid; do kill -KILL "$p" 2>/dev/null; done
    [ -f "$tmp/daemon2.pid" ] && kill -KILL "$(cat "$tmp/daemon2.pid")" 2>/dev/null
    rm -rf "$tmp"
}
trap cleanup EXIT
. "$(dirname "$0")/../wait.sh" # wait_until
if [ -n "$keyed" ]; then
    (umask 077 && od -An -tx1 -N32 /dev/urandom | tr -d ' \n' >"$tmp/key" && echo >>"$tmp/key")
    printf '#!/bin/sh\nexec "%s" --command-key-file "%s" "$@"\n' "$D" "$tmp/key" >"$tmp/wormgeard"
    chmod +x "$tmp/wormgeard"
    D=$tmp/wormgeard
    export WORMGEAR_KEY_FILE="$tmp/key"
fi
export WORMGEAR_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0" WORMGEAR_PREFIX=WEBT_
"$D" --state-dir "$tmp" >"$tmp/d.log" 2>&1 &
dpid=$!
extra=
[ "$T" = slowclient ] && extra="--queue 256 --scope-hz 2000 --poincare-hz 5000"
"$W" --port 0 --allow-commands $extra >"$tmp/w.out" 2>"$tmp/w.err" &
wpid=$!
"$W" --port 0 >"$tmp/r.out" 2>"$tmp/r.err" &
rpid=$!
port_of() { sed -n 's|.*http://127.0.0.1:\([0-9]*\)/.*|\1|p' "$1"; }
both_listen() { [ -n "$(port_of "$tmp/w.out")" ] && [ -n "$(port_of "$tmp/r.out")" ]; }
wait_until 5 both_listen
port=$(port_of "$tmp/w.out") rport=$(port_of "$tmp/r.out")
if [ -z "$port" ] || [ -z "$rport" ]; then
    echo "FAIL: wgweb did not start"; cat "$tmp/w.out" "$tmp/w.err" "$tmp/r.err"; exit 1
fi
export WG_DAEMON_PID=$dpid WG_DAEMON="$D" WG_STATE_DIR="$tmp" WG_DAEMON2_PIDFILE="$tmp/daemon2.pid"
export WG_OUT="$OUT" WG_RO_URL="ws://127.0.0.1:$rport/" WGWEB_PID=$wpid
"$node" "$JS/$T.mjs" "ws://127.0.0.1:$port/"
status=$?
for p in $wpid $rpid; do
    kill -TERM "$p" 2>/dev/null
    wait "$p"
    rc=$?
    [ $rc -eq 0 ] || { echo "FAIL: wgweb exit $rc after SIGTERM"; status=1; }
done
wpid= rpid=
if [ -n "$keyed" ] && ! grep -q "signed commands only" "$tmp/d.log"; then
    echo "FAIL: the daemon did not take the key: $(tail -3 "$tmp/d.log")"; status=1
fi
if grep -q "Sanitizer" "$tmp/w.err" "$tmp/r.err"; then
    echo "FAIL: sanitizer report:"; cat "$tmp/w.err" "$tmp/r.err"; status=1
fi
[ $status -eq 0 ] || { echo "--- wgweb stderr"; cat "$tmp/w.err"; }
exit $status
