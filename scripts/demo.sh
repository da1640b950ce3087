#!/usr/bin/env bash
# Sets up, builds, and runs HMT-SLAM on the embedded Malaga one-loop log.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
OUT=${OUT:-out/malaga}
./build/apps/hmt-slam run --config config/default.ini --out "$OUT" --report
echo "map image: $(pwd)/$OUT/map.png"
echo "report (open in a browser): $(pwd)/$OUT/report/index.html"
