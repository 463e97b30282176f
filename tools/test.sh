#!/usr/bin/env bash
# Set up, build and run the whole wormgear test suite: a Release build and an
# AddressSanitizer + UBSan build, each under ctest. Run as root on Debian 12.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
jobs=$(nproc)
for kind in release asan; do
  dir=build/$kind
  if [ $kind = asan ]; then extra=(-DWG_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug); else extra=(-DCMAKE_BUILD_TYPE=Release); fi
  echo "== $kind build"
  cmake -S . -B "$dir" "${extra[@]}" >/dev/null
  cmake --build "$dir" -j"$jobs" 2>&1 | grep -E "warning|error" || true
  cmake --build "$dir" -j"$jobs" >/dev/null
  echo "== $kind tests"
  (cd "$dir" && ctest --output-on-failure --timeout 600)
done
