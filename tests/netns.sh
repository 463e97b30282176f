#!/bin/sh
# netns.sh [--own [-m]] CMD ARGS... - run a system test host-locally: in a
# private network namespace with lo up and a multicast route on it (unshare
# -n, needs root or user namespaces, and iproute2), else on the host (the
# tests then use a ttl=0 URL on a random port, which never leaves this
# machine).
# --own: for a test that changes the network (deletes that route) or, with
# -m, mounts (then a mount namespace too): never on the host. Where the
# namespaces cannot be made, exit 77 (skipped); the test runs with
# WG_OWN_NS=1, which such a test requires before it touches anything.
own= flags=-n
if [ "${1:-}" = --own ]; then
    own=1
    shift
    [ "${1:-}" = -m ] && { flags=-mn; shift; }
fi
if command -v ip >/dev/null 2>&1 && unshare $flags true 2>/dev/null; then
    [ -n "$own" ] && export WG_OWN_NS=1
    exec unshare $flags sh -c 'ip link set lo up && ip route add 239.0.0.0/8 dev lo && exec "$@"' \
        netns "$@"
fi
if [ -n "$own" ]; then
    echo "SKIP: no namespace of its own here (unshare $flags, iproute2)"
    exit 77
fi
echo "netns.sh: no network namespace here; running on the host with a ttl=0 URL" >&2
exec "$@"
