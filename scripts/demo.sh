#!/usr/bin/env bash
# Sets up, builds, and runs HMT-SLAM on the embedded Malaga one-loop log.
# OUT: the output folder (default <repo>/out/malaga); a relative OUT is taken
# from where the script is called, as any path a user types.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
OUT=$(realpath -m "${OUT:-$repo/out/malaga}")
cd "$repo"
bash scripts/setup.sh
bash scripts/build.sh
./build/apps/hmt-slam run --config config/default.ini --out "$OUT" --report
echo "map image: $OUT/map.png"
echo "report (open in a browser): $OUT/report/index.html"
