#!/usr/bin/env bash
# A ROS bag made from a CARMEN log maps like the log itself: log-to-bag
# writes the log as two bags (odometry as nav_msgs/Odometry, and as /tf
# transforms; the laser's mounting on /tf_static), then `hmt-slam run` maps
# the log and both bags with the same configuration. Prints, for each, the
# position RMSE against the log's reference trajectory (scripts/ate.py), the
# relation error where the datasets have relations (scripts/relation_error.py),
# the wall time and peak memory, and whether the bags' maps and trajectories
# are byte-identical to the log's.
#
# Environment (defaults in brackets):
#   LOG       the shared CARMEN log's name [intel]
#   DATASETS  the shared datasets [<repo>/../shared/datasets]
#   CONFIG    [<repo>/config/default.ini]
#   OUT_DIR   [/tmp/hmt-bench-rosbag]
#   BUILD     the build folder with apps/hmt-slam and apps/log-to-bag [<repo>/build]
#   PYTHON    a Python 3 with numpy [/usr/bin/python3]
set -euo pipefail
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BENCH_NAME=bench_rosbag
# shellcheck source=scripts/bench_lib.sh
source "$REPO/scripts/bench_lib.sh"
LOG=${LOG:-intel}
DATASETS=${DATASETS:-$REPO/../shared/datasets}
CONFIG=${CONFIG:-$REPO/config/default.ini}
OUT_DIR=${OUT_DIR:-/tmp/hmt-bench-rosbag}
BUILD=${BUILD:-$REPO/build}
PYTHON=${PYTHON:-/usr/bin/python3}
HMT_SLAM=$BUILD/apps/hmt-slam
LOG_TO_BAG=$BUILD/apps/log-to-bag
bench_need_tool "$HMT_SLAM" "build the hmt-slam target"
bench_need_tool "$LOG_TO_BAG" "build the log-to-bag target"
bench_need_tool "$PYTHON" "Debian package python3"
log_file=$DATASETS/carmen/$LOG.log.gz
reference=$DATASETS/carmen/$LOG.reference.txt.gz
relations=$DATASETS/relations/$LOG.relations
[[ -f "$log_file" ]] || bench_die "no log $log_file"
mkdir -p "$OUT_DIR"

for odometry in topic tf; do
  bench_log "$LOG: writing $OUT_DIR/$LOG.$odometry.bag"
  "$LOG_TO_BAG" --input "$log_file" --output "$OUT_DIR/$LOG.$odometry.bag" --odometry "$odometry" >&2
done

printf '| input | ATE RMSE (max) m | relation error m / deg | wall s | peak RSS MB | same map and trajectory as the log |\n'
printf '|---|---|---|---|---|---|\n'
for input in log topic tf; do
  if [[ $input == log ]]; then in=$log_file; else in=$OUT_DIR/$LOG.$input.bag; fi
  out=$OUT_DIR/run_$input
  bench_log "$LOG: hmt-slam run on $(basename "$in")"
  rm -rf "$out"
  bench_measure 3600 "$OUT_DIR/time_$input.txt" "$OUT_DIR/output_$input.txt" \
    "$HMT_SLAM" run --config "$CONFIG" --input "$in" --out "$out" --quiet ||
    bench_die "hmt-slam failed on $in (see $OUT_DIR/output_$input.txt)"
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, p, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + p[i]; printf "%.1f", s}' "$OUT_DIR/time_$input.txt")
  rss=$(awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$OUT_DIR/time_$input.txt")
  ate=-
  if [[ -f "$reference" ]]; then
    ate=$("$PYTHON" "$REPO/scripts/ate.py" "$out/trajectory.tum" "$reference" |
          sed -n 's/.*RMSE \([0-9.]*\) m, max \([0-9.]*\) m.*/\1 (\2)/p')
  fi
  rel=-
  if [[ -f "$relations" ]]; then
    rel=$("$PYTHON" "$REPO/scripts/relation_error.py" "$out/trajectory.tum" "$relations" |
          sed -n 's/.*translational \([0-9.]*\) .* rotational \([0-9.]*\) .*/\1 \/ \2/p')
  fi
  same=-
  if [[ $input != log ]]; then
    same=yes
    for f in trajectory.tum map.pgm topology.json; do
      cmp -s "$out/$f" "$OUT_DIR/run_log/$f" || same="no ($f differs)"
    done
  fi
  printf '| %s | %s | %s | %s | %s | %s |\n' "$(basename "$in")" "$ate" "$rel" "$wall" "$rss" "$same"
done
