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

Usage: relation_error.py TRAJECTORY RELATIONS [--json]
TRAJECTORY: TUM ("t x y z qx qy qz qw") or "t x y theta" per line.
"""
import bisect
import json
import math
import sys


def load_trajectory(path):
    traj = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            s = line.split()
            if not s or s[0].startswith("#"):
                continue
            v = [float(x) for x in s]
            if len(v) == 8:
                qz, qw = v[6], v[7]
                theta = 2.0 * math.atan2(qz, qw)
            elif len(v) == 4:
                theta = v[3]
            else:
                raise SystemExit(f"{path}:{n}: expected 4 or 8 fields, got {len(v)}")
            traj.append((v[0], v[1], v[2], theta))
    traj.sort(key=lambda p: p[0])
    return traj


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


def evaluate(traj, relations_path):
    times = [p[0] for p in traj]
    et, er = [], []
    with open(relations_path) as f:
        for line in f:
            s = line.split()
            if len(s) < 8:
                continue
            t1, t2, x, y, yaw = float(s[0]), float(s[1]), float(s[2]), float(s[3]), float(s[7])
            i, j = nearest_index(times, t1), nearest_index(times, t2)
            if i is None or j is None or i == j:
                continue
            r = relative(traj[i][1:], traj[j][1:])
            et.append(math.hypot(r[0] - x, r[1] - y))
            er.append(abs(wrap(r[2] - yaw)))
    return et, er


def stats(v):
    if not v:
        return float("nan"), float("nan")
    m = sum(v) / len(v)
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / len(v))
    return m, sd


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) != 2:
        raise SystemExit(__doc__)
    et, er = evaluate(load_trajectory(args[0]), args[1])
    tm, ts = stats(et)
    rm, rs = stats([math.degrees(x) for x in er])
    t2m, t2s = stats([x * x for x in et])
    r2m, r2s = stats([math.degrees(x) ** 2 for x in er])
    res = {"count": len(et), "trans_mean_m": tm, "trans_std_m": ts,
           "rot_mean_deg": rm, "rot_std_deg": rs,
           "trans_sq_mean": t2m, "trans_sq_std": t2s,
           "rot_sq_mean": r2m, "rot_sq_std": r2s}
    if "--json" in sys.argv:
        print(json.dumps(res))
    else:
        print(f"relations: {len(et)}  translational {tm:.4f} +- {ts:.4f} m  "
              f"rotational {rm:.3f} +- {rs:.3f} deg")
    if not et:
        sys.exit(3)


if __name__ == "__main__":
    main()
