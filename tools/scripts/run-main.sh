#!/usr/bin/env bash
# README command 1: install what is missing, build Strata (release) and run the main job on the bundled
# default level (assets/levels/courtyard.obj): a moving world with agents and background navmesh tiles.
# The navmesh goes to build/demo/navmesh.obj, a top-down picture to build/demo/navmesh.png, and the browser
# viewer of the recorded run to build/demo/view/index.html.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
bash "$root/tools/scripts/install-deps.sh"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DSTRATA_BUILD_TESTS=OFF > /dev/null
cmake --build "$root/build" --target strata -j "$(nproc)"
"$root/build/tools/strata" demo "$root/assets/levels/courtyard.obj" --out-dir "$root/build/demo" \
  --record "$root/build/demo/run.json"
"$root/build/tools/strata" view "$root/build/demo/run.json" --out "$root/build/demo/view"
echo "open build/demo/view/index.html in a browser, or serve it: build/tools/strata view build/demo/run.json --out build/demo/view --serve"
