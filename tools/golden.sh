#!/usr/bin/env bash
# Fingerprint of what the offline tools write, to show that a refactoring
# changed no output: runs a fixed set of wgsim and wgsweep commands from the
# build directory BUILD and prints one "sha256  file" line per output (PNG
# plots excepted: their text goes through fontconfig). Compare two builds:
#   tools/golden.sh build-old > a; tools/golden.sh build-new > b; diff a b
# Needs: WG_SCENE_PATH or the source tree's scenes/ (set below).
# --help: this text.
set -euo pipefail
. "$(dirname "$0")/args.sh"
args_help "$@"
[ $# -eq 1 ] || args_refuse golden.sh "BUILD_DIR, one argument, got $#"
for p in wgsim wgsweep; do
  [ -n "$(find "$1" -name $p -type f -perm -u+x 2>/dev/null | head -1)" ] ||
    args_refuse golden.sh "BUILD_DIR '$1': no $p in it (a build directory, e.g. build/release)"
done
build=$(cd "$1" && pwd)
src=$(cd "$(dirname "$0")/.." && pwd)
export WG_SCENE_PATH=$src/scenes
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# Run them by name, so the command line they record is the same for any build.
mkdir "$out/bin"
for p in wgsim wgsweep; do
  ln -s "$(find "$build" -name $p -type f -perm -u+x | head -1)" "$out/bin/$p"
done
export PATH=$out/bin:$PATH
sim=wgsim sweep=wgsweep
cd "$out"
for sc in table3 lowfreq realistic torsional table3-physical; do
  "$sim" --scene "$sc" --set omega=0.7 --periods 40 --transient 20 \
         --poincare "$sc.poincare.csv" --events "$sc.events.csv" >/dev/null
done
"$sim" --set omega=1.2 --periods 5 --transient 0 --trace trace.csv >/dev/null
"$sim" --set omega=0.7 --stepper rk4 --periods 20 --transient 0 --poincare rk4.csv >/dev/null
"$sim" --set omega=0.9 --periods 10 --units physical --poincare phys.csv --events physev.csv >/dev/null
"$sim" --set omega=1.3 --periods 30 >/dev/null # summary path (timings vary: not hashed)
"$sweep" --quiet --no-png --values xi_p=0.08,0.10,0.12 --step 0.01 --out study >/dev/null
"$sweep" --quiet --no-png --param k_a --from 0.1 --to 0.5 --points 9 --set omega=1.3 --out ka >/dev/null
"$sweep" --quiet --no-png --map xi_p=0.05:0.15:3 --step 0.1 --out map >/dev/null
"$sweep" --quiet --no-png --at 1.2 --at-periods 200 --floquet --out view >/dev/null
# JSON and Markdown carry the wall time; blank it before hashing.
for f in *.json *.md; do
  sed -E 's/"(wall|cpu)_s": *[0-9.e+-]+/"\1_s": 0/; s/Wall time [0-9.]+ s/Wall time - s/' "$f" > "$f.x"
  mv "$f.x" "$f"
done
sha256sum $(ls | grep -v -E '\.png$|^bin$' | sort)
