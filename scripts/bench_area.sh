#!/usr/bin/env bash
# Area abstraction benchmark.
#
# 1. Offline grouping (hmt-partition, 001 Sec. IV) on the embedded Malaga log
#    (poses from its odometry) and on Intel (poses from intel.reference.txt.gz),
#    with keyframes every 0.5 m / 0.5 rad (the tool's default) and with every
#    scan a keyframe. The grouping time is the tool's own measure of steps 1-3
#    on the keyframes (SSO weight matrix + recursive Ncut; summary.json
#    time_s.grouping); the total also counts reading the log, the local maps,
#    the topology and writing every image. Target: grouping at most 0.25 s per
#    100 scans grouped (per 100 keyframes: they are the nodes of the graph).
# 2. Online area detection: Google Benchmark hmt_area_bench, BM_OnlineKeyframe
#    at windows of 50..500 keyframes (synthetic corridor scans, see
#    libs/area/bench/area_bench.cc); scripts/plot_area_bench.py prints the
#    table, checks the targets (<= 2 ms per keyframe at 300; cost(500) /
#    cost(50) <= 10, i.e. no faster than linear) and plots cost vs window.
#
# Runs are sequential (one process at a time, single-threaded).
#
# Environment (defaults in brackets):
#   BUILD_DIR      [<repo>/build]
#   HMT_PARTITION  [$BUILD_DIR/apps/hmt-partition]
#   AREA_BENCH     [$BUILD_DIR/libs/area/hmt_area_bench] (built when Google
#                  Benchmark is installed: Debian libbenchmark-dev)
#   DATASETS       [<repo>/../shared/datasets]
#   CONFIG         hmt-partition's configuration [<repo>/config/default.ini]
#   REPEAT         hmt-partition runs per case; the fastest is reported [3]
#   REPETITIONS    Google Benchmark repetitions; medians are reported [3]
#   OUT_DIR        area.md, area_online.json and area_online.png [/tmp/hmt-bench/area]
#   WORK_DIR       hmt-partition outputs [/tmp/hmt-bench/area-work]
#   PYTHON         a python3 with matplotlib [first of /usr/bin/python3, python3]
#
# Exit status: 0 when every target is met, 1 when a run fails or a target is
# missed (the tables are printed and written anyway), 2 on a set-up error.
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${BUILD_DIR:-$REPO/build}
HMT_PARTITION=${HMT_PARTITION:-$BUILD_DIR/apps/hmt-partition}
AREA_BENCH=${AREA_BENCH:-$BUILD_DIR/libs/area/hmt_area_bench}
DATASETS=$(realpath -m "${DATASETS:-$REPO/../shared/datasets}")
CONFIG=$(realpath -m "${CONFIG:-$REPO/config/default.ini}")
REPEAT=${REPEAT:-3}
REPETITIONS=${REPETITIONS:-3}
OUT_DIR=${OUT_DIR:-/tmp/hmt-bench/area}
WORK_DIR=${WORK_DIR:-/tmp/hmt-bench/area-work}
TARGET_S_PER_100=0.25

log() { printf '[bench_area] %s\n' "$*" >&2; }
die() {
  printf 'bench_area: error: %s\n' "$*" >&2
  exit 2
}

# ---------------------------------------------------------------- checks
[[ "$REPEAT" =~ ^[1-9][0-9]*$ ]] || die "REPEAT must be a positive integer, not '$REPEAT'"
[[ "$REPETITIONS" =~ ^[1-9][0-9]*$ ]] || die "REPETITIONS must be a positive integer, not '$REPETITIONS'"
[[ -x "$HMT_PARTITION" ]] || die "$HMT_PARTITION not found: build it with scripts/build.sh"
[[ -r "$CONFIG" ]] || die "configuration $CONFIG not found"
[[ -x "$AREA_BENCH" ]] || die "$AREA_BENCH not found: install Google Benchmark (libbenchmark-dev) and rebuild"
if [[ -z "${PYTHON:-}" ]]; then
  for p in /usr/bin/python3 python3; do
    if command -v "$p" >/dev/null 2>&1 && "$p" -c 'import matplotlib' 2>/dev/null; then
      PYTHON=$p
      break
    fi
  done
  [[ -n "${PYTHON:-}" ]] || die "no python3 with matplotlib found (Debian: python3-matplotlib); set PYTHON"
fi
INTEL_LOG=$DATASETS/carmen/intel.log.gz
INTEL_REF=$DATASETS/carmen/intel.reference.txt.gz
[[ -r "$INTEL_LOG" && -r "$INTEL_REF" ]] || die "Intel log or reference not found under $DATASETS/carmen"
mkdir -p "$OUT_DIR" "$WORK_DIR" || die "cannot create $OUT_DIR or $WORK_DIR"

status=0

# ------------------------------------------------------- 1. offline grouping
# run_case NAME ARGS...: REPEAT runs of hmt-partition into WORK_DIR/NAME;
# prints one table row (fastest grouping time, and that run's figures).
run_case() {
  local name=$1
  shift
  local best="" out rc
  for ((r = 1; r <= REPEAT; r++)); do
    out=$WORK_DIR/$name.$r
    rm -rf "$out"
    rc=0
    (cd "$REPO" && "$HMT_PARTITION" --config "$CONFIG" --quiet --set output.pgm=false \
      --out "$out" "$@") >"$WORK_DIR/$name.$r.log" 2>&1 </dev/null || rc=$?
    if [[ $rc -ne 0 ]]; then
      log "$name: hmt-partition failed (exit $rc), see $WORK_DIR/$name.$r.log"
      printf '| %s | FAIL (exit %s) | | | | | | | |\n' "$name" "$rc"
      return 1
    fi
    best=$("$PYTHON" - "$out/summary.json" "$best" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
prev = sys.argv[2]
if prev and float(prev.split()[0]) <= s["time_s"]["grouping"]:
    print(prev)
else:
    print(s["time_s"]["grouping"], sys.argv[1])
EOF
)
  done
  "$PYTHON" - "${best#* }" "$name" "$TARGET_S_PER_100" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
t = s["time_s"]
kf = s["keyframes"]
per100 = 100.0 * t["grouping"] / kf
verdict = "PASS" if per100 <= float(sys.argv[3]) else "FAIL"
print(f"| {sys.argv[2]} | {s['scans']} | {kf} | {s['groups']} | {t['grouping']:.3f} "
      f"| {per100:.3f} | {verdict} | {t['total']:.2f} | {100.0 * t['total'] / s['scans']:.3f} |")
EOF
}

offline_table() {
  echo "## Offline grouping (hmt-partition; fastest of $REPEAT runs)"
  echo
  echo "Grouping = SSO weight matrix + recursive Ncut over the keyframes (target <= $TARGET_S_PER_100 s per 100)."
  echo "Total = the whole tool: reading the log, keyframes, grouping, local maps, topology, images."
  echo
  echo "| case | scans | keyframes | groups | grouping s | grouping s / 100 keyframes | target | total s | total s / 100 scans |"
  echo "|---|---:|---:|---:|---:|---:|---|---:|---:|"
  run_case malaga --input datasets/malaga_one_loop.rawlog || status=1
  run_case malaga-every-scan --input datasets/malaga_one_loop.rawlog \
    --keyframe-distance 0 --keyframe-angle 0 || status=1
  run_case intel --input "$INTEL_LOG" --poses "$INTEL_REF" || status=1
  run_case intel-every-scan --input "$INTEL_LOG" --poses "$INTEL_REF" \
    --keyframe-distance 0 --keyframe-angle 0 || status=1
}

log "offline grouping: hmt-partition on Malaga and Intel ($REPEAT runs each)"
offline=$(offline_table) || status=1
grep -q '| FAIL' <<<"$offline" && status=1

# ------------------------------------------------------- 2. online cost
log "online cost: hmt_area_bench BM_OnlineKeyframe ($REPETITIONS repetitions)"
bench_json=$OUT_DIR/area_online.json
rc=0
"$AREA_BENCH" --benchmark_filter='^BM_OnlineKeyframe/' --benchmark_repetitions="$REPETITIONS" \
  --benchmark_out="$bench_json" --benchmark_out_format=json \
  >"$WORK_DIR/area_bench.log" 2>&1 </dev/null || rc=$?
if [[ $rc -ne 0 ]]; then
  log "hmt_area_bench failed (exit $rc), see $WORK_DIR/area_bench.log"
  online="hmt_area_bench FAILED (exit $rc)"
  status=1
else
  rc=0
  online=$("$PYTHON" "$REPO/scripts/plot_area_bench.py" "$bench_json" "$OUT_DIR/area_online.png") || rc=$?
  [[ $rc -eq 0 ]] || status=1
fi

report=$(
  echo "# Area abstraction benchmark"
  echo
  echo "$(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores; $(uname -m)"
  echo
  echo "$offline"
  echo
  echo "## Online area detection (hmt_area_bench, medians of $REPETITIONS repetitions)"
  echo
  echo "$online"
)
printf '%s\n' "$report" | tee "$OUT_DIR/area.md"
log "written: $OUT_DIR/area.md, $OUT_DIR/area_online.png; run outputs in $WORK_DIR"
exit "$status"
