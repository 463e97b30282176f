#!/bin/sh
# test_cli.sh WGWEB - wgweb's command line: --help lists every option with
# its default and range, usage errors name the option and exit 2, another
# --listen address than loopback prints a warning (run through netns.sh:
# nothing outside this host can reach it), a port in use fails with 1.
W=$1
status=0
tmp=$(mktemp -d) || exit 1
pids=
trap 'for p in $pids; do kill -KILL $p 2>/dev/null; done; rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; status=1; }
. "$(dirname "$0")/../wait.sh" # wait_until
expect() {
    want=$1; shift
    "$@" >"$tmp/out" 2>"$tmp/err"; got=$?
    [ "$got" -eq "$want" ] || fail "$* -> exit $got, want $want: $(cat "$tmp/out" "$tmp/err")"
}
has() { grep -q -- "$2" "$tmp/$1" || fail "$1 lacks '$2': $(cat "$tmp/$1")"; }
expect 0 "$W" --help
for o in --url --prefix --listen --port --web-root --allow-commands --contacts --scope-hz \
         --poincare-hz --contact-hz --queue --max-clients --max-frame --heartbeat --ack-timeout; do
    has out "$o"
done
has out "default 8765; \[0, 65535\]"
has out "default 300; \[1, 20000\]"
expect 2 "$W" --scope-hz 0
has err "scope-hz '0': a number /scope samples per wall second in \[1, 20000\]"
expect 2 "$W" --port 70000
expect 2 "$W" --queue 1.5
has err "an integer"
expect 2 "$W" --contacts some
has err "mesh or all"
expect 2 "$W" --bogus
has err "unknown option"
expect 2 "$W" stray
# Not loopback: a warning (in a private network namespace, no one else can reach it).
export WORMGEAR_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0"
"$W" --listen 0.0.0.0 --port 0 --allow-commands >"$tmp/out" 2>"$tmp/err" &
pids=$!
wait_until 5 grep -q 'http://0.0.0.0:' "$tmp/out" # until it says where it listens
has err "WARNING: listening on 0.0.0.0, not loopback"
has err "can command it"
has out "commands allowed"
port=$(sed -n 's|.*http://0.0.0.0:\([0-9]*\)/.*|\1|p' "$tmp/out")
expect 1 "$W" --port "$port" --listen 0.0.0.0
has err "cannot listen on 0.0.0.0 port $port"
kill -TERM $pids; wait $pids || fail "wgweb exit $? after SIGTERM"
pids=
[ $status -eq 0 ] && echo "all checks passed"
exit $status
