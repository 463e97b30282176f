#!/bin/sh
# test_cli.sh WGWEB - wgweb's command line: --help lists every option with
# its default and range, usage errors name the option and exit 2, --listen
# takes IP addresses only and warns when one is not loopback (no address but
# loopback is used: run through netns.sh), a port in use fails with 1, and
# so does a web root that cannot be used; one without index.html serves no
# file (a SIGTERM in the start, while main holds it, is a clean stop).
W=$1
status=0
tmp=$(mktemp -d) || exit 1
pids=
trap 'for p in $pids; do kill -KILL $p 2>/dev/null; done; rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; status=1; }
. "$(dirname "$0")/../wait.sh" # wait_until, stderr_stall
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
# The web root: one that cannot be used exits 1 with the reason (it ran on,
# saying "only the Foxglove WebSocket is served"); a directory without
# index.html serves no file at all (it served them: GET /secret.txt -> 200).
export WORMGEAR_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0"
expect 1 timeout 5 "$W" --port 0 --web-root "$tmp/nonexistent" # 124: it ran on
has err "web root '$tmp/nonexistent': No such file or directory (--web-root or \$WGWEB_ROOT: a"
[ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "more than one message: $(cat "$tmp/err")"
echo x >"$tmp/plain"
expect 1 timeout 5 "$W" --port 0 --web-root "$tmp/plain"
has err "web root '$tmp/plain': Not a directory"
mkdir "$tmp/root" && echo topsecret >"$tmp/root/secret.txt"
"$W" --port 0 --web-root "$tmp/root" >"$tmp/out" 2>"$tmp/err" &
pids=$!
wait_until 5 grep -q 'http://127.0.0.1:' "$tmp/out"
has err "no dashboard in $tmp/root (index.html missing): only the Foxglove WebSocket is served"
port=$(sed -n 's|.*http://127.0.0.1:\([0-9]*\)/.*|\1|p' "$tmp/out")
for path in /secret.txt /; do
    code=$(curl -s -o "$tmp/body" -w '%{http_code}' "http://127.0.0.1:$port$path")
    [ "$code" = 404 ] && ! grep -q topsecret "$tmp/body" || fail "GET $path -> $code, want 404"
done
kill -TERM $pids; wait $pids || fail "wgweb exit $? after SIGTERM"
pids=
# --listen takes an IP address of this host. A name lws could not find
# ("localhost" then, "127.1", a typo) left wgweb running, listening nowhere
# and printing http://localhost:0/.
for a in lo 127.1 nosuch0 ''; do
    expect 2 timeout 5 "$W" --listen "$a" --port 0 # 124: it ran on
    has err "--listen '$a': not an IP address; an IPv4 or IPv6 address of this host"
done
# Not loopback: the warning comes before the socket, so it is checked without
# any address but loopback in use: 192.0.2.1 (TEST-NET-1, RFC 5737) is no
# interface's here, and nothing binds.
expect 1 timeout 5 "$W" --listen 192.0.2.1 --port 0 --allow-commands
has err "WARNING: --listen 192.0.2.1 is not loopback: every host that reaches it sees the daemon's data and can command it (--allow-commands)"
has err "cannot listen on 192.0.2.1: Cannot assign requested address"
[ "$(wc -l <"$tmp/err")" -eq 2 ] || fail "not two messages: $(cat "$tmp/err")"
# Loopback, no warning, and it serves: localhost as 127.0.0.1, IPv6 in brackets.
v6=; ip -6 addr show dev lo 2>/dev/null | grep -q '::1/128' && v6='::1 ::ffff:127.0.0.1'
[ -n "$v6" ] || echo "no ::1 on lo here: IPv6 --listen not checked"
for a in localhost 127.0.0.2 $v6; do
    "$W" --listen "$a" --port 0 --allow-commands >"$tmp/out" 2>"$tmp/err" &
    pids=$!
    wait_until 5 grep -q 'http://' "$tmp/out"
    url=$(sed -n 's|.* -> \(http://[^ ]*/\) .*|\1|p' "$tmp/out")
    case $a in localhost) want=http://127.0.0.1: ;; *:*) want="http://[$a]:" ;; *) want="http://$a:" ;; esac
    case $url in "$want"[1-9]*/) ;; *) fail "--listen $a: URL '$url', want $want<port>/" ;; esac
    ! grep -q WARNING "$tmp/err" || fail "--listen $a warned: $(cat "$tmp/err")"
    has out "commands allowed"
    code=$(curl -s -o /dev/null -w '%{http_code}' "$url")
    [ "$code" != 000 ] || fail "--listen $a: nothing answers at $url"
    if [ "$a" = 127.0.0.2 ]; then # a port in use: exit 1, with the reason
        port=${url##*:}; port=${port%/}
        expect 1 timeout 5 "$W" --port "$port" --listen 127.0.0.2
        has err "cannot listen on 127.0.0.2 port $port"
    fi
    kill -TERM $pids; wait $pids || fail "wgweb --listen $a exit $? after SIGTERM"
    pids=
done
# SIGTERM during the start (LCM, the listening socket): a clean stop, 0 (it
# was 143 until the loop's watchers came). The start is stopped at a known
# point: stderr is a pipe already full and the web root has no index.html,
# so wgweb blocks writing "no dashboard" (after LCM, before the socket and
# the watchers). There, by /proc, every thread must hold INT and TERM and
# no handler be there yet; SIGTERM is sent, the pipe drained.
sigfield() { sed -n "s/^$2:[[:space:]]*//p" "/proc/$1/status" 2>/dev/null; }
stderr_stall "$tmp/errpipe" || fail "cannot fill the pipe"
"$W" --listen 127.0.0.1 --port 0 --web-root "$tmp/root" >/dev/null 2>"$tmp/errpipe" 3>&- &
p=$!
pids=$p
if wait_until 20 in_stderr_write $p; then
    cgt=$(sigfield $p SigCgt)
    [ $((0x$cgt & 0x4002)) -eq 0 ] || fail "SIGTERM: handlers before the socket (SigCgt $cgt)"
    open=$(thread_unheld $p 0x4002)
    [ -z "$open" ] || fail "SIGTERM: at the start, thread $open (tid, SigBlk) does not hold INT, TERM"
    echo "SIGTERM sent during the start ($(sigfield $p Threads) threads, SigBlk $(sigfield $p SigBlk))"
else
    fail "SIGTERM: wgweb never wrote its warning: $(cat "/proc/$p/syscall" 2>&1)"
fi
kill -TERM $p
cat <&3 >"$tmp/raw" & # the drain: the fill's zeros, then wgweb's lines
drain=$!
wait $p
rc=$?
pids=
wait_until 5 grep -q "no dashboard" "$tmp/raw"
kill $drain; wait $drain 2>/dev/null
exec 3>&-
[ $rc -eq 0 ] || fail "SIGTERM during the start: exit $rc, want 0"
tr -d '\000' <"$tmp/raw" >"$tmp/err"
has err "no dashboard in $tmp/root"
[ $status -eq 0 ] && echo "all checks passed"
exit $status
