#!/usr/bin/env bash
# Set up, build and run wormgear's main job on the default scene (table3).
# Run as root on Debian 12. Extra arguments go to the program.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j"$(nproc)" >/dev/null
export WG_SCENE_PATH=$PWD/scenes
exec build/release/clients/wgsim --scene table3 "$@"
