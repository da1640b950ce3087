# shellcheck shell=bash
# shellcheck disable=SC2034  # BENCH_* results are read by the callers
# Shared helpers for the benchmark scripts (scripts/bench_*.sh). Source it:
#   source "$(dirname "$0")/bench_lib.sh"
# Every function prints its result on stdout; messages go to stderr.

bench_log() { printf '[%s] %s\n' "${BENCH_NAME:-bench}" "$*" >&2; }

bench_die() {
  printf '%s: error: %s\n' "${BENCH_NAME:-bench}" "$*" >&2
  exit 1
}

# bench_need_tool NAME [HINT]: fails unless NAME is an executable (path or PATH).
bench_need_tool() {
  if [[ "$1" == */* ]]; then
    [[ -x "$1" ]] || bench_die "$1 not found or not executable${2:+ ($2)}"
  else
    command -v "$1" >/dev/null 2>&1 || bench_die "'$1' not found in PATH${2:+ ($2)}"
  fi
}

# bench_need_counts NAME VALUE: fails unless VALUE is a space-separated,
# non-empty list of non-negative integers (seeds, worlds), naming NAME.
bench_need_counts() {
  local v
  [[ -n "${2// /}" ]] || bench_die "$1 is empty"
  for v in $2; do
    [[ "$v" =~ ^[0-9]+$ ]] || bench_die "$1 must be non-negative integers, not '$v'"
  done
}

# bench_measure TIMEOUT_S TIME_FILE OUTPUT_FILE CMD [ARGS...]
# Runs CMD under GNU time -v (written to TIME_FILE) with a timeout, stdin from
# /dev/null (nothing may wait for a key), stdout+stderr to OUTPUT_FILE.
# Returns CMD's exit status, 124 on timeout (as timeout(1) does). time runs
# outside timeout, so a run that is killed still leaves its report (the
# figures of timeout's process include the command it waited for): the time
# and memory it had reached, lower bounds of what it needed.
bench_measure() {
  local t=$1 tf=$2 out=$3
  shift 3
  local rc=0
  /usr/bin/time -v -o "$tf" timeout --kill-after=10 "$t" "$@" </dev/null >"$out" 2>&1 || rc=$?
  return "$rc"
}

# bench_measure_best REPEAT TIMEOUT DIR CMD [ARGS...]
# Runs CMD REPEAT times with bench_measure (reports DIR/time.K.txt, output
# DIR/output.K.txt) and sets BENCH_WALL, BENCH_CPU, BENCH_RSS from the fastest
# run: the minimum is the figure least disturbed by other work on the machine.
# On the first failing run sets BENCH_ERR and returns 1; when that run timed
# out, BENCH_WALL, BENCH_CPU and BENCH_RSS are what it had reached, prefixed
# with ">" (lower bounds).
bench_measure_best() {
  local repeat=$1 t=$2 d=$3 k rc wall
  shift 3
  BENCH_WALL=- BENCH_CPU=- BENCH_RSS=- BENCH_ERR=
  for ((k = 1; k <= repeat; k++)); do
    rc=0
    bench_measure "$t" "$d/time.$k.txt" "$d/output.$k.txt" "$@" || rc=$?
    if [[ $rc -ne 0 ]]; then
      BENCH_ERR="$(bench_exit_reason "$rc" "$d/time.$k.txt"), see $d/output.$k.txt"
      if [[ $rc -eq 124 || $rc -eq 137 ]] && wall=$(bench_wall_s "$d/time.$k.txt") &&
         BENCH_CPU=$(bench_cpu_s "$d/time.$k.txt") && BENCH_RSS=$(bench_rss_mb "$d/time.$k.txt"); then
        BENCH_WALL=">$wall" BENCH_CPU=">$BENCH_CPU" BENCH_RSS=">$BENCH_RSS"
      else
        BENCH_WALL=- BENCH_CPU=- BENCH_RSS=-
      fi
      return 1
    fi
    if ! wall=$(bench_wall_s "$d/time.$k.txt"); then
      BENCH_ERR="no time report in $d/time.$k.txt"
      return 1
    fi
    if [[ $BENCH_WALL == - ]] || awk -v a="$wall" -v b="$BENCH_WALL" 'BEGIN { exit !(a < b) }'; then
      BENCH_WALL=$wall
      if ! BENCH_CPU=$(bench_cpu_s "$d/time.$k.txt") || ! BENCH_RSS=$(bench_rss_mb "$d/time.$k.txt"); then
        BENCH_ERR="incomplete time report in $d/time.$k.txt"
        return 1
      fi
    fi
  done
}

# bench_wall_s TIME_FILE: wall-clock seconds from a `time -v` report.
bench_wall_s() {
  awk -F': ' '/Elapsed \(wall clock\) time/ {
      n = split($2, p, ":"); s = 0
      for (i = 1; i <= n; i++) s = s * 60 + p[i]
      printf "%.2f\n", s; found = 1 }
    END { if (!found) exit 1 }' "$1"
}

# bench_cpu_s TIME_FILE: user + system CPU seconds from a `time -v` report.
bench_cpu_s() {
  awk -F': ' '/(User|System) time \(seconds\)/ { s += $2; n++ }
    END { if (n != 2) exit 1; printf "%.2f\n", s }' "$1"
}

# bench_rss_mb TIME_FILE: peak resident set size (MiB) from a `time -v` report.
bench_rss_mb() {
  awk -F': ' '/Maximum resident set size \(kbytes\)/ { printf "%.0f\n", $2 / 1024; found = 1 }
    END { if (!found) exit 1 }' "$1"
}

# bench_ratio A B [DIGITS]: A/B, or "-" when either is missing or B is zero.
# A lower bound A (">x", a run that timed out) gives a lower bound ">x/B".
bench_ratio() {
  awk -v a="$1" -v b="$2" -v d="${3:-2}" 'BEGIN {
    num = "^[-+]?[0-9]*[.]?[0-9]+([eE][-+]?[0-9]+)?$"  # "-" (no figure) is not a number
    bound = ""
    if (substr(a, 1, 1) == ">") { bound = ">"; a = substr(a, 2) }
    if (a !~ num || b !~ num || b + 0 == 0) { print "-"; exit }
    printf "%s%.*f\n", bound, d, a / b }'
}

# bench_exit_reason RC TIME_FILE: short text for a failed run.
bench_exit_reason() {
  local rc=$1 tf=$2
  if [[ $rc -eq 124 || $rc -eq 137 ]]; then echo "timeout"
  elif [[ -s "$tf" ]] && grep -q '^Command terminated by signal' "$tf"; then
    sed -n 's/^Command terminated by signal \([0-9]*\).*/signal \1/p' "$tf" | head -1
  else echo "exit $rc"
  fi
}

# bench_ini_set FILE SECTION KEY VALUE: sets KEY=VALUE in [SECTION] of an INI
# file (MRPT style: `key = value  // comment`), replacing every existing
# assignment of KEY in that section or appending one at its end.
bench_ini_set() {
  local file=$1 tmp
  tmp=$(mktemp "$file.XXXXXX")
  BENCH_SEC=$2 BENCH_KEY=$3 BENCH_VAL=$4 awk '
    function flush() { if (insec && !done) { print ENVIRON["BENCH_KEY"] "=" ENVIRON["BENCH_VAL"]; done = 1 } }
    /^[ \t]*\[.*\][ \t]*$/ {
      flush()
      s = $0; gsub(/^[ \t]*\[|\][ \t]*$/, "", s)
      insec = (s == ENVIRON["BENCH_SEC"]); seen = seen || insec
      print; next }
    insec {
      line = $0; sub(/^[ \t]+/, "", line)
      k = line; sub(/[ \t]*=.*/, "", k)
      if (line ~ /=/ && k == ENVIRON["BENCH_KEY"]) {
        if (!done) print ENVIRON["BENCH_KEY"] "=" ENVIRON["BENCH_VAL"]
        done = 1; next } }
    { print }
    END {
      flush()
      if (!seen) { print "[" ENVIRON["BENCH_SEC"] "]"; print ENVIRON["BENCH_KEY"] "=" ENVIRON["BENCH_VAL"] } }
  ' "$file" >"$tmp" && mv "$tmp" "$file"
}

# bench_ini_get FILE SECTION KEY: the value of KEY in [SECTION] (first
# assignment; `//` and `;` comments and surrounding blanks removed).
bench_ini_get() {
  BENCH_SEC=$2 BENCH_KEY=$3 awk '
    /^[ \t]*\[.*\][ \t]*$/ { s = $0; gsub(/^[ \t]*\[|\][ \t]*$/, "", s); insec = (s == ENVIRON["BENCH_SEC"]); next }
    insec {
      line = $0; sub(/^[ \t]+/, "", line)
      k = line; sub(/[ \t]*=.*/, "", k)
      if (line ~ /=/ && k == ENVIRON["BENCH_KEY"]) {
        v = line; sub(/^[^=]*=[ \t]*/, "", v); sub(/[ \t]*(\/\/|;).*$/, "", v); sub(/[ \t]+$/, "", v)
        print v; found = 1; exit } }
    END { if (!found) exit 1 }' "$1"
}

# bench_json_cell SCRIPT FORMAT ARG...: runs scripts/SCRIPT ARG... --json
# and prints FORMAT (a Python expression over the result `r`), or
# "FAIL (<its last line of error>)".
bench_json_cell() {
  local js script=$1 format=$2
  shift 2
  if ! js=$("${PYTHON:-/usr/bin/python3}" "$BENCH_REPO/scripts/$script" "$@" --json 2>&1); then
    echo "FAIL (${js##*$'\n'})"
    return 0
  fi
  "${PYTHON:-/usr/bin/python3}" -c '
import json, sys
r = json.loads(sys.argv[1])
print(eval(sys.argv[2]))' "$js" "$format"
}

# bench_relation_cell TRAJ RELATIONS: "0.099 ± 0.121 m, 2.32° (144)" from
# scripts/relation_error.py, or "FAIL (...)".
bench_relation_cell() {
  bench_json_cell relation_error.py \
    '"%.3f ± %.3f m, %.2f° (%d)" % (r["trans_mean_m"], r["trans_std_m"], r["rot_mean_deg"], r["count"])' "$1" "$2"
}

# bench_ate_cell TRAJ REFERENCE [ate.py options]: "0.097 (0.36)" (RMSE and
# max, metres) from scripts/ate.py, or "FAIL (...)".
bench_ate_cell() {
  bench_json_cell ate.py '"%.3f (%.2f)" % (r["rmse_m"], r["max_m"])' "$@"
}

# bench_sharpness_cell LOG TRAJ REFERENCE [options]: "0.948", the scan end-point
# cells TRAJ draws the log with over those REFERENCE draws it with
# (scripts/map_sharpness.py; below 1: TRAJ's map is the sharper), or
# "FAIL (...)".
bench_sharpness_cell() {
  bench_json_cell map_sharpness.py '"%.3f" % r["ratio"]' "$@"
}

# bench_machine: one line describing the machine.
bench_machine() {
  local cpu
  cpu=$(sed -n 's/^model name[ \t]*: //p' /proc/cpuinfo 2>/dev/null | head -1)
  printf '%s cores (nproc), %s, %s MB RAM\n' "$(nproc)" "${cpu:-unknown CPU}" \
    "$(awk '/^MemTotal:/ { printf "%.0f", $2 / 1024 }' /proc/meminfo 2>/dev/null)"
}

# bench_load: the 1, 5 and 15 minute load averages.
bench_load() { cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?'; }

# bench_git_rev: short commit of the repository, "+dirty" with local changes.
bench_git_rev() {
  local rev
  rev=$(git -C "$BENCH_REPO" rev-parse --short HEAD 2>/dev/null) || { echo "unknown"; return 0; }
  if ! git -C "$BENCH_REPO" diff --quiet HEAD -- 2>/dev/null; then rev="$rev+dirty"; fi
  echo "$rev"
}
