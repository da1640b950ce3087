#!/usr/bin/env bash
# Metric SLAM benchmark: our `hmt-slam run` against MRPT's `rbpf-slam`
# (Debian mrpt-apps) with its gridmapping_optimal_sampling.ini, on the same
# logs and the same particle count. Per log: wall time and peak RSS of both
# (GNU time -v), the ratios MRPT/ours, and, for logs with ground-truth
# relations (intel), the relation error (Kuemmerle et al. 2009) of both;
# for logs with a reference trajectory (NAME.reference.txt.gz), the position
# RMSE of both against it (scripts/ate.py); with MODE=run, our areas and
# accepted loop closures (summary.json).
#
# Ours reads config/NAME.ini when the log has one (its tuned [area] tau),
# config/default.ini otherwise. Runs are strictly sequential (one heavy
# process at a time). CARMEN logs are converted once by `hmt-slam convert
# --format sf` into CACHE_DIR; both programs then read that same
# Actions/SensoryFrame rawlog.
#
# Environment (defaults in brackets):
#   LOGS        logs to run ["malaga edmonton aces intel"]; "malaga" is the
#               embedded datasets/malaga_one_loop.rawlog, any other NAME is
#               $DATASETS/carmen/NAME.log.gz
#   MODE        ours: "run" (HMT-SLAM) or "metric" (the single-map RBPF) [run]
#   PARTICLES   particles for both programs [30]
#   THREADS     our metric_slam.threads [config default: 0 = one per core];
#               rbpf-slam is single-threaded
#   SEED        random seed for both (ours metric_slam.seed, MRPT RANDOM_SEED) [1]
#   REPEAT      runs of each program per log; the fastest is reported [1]
#   TIMEOUT     seconds per run before it is killed and reported FAIL [1800];
#               a killed MRPT run shows the time and memory it had reached
#               (">x", lower bounds, and so are its ratios)
#   OUT_DIR     where metric.md and per-log trajectories go [/tmp/hmt-bench/results]
#   CACHE_DIR   converted rawlogs [/tmp/hmt-bench/cache]
#   WORK_DIR    run outputs, logs and time reports [/tmp/hmt-bench/work]
#   DATASETS    [<repo>/../shared/datasets]
#   HMT_SLAM    our binary [<repo>/build/apps/hmt-slam]
#   RBPF_SLAM   [rbpf-slam]
#   MRPT_INI    [/usr/share/mrpt/config_files/rbpf-slam/gridmapping_optimal_sampling.ini]
#   MRPT_UPDATES when rbpf-slam runs its filter and inserts scans [matched]:
#               "matched" sets its localizeLin/AngDistance and
#               insertionLin/AngDistance to our run's update_distance /
#               update_angle and map_update_distance / map_update_angle
#               (read back from our run's config_effective.ini), so both
#               filters process the same scans, as the paper's Table I
#               compared the two methods over the same updates; "ini" keeps
#               MRPT_INI's own (1 m / 40 degrees in the stock file: about a
#               third of the scans of these logs, which are already thinned
#               to one scan every 0.3-0.6 m)
#   CONFIG      our config for every log [config/NAME.ini when the log has
#               one, else config/default.ini]
#   TABLE       file name of the table in OUT_DIR [metric.md]
#   TITLE       the table's heading [Metric SLAM: hmt-slam vs MRPT rbpf-slam]
#   RECONVERT=1 convert the CARMEN logs again even if cached
#   PYTHON      the Python 3 with numpy the scripts run with [/usr/bin/python3]
#
# Exit status: 0 when every run succeeded, 1 when a row says FAIL (the table is
# written anyway) or on a usage / set-up error.
set -euo pipefail

BENCH_NAME=bench_metric
BENCH_REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=scripts/bench_lib.sh
source "$BENCH_REPO/scripts/bench_lib.sh"

LOGS=${LOGS:-malaga edmonton aces intel}
PARTICLES=${PARTICLES:-30}
MODE=${MODE:-run}
THREADS=${THREADS:-}
SEED=${SEED:-1}
REPEAT=${REPEAT:-1}
TIMEOUT=${TIMEOUT:-1800}
OUT_DIR=${OUT_DIR:-/tmp/hmt-bench/results}
CACHE_DIR=${CACHE_DIR:-/tmp/hmt-bench/cache}
WORK_DIR=${WORK_DIR:-/tmp/hmt-bench/work}
DATASETS=$(realpath -m "${DATASETS:-$BENCH_REPO/../shared/datasets}")
HMT_SLAM=${HMT_SLAM:-$BENCH_REPO/build/apps/hmt-slam}
RBPF_SLAM=${RBPF_SLAM:-rbpf-slam}
MRPT_INI=${MRPT_INI:-/usr/share/mrpt/config_files/rbpf-slam/gridmapping_optimal_sampling.ini}
CONFIG=${CONFIG:-}
MRPT_UPDATES=${MRPT_UPDATES:-matched}
TABLE=${TABLE:-metric.md}
TITLE=${TITLE:-Metric SLAM: hmt-slam vs MRPT rbpf-slam}
PYTHON=${PYTHON:-/usr/bin/python3}
export PYTHON

# ---------------------------------------------------------------- checks
[[ "$MODE" == run || "$MODE" == metric ]] || bench_die "MODE must be 'run' or 'metric', not '$MODE'"
[[ "$MRPT_UPDATES" == matched || "$MRPT_UPDATES" == ini ]] || bench_die "MRPT_UPDATES must be 'matched' or 'ini', not '$MRPT_UPDATES'"
[[ "$PARTICLES" =~ ^[1-9][0-9]*$ ]] || bench_die "PARTICLES must be a positive integer, not '$PARTICLES'"
[[ "$SEED" =~ ^[0-9]+$ ]] || bench_die "SEED must be a non-negative integer, not '$SEED'"
[[ -z "$THREADS" || "$THREADS" =~ ^[0-9]+$ ]] || bench_die "THREADS must be a non-negative integer, not '$THREADS'"
[[ "$REPEAT" =~ ^[1-9][0-9]*$ ]] || bench_die "REPEAT must be a positive integer, not '$REPEAT'"
[[ "$TIMEOUT" =~ ^[1-9][0-9]*$ ]] || bench_die "TIMEOUT must be a positive number of seconds, not '$TIMEOUT'"
[[ -n "${LOGS// /}" ]] || bench_die "LOGS is empty"
[[ -x /usr/bin/time ]] || bench_die "/usr/bin/time (GNU time) not found: apt-get install time"
bench_need_tool timeout
bench_need_tool "$PYTHON" "Debian package python3"
bench_need_tool "$RBPF_SLAM" "Debian package mrpt-apps"
bench_need_tool "$HMT_SLAM" "build it with scripts/build.sh"
[[ -r "$MRPT_INI" ]] || bench_die "MRPT config $MRPT_INI not found (Debian package mrpt-common)"
[[ -z "$CONFIG" || -r "$CONFIG" ]] || bench_die "$CONFIG not found"
for f in relation_error.py ate.py bench/mrpt_path.py; do
  [[ -r "$BENCH_REPO/scripts/$f" ]] || bench_die "scripts/$f not found"
done
mkdir -p "$OUT_DIR" "$CACHE_DIR" "$WORK_DIR" || bench_die "cannot create the output folders"

# ------------------------------------------------------------ per-log steps
# Each sets ERR on failure and returns 1; nothing here exits the script.

# log_input NAME: the rawlog both programs read (converting CARMEN once).
log_input() {
  local name=$1
  if [[ $name == malaga ]]; then
    INPUT=$BENCH_REPO/datasets/malaga_one_loop.rawlog
    [[ -r $INPUT ]] || { ERR="$INPUT missing"; return 1; }
    return 0
  fi
  local src=$DATASETS/carmen/$name.log.gz
  [[ -r $src ]] || { ERR="no log $src"; return 1; }
  INPUT=$CACHE_DIR/$name.rawlog
  if [[ ${RECONVERT:-0} == 1 || ! -s $INPUT || $src -nt $INPUT ]]; then
    bench_log "$name: converting $src -> $INPUT"
    local part=$CACHE_DIR/$name.part.rawlog
    rm -f "$part"
    if ! timeout "$TIMEOUT" "$HMT_SLAM" convert --input "$src" --output "$part" --format sf \
        </dev/null >"$WORK_DIR/$name/convert.log" 2>&1 || [[ ! -s $part ]]; then
      rm -f "$part"
      ERR="conversion failed: $(tail -n 1 "$WORK_DIR/$name/convert.log")"
      return 1
    fi
    mv -f "$part" "$INPUT"
  fi
}

# config_for NAME: our config for a log (CONFIG, or the log's own, or the default).
config_for() {
  if [[ -n $CONFIG ]]; then echo "$CONFIG"
  elif [[ -r $BENCH_REPO/config/$1.ini ]]; then echo "$BENCH_REPO/config/$1.ini"
  else echo "$BENCH_REPO/config/default.ini"; fi
}

# run_ours NAME: sets OURS_WALL OURS_CPU OURS_RSS OURS_SCANS OURS_TRAJ.
run_ours() {
  local name=$1
  local d=$WORK_DIR/$name/ours
  rm -rf "$d" && mkdir -p "$d"
  local args=("$MODE" --config "$(config_for "$name")" --input "$INPUT" --out "$d/out" --quiet
    --set "metric_slam.particles=$PARTICLES" --set "metric_slam.seed=$SEED")
  [[ -n $THREADS ]] && args+=(--set "metric_slam.threads=$THREADS")
  bench_log "$name: hmt-slam $MODE ($PARTICLES particles)"
  if ! bench_measure_best "$REPEAT" "$TIMEOUT" "$d" "$HMT_SLAM" "${args[@]}"; then
    ERR=$BENCH_ERR
    return 1
  fi
  OURS_WALL=$BENCH_WALL OURS_CPU=$BENCH_CPU OURS_RSS=$BENCH_RSS
  OURS_TRAJ=$d/out/trajectory.tum
  [[ -s $OURS_TRAJ ]] || { ERR="no trajectory.tum"; return 1; }
  OURS_SCANS=$(grep -cv '^[[:space:]]*\(#\|$\)' "$OURS_TRAJ" || true)
  if [[ $MODE == run ]]; then
    read -r OURS_AREAS OURS_CLOSURES < <("$PYTHON" -c 'import json, sys
j = json.load(open(sys.argv[1]))
print(j["areas"], j["loop_closures_accepted"])' "$d/out/summary.json" 2>/dev/null || echo "- -")
  fi
}

# mrpt_ini OUTDIR FILE: MRPT's ini with every file-writing or window
# option off, our rawlog, particle count and seed.
#
# What rbpf-slam (MRPT 2.5, libs/apps/src/RBPF_SLAM_App.cpp) writes:
#  - every LOG_FREQUENCY steps (LOG_FREQUENCY=0 skips the whole block):
#    GENERATE_LOG_INFO (entropy + EMMI_gridmap_*.png), SAVE_POSE_LOG
#    (mapbuild_posepdf_*.txt), SAVE_MAP_IMAGES (maps/, mapping_*.png),
#    SAVE_3D_SCENE (3D/*.3Dscene), SHOW_PROGRESS_IN_WINDOW (a 3D window, which
#    also makes it wait for a key at the end), GENERATE_LOG_JOINT_H; all are
#    also switched off one by one;
#  - always, whatever the options: log_times.txt, log_estimated_path.txt,
#    log_odometry_path.txt, log_ParticlesStats.txt (one short line per scan),
#    log_MemoryUsage.txt (opened, appended, closed each scan) and, at the end,
#    _finalmap_.simplemap, finalMap_*.png and most_likely_path.txt. These
#    cost milliseconds in total and cannot be turned off; the trajectory is
#    taken from them, so no extra logging and no second run are needed.
#  - it deletes the files in logOutput_dir first: give it a folder of its own.
#  - it quits when ESC arrives on stdin: stdin is /dev/null.
#  - verbosity (the app) and verbosity_level (the map builder) at WARN: the
#    file's DEBUG prints several lines per particle and per scan.
mrpt_ini() {
  local outdir=$1 ini=$2 kv
  cp "$MRPT_INI" "$ini" || return 1
  for kv in "rawlog_file=$INPUT" rawlog_offset=0 "logOutput_dir=$outdir" \
      LOG_FREQUENCY=0 GENERATE_LOG_JOINT_H=0 GENERATE_LOG_INFO=0 SAVE_MAP_IMAGES=0 \
      SAVE_3D_SCENE=0 SAVE_POSE_LOG=0 SAVE_ENOSE_READINGS=0 CAMERA_3DSCENE_FOLLOWS_ROBOT=0 \
      SHOW_PROGRESS_IN_WINDOW=0 SHOW_PROGRESS_IN_WINDOW_DELAY_MS=0 \
      verbosity=WARN verbosity_level=WARN \
      adaptiveSampleSize=0 "sampleSize=$PARTICLES" "RANDOM_SEED=$SEED" "${MRPT_MATCHED[@]}"; do
    bench_ini_set "$ini" MappingApplication "${kv%%=*}" "${kv#*=}" || return 1
  done
}

# matched_updates NAME: MRPT_MATCHED, the ini keys that make rbpf-slam filter
# and insert on our run's thresholds (empty with MRPT_UPDATES=ini).
matched_updates() {
  MRPT_MATCHED=()
  [[ $MRPT_UPDATES == matched ]] || return 0
  local eff=$WORK_DIR/$1/ours/out/config_effective.ini k v lin ang ins_lin ins_ang
  [[ -r $eff ]] || { ERR="no config_effective.ini from our run to match MRPT's updates to"; return 1; }
  local -A ours=()
  for k in update_distance update_angle map_update_distance map_update_angle; do
    v=$(bench_ini_get "$eff" metric_slam "$k") || { ERR="$k not in $eff"; return 1; }
    ours[$k]=$v
  done
  # Angles in degrees; six significant digits are exact enough for both.
  read -r lin ang ins_lin ins_ang < <("$PYTHON" -c 'import math, sys
u, ua, m, ma = map(float, sys.argv[1:])
print("%.6g %.6g %.6g %.6g" % (u, math.degrees(ua), m, math.degrees(ma)))' \
    "${ours[update_distance]}" "${ours[update_angle]}" \
    "${ours[map_update_distance]}" "${ours[map_update_angle]}") ||
    { ERR="cannot read our update thresholds from $eff"; return 1; }
  MRPT_MATCHED=("localizeLinDistance=$lin" "localizeAngDistance_deg=$ang"
    "insertionLinDistance=$ins_lin" "insertionAngDistance_deg=$ins_ang")
}

# run_mrpt NAME: sets MRPT_WALL MRPT_CPU MRPT_RSS MRPT_SCANS MRPT_TRAJ MRPT_MEAN_TRAJ.
run_mrpt() {
  local name=$1
  local d=$WORK_DIR/$name/mrpt
  rm -rf "$d" && mkdir -p "$d/out"
  matched_updates "$name" || return 1
  mrpt_ini "$d/out" "$d/rbpf-slam.ini" || { ERR="cannot write the ini"; return 1; }
  local lin ang
  lin=$(bench_ini_get "$d/rbpf-slam.ini" MappingApplication localizeLinDistance) &&
    ang=$(bench_ini_get "$d/rbpf-slam.ini" MappingApplication localizeAngDistance_deg) ||
    { ERR="no localizeLinDistance / localizeAngDistance_deg in the ini"; return 1; }
  MRPT_UPDATE="$lin m or ${ang}°"
  bench_log "$name: rbpf-slam ($PARTICLES particles)"
  if ! bench_measure_best "$REPEAT" "$TIMEOUT" "$d" "$RBPF_SLAM" "$d/rbpf-slam.ini"; then
    ERR=$BENCH_ERR
    # A timed-out run still shows how far it got (lower bounds, ">x").
    MRPT_WALL=$BENCH_WALL MRPT_CPU=$BENCH_CPU MRPT_RSS=$BENCH_RSS
    return 1
  fi
  MRPT_WALL=$BENCH_WALL MRPT_CPU=$BENCH_CPU MRPT_RSS=$BENCH_RSS
  MRPT_TRAJ=$d/trajectory.tum
  MRPT_MEAN_TRAJ=$d/trajectory_mean.tum
  if ! "$PYTHON" "$BENCH_REPO/scripts/bench/mrpt_path.py" "$d/out" --localize "$lin" "$ang" >"$MRPT_TRAJ" 2>"$d/path.err" ||
     ! "$PYTHON" "$BENCH_REPO/scripts/bench/mrpt_path.py" "$d/out" --mean >"$MRPT_MEAN_TRAJ" 2>>"$d/path.err"; then
    ERR="no trajectory: $(tail -n 1 "$d/path.err")"
    return 1
  fi
  MRPT_SCANS=$(wc -l <"$MRPT_TRAJ")
}

join_status() {
  local out=${status[0]} i
  for ((i = 1; i < ${#status[@]}; i++)); do out+="; ${status[i]}"; done
  echo "$out"
}

# ------------------------------------------------------------------- main
MACHINE=$(bench_machine)
LOAD_START=$(bench_load)
MRPT_VERSION=$(dpkg-query -W -f='${Version}' mrpt-apps 2>/dev/null || echo unknown)
REV=$(bench_git_rev)
MRPT_UPDATE="?"  # set by run_mrpt from the ini it writes
if [[ -n $THREADS ]]; then OURS_THREADS=$THREADS; else OURS_THREADS="config default"; fi

ROWS=()
NOTES=()
SCAN_NOTE=0
FAILED=0
for name in $LOGS; do
  mkdir -p "$WORK_DIR/$name"
  OURS_WALL=- OURS_CPU=- OURS_RSS=- OURS_SCANS=- OURS_TRAJ='' OURS_AREAS=- OURS_CLOSURES=-
  MRPT_WALL=- MRPT_CPU=- MRPT_RSS=- MRPT_SCANS=- MRPT_TRAJ='' MRPT_MEAN_TRAJ=''
  status=() ours_rel=- mrpt_rel=- ours_ate=- mrpt_ate=- ours_cells=- mrpt_cells=-
  if ! log_input "$name"; then
    bench_log "$name: FAIL: $ERR"
    FAILED=1
    ROWS+=("| $name | - | - | - | - | - | - | - | - | - | - | - | - | - | - | - | - | - | - | FAIL: $ERR |")
    continue
  fi
  if ! run_ours "$name"; then status+=("ours FAIL: $ERR"); bench_log "$name: ours FAIL: $ERR"; fi
  if ! run_mrpt "$name"; then status+=("MRPT FAIL: $ERR"); bench_log "$name: MRPT FAIL: $ERR"; fi

  rel=$DATASETS/relations/$name.relations
  if [[ -r $rel ]]; then
    [[ -n $OURS_TRAJ ]] && ours_rel=$(bench_relation_cell "$OURS_TRAJ" "$rel")
    [[ -n $MRPT_TRAJ ]] && mrpt_rel=$(bench_relation_cell "$MRPT_TRAJ" "$rel")
    [[ -n $MRPT_MEAN_TRAJ ]] &&
      NOTES+=("- $name: MRPT's on-line mean estimate (log_estimated_path.txt, not smoothed) scores $(bench_relation_cell "$MRPT_MEAN_TRAJ" "$rel").")
  fi
  ref=$DATASETS/carmen/$name.reference.txt.gz
  if [[ -r $ref ]]; then
    [[ -n $OURS_TRAJ ]] && ours_ate=$(bench_ate_cell "$OURS_TRAJ" "$ref")
    # rbpf-slam skips the log's first scan (no odometry precedes it): its
    # poses are scans 1.. of the log, matched by index from there, since
    # some logs' timestamps (csail's, the corridor's: rounded to 10 s) tell
    # no scan apart.
    mrpt_offset=()
    if [[ $OURS_SCANS =~ ^[0-9]+$ && $MRPT_SCANS =~ ^[0-9]+$ ]] && ((MRPT_SCANS == OURS_SCANS - 1)); then
      mrpt_offset=(--offset 1)
    fi
    [[ -n $MRPT_TRAJ ]] && mrpt_ate=$(bench_ate_cell "$MRPT_TRAJ" "$ref" "${mrpt_offset[@]}")
    carmen=$DATASETS/carmen/$name.log.gz
    if [[ -r $carmen ]]; then
      [[ -n $OURS_TRAJ ]] && ours_cells=$(bench_sharpness_cell "$carmen" "$OURS_TRAJ" "$ref")
      [[ -n $MRPT_TRAJ ]] && mrpt_cells=$(bench_sharpness_cell "$carmen" "$MRPT_TRAJ" "$ref" "${mrpt_offset[@]}")
    fi
  fi
  # Keep the trajectories next to the table.
  mkdir -p "$OUT_DIR/$name"
  [[ -n $OURS_TRAJ ]] && cp "$OURS_TRAJ" "$OUT_DIR/$name/ours.tum"
  [[ -n $MRPT_TRAJ ]] && cp "$MRPT_TRAJ" "$OUT_DIR/$name/mrpt.tum"

  scans=$OURS_SCANS
  if [[ $scans == - ]]; then scans=$MRPT_SCANS
  elif [[ $MRPT_SCANS != - && $MRPT_SCANS != "$OURS_SCANS" ]]; then
    scans="$OURS_SCANS / $MRPT_SCANS"
    SCAN_NOTE=1
  fi
  if [[ ${#status[@]} -eq 0 ]]; then status=(ok); else FAILED=1; fi
  ROWS+=("| $name | $(basename "$(config_for "$name")") | $scans | $OURS_WALL | $MRPT_WALL | $(bench_ratio "$MRPT_WALL" "$OURS_WALL") | $OURS_CPU | $MRPT_CPU | $OURS_RSS | $MRPT_RSS | $(bench_ratio "$MRPT_RSS" "$OURS_RSS") | $OURS_AREAS | $OURS_CLOSURES | $ours_ate | $mrpt_ate | $ours_cells | $mrpt_cells | $ours_rel | $mrpt_rel | $(join_status) |")
done

LOAD_END=$(bench_load)

report() {
  echo "## $TITLE"
  echo
  echo "- machine: $MACHINE"
  echo "- load average (1/5/15 min) at start: $LOAD_START, at end: $LOAD_END (other work on the machine inflates the times)"
  echo "- particles: $PARTICLES (both); seed $SEED; our threads: $OURS_THREADS (rbpf-slam: 1)"
  echo "- ours: \`hmt-slam $MODE\` with the config in the table (config/), commit $REV"
  if [[ $MRPT_UPDATES == matched ]]; then
    echo "- MRPT: rbpf-slam $MRPT_VERSION with $(basename "$MRPT_INI") (files, windows and logging off), its filter and map updates set to ours (MRPT_UPDATES=matched: runs the filter after $MRPT_UPDATE of odometry, as ours does), otherwise unchanged"
  else
    echo "- MRPT: rbpf-slam $MRPT_VERSION with $(basename "$MRPT_INI") (files, windows and logging off, otherwise unchanged: MRPT_UPDATES=ini)"
  fi
  echo "- both read the same rawlog (CARMEN logs converted once by \`hmt-slam convert --format sf\`)"
  echo "- wall time, CPU time (user + system, all threads) and peak RSS from GNU \`time -v\` of the whole process (reading the log and writing the map included); fastest of $REPEAT run(s) each"
  echo
  echo "| log | our config | scans | ours wall (s) | MRPT wall (s) | MRPT/ours time | ours CPU (s) | MRPT CPU (s) | ours peak RSS (MB) | MRPT peak RSS (MB) | MRPT/ours RSS | areas | closures | ours ATE | MRPT ATE | ours map cells / ref | MRPT map cells / ref | ours relation error | MRPT relation error | status |"
  echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---:|---:|---|---|---|"
  printf '%s\n' "${ROWS[@]}"
  echo
  echo "ATE: position RMSE (max) in metres against \`carmen/NAME.reference.txt.gz\` (a GMapping trajectory, not ground truth) after the best rigid 2D alignment, scans matched by index (scripts/ate.py); \"-\" where a log has none. Areas and closures: ours (summary.json), with MODE=run."
  echo "Map cells / ref: the 5 cm cells the log's scan end points (below 20 m) fill when drawn at the trajectory's poses, over the same for the reference (scripts/map_sharpness.py): below 1, the trajectory draws the log sharper (more self-consistently) than the reference, which ATE cannot tell; it needs no ground truth."
  echo "Relation error: translational mean ± std, rotational mean (number of relations), against \`relations/NAME.relations\`; \"-\" where a log has none. GMapping's reference trajectory scores 0.0545 ± 0.0728 m, 1.13° (116) on intel."
  echo "MRPT's trajectory is its final most likely particle's path (most_likely_path.txt, one pose per filter update: rbpf-slam updates only after $MRPT_UPDATE of odometry with this ini) expanded to every scan by odometry, with the timestamps of log_estimated_path.txt; scored as the log's scans from the second on (rbpf-slam skips the first, below), by index, since csail's and the corridor's timestamps are rounded to 10 s and tell no scan apart; it comes from files rbpf-slam always writes, so the timed run is the only run."
  echo "MRPT's odometry noise is not in its ini: it is the motion model stored in the rawlog's actions (\`hmt-slam convert\` writes MRPT's default CActionRobotMovement2D Gaussian model; the Malaga log has its own)."
  if [[ $SCAN_NOTE == 1 ]]; then
    echo "Scans \"ours / MRPT\": rbpf-slam's rawlog reader (CRawlog::getActionObservationPairOrObservation) skips every sensory frame until the first action, so it drops the first scan of a rawlog that starts with a sensory frame (MRPT's own Malaga log and ours do)."
  fi
  if [[ ${#NOTES[@]} -gt 0 ]]; then
    echo
    printf '%s\n' "${NOTES[@]}"
  fi
}

report | tee "$OUT_DIR/$TABLE"
bench_log "table written to $OUT_DIR/$TABLE; run outputs in $WORK_DIR"
if [[ $FAILED == 1 ]]; then
  bench_log "some runs failed (FAIL in the table)"
  exit 1
fi
