#!/bin/sh
# ns_own.sh [-m] CMD ARGS... - run a test that changes the network (deletes
# its multicast route) or, with -m, mounts: in namespaces of its own, a
# network one (lo up, a multicast route on it) and with -m a mount one, and
# with WG_OWN_NS=1 set, which such a test requires before it touches
# anything. Unlike netns.sh there is no fallback to the host: where the
# namespaces cannot be made, exit 77 (skipped).
flags=-n
[ "${1:-}" = -m ] && { flags=-mn; shift; }
if ! command -v ip >/dev/null 2>&1 || ! unshare $flags true 2>/dev/null; then
    echo "SKIP: no namespace of its own here (unshare $flags, iproute2)"
    exit 77
fi
WG_OWN_NS=1 exec unshare $flags sh -c \
    'ip link set lo up && ip route add 239.0.0.0/8 dev lo && exec "$@"' ns_own "$@"
