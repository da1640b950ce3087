#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, clang with AddressSanitizer +
# UndefinedBehaviorSanitizer, into build-fuzz/) and runs each over its corpus.
#
#   bash scripts/fuzz.sh                 # CI: every target, a bounded number of runs
#   bash scripts/fuzz.sh long SECONDS    # a campaign: every target for SECONDS each
#   bash scripts/fuzz.sh long SECONDS fuzz_carmen ...   # ... or the ones named
#
# CI mode replays the corpus (fuzz/corpus/<target>/: real log slices, the
# inputs of the bad-input tests, and every input that ever crashed a target)
# and then mutates it for FUZZ_RUNS executions (default 5000), so a
# regression in a reader fails CI. Long mode writes new interesting inputs to
# build-fuzz/corpus/<target>/ (fuzz/corpus is read-only to it) and crashing
# inputs to build-fuzz/findings/<target>/; each run's libFuzzer log is in
# build-fuzz/logs/. One fuzzing process at a time, one job each.
#
# A finding is anything but a clean refusal: a sanitizer report, an
# uncaught exception other than the project's errors, a broken invariant of
# the result, a run over 10 s, more than 2 GB resident or one allocation over
# 1 GB.
set -euo pipefail
cd "$(dirname "$0")/.."
MODE=${1:-ci}
DIR=build-fuzz
TARGETS=(fuzz_rawlog fuzz_carmen fuzz_poses fuzz_config fuzz_topology fuzz_session)

case "$MODE" in
  ci) RUNS=${FUZZ_RUNS:-5000} ;;
  long)
    SECONDS_EACH=${2:?usage: $0 long SECONDS [target...]}
    if [ $# -gt 2 ]; then TARGETS=("${@:3}"); fi ;;
  *) echo "usage: $0 [ci | long SECONDS [target...]]" >&2; exit 2 ;;
esac

for tool in clang clang++; do
  command -v "$tool" >/dev/null || { echo "fuzz: $tool not found (scripts/setup.sh installs it)" >&2; exit 1; }
done

t0=$SECONDS
# -O1 -g1: fast enough to fuzz, cheap to build, line numbers in the reports.
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
CC=clang CXX=clang++ cmake -S . -B "$DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DHMT_FUZZ=ON -DHMT_BUILD_TESTS=OFF \
  "${launcher[@]}" >/dev/null
cmake --build "$DIR" -j "${JOBS:-$(nproc)}" --target "${TARGETS[@]}"
echo "fuzz: built ${#TARGETS[@]} targets in $((SECONDS - t0))s"

# As in scripts/sanitize.sh: the sanitizer runtimes do not cope with the
# address-space randomisation of kernels with vm.mmap_rnd_bits above 28.
WRAP=()
if [ "$(cat /proc/sys/vm/mmap_rnd_bits 2>/dev/null || echo 28)" -gt 28 ] &&
   setarch "$(uname -m)" -R true 2>/dev/null; then
  WRAP=(setarch "$(uname -m)" -R)
  echo "fuzz: vm.mmap_rnd_bits > 28, running without address randomisation"
fi

export ASAN_OPTIONS="halt_on_error=1 detect_leaks=1 allocator_may_return_null=0"
export UBSAN_OPTIONS="halt_on_error=1 print_stacktrace=1"
# One fuzzing process, in this process: libFuzzer's -jobs/-workers would fork
# a child that logs to ./fuzz-N.log instead.
COMMON=(-rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=10 -max_len=65536 -print_final_stats=1)
mkdir -p "$DIR/logs"
summary=()
for t in "${TARGETS[@]}"; do
  corpus=fuzz/corpus/$t
  dict=fuzz/dict/$t.dict
  [ -d "$corpus" ] || { echo "fuzz: no corpus $corpus" >&2; exit 1; }
  args=("${COMMON[@]}" -artifact_prefix="$DIR/findings/$t/")
  [ -f "$dict" ] && args+=(-dict="$dict")
  log=$DIR/logs/$t.$MODE.log
  mkdir -p "$DIR/findings/$t"
  if [ "$MODE" = ci ]; then
    # A scratch corpus: CI's new inputs are not kept.
    work=$(mktemp -d)
    run=("$DIR/fuzz/$t" "${args[@]}" -runs="$RUNS" -seed=1 "$work" "$corpus")
  else
    mkdir -p "$DIR/corpus/$t"
    run=("$DIR/fuzz/$t" "${args[@]}" -max_total_time="$SECONDS_EACH"
         "$DIR/corpus/$t" "$corpus")
  fi
  echo "fuzz: $t: ${run[*]}"
  s0=$SECONDS
  if ! "${WRAP[@]}" "${run[@]}" >"$log" 2>&1; then
    tail -n 60 "$log" >&2
    echo "fuzz: $t FAILED (log: $log; the crashing input is in $DIR/findings/$t)" >&2
    exit 1
  fi
  [ "$MODE" = ci ] && rm -rf "$work"
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  summary+=("$t: ${execs:-?} executions in $((SECONDS - s0))s")
done
for s in "${summary[@]}"; do echo "fuzz: $s"; done
echo "fuzz: clean ($((SECONDS - t0))s in all)"
