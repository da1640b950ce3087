#!/usr/bin/python3
"""TSBI time per new-area event against the number of areas, from the output
folders of `hmt-slam run` (process_times.csv: tsbi_ms per step;
tsbi_events.csv: the steps with a new-area event and the new area's id).

    scripts/plot_tsbi_cost.py OUT_DIR [OUT_DIR ...] [--label NAME ...] [--out PNG]

The number of areas at an event is the largest id of the new areas created
there minus one (ids count the areas created so far, from 1); at an event
whose new-area outcome was dropped (too improbable to follow), the largest
area id it names. With several
folders (e.g. before and after a change) their points share the axes. The PNG
defaults to OUT_DIR/report/tsbi_cost.png of the first folder. Each folder's
events are also summarised on stdout: their count, total and median time,
and the median in each quarter of the area count (does the cost grow with
the map?).
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def events(out_dir):
    """(areas, tsbi_ms) for every step with a new-area event."""
    new_area, named = {}, {}
    path = os.path.join(out_dir, "tsbi_events.csv")
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            step = int(row["step"])
            ids = [int(row[k]) for k in ("from_area", "area") if row[k]]
            named[step] = max([named.get(step, 0)] + ids)
            if row["outcome"] == "new" and row["area"]:
                new_area[step] = max(new_area.get(step, 0), int(row["area"]) - 1)
    for step, top in named.items():
        new_area.setdefault(step, top)
    ms = {}
    with open(os.path.join(out_dir, "process_times.csv"), newline="") as f:
        for row in csv.DictReader(f):
            ms[int(row["step"])] = float(row["tsbi_ms"])
    pts = [(new_area[s], ms[s]) for s in sorted(new_area) if s in ms]
    if not pts:
        sys.exit(f"{out_dir}: no new-area event with a time")
    return pts


def median(v):
    v = sorted(v)
    return v[len(v) // 2] if v else float("nan")


def summary(label, pts):
    """One line: events, total, median, and the median per quarter of the
    area count."""
    top = max(x for x, _ in pts)
    quarters = [[y for x, y in pts if q * top / 4 < x <= (q + 1) * top / 4 or (q == 0 and x == 0)]
                for q in range(4)]
    return (f"{label}: {len(pts)} events, total {sum(y for _, y in pts) / 1000:.2f} s, "
            f"median {median([y for _, y in pts]):.1f} ms; median by area quarter (up to "
            f"{top} areas): " + ", ".join(f"{median(q):.1f} ms ({len(q)})" for q in quarters))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out_dirs", nargs="+")
    ap.add_argument("--label", action="append", default=[])
    ap.add_argument("--out")
    a = ap.parse_args()
    labels = a.label + [os.path.basename(os.path.normpath(d)) for d in a.out_dirs[len(a.label):]]
    out = a.out or os.path.join(a.out_dirs[0], "report", "tsbi_cost.png")
    fig, ax = plt.subplots(figsize=(8, 5))
    for d, label in zip(a.out_dirs, labels):
        pts = events(d)
        xs, ys = zip(*pts)
        total = sum(ys)
        print(summary(label, pts))
        ax.scatter(xs, ys, s=10, alpha=0.6,
                   label=f"{label}: {len(pts)} events, {total / 1000:.1f} s, "
                         f"median {sorted(ys)[len(ys) // 2]:.0f} ms")
    ax.set_xlabel("areas in the map")
    ax.set_ylabel("TSBI time at the new-area event (ms)")
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    ax.set_title("Topological inference cost per new-area event")
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
