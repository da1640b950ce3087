#!/usr/bin/python3
"""Whether a trajectory closes the loops its reference closes.

Position RMSE after one rigid fit (scripts/ate.py) mixes two things: how
the map is bent as a whole, and whether it holds together where the robot
came back. This measures the second. A loop of the reference is a place the
robot returns to after driving at least --min-path metres: a pair of poses
(i, j), j later, at most --radius apart in the reference. Consecutive
returns along the same earlier stretch (driving down a known corridor) form
one loop. At every pair of a loop the relative pose of j seen from i is
taken from both trajectories; the loop's error is the median over its pairs
of the difference in position. The loop counts as closed when that error is
at most --tolerance: where a loop is left open or closed at a wrong place,
the two ends of it are apart by far more than the references' few
centimetres.

Usage: loops_closed.py TRAJECTORY REFERENCE [--json] [--min-path M]
                       [--radius M] [--tolerance M] [--list]
  TRAJECTORY, REFERENCE: TUM or "t x y theta" per line (gzip if .gz), one
       pose per scan (matched by index), or matched by timestamp as
       scripts/ate.py does.
  --min-path: path length between the two visits [20 m]
  --radius: distance in the reference that makes a return [1 m]
  --tolerance: a loop's median error that still counts as closed [0.3 m]
  --list: every loop, not only the open ones
Prints the loops found and closed, and each open loop (its first pair's
steps, the path length between the visits, the pairs, the median and the
largest error). Exit 4 on a bad file or too few matched poses, 2 on bad
arguments.
"""
import argparse
import json
import math
import sys

import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from ate import load_poses, nearest_times  # noqa: E402

# Returns of one loop: the next pair is at most this many scans after the
# last, and its earlier end at most this far along the path from the last's.
MAX_SCAN_GAP = 5
MAX_PATH_JUMP = 5.0


def matched(est, ref):
    """(est, ref) rows (t, x, y, theta) of the same scans: by index when the
    two have one pose per scan each, else by timestamp."""
    if len(est) == len(ref):
        return est, ref
    ok, index = nearest_times(ref[:, 0], est[:, 0])
    return est[ok], ref[index[ok]]


def relative(p, i, j):
    """Pose j seen from pose i: (dx, dy) in i's frame, for arrays of i, j."""
    d = p[j, 1:3] - p[i, 1:3]
    c, s = np.cos(p[i, 3]), np.sin(p[i, 3])
    return np.stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]], axis=1)


def find_loops(ref, min_path, radius):
    """The reference's loops: lists of (i, j) pairs, in the order of j."""
    xy = ref[:, 1:3]
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(xy, axis=0), axis=1))])
    pairs = []
    for j in range(len(ref)):
        earlier = np.nonzero(s[j] - s[: j + 1] >= min_path)[0]
        if len(earlier) == 0:
            continue
        d = np.linalg.norm(xy[earlier] - xy[j], axis=1)
        k = int(np.argmin(d))
        if d[k] <= radius:
            pairs.append((int(earlier[k]), j))
    loops = []
    for i, j in pairs:
        if loops:
            li, lj = loops[-1][-1]
            if j - lj <= MAX_SCAN_GAP and abs(s[i] - s[li]) <= MAX_PATH_JUMP:
                loops[-1].append((i, j))
                continue
        loops.append([(i, j)])
    return loops, s


def evaluate(est, ref, min_path, radius, tolerance):
    loops, s = find_loops(ref, min_path, radius)
    out = []
    for pairs in loops:
        i = np.array([p[0] for p in pairs])
        j = np.array([p[1] for p in pairs])
        err = np.linalg.norm(relative(est, i, j) - relative(ref, i, j), axis=1)
        med = float(np.median(err))
        out.append({"first_pair": [int(i[0]), int(j[0])],
                    "path_m": float(s[j[0]] - s[i[0]]), "pairs": len(pairs),
                    "median_error_m": med, "max_error_m": float(err.max()),
                    "closed": med <= tolerance})
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("trajectory")
    ap.add_argument("reference")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--min-path", type=float, default=20.0)
    ap.add_argument("--radius", type=float, default=1.0)
    ap.add_argument("--tolerance", type=float, default=0.3)
    a = ap.parse_args()
    for name in ("min_path", "radius", "tolerance"):
        v = getattr(a, name)
        if not (math.isfinite(v) and v > 0):
            ap.error(f"--{name.replace('_', '-')} must be a positive number, not {v}")
    try:
        est, ref = load_poses(a.trajectory), load_poses(a.reference)
    except SystemExit as e:  # ate.py's clear message for a bad file
        print(e, file=sys.stderr)
        sys.exit(4)
    e, r = matched(est, ref)
    if len(e) < max(len(est), len(ref)) / 2:
        print(f"loops_closed.py: only {len(e)} of {len(est)} poses of {a.trajectory} match "
              f"a pose of {a.reference}", file=sys.stderr)
        sys.exit(4)
    loops = evaluate(e, r, a.min_path, a.radius, a.tolerance)
    closed = sum(1 for lp in loops if lp["closed"])
    if a.json:
        print(json.dumps({"loops": len(loops), "closed": closed, "tolerance_m": a.tolerance,
                          "each": loops}))
        return
    print(f"{a.trajectory}: {closed} of {len(loops)} loops of the reference closed "
          f"(median error at most {a.tolerance:g} m; returns within {a.radius:g} m after "
          f"{a.min_path:g} m of path)")
    for lp in loops:
        if a.list or not lp["closed"]:
            i, j = lp["first_pair"]
            print(f"  {'closed' if lp['closed'] else 'OPEN  '} steps {i} -> {j}: "
                  f"{lp['path_m']:.0f} m of path, {lp['pairs']} pairs, error median "
                  f"{lp['median_error_m']:.3f} m, max {lp['max_error_m']:.3f} m")


if __name__ == "__main__":
    main()
