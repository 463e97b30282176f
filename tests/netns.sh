#!/bin/sh
# netns.sh CMD ARGS... - run a system test host-locally: in a private network
# namespace with lo up and a multicast route on it (unshare -n, needs root or
# user namespaces, and iproute2), else on the host (the tests then use a
# ttl=0 URL on a random port, which never leaves this machine).
if command -v ip >/dev/null 2>&1 && unshare -n true 2>/dev/null; then
    exec unshare -n sh -c 'ip link set lo up && ip route add 239.0.0.0/8 dev lo && exec "$@"' \
        netns "$@"
fi
echo "netns.sh: no network namespace here; running on the host with a ttl=0 URL" >&2
exec "$@"
