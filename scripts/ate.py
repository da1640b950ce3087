#!/usr/bin/python3
"""Absolute trajectory error against a reference trajectory.

Position RMSE (and maximum) after the best rigid 2D alignment (rotation +
translation, no scale: Umeyama / Kabsch on the positions) of the estimate
to the reference, poses matched by index (one line per scan in both) or,
when the two differ in length (a tool that dropped a scan), by timestamp
(nearest within 0.01 s; the unmatched are left out and counted; a
reference time within 0.02 s of another matches nothing, being ambiguous). The
references shipped with the datasets are GMapping trajectories, good to a
few centimetres: this says "is the map roughly right", not ground truth.

Usage: ate.py TRAJECTORY REFERENCE [--json] [--offset K]
--offset K: pose i of TRAJECTORY is pose K + i of REFERENCE, whatever the
timestamps (a tool that began at the log's scan K: MRPT's rbpf-slam skips
the first scan, which no odometry precedes).
Both files: TUM ("t x y z qx qy qz qw") or "t x y theta" per line; gzip
when the name ends in .gz. Exit 4 on a malformed or empty file, or when
fewer than half of the poses can be matched.
"""
import gzip
import json
import math
import sys

import numpy as np


def load_poses(path):
    """(t, x, y, theta) rows; theta from the quaternion of a TUM line."""
    opener = gzip.open if path.endswith(".gz") else open
    rows = []
    try:
        with opener(path, "rt") as f:
            for n, line in enumerate(f, 1):
                s = line.split()
                if not s or s[0].startswith("#"):
                    continue
                if len(s) not in (4, 8):
                    raise SystemExit(f"ate.py: {path}:{n}: expected 4 or 8 fields, got {len(s)}")
                try:
                    theta = (2.0 * math.atan2(float(s[6]), float(s[7])) if len(s) == 8
                             else float(s[3]))
                    rows.append((float(s[0]), float(s[1]), float(s[2]), theta))
                except ValueError:
                    raise SystemExit(f"ate.py: {path}:{n}: not a number")
    except OSError as e:
        raise SystemExit(f"ate.py: {path}: {e.strerror or e}")
    if not rows:
        raise SystemExit(f"ate.py: {path}: no poses")
    return np.array(rows)


def load_positions(path):
    """(t, x, y) rows."""
    return load_poses(path)[:, :3]


def nearest_times(times, queries, tol=0.01):
    """For each query time, the index of the nearest of `times`, and whether
    it is a match: within `tol`, and the only one of `times` within 2 tol of
    the time it matched. A time that several poses share (a log whose
    timestamps are rounded, csail's to 10 s; a repeated stamp) cannot say
    which of them a query is, so it matches none: (mask, indices)."""
    order = np.argsort(times, kind="stable")
    t = times[order]
    i = np.clip(np.searchsorted(t, queries), 1, max(len(t) - 1, 1))
    lo = np.clip(i - 1, 0, len(t) - 1)
    hi = np.clip(i, 0, len(t) - 1)
    near = np.where(np.abs(t[lo] - queries) <= np.abs(t[hi] - queries), lo, hi)
    gap = np.full(len(t), np.inf)
    if len(t) > 1:
        d = np.diff(t)
        gap[:-1] = d
        gap[1:] = np.minimum(gap[1:], d)
    return (np.abs(t[near] - queries) <= tol) & (gap[near] > 2 * tol), order[near]


def match(est, ref, tol=0.01, offset=None):
    """Positions of the pose pairs: by index (from `offset` of ref, if
    given), or by nearest timestamp."""
    if offset is not None:
        n = max(0, min(len(est), len(ref) - offset))
        return est[:n, 1:], ref[offset:offset + n, 1:]
    if len(est) == len(ref):
        return est[:, 1:], ref[:, 1:]
    ok, index = nearest_times(ref[:, 0], est[:, 0], tol)
    return est[ok, 1:], ref[index[ok], 1:]


def rigid_fit(est, ref):
    """The rotation R and the two means with R (est - mean_est) + mean_ref
    closest to ref."""
    me, mr = est.mean(axis=0), ref.mean(axis=0)
    u, _, vt = np.linalg.svd((est - me).T @ (ref - mr))
    d = np.sign(np.linalg.det(vt.T @ u.T))
    return vt.T @ np.diag([1.0, d]) @ u.T, me, mr


def align(est, ref):
    """est moved by the rotation and translation that best fit it to ref."""
    r, me, mr = rigid_fit(est, ref)
    return (r @ (est - me).T).T + mr


def ate(est, ref):
    """RMSE and max of |R est + t - ref| for the best rotation R and translation t."""
    e = np.linalg.norm(align(est, ref) - ref, axis=1)
    return math.sqrt(float((e ** 2).mean())), float(e.max())


def load_by_index(paths, script):
    """The poses of each file, matched by index: SystemExit with the reason
    when a file is bad or the files hold different numbers of poses."""
    poses = [load_poses(p) for p in paths]
    for path, p in zip(paths[1:], poses[1:]):
        if len(p) != len(poses[0]):
            raise SystemExit(f"{script}: {paths[0]} has {len(poses[0])} poses and {path} "
                             f"{len(p)}: matched by index, they must be as many")
    return poses


def load_matched(est_path, ref_path, offset=None):
    """The matched positions of two trajectory files; SystemExit with the
    reason when a file is bad or fewer than half of the poses match."""
    est, ref = load_positions(est_path), load_positions(ref_path)
    e, r = match(est, ref, offset=offset)
    if len(e) < max(len(est), len(ref)) / 2:
        raise SystemExit(f"ate.py: only {len(e)} of {len(est)} poses of {est_path} match a pose "
                         f"of {ref_path} (by index, or by a timestamp within 0.01 s that no "
                         f"other pose of the reference shares)")
    return e, r


def main(argv):
    args, offset, it = [], None, iter(argv[1:])
    for a in it:
        if a == "--offset":
            try:
                offset = int(next(it))
            except (StopIteration, ValueError):
                offset = -1
            if offset < 0:
                print("ate.py: --offset needs a scan count >= 0", file=sys.stderr)
                return 2
        elif a != "--json":
            args.append(a)
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        est, ref = load_matched(args[0], args[1], offset)
    except SystemExit as e:
        print(e, file=sys.stderr)
        return 4
    rmse, worst = ate(est, ref)
    if "--json" in argv:
        print(json.dumps({"count": len(est), "rmse_m": rmse, "max_m": worst}))
    else:
        print(f"{len(est)} poses: position RMSE {rmse:.3f} m, max {worst:.3f} m")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
