#!/bin/sh
# test_deb.sh CPACK BUILD WORMGEARD - the Debian package `cpack -G DEB`
# makes from a build: its file list (binaries under /usr, the unit in the
# systemd system directory, the config in /etc/wormgear as a conffile,
# scenes and docs under /usr/share), dependencies found by dpkg-shlibdeps,
# the unit's paths; `systemd-analyze verify` on the packaged unit.
cpack=$1 build=$2 bin=$3
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }

"$cpack" --config "$build/CPackConfig.cmake" -G DEB -B "$tmp" >"$tmp/cpack.log" 2>&1 ||
    { cat "$tmp/cpack.log"; echo "FAIL: cpack"; exit 1; }
deb=$(ls "$tmp"/wormgear_*.deb 2>/dev/null | head -1)
[ -n "$deb" ] || { cat "$tmp/cpack.log"; echo "FAIL: no .deb"; exit 1; }
dpkg-deb -c "$deb" | awk '{print $6}' | sed 's#^\./#/#' >"$tmp/files"
for f in /usr/bin/wgsim /usr/bin/wgsweep /usr/bin/wgctl /usr/bin/wgmon /usr/bin/wgrig \
         /usr/bin/wglog /usr/bin/wgspy /usr/sbin/wormgeard /usr/lib/systemd/system/wormgeard.service \
         /etc/wormgear/wormgeard.conf /usr/share/wormgear/scenes/table3.ini \
         /usr/share/doc/wormgear/daemon.md /usr/share/doc/wormgear/PROTOCOL.md; do
    grep -qx "$f" "$tmp/files" || fail "not in the package: $f"
done
grep -q '^/usr/lib/\(.*/\)\{0,1\}wormgear/libwgmcast_preload.so$' "$tmp/files" ||
    fail "not in the package: /usr/lib/wormgear/libwgmcast_preload.so (wgspy's filter)"
if grep -v -E '^/(usr|etc)(/|$)' "$tmp/files" | grep -v '^/$'; then fail "files outside /usr and /etc"; fi
dpkg-deb -I "$deb" conffiles >"$tmp/conffiles" 2>&1
grep -qx /etc/wormgear/wormgeard.conf "$tmp/conffiles" || fail "config not a conffile: $(cat "$tmp/conffiles")"
dpkg-deb -f "$deb" Depends >"$tmp/depends"
for d in liblcm1 libev4 libinih1 libsystemd0 libsodium23; do
    grep -q "$d" "$tmp/depends" || fail "Depends lacks $d: $(cat "$tmp/depends")"
done
dpkg-deb -x "$deb" "$tmp/root"
unit=$tmp/root/usr/lib/systemd/system/wormgeard.service
grep -q '^ExecStart=/usr/sbin/wormgeard --config /etc/wormgear/wormgeard.conf$' "$unit" || fail "ExecStart"
grep -q '^ConfigurationDirectory=wormgear$' "$unit" || fail "ConfigurationDirectory"
grep -q '^DynamicUser=yes$' "$unit" || fail "DynamicUser"
grep -q '^Documentation=file:/usr/share/doc/wormgear/daemon.md' "$unit" || fail "Documentation"
if command -v systemd-analyze >/dev/null 2>&1; then
    sed "s|^ExecStart=/usr/sbin/wormgeard|ExecStart=$bin|" "$unit" >"$tmp/wormgeard.service"
    (cd "$tmp" && systemd-analyze verify "$tmp/wormgeard.service") || fail "systemd-analyze verify"
fi
echo "$(basename "$deb"): $(wc -l <"$tmp/files") entries; Depends: $(cat "$tmp/depends")"
[ $status = 0 ] && echo "ok"
exit $status
