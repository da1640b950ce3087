#!/usr/bin/python3
"""Online area-detection cost against window size, from hmt_area_bench.

Reads the Google Benchmark JSON of BM_OnlineKeyframe/<window> (one keyframe:
add_keyframe() + update() with the graph full at <window> keyframes), prints
a table, checks the targets and writes a plot:

  - at most TARGET_MS (2 ms) per keyframe with 300 keyframes in the window;
  - growing no faster than linearly: cost(largest) / cost(smallest) at most
    the ratio of the window sizes (500 / 50 = 10).

The checks use CPU time: on a shared machine the wall time also counts the
time spent waiting for a core. Both are printed and plotted.

Usage: plot_area_bench.py BENCH.json OUT.png
Exit status: 0 when both targets are met, 1 when one is missed, 2 on bad input.
"""
import json
import os
import statistics
import sys

TARGET_WINDOW = 300
TARGET_MS = 2.0
PREFIX = "BM_OnlineKeyframe/"


def to_ms(value, unit):
    return value * {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[unit]


def load(path):
    """{window: (real_ms, cpu_ms, sso_pairs_per_kf)}, medians over repetitions."""
    with open(path) as f:
        data = json.load(f)
    runs = {}
    for b in data.get("benchmarks", []):
        name = b.get("run_name", b["name"])
        if not name.startswith(PREFIX):
            continue
        if b.get("run_type") == "aggregate":
            continue  # recomputed below from the repetitions
        window = int(name[len(PREFIX):].split("/")[0])
        unit = b.get("time_unit", "ns")
        runs.setdefault(window, []).append(
            (to_ms(b["real_time"], unit), to_ms(b["cpu_time"], unit),
             b.get("sso_pairs_per_kf", float("nan"))))
    if not runs:
        # Only aggregates were written: take their medians.
        for b in data.get("benchmarks", []):
            name = b.get("run_name", b["name"])
            if name.startswith(PREFIX) and b.get("aggregate_name") == "median":
                window = int(name[len(PREFIX):].split("/")[0])
                unit = b.get("time_unit", "ns")
                runs[window] = [(to_ms(b["real_time"], unit), to_ms(b["cpu_time"], unit),
                                 b.get("sso_pairs_per_kf", float("nan")))]
    return {w: tuple(statistics.median(r[i] for r in rs) for i in range(3))
            for w, rs in sorted(runs.items())}


def main():
    if len(sys.argv) != 3:
        print("usage: plot_area_bench.py BENCH.json OUT.png", file=sys.stderr)
        return 2
    try:
        rows = load(sys.argv[1])
    except (OSError, ValueError, KeyError) as e:
        print(f"plot_area_bench: cannot read {sys.argv[1]}: {e}", file=sys.stderr)
        return 2
    if len(rows) < 2:
        print(f"plot_area_bench: {sys.argv[1]} has fewer than two {PREFIX}* results",
              file=sys.stderr)
        return 2

    windows = list(rows)
    print("| window | CPU ms/keyframe | wall ms/keyframe | SSO pairs/keyframe |")
    print("|---:|---:|---:|---:|")
    for w in windows:
        real, cpu, pairs = rows[w]
        print(f"| {w} | {cpu:.3f} | {real:.3f} | {pairs:.0f} |")

    ok = True
    if TARGET_WINDOW in rows:
        cpu = rows[TARGET_WINDOW][1]
        verdict = "PASS" if cpu <= TARGET_MS else "FAIL"
        ok &= cpu <= TARGET_MS
        print(f"\nwindow {TARGET_WINDOW}: {cpu:.3f} ms CPU per keyframe "
              f"(target <= {TARGET_MS} ms): {verdict}")
    else:
        print(f"\nwindow {TARGET_WINDOW}: not measured")
    lo, hi = windows[0], windows[-1]
    ratio = rows[hi][1] / rows[lo][1]
    linear = hi / lo
    verdict = "PASS" if ratio <= linear else "FAIL"
    ok &= ratio <= linear
    print(f"growth: cost({hi}) / cost({lo}) = {ratio:.2f} vs {linear:.0f} "
          f"for linear growth: {verdict}")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_area_bench: matplotlib not found (Debian: python3-matplotlib); "
              "no plot written", file=sys.stderr)
        return 0 if ok else 1
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=120)
    ax.plot(windows, [rows[w][1] for w in windows], "o-", label="CPU time")
    ax.plot(windows, [rows[w][0] for w in windows], "s--", alpha=0.6, label="wall time")
    ax.plot([0, hi], [0, rows[lo][1] * hi / lo], ":", color="grey",
            label=f"linear from window {lo}")
    ax.plot([TARGET_WINDOW], [TARGET_MS], "r*", markersize=12,
            label=f"target: {TARGET_MS:g} ms at {TARGET_WINDOW}")
    ax.set_xlabel("keyframes in the window")
    ax.set_ylabel("ms per keyframe (add + update)")
    ax.set_title("Online area detection: cost per keyframe")
    ax.set_xlim(0, hi * 1.05)
    ax.set_ylim(0, max(TARGET_MS, max(max(r[0], r[1]) for r in rows.values())) * 1.15)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    tmp = sys.argv[2] + ".tmp.png"  # complete or absent, like the tools' outputs
    fig.savefig(tmp)
    os.replace(tmp, sys.argv[2])
    print(f"plot: {sys.argv[2]}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
