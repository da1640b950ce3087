#!/usr/bin/python3
"""How a trajectory's error grows with the distance travelled: the relative
pose error between pose i and the pose about d metres further along the
reference's path, for bins of d (2-5, 5-10, 10-20, 20-40, 40-80 and
80-160 m), as the RMS and 95th percentile of the heading error (rad) and of
the position error (m, the relative translation in pose i's frame).

Run on the trajectory of `hmt-slam metric` (one map, no topology) it
measures the open-loop drift that an arc between two area origins d metres
apart accumulates: the data behind the arc floors of `[hmt]`
(arc_std_theta + arc_std_theta_per_metre d, arc_std_xy + arc_std_xy_per_metre d).

Usage: drift.py TRAJECTORY REFERENCE [--json]
Poses are matched by index (one line per scan in both files; TUM or
"t x y theta", gzip when the name ends in .gz). Exit 4 on a malformed or
empty file or when the two differ in length.
"""
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ate import load_by_index  # noqa: E402
from relation_error import errors, relative  # noqa: E402

BINS = [(2, 5), (5, 10), (10, 20), (20, 40), (40, 80), (80, 160)]


def error_stats(heading, position):
    """RMS and 95th percentile of heading (rad) and position (m) errors."""
    th, xy = np.asarray(heading, dtype=float), np.asarray(position, dtype=float)
    return dict(heading_rms_rad=float(np.sqrt(np.mean(th ** 2))),
                heading_p95_rad=float(np.percentile(th, 95)),
                position_rms_m=float(np.sqrt(np.mean(xy ** 2))),
                position_p95_m=float(np.percentile(xy, 95)))


def drift(est, ref, stride=3):
    """Per bin: pairs, mean distance, heading and position error RMS and p95."""
    along = np.r_[0.0, np.cumsum(np.hypot(np.diff(ref[:, 1]), np.diff(ref[:, 2])))]
    out = []
    for lo, hi in BINS:
        th, xy, dist = [], [], []
        for i in range(0, len(ref), stride):
            js = np.nonzero((along - along[i] >= lo) & (along - along[i] < hi))[0]
            if len(js) == 0:
                continue
            j = js[len(js) // 2]  # the bin's middle, not its first pose
            # The same error as a ground-truth relation's (relation_error.py).
            e_xy, e_th = errors(relative(ref[i, 1:], ref[j, 1:]),
                                relative(est[i, 1:], est[j, 1:]))
            xy.append(e_xy)
            th.append(e_th)
            dist.append(along[j] - along[i])
        row = {"from_m": lo, "to_m": hi, "pairs": len(th)}
        if th:
            row.update(mean_distance_m=float(np.mean(dist)), **error_stats(th, xy))
        out.append(row)
    return out


def main(argv):
    args = [a for a in argv[1:] if a != "--json"]
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        est, ref = load_by_index(args, "drift.py")
    except SystemExit as e:
        print(e, file=sys.stderr)
        return 4
    rows = drift(est, ref)
    if "--json" in argv:
        print(json.dumps(rows, indent=1))
        return 0
    print("distance (m)  pairs  heading rms / p95 (rad)  position rms / p95 (m)")
    for r in rows:
        if not r["pairs"]:
            print(f"{r['from_m']:>4}-{r['to_m']:<4}      0")
            continue
        print(f"{r['from_m']:>4}-{r['to_m']:<4}  {r['pairs']:>6}  {r['heading_rms_rad']:.4f} / "
              f"{r['heading_p95_rad']:.4f}        {r['position_rms_m']:.3f} / "
              f"{r['position_p95_m']:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
