#!/usr/bin/python3
"""Relation-based SLAM accuracy (Kuemmerle et al. 2009, "On measuring the
accuracy of SLAM algorithms").

For each ground-truth relation (t1, t2, dx, dy, dyaw), the same relative pose
is taken from the trajectory (inverse of pose(t1) composed with pose(t2));
the translational error is the norm of the (x, y) difference, the rotational
error the absolute normalised angle difference. Timestamps are matched to the
nearest trajectory timestamp within 0.01 s; relations without a match on both
ends are skipped, and so are those whose two ends match one and the same
pose (a few milliseconds apart in a log of coarse timestamps, yet a true
motion of 0.3-0.4 m: the trajectory cannot measure them; on Intel 28 of the
144 matched, leaving the 116 usable relations of the datasets' README).

Usage: relation_error.py TRAJECTORY RELATIONS [--json] [--worst N [--against OTHER]]
TRAJECTORY, OTHER: TUM ("t x y z qx qy qz qw") or "t x y theta" per line,
gzip if the name ends in .gz.

--worst N lists the N relations with the largest translational error (scan
indices, the true distance, both errors) and the mean without them; with
--against OTHER (another trajectory of the same log, e.g. the dataset's
reference), each listed relation also shows OTHER's errors and how far the
two trajectories' own relative poses differ. Two independent estimates that
agree with each other to centimetres and both miss a relation by decimetres
point at the relation (or at what this log can measure of it), not at
either estimate.
"""
import argparse
import bisect
import json
import math
import sys

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from ate import load_poses  # noqa: E402


def load_trajectory(path):
    """(t, x, y, theta) tuples in time order; gzip if the name ends in .gz
    (the datasets' references are), with ate.py's clear errors."""
    return sorted(tuple(float(v) for v in row) for row in load_poses(path))


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


def relative(a, b):
    """a^-1 (+) b for poses (x, y, theta)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    c, s = math.cos(a[2]), math.sin(a[2])
    return (c * dx + s * dy, -s * dx + c * dy, wrap(b[2] - a[2]))


def nearest_index(times, t, tol=0.01):
    i = bisect.bisect_left(times, t)
    best = None
    for j in (i - 1, i):
        if 0 <= j < len(times) and abs(times[j] - t) <= tol:
            if best is None or abs(times[j] - t) < abs(times[best] - t):
                best = j
    return best


def scored(traj, relations_path):
    """Every usable relation: (i, j, truth (x, y, yaw), estimate (x, y, yaw))
    with i, j the trajectory's indices of its two ends."""
    times = [p[0] for p in traj]
    out = []
    with open(relations_path) as f:
        for line in f:
            s = line.split()
            if len(s) < 8:
                continue
            t1, t2, x, y, yaw = float(s[0]), float(s[1]), float(s[2]), float(s[3]), float(s[7])
            i, j = nearest_index(times, t1), nearest_index(times, t2)
            if i is None or j is None or i == j:
                continue
            out.append((i, j, (x, y, yaw), relative(traj[i][1:], traj[j][1:])))
    return out


def errors(truth, est):
    """Translational and absolute rotational error of one relation."""
    return math.hypot(est[0] - truth[0], est[1] - truth[1]), abs(wrap(est[2] - truth[2]))


def evaluate(rows):
    """Translational and rotational errors of the rows of scored()."""
    et, er = [], []
    for _, _, truth, est in rows:
        t, r = errors(truth, est)
        et.append(t)
        er.append(r)
    return et, er


def worst(rows, n, rows_other=None):
    """The n rows of scored() of largest translational error, as printable
    lines, with another trajectory's errors (its rows for the same
    relations) and the two estimates' difference when given."""
    if rows_other is not None and len(rows_other) != len(rows):
        raise SystemExit("--against: the two trajectories do not match the same relations "
                         f"({len(rows)} and {len(rows_other)})")
    order = sorted(range(len(rows)), key=lambda k: -errors(rows[k][2], rows[k][3])[0])
    lines = []
    for k in order[:n]:
        i, j, truth, est = rows[k]
        t, r = errors(truth, est)
        line = (f"scans {i:5d} {j:5d}  true {math.hypot(truth[0], truth[1]):6.3f} m  "
                f"error {t:.3f} m {math.degrees(r):6.2f} deg")
        if rows_other is not None:
            oest = rows_other[k][3]
            ot, orr = errors(truth, oest)
            dt, dr = errors(oest, est)
            line += (f"  | other {ot:.3f} m {math.degrees(orr):6.2f} deg"
                     f"  | between them {dt:.3f} m {math.degrees(dr):6.2f} deg")
        lines.append(line)
    rest = [errors(rows[k][2], rows[k][3])[0] for k in order[n:]]
    lines.append(f"mean translational error without these {n}: "
                 f"{stats(rest)[0]:.4f} m over {len(rest)}")
    return lines


def stats(v):
    if not v:
        return float("nan"), float("nan")
    m = sum(v) / len(v)
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / len(v))
    return m, sd


def positive_count(value):
    try:
        n = int(value)
    except ValueError:
        n = 0
    if n < 1:
        raise argparse.ArgumentTypeError(f"not a count: {value}")
    return n


def main():
    ap = argparse.ArgumentParser(usage=__doc__, add_help=False)
    ap.add_argument("trajectory")
    ap.add_argument("relations")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--worst", type=positive_count)
    ap.add_argument("--against")
    a = ap.parse_args()
    if a.against is not None and a.worst is None:
        ap.error("--against goes with --worst N")
    rows = scored(load_trajectory(a.trajectory), a.relations)
    et, er = evaluate(rows)
    tm, ts = stats(et)
    rm, rs = stats([math.degrees(x) for x in er])
    t2m, t2s = stats([x * x for x in et])
    r2m, r2s = stats([math.degrees(x) ** 2 for x in er])
    res = {"count": len(et), "trans_mean_m": tm, "trans_std_m": ts,
           "rot_mean_deg": rm, "rot_std_deg": rs,
           "trans_sq_mean": t2m, "trans_sq_std": t2s,
           "rot_sq_mean": r2m, "rot_sq_std": r2s}
    if a.json:
        print(json.dumps(res))
    else:
        print(f"relations: {len(et)}  translational {tm:.4f} +- {ts:.4f} m  "
              f"rotational {rm:.3f} +- {rs:.3f} deg")
    if a.worst is not None and rows:
        rows_other = (scored(load_trajectory(a.against), a.relations)
                      if a.against is not None else None)
        for line in worst(rows, a.worst, rows_other):
            print(line)
    if not et:
        sys.exit(3)


if __name__ == "__main__":
    main()
