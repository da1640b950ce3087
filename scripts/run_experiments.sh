#!/usr/bin/env bash
# Runs the experiments of the area-abstraction paper (000 Sec. 6) with the full
# number of runs, then plots them. Builds nothing: it needs the hmt-experiments
# executable (scripts/build.sh builds it into build/apps/).
#
#   OUT_DIR  output folder (default /tmp/hmt-experiments)
#   BIN      the executable (default build/apps/hmt-experiments)
#   RUNS     simulation runs of the information-loss experiment (default 150)
#   THREADS  worker threads (default 2)
#   PYTHON   a Python 3 with matplotlib (default: the first of /usr/bin/python3,
#            python3 that imports it)
#
# Writes, under OUT_DIR:
#   info_loss/          the information-loss experiment (Eq. 22, Fig. 8) with the
#                       default simulation: CSVs, JSON, table.txt and
#                       fig8a_map.png, fig8b_loss_vs_k.png, fig8c_loss_vs_tau.png
#   info_loss_<variant>/  the same with one setting changed (see VARIANTS below)
#   field_of_view/      the field-of-view experiment (Sec. 6.2): CSV, JSON,
#                       table.txt, fov_areas_tau*.png, fov_areas_vs_tau.png
set -euo pipefail
cd "$(dirname "$0")/.."

OUT_DIR=${OUT_DIR:-/tmp/hmt-experiments}
BIN=${BIN:-build/apps/hmt-experiments}
RUNS=${RUNS:-150}
THREADS=${THREADS:-2}

if [ ! -x "$BIN" ]; then
  echo "run_experiments: '$BIN' not found; build first (scripts/build.sh) or set BIN" >&2
  exit 1
fi
if [ -z "${PYTHON:-}" ]; then
  for p in /usr/bin/python3 python3; do
    if command -v "$p" >/dev/null && "$p" -c 'import matplotlib' 2>/dev/null; then
      PYTHON=$p
      break
    fi
  done
fi
if [ -z "${PYTHON:-}" ]; then
  echo "run_experiments: no Python 3 with matplotlib (install python3-matplotlib or set PYTHON)" >&2
  exit 1
fi
mkdir -p "$OUT_DIR"

# name | extra arguments of info-loss
VARIANTS=(
  "mrpt_demo_noise|--range-std 0.01 --bearing-std-deg 0.1 --odo-xy-std 0.04 --odo-phi-std-deg 0.2"
  "range_10m|--max-range 10"
  "landmarks_120|--landmarks 120"
  "fov_360|--fov-deg 360"
  "marginal_information|--information marginal"
  "no_ids|--no-ids"
)

run_info_loss() {  # dir, extra args...
  local dir=$1
  shift
  echo "== info-loss -> $dir $*"
  local t0=$SECONDS
  "$BIN" info-loss --runs "$RUNS" --threads "$THREADS" --quiet --out "$dir" "$@" \
    | tee "$dir.table.tmp"
  mkdir -p "$dir"
  mv "$dir.table.tmp" "$dir/table.txt"
  echo "   ($((SECONDS - t0)) s)"
}

start=$SECONDS
run_info_loss "$OUT_DIR/info_loss"
for v in "${VARIANTS[@]}"; do
  name=${v%%|*}
  # shellcheck disable=SC2086
  run_info_loss "$OUT_DIR/info_loss_$name" ${v#*|}
done

echo "== field-of-view -> $OUT_DIR/field_of_view"
mkdir -p "$OUT_DIR/field_of_view"
"$BIN" field-of-view --out "$OUT_DIR/field_of_view" \
  --taus 0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8,0.9,1.0 | tee "$OUT_DIR/field_of_view/table.txt"

echo "== plots"
plot_args=(--info-loss "$OUT_DIR/info_loss")
for v in "${VARIANTS[@]}"; do plot_args+=(--info-loss "$OUT_DIR/info_loss_${v%%|*}"); done
plot_args+=(--fov "$OUT_DIR/field_of_view" --fov-tau 0.5 --fov-tau 1.0)
"$PYTHON" scripts/plot_experiments.py "${plot_args[@]}"

echo "run_experiments: done in $((SECONDS - start)) s; outputs in $OUT_DIR"
