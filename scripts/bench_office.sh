#!/usr/bin/env bash
# The default configuration on the simulated office floor: a long indoor run
# through corridors that all look alike (scripts/sim_office.py: 130 x 40 m,
# doors every few metres, parallel corridors 18.4 m apart, about 2 km and
# 5 000 scans a world). Each of WORLDS is written as a log with its true
# poses, then mapped once per seed of SEEDS and scored by
# scripts/bench_seeds.sh, as the shared logs are: position RMSE against the
# true poses, loops of the truth closed, wall time, peak RSS, areas and
# closures, per world and over every run. A run above THRESHOLD (2 m by
# default) holds a misplaced block: a corridor twice, or a block shifted
# across the floor. The failures are chaotic (one seed maps a world and the
# next breaks it), so judge a change over every world at three seeds or
# more (18 runs: about 20 minutes two at a time).
#
# Environment:
#   WORLDS     worlds, each one seed of sim_office.py [1 2 3 4 5 6]
#   SEEDS      filter seeds (metric_slam.seed) [1 2 3]
#   LENGTH     metres each walk goes [2000]
#   ODOMETRY   fair or harsh [fair]
#   THRESHOLD  position RMSE above which a run counts as broken (m) [2]
#   OUT_DIR    [/tmp/hmt-bench-office]; the logs go to OUT_DIR/datasets
#   JOBS, CONFIG, HMT_SLAM, TIMEOUT: as bench_seeds.sh
# Extra arguments go to every `hmt-slam run` (e.g. --set k=v to try a change).
set -euo pipefail
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
WORLDS=${WORLDS:-1 2 3 4 5 6}
LENGTH=${LENGTH:-2000}
ODOMETRY=${ODOMETRY:-fair}
OUT_DIR=${OUT_DIR:-/tmp/hmt-bench-office}
BENCH_NAME=bench_office
# shellcheck source=scripts/bench_lib.sh
source "$REPO/scripts/bench_lib.sh"

bench_need_counts WORLDS "$WORLDS"

# Written afresh every time: a log left by an older simulator would be
# scored against what that one drew.
data=$OUT_DIR/datasets
rm -rf "${data:?}"
mkdir -p "$data/carmen"
logs=()
for w in $WORLDS; do
  /usr/bin/python3 "$REPO/scripts/sim_office.py" "$data/carmen/office$w" --seed "$w" \
    --length "$LENGTH" --odometry "$ODOMETRY" >/dev/null ||
    bench_die "sim_office.py failed for world $w (LENGTH=$LENGTH, ODOMETRY=$ODOMETRY)"
  logs+=("office$w")
done

LOGS="${logs[*]}" DATASETS="$data" OUT_DIR="$OUT_DIR" SEEDS="${SEEDS:-1 2 3}" \
  THRESHOLD="${THRESHOLD:-2}" exec bash "$REPO/scripts/bench_seeds.sh" "$@"
