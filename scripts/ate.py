#!/usr/bin/python3
"""Absolute trajectory error: position RMSE of a trajectory against a
reference after the best rigid 2D alignment (rotation + translation, no
scale; closed form: the rotation that best maps the centred estimated
positions onto the centred reference ones, Kabsch/Umeyama in 2D).

Scans are matched by index (the i-th pose of each file is the i-th scan of
the log), so both files must hold the same number of poses.

Usage: ate.py TRAJECTORY REFERENCE [--json]
TRAJECTORY: TUM ("t x y z qx qy qz qw") or "t x y theta" per line.
REFERENCE:  "t x y theta" per line (gzip or not), '#' comments allowed,
            e.g. /work/shared/datasets/carmen/NAME.reference.txt.gz
Prints the RMSE, mean, median and max position error (m) over the poses.
"""
import gzip
import json
import math
import sys


def load(path):
    opener = gzip.open if path.endswith(".gz") else open
    poses = []
    with opener(path, "rt") as f:
        for n, line in enumerate(f, 1):
            s = line.split()
            if not s or s[0].startswith("#"):
                continue
            try:
                v = [float(x) for x in s]
            except ValueError:
                raise SystemExit(f"{path}:{n}: not a number in {line.strip()!r}")
            if len(v) not in (4, 8):
                raise SystemExit(f"{path}:{n}: expected 4 or 8 fields, got {len(v)}")
            poses.append((v[1], v[2]))
    return poses


def align(est, ref):
    """Rotation angle and translation that map est onto ref best (least squares)."""
    n = len(est)
    ex = sum(p[0] for p in est) / n
    ey = sum(p[1] for p in est) / n
    rx = sum(p[0] for p in ref) / n
    ry = sum(p[1] for p in ref) / n
    dot = cross = 0.0
    for (a, b), (c, d) in zip(est, ref):
        a, b, c, d = a - ex, b - ey, c - rx, d - ry
        dot += a * c + b * d
        cross += a * d - b * c
    th = math.atan2(cross, dot)
    co, si = math.cos(th), math.sin(th)
    return th, (rx - (co * ex - si * ey), ry - (si * ex + co * ey))


def main(argv):
    args = [a for a in argv[1:] if a != "--json"]
    if len(args) != 2:
        raise SystemExit(__doc__)
    est, ref = load(args[0]), load(args[1])
    if len(est) != len(ref):
        raise SystemExit(f"{args[0]} has {len(est)} poses, {args[1]} {len(ref)}: "
                         "scans are matched by index, the counts must agree")
    if len(est) < 2:
        raise SystemExit("need at least two poses")
    th, (tx, ty) = align(est, ref)
    co, si = math.cos(th), math.sin(th)
    errs = sorted(math.hypot(co * x - si * y + tx - rx, si * x + co * y + ty - ry)
                  for (x, y), (rx, ry) in zip(est, ref))
    out = {
        "poses": len(errs),
        "rmse": math.sqrt(sum(e * e for e in errs) / len(errs)),
        "mean": sum(errs) / len(errs),
        "median": errs[len(errs) // 2],
        "max": errs[-1],
    }
    if "--json" in argv:
        print(json.dumps(out))
    else:
        print(f"poses {out['poses']}  rmse {out['rmse']:.4f} m  mean {out['mean']:.4f} m  "
              f"median {out['median']:.4f} m  max {out['max']:.4f} m")


if __name__ == "__main__":
    main(sys.argv)
