#!/usr/bin/env bash
# README command 1: install what is missing, build Strata (release) and run the main job on the bundled
# default scene (assets/scenes/playground.json). States go to build/playground.jsonl.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
bash "$root/tools/scripts/install-deps.sh"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DSTRATA_BUILD_TESTS=OFF > /dev/null
cmake --build "$root/build" --target strata -j "$(nproc)"
"$root/build/tools/strata" simulate "$root/assets/scenes/playground.json" --steps 600 --every 10 \
  --out "$root/build/playground.jsonl"
