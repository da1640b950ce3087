#!/usr/bin/python3
"""Per-lap figures of a run on a log built by soak_log.py.

Usage: soak_report.py OUT_DIR SCANS_PER_LAP [--json]

From the run's memory.csv, process_times.csv, topological_pmf.csv and
topology.json, per lap: peak RSS and map memory reached by the end of the
lap, the mean per-scan time of each process (ms), the areas created during
the lap, and the share of the lap's scans whose most probable area was
created in the first lap (a lap that closes into the first lap's areas
spends nearly all its scans there; one that does not makes its own).
Exit 4 when a file is missing or malformed.
"""
import csv
import json
import sys
from collections import defaultdict


def fail(message):
    print(f"soak_report.py: {message}", file=sys.stderr)
    sys.exit(4)


def rows(path):
    try:
        with open(path, newline="") as f:
            return list(csv.DictReader(f))
    except OSError as e:
        fail(f"cannot read {path}: {e.strerror}")


def main():
    args = [a for a in sys.argv[1:] if a != "--json"]
    if len(args) != 2:
        sys.exit(__doc__.strip().splitlines()[2])
    out, lap_scans = args[0], int(args[1])
    try:
        memory = [(int(r["step"]), float(r["peak_rss_mb"]), float(r["map_memory_mb"]))
                  for r in rows(f"{out}/memory.csv")]
        times = [(int(r["step"]), [float(r[k]) for k in ("metric_slam_ms", "aam_ms", "tsbi_ms", "tlca_ms")])
                 for r in rows(f"{out}/process_times.csv")]
        best = {}
        for r in rows(f"{out}/topological_pmf.csv"):
            step, p = int(r["step"]), float(r["probability"])
            if step not in best or p > best[step][1]:
                best[step] = (int(r["area"]), p)
        with open(f"{out}/topology.json") as f:
            areas = {a["id"]: a["created_step"] for a in json.load(f)["areas"]}
    except (KeyError, ValueError, OSError, json.JSONDecodeError) as e:
        fail(f"{out}: malformed run output ({e})")
    laps = max(s for s, _ in times) // lap_scans + 1
    table = []
    for lap in range(laps):
        lo, hi = lap * lap_scans, (lap + 1) * lap_scans
        mem = [m for m in memory if m[0] < hi]
        lap_times = [t for s, t in times if lo <= s < hi]
        steps = [s for s in best if lo <= s < hi]
        in_first = sum(1 for s in steps if areas.get(best[s][0], hi) < lap_scans)
        table.append({
            "lap": lap + 1,
            "peak_rss_mb": max((m[1] for m in mem), default=0.0),
            "map_memory_mb": max((m[2] for m in mem if m[0] >= lo), default=0.0),
            "ms_per_scan": [sum(t[i] for t in lap_times) / max(len(lap_times), 1) for i in range(4)],
            "areas_created": sum(1 for c in areas.values() if lo <= c < hi),
            "share_in_first_lap_areas": in_first / max(len(steps), 1),
        })
    if "--json" in sys.argv:
        print(json.dumps(table, indent=2))
        return
    print("| lap | peak RSS MB (so far) | map MB (lap max) | ms/scan metric | aam | tsbi | tlca | areas created | scans in lap-1 areas |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in table:
        m = r["ms_per_scan"]
        print(f"| {r['lap']} | {r['peak_rss_mb']:.0f} | {r['map_memory_mb']:.1f} | {m[0]:.1f} | {m[1]:.2f} | "
              f"{m[2]:.1f} | {m[3]:.2f} | {r['areas_created']} | {100 * r['share_in_first_lap_areas']:.0f}% |")


if __name__ == "__main__":
    main()
