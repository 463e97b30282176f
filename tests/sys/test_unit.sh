#!/bin/sh
# test_unit.sh UNIT.in WORMGEARD - the systemd unit template, with Debian's
# paths filled in as the .deb does (and ExecStart pointing at the binary
# under test): `systemd-analyze verify` and `systemd-analyze security
# --offline=yes` (exposure must stay <= 2.0).
# Exit 77 (ctest: skipped) when systemd-analyze is not installed.
unit=$1 bin=$2
if ! command -v systemd-analyze >/dev/null 2>&1; then
    echo "SKIP: systemd-analyze not found (Debian: apt-get install systemd)"
    exit 77
fi
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
# verify checks that ExecStart exists: point it at the binary under test
sed -e "s|@WG_SBINDIR@/wormgeard|$bin|" -e "s|@WG_CONFDIR@|/etc/wormgear|g" \
    -e "s|@WG_DOCDIR@|/usr/share/doc/wormgear|g" -e "s|@WG_UNITDIR@|/usr/lib/systemd/system|g" \
    -e "s|@WG_CONFIGURATION_DIRECTORY@|ConfigurationDirectory=wormgear|" "$unit" >"$tmp/wormgeard.service"
if grep -n '@WG_' "$tmp/wormgeard.service"; then
    echo "FAIL: placeholders left in the unit"
    exit 1
fi
cd "$tmp" || exit 1
if ! systemd-analyze verify "$tmp/wormgeard.service"; then
    echo "FAIL: systemd-analyze verify"
    exit 1
fi
out=$(systemd-analyze security --offline=yes "$tmp/wormgeard.service" 2>&1)
score=$(printf '%s\n' "$out" | sed -n 's/.*Overall exposure level for [^:]*: \([0-9.]*\).*/\1/p')
printf '%s\n' "$out" | grep -v '^✓' | tail -n 20
echo "systemd-analyze security --offline=yes: exposure $score"
[ -n "$score" ] || { echo "FAIL: no exposure score"; exit 1; }
awk -v s="$score" 'BEGIN { exit !(s <= 2.0) }' || { echo "FAIL: exposure $score > 2.0"; exit 1; }
echo "ok"
