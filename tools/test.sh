#!/usr/bin/env bash
# Set up, build and run the whole wormgear test suite: a Release build and an
# AddressSanitizer + UBSan build, each under ctest, then wgsweep built with
# MPI and its identical-output test under mpirun. Run as root on Debian 12.
# Ends with one line totalling the three runs. No arguments (--help: this).
set -euo pipefail
. "$(dirname "$0")/args.sh"
args_none test.sh "$@"
cd "$(dirname "$0")/.."
bash tools/setup.sh
jobs=$(nproc)
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
run_ctest() { # run_ctest NAME DIR [ctest args...]
  local name=$1 dir=$2; shift 2
  echo "== $name tests"
  (cd "$dir" && ctest --output-on-failure --timeout 600 "$@") 2>&1 | tee "$logs/$name"
  return "${PIPESTATUS[0]}"
}
status=0
for kind in release asan; do
  dir=build/$kind
  if [ $kind = asan ]; then extra=(-DWG_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug); else extra=(-DCMAKE_BUILD_TYPE=Release); fi
  echo "== $kind build"
  cmake -S . -B "$dir" "${extra[@]}" >/dev/null
  cmake --build "$dir" -j"$jobs" >/dev/null
  run_ctest "$kind" "$dir" || status=1
done
# wgsweep across MPI ranks (OpenMPI): its output must equal the serial run's.
echo "== mpi build (wgsweep only)"
cmake -S . -B build/mpi -DCMAKE_BUILD_TYPE=Release -DWG_MPI=ON >/dev/null
cmake --build build/mpi -j"$jobs" --target wgsweep >/dev/null
run_ctest mpi build/mpi -R 'clients\.wgsweep_cli' || status=1
# Total over the three runs: "N% tests passed, F tests failed out of T".
total=0 failed=0
for f in "$logs"/*; do
  line=$(grep -E "tests passed, [0-9]+ tests? failed out of [0-9]+" "$f" | tail -1 || true)
  [ -n "$line" ] || { echo "no ctest summary in $(basename "$f")"; status=1; continue; }
  t=$(sed -E 's/.* out of ([0-9]+).*/\1/' <<<"$line")
  fl=$(sed -E 's/.*, ([0-9]+) tests? failed.*/\1/' <<<"$line")
  total=$((total + t)) failed=$((failed + fl))
done
echo "all runs (release, asan, mpi): $((total - failed)) passed, $failed failed"
exit $status
