#!/usr/bin/env bash
# Table I of paper 002 reproduced: HMT-SLAM (`hmt-slam run`, each log with
# its config/NAME.ini, or config/default.ini) against MRPT's global RBPF
# (`rbpf-slam`, gridmapping_optimal_sampling.ini, logging off, the same
# particle count for its one filter as ours per hypothesis, and by default
# its filter and map updates on our thresholds: MRPT_UPDATES) on the classic
# logs, in one go. Prints wall time, CPU time, peak memory, their ratios
# MRPT/ours, and the Intel relation error of both. The paper's targets: at
# least 4x faster and 5x less peak memory, with equal or better error.
#
# Everything is run by scripts/bench_metric.sh (one heavy process at a time);
# its environment variables apply (PARTICLES, SEED, REPEAT, TIMEOUT,
# OUT_DIR, ...). LOGS defaults to the six logs of the table.
set -euo pipefail
export LOGS=${LOGS:-malaga edmonton aces intel acapulco infinite-corridor}
export MODE=run
export TABLE=${TABLE:-table1.md}
export TITLE=${TITLE:-"Table I (002): HMT-SLAM against the global RBPF of MRPT (rbpf-slam)"}
exec bash "$(dirname "${BASH_SOURCE[0]}")/bench_metric.sh"
