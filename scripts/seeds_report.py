#!/usr/bin/python3
"""The table of scripts/bench_seeds.sh: how the default configuration does
on every log over several seeds of the metric filter.

A single draw of a particle filter says little about a change: on the shared
logs the position RMSE of one log moves by a factor of two to five from seed
to seed (edmonton 0.23-1.13 m over seeds 1-3). So a change is judged on every
log over several seeds, by the mean and the worst run, and by how many runs
miss the target.

Usage: seeds_report.py OUT_DIR [--threshold M]
  OUT_DIR holds LOG/seedS/ folders, each with
    ate.json        scripts/ate.py --json of the run's trajectory
    relations.json  (optional) scripts/relation_error.py --json
    loops.json      (optional) scripts/loops_closed.py --json
    closures.json   (optional) scripts/closure_check.py --json
    time.txt        (optional) GNU time -v of the run
    summary.json    (optional) the run's own summary (areas, loop closures)
    error.txt       (optional) why the run failed; it is then counted as
                    failed, never left out
  --threshold M: position RMSE a run must not exceed (m) [0.15]

Prints a Markdown table: per log, each seed's position RMSE (and, where
given, relation error), the mean and the worst, the mean wall time and peak
RSS, areas and closures, the closures the reference agrees with and the
reference's loops closed over all seeds; then every run's mean, the worst,
the runs above the threshold, each run's closures the reference disagrees
with (and the first of them: where its map broke), each loop left open
(beyond MAX_LOOPS_LISTED of them, a line a run instead) and the failed
runs. Exit 4 when OUT_DIR holds no run.
"""
import argparse
import json
import math
import os
import re
import sys

# More open loops than this are summed up a run a line.
MAX_LOOPS_LISTED = 30
# closure_check.py's verdicts of a closure the reference disagrees with.
WRONG = ("wrong_place", "elsewhere")


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def time_report(path):
    """(wall s, peak RSS MB) from a GNU time -v report, None where absent."""
    wall = rss = None
    try:
        with open(path) as f:
            for line in f:
                key, _, value = line.strip().partition(": ")
                if key == "Elapsed (wall clock) time (h:mm:ss or m:ss)":
                    wall = 0.0
                    for part in value.split(":"):
                        wall = wall * 60 + float(part)
                elif key == "Maximum resident set size (kbytes)":
                    rss = float(value) / 1024
    except (OSError, ValueError):
        return None, None
    return wall, rss


def read_run(d):
    """One run's figures; 'error' says why it has none."""
    run = {"rmse": None, "relations": None, "wall": None, "rss": None,
           "areas": None, "closures": None, "loops": None, "verdicts": None,
           "first_wrong": None, "error": None}
    err = os.path.join(d, "error.txt")
    if os.path.exists(err):
        with open(err) as f:
            run["error"] = f.read().strip() or "failed"
    ate = read_json(os.path.join(d, "ate.json"))
    if ate is not None and isinstance(ate.get("rmse_m"), (int, float)):
        run["rmse"] = float(ate["rmse_m"])
    elif run["error"] is None:
        run["error"] = "no ate.json"
    rel = read_json(os.path.join(d, "relations.json"))
    if rel is not None:
        value = rel.get("trans_mean_m")
        if isinstance(value, (int, float)):
            run["relations"] = float(value)
    loops = read_json(os.path.join(d, "loops.json"))
    if loops is not None and isinstance(loops.get("each"), list):
        run["loops"] = loops["each"]
    checked = read_json(os.path.join(d, "closures.json"))
    if checked is not None and isinstance(checked.get("counts"), dict):
        run["verdicts"] = checked["counts"]
        if isinstance(checked.get("first_wrong_closure"), dict):
            run["first_wrong"] = checked["first_wrong_closure"]
    run["wall"], run["rss"] = time_report(os.path.join(d, "time.txt"))
    summary = read_json(os.path.join(d, "summary.json")) or {}
    if isinstance(summary.get("areas"), int):
        run["areas"] = summary["areas"]
    if isinstance(summary.get("loop_closures_accepted"), int):
        run["closures"] = summary["loop_closures_accepted"]
    return run


def seed_of(name):
    m = re.fullmatch(r"seed(\d+)", name)
    return int(m.group(1)) if m else None


def collect(out_dir):
    """{log: {seed: run}}: the logs named in OUT_DIR/logs.txt, in its order
    (the benchmark's), or without it every log folder, sorted."""
    logs = {}
    for log in sorted(os.listdir(out_dir)):
        ld = os.path.join(out_dir, log)
        if not os.path.isdir(ld):
            continue
        runs = {}
        for name in os.listdir(ld):
            seed = seed_of(name)
            if seed is not None and os.path.isdir(os.path.join(ld, name)):
                runs[seed] = read_run(os.path.join(ld, name))
        if runs:
            logs[log] = dict(sorted(runs.items()))
    order_file = os.path.join(out_dir, "logs.txt")
    if os.path.exists(order_file):
        with open(order_file) as f:
            order = [w for w in f.read().split() if w in logs]
        logs = {k: logs[k] for k in order}
    return logs


def fmt(v, digits=3):
    return "-" if v is None else f"{v:.{digits}f}"


def mean(values):
    values = [v for v in values if v is not None]
    return sum(values) / len(values) if values else None


def report(logs, threshold):
    seeds = sorted({s for runs in logs.values() for s in runs})
    lines = []
    head = ["log"] + [f"seed {s}" for s in seeds] + ["mean", "worst", "wall s", "peak MB",
                                                     "areas", "closures", "closures right",
                                                     "loops closed"]
    lines.append("| " + " | ".join(head) + " |")
    lines.append("|" + "---|" * len(head))
    every, failed, open_loops, wrong = [], [], [], []
    for log, runs in logs.items():
        row = [log]
        for s in seeds:
            r = runs.get(s)
            if r is None:
                row.append("")
            elif r["error"] is not None:
                row.append("failed")
                failed.append(f"{log} seed {s}: {r['error']}")
            else:
                cell = fmt(r["rmse"])
                if r["relations"] is not None:
                    cell += f" (rel. {fmt(r['relations'], 4)})"
                row.append(cell)
                every.append((r["rmse"], log, s))
        ok = [r for r in runs.values() if r["error"] is None]
        rmse = [r["rmse"] for r in ok]
        row += [fmt(mean(rmse)), fmt(max(rmse) if rmse else None),
                fmt(mean([r["wall"] for r in ok]), 1), fmt(mean([r["rss"] for r in ok]), 0),
                fmt(mean([r["areas"] for r in ok]), 1), fmt(mean([r["closures"] for r in ok]), 1)]
        judged = [(s, r) for s, r in runs.items()
                  if r["error"] is None and r["verdicts"] is not None]
        if judged:
            right = sum(r["verdicts"].get("right", 0) for _, r in judged)
            bad = [(s, r, sum(r["verdicts"].get(v, 0) for v in WRONG)) for s, r in judged]
            row.append(f"{right}/{right + sum(n for _, _, n in bad)}")
            wrong += [(log, s, n, r["first_wrong"]) for s, r, n in bad if n]
        else:
            row.append("-")
        with_loops = [(s, r["loops"]) for s, r in runs.items()
                      if r["error"] is None and r["loops"] is not None]
        if with_loops:
            total = sum(len(each) for _, each in with_loops)
            closed = sum(1 for _, each in with_loops for lp in each if lp.get("closed"))
            row.append(f"{closed}/{total}")
            open_loops += [(log, s, lp) for s, each in with_loops for lp in each
                           if not lp.get("closed")]
        else:
            row.append("-")
        lines.append("| " + " | ".join(row) + " |")
    lines.append("")
    if every:
        worst = max(every)
        above = sum(1 for v, _, _ in every if v > threshold)
        lines.append(f"- runs: {len(every) + len(failed)}; position RMSE mean "
                     f"{fmt(mean([v for v, _, _ in every]))} m, worst {fmt(worst[0])} m "
                     f"({worst[1]} seed {worst[2]}); above {threshold:g} m: {above}")
    rel = [r["relations"] for runs in logs.values() for r in runs.values()
           if r["error"] is None and r["relations"] is not None]
    if rel:
        lines.append(f"- relation error: mean {fmt(mean(rel), 4)} m over {len(rel)} runs, "
                     f"worst {fmt(max(rel), 4)} m")
    if any(r["verdicts"] is not None for runs in logs.values() for r in runs.values()):
        lines.append(f"- closures the references disagree with: {sum(n for _, _, n, _ in wrong)}")
        for log, seed, n, first in wrong:
            where = (f", the first at step {first.get('step')} ({first.get('from_area')} -> "
                     f"{first.get('area')}, {first.get('verdict')})" if first else "")
            lines.append(f"  - {log} seed {seed}: {n}{where}")
    lines.append(f"- loops of the references left open: {len(open_loops)}")
    if len(open_loops) <= MAX_LOOPS_LISTED:
        for log, seed, lp in open_loops:
            i, j = lp.get("first_pair", ["?", "?"])
            lines.append(f"  - {log} seed {seed}: steps {i} -> {j} "
                         f"({fmt(lp.get('path_m'), 0)} m of path), error median "
                         f"{fmt(lp.get('median_error_m'))} m")
    else:
        # Hundreds of lines (a broken map leaves most returns open) would
        # bury the rest: a line a run, the loops themselves in its loops.json.
        per_run = {}
        for log, seed, lp in open_loops:
            per_run.setdefault((log, seed), []).append(lp.get("median_error_m"))
        for (log, seed), errors in per_run.items():
            known = [e for e in errors if e is not None]
            lines.append(f"  - {log} seed {seed}: {len(errors)} open, error median up to "
                         f"{fmt(max(known) if known else None)} m ({log}/seed{seed}/loops.json)")
    lines.append(f"- failed runs: {len(failed)}")
    lines += [f"  - {f}" for f in failed]
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("--threshold", type=float, default=0.15)
    a = ap.parse_args()
    if not (a.threshold > 0 and math.isfinite(a.threshold)):
        sys.exit("seeds_report.py: --threshold must be a positive number")
    if not os.path.isdir(a.out_dir):
        print(f"seeds_report.py: {a.out_dir}: not a folder", file=sys.stderr)
        sys.exit(4)
    logs = collect(a.out_dir)
    if not logs:
        print(f"seeds_report.py: {a.out_dir}: no LOG/seedS runs", file=sys.stderr)
        sys.exit(4)
    print(report(logs, a.threshold))


if __name__ == "__main__":
    main()
