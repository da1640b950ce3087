#!/usr/bin/env bash
# Sets up, builds, and runs every unit and end-to-end test; then the sanitizer
# gate (scripts/sanitize.sh: the end-to-end runs under ThreadSanitizer and
# under Address+UndefinedBehaviorSanitizer; HMT_SKIP_SANITIZERS=1 skips it);
# then every fuzz target briefly over its corpus (scripts/fuzz.sh;
# HMT_SKIP_FUZZ=1 skips it).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
(cd build && ctest --output-on-failure -j "$(nproc)")
if [ "${HMT_SKIP_SANITIZERS:-0}" = 1 ]; then
  echo "test: sanitizer builds skipped (HMT_SKIP_SANITIZERS=1)"
else
  bash scripts/sanitize.sh all
fi
if [ "${HMT_SKIP_FUZZ:-0}" = 1 ]; then
  echo "test: fuzz targets skipped (HMT_SKIP_FUZZ=1)"
else
  bash scripts/fuzz.sh
fi
