#!/usr/bin/env bash
# Set up, build and run wormgear's main job: the wormgeard daemon in the
# foreground on the default scene (table3), at physical real time, printing a
# one-line status each second, on the host-local LCM URL
# udpm://239.255.76.67:7667?ttl=0. Stop it with Ctrl-C. Run as root on
# Debian 12. Extra arguments go to wormgeard (see wormgeard --help).
# --help (or -h) as the first argument: this text, then wormgeard's own
# options if it is built, with nothing installed or built.
set -euo pipefail
. "$(dirname "$0")/args.sh"
case ${1:-} in
-h | --help) # before the cd below: $0 may be a path relative to here
    (args_help --help)
    echo
    d=$(dirname "$0")/../build/release/daemon/wormgeard
    if [ -x "$d" ]; then
        echo "wormgeard's options (build/release/daemon/wormgeard --help):"
        exec "$d" --help
    fi
    echo "wormgeard's options: build/release/daemon/wormgeard --help, once this script has built it"
    exit 0
    ;;
esac
cd "$(dirname "$0")/.."
bash tools/setup.sh
# said on stderr, as the build's own output goes nowhere: the first build
# takes minutes (6-7 on a 2-core VM) and showed nothing
echo "run: building build/release (minutes the first time, seconds after)..." >&2
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
# everything a user reaches for next: the clients, the lcm-spy jar, the tests
cmake --build build/release -j"$(nproc)" >/dev/null
mkdir -p "${WG_STATE_DIR:=/var/lib/wormgeard}"
echo "run: starting wormgeard (Ctrl-C stops it); clients in build/release/clients" >&2
exec build/release/daemon/wormgeard --foreground --state-dir "$WG_STATE_DIR" "$@"
