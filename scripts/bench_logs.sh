#!/usr/bin/env bash
# Every log with the default configuration, as a new user runs them: our
# `hmt-slam run --config config/default.ini` on each shared CARMEN log and
# the embedded Malaga log, against MRPT's `rbpf-slam` with its stock
# gridmapping_optimal_sampling.ini (its own update thresholds, the same
# particle count): each tool at its own default settings, the time and
# memory to each tool's map. Per log: wall and CPU time, peak RSS, their
# ratios, our areas and accepted loop closures, the position RMSE of both
# against the log's reference trajectory, and the Intel relation error.
#
# Everything is run by scripts/bench_metric.sh, one heavy process at a time;
# its environment variables apply (PARTICLES, SEED, REPEAT, TIMEOUT, OUT_DIR,
# DATASETS, ...). LOGS defaults to every log below; a per-log INI is never
# used (CONFIG is config/default.ini unless set).
set -euo pipefail
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
export LOGS=${LOGS:-malaga seattle freiburg-101 csail edmonton aces fhw intel acapulco infinite-corridor}
export MODE=run
export CONFIG=${CONFIG:-$REPO/config/default.ini}
export MRPT_UPDATES=${MRPT_UPDATES:-ini}
export TIMEOUT=${TIMEOUT:-1800}
export TABLE=${TABLE:-logs.md}
export TITLE=${TITLE:-"Every log, default configuration: HMT-SLAM against MRPT's rbpf-slam (stock ini)"}
exec bash "$REPO/scripts/bench_metric.sh"
