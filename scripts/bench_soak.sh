#!/usr/bin/env bash
# Soak benchmark: one log's loop driven LAPS times in a row (scripts/
# soak_log.py: the infinite corridor five times by default, about 10 km and
# 9 700 scans; the robot comes back to its start every lap), mapped with
# config/default.ini. Prints the run's wall time and peak RSS (GNU time)
# and, per lap (scripts/soak_report.py), the memory reached, the per-scan
# time of each process and how much of the lap was spent in the first lap's
# areas. Memory should stop growing after the first lap, time per scan
# should stay flat, and every later lap should close into the first lap's
# areas.
#
# Environment: LOG [infinite-corridor], LAPS [5], DATASETS
# [<repo>/../shared/datasets], OUT_DIR [/tmp/hmt-soak], HMT_SLAM
# [<repo>/build/apps/hmt-slam], extra hmt-slam arguments after the script's.
set -euo pipefail
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
LOG=${LOG:-infinite-corridor}
LAPS=${LAPS:-5}
DATASETS=$(realpath -m "${DATASETS:-$REPO/../shared/datasets}")
OUT_DIR=${OUT_DIR:-/tmp/hmt-soak}
HMT_SLAM=${HMT_SLAM:-$REPO/build/apps/hmt-slam}
src=$DATASETS/carmen/$LOG.log.gz
ref=$DATASETS/carmen/$LOG.reference.txt.gz
for f in "$src" "$ref" "$HMT_SLAM" /usr/bin/time; do
  [ -e "$f" ] || { echo "bench_soak: missing $f" >&2; exit 1; }
done
mkdir -p "$OUT_DIR"
soak=$OUT_DIR/$LOG-x$LAPS.log.gz
/usr/bin/python3 "$REPO/scripts/soak_log.py" "$src" "$ref" "$LAPS" "$soak"
lap_scans=$(zcat "$src" | grep -c '^FLASER')
/usr/bin/time -v -o "$OUT_DIR/time.txt" "$HMT_SLAM" run --config "$REPO/config/default.ini" \
  --input "$soak" --out "$OUT_DIR/run" --quiet "$@"
wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$OUT_DIR/time.txt")
rss=$(awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$OUT_DIR/time.txt")
echo "$LOG x $LAPS laps ($lap_scans scans a lap): wall $wall, peak RSS $rss MB"
/usr/bin/python3 "$REPO/scripts/soak_report.py" "$OUT_DIR/run" "$lap_scans"
