#!/bin/sh
# test_full.sh WORMGEARD WGCTL - the state dir full (a 256 KiB tmpfs filled
# up): `save` over an existing snapshot and a new one are each refused with
# the reason (EIO: No space left on device), exit 1; the old snapshot keeps
# its bytes, no temporary file is left, the daemon runs on and restores the
# old one; with room again, the save works.
#
# Runs in mount and network namespaces of its own, through tests/netns.sh
# --own -m (the tmpfs and the route are theirs): skipped (77) where they
# cannot be made.
D=$1 C=$2
[ "${WG_OWN_NS:-}" = 1 ] ||
    { echo "test_full.sh mounts a tmpfs: run it through tests/netns.sh --own -m"; exit 2; }
code=0
tmp=$(mktemp -d) || exit 1
sd=$tmp/state
dpid=
cleanup() {
    [ -n "$dpid" ] && kill -KILL "$dpid" 2>/dev/null
    umount "$sd" 2>/dev/null
    rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; code=1; }
. "$(dirname "$0")/../wait.sh" # wait_until, wait_exit
export WORMGEAR_URL="udpm://239.255.76.67:7667?ttl=0" WORMGEAR_PREFIX=FULL_
mkdir "$sd" && mount -t tmpfs -o size=256k none "$sd" || { echo "SKIP: no tmpfs"; exit 77; }
# expect CODE CMD...: run, keep stdout and stderr in $tmp/out
expect() {
    want=$1; shift
    "$@" >"$tmp/out" 2>&1; got=$?
    [ "$got" -eq "$want" ] || fail "$* -> exit $got, want $want: $(cat "$tmp/out")"
}
has() { grep -q -- "$2" "$1" || fail "$1 lacks '$2': $(cat "$1")"; }

"$D" --state-dir "$sd" >"$tmp/d.log" 2>&1 &
dpid=$!
wait_until 20 grep -q "ready:" "$tmp/d.log" || { fail "the daemon did not start"; exit 1; }
expect 0 "$C" save a
cp "$sd/a.wgstate" "$tmp/a.before"
dd if=/dev/zero of="$sd/filler" bs=1k 2>/dev/null # until the tmpfs is full
expect 0 "$C" set omega=1.2
for name in a b; do
    expect 1 "$C" save "$name"
    has "$tmp/out" "save refused (EIO): cannot write $sd/$name.wgstate: No space left on device"
done
cmp -s "$sd/a.wgstate" "$tmp/a.before" || fail "a.wgstate changed by the refused save"
left=$(ls -A "$sd" | grep -v -x -e a.wgstate -e filler)
[ -z "$left" ] || fail "left in the state dir: $left"
expect 0 "$C" get omega
has "$tmp/out" "omega = 1.2 "
expect 0 "$C" restore a
expect 0 "$C" get omega
has "$tmp/out" "omega = 1 "
rm "$sd/filler"
expect 0 "$C" save b
[ -s "$sd/b.wgstate" ] || fail "no b.wgstate after the room came back"
[ "$(grep -c 'refused save' "$tmp/d.log")" = 2 ] ||
    fail "the daemon's log lacks the two refusals: $(cat "$tmp/d.log")"
kill -TERM "$dpid"
wait_exit "$dpid" 10
dpid=
[ "$exit_status" = 0 ] || fail "wormgeard -> exit $exit_status on SIGTERM"
[ "$code" = 0 ] &&
    echo "ok: saves in a full state dir refused with the reason, the old snapshot whole"
exit $code
