#!/usr/bin/python3
"""How sharp a trajectory draws its log's scans: a measure of a trajectory
that needs no reference.

Every scan's end points (returns below --max-range) are placed at the
trajectory's pose for that scan and counted as distinct cells of a square
grid (--cell, 5 cm). A wall seen many times from poses that agree is one
line of cells; seen from poses that disagree (an area misplaced, a heading
off) it is drawn twice or smeared, and the count grows. So of two
trajectories of the same log, the one with fewer cells is the more
self-consistent; neither needs to be right. The count depends on the frame
(a wall along a grid axis fills fewer cells than a diagonal one), so with a
REFERENCE the trajectory is first moved into the reference's frame by the
rigid fit of scripts/ate.py, and the two are drawn in one frame; counts of
one log only are comparable.

ATE against a reference trajectory (scripts/ate.py) cannot say which of the
two is off; this can, when the two differ by more than the references' own
few centimetres.

Usage: map_sharpness.py LOG TRAJECTORY [REFERENCE] [--json] [--cell M]
                        [--max-range M] [--blocks K] [--png OUT --window X,Y,H]
                        [--offset K]
  LOG: a CARMEN log (.log or .log.gz; FLASER or ROBOTLASER1 lines), the
       one both trajectories were estimated from.
  TRAJECTORY, REFERENCE: TUM or "t x y theta" per line (gzip if .gz), one
       pose per scan (matched by index), or matched by timestamp as
       scripts/ate.py does.
  --blocks K: also list the K square blocks of 4 m (in the reference's
       frame) where each of the two needs the most cells more than the
       other: where to look.
  --png OUT --window X,Y,H: draws the cells within H metres of (X, Y) (the
       reference's frame) as OUT, a PNG of two panels: the trajectory's
       left, the reference's right, one pixel per cell.
  --offset K: pose i of TRAJECTORY is scan K + i of the log, whatever the
       timestamps (a tool that began at scan K: MRPT's rbpf-slam skips the
       first scan, which no odometry precedes).
Exit 4 on a malformed or empty file, or when fewer than half of the poses
match a scan.
"""
import gzip
import json
import math
import sys
from collections import Counter

import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from ate import load_poses, nearest_times, rigid_fit  # noqa: E402


def fail(msg):
    raise SystemExit(f"map_sharpness.py: {msg}")


def beam_angles(n, start=None, resolution=None):
    """FLASER's rule as hmt-slam's CARMEN reader applies it: first beam at
    -90 degrees, 1 degree apart for 180/181 beams, 0.5 for 360/361, else
    spread over 180 degrees."""
    if start is not None:
        return start + resolution * np.arange(n)
    if n in (180, 181):
        res = math.radians(1.0)
    elif n in (360, 361):
        res = math.radians(0.5)
    else:
        res = math.pi / (n - 1) if n > 1 else 0.0
    return -math.pi / 2 + res * np.arange(n)


def laser_readings(s):
    """(field of the first reading, beam count, readings, bearings) of the
    fields `s` of a FLASER or ROBOTLASER1 line; ValueError or IndexError where
    they do not parse. The readings are as many as the line holds, up to the
    count: the caller tells a short line."""
    if s[0] == "FLASER":
        first, n = 2, int(s[1])
        angles = beam_angles(n)
    else:  # ROBOTLASER1 type start fov resolution max_range accuracy mode n r1..rn
        first, n = 9, int(s[8])
        angles = beam_angles(n, float(s[2]), float(s[4]))
    return first, n, np.array(s[first:first + n], dtype=float), angles


def load_scans(path):
    """(timestamp, bearings, ranges) per FLASER / ROBOTLASER1 line."""
    opener = gzip.open if path.endswith(".gz") else open
    scans = []
    try:
        with opener(path, "rt", errors="replace") as f:
            for no, line in enumerate(f, 1):
                s = line.split()
                if not s or s[0] not in ("FLASER", "ROBOTLASER1"):
                    continue
                try:
                    _, n, ranges, angles = laser_readings(s)
                    stamp = float(s[-3])
                except (ValueError, IndexError):
                    fail(f"{path}:{no}: malformed {s[0]} line")
                if len(ranges) != n:
                    fail(f"{path}:{no}: {s[0]} line shorter than its {n} ranges")
                scans.append((stamp, angles, ranges))
    except OSError as e:
        fail(f"{path}: {e.strerror or e}")
    if not scans:
        fail(f"{path}: no FLASER or ROBOTLASER1 line")
    return scans


def match_scans(poses, scans, path):
    """Scan index per pose: by index when the counts agree, else the scan
    with the nearest timestamp within 0.01 s (none if another scan's
    timestamp lies within 0.02 s of it: ambiguous)."""
    if len(poses) == len(scans):
        return poses, np.arange(len(scans))
    ok, index = nearest_times(np.array([s[0] for s in scans]), poses[:, 0])
    if ok.sum() < max(len(poses), len(scans)) / 2:
        fail(f"only {ok.sum()} of {len(poses)} poses of {path} match a scan of the log "
             f"(by a timestamp within 0.01 s that no other scan shares)")
    return poses[ok], index[ok]


def offset_scans(poses, scans, offset, path):
    """Scan index per pose by `--offset`: pose i is scan offset + i; the poses
    past the log's last scan are dropped, and, as when matching by time,
    fewer than half of the poses left is an error."""
    index = np.arange(len(poses)) + offset
    ok = index < len(scans)
    if ok.sum() < max(len(poses), len(scans)) / 2:
        fail(f"only {ok.sum()} of {len(poses)} poses of {path} fall on a scan of the log "
             f"from scan {offset} on (the log has {len(scans)} scans)")
    return poses[ok], index[ok]


def end_point_cells(poses, index, scans, cell, max_range, transform=None):
    cells = set()
    for (t, x, y, th), k in zip(poses, index):
        _, angles, ranges = scans[k]
        ok = np.isfinite(ranges) & (ranges > 0.0) & (ranges < max_range)
        if transform is not None:
            (x, y), th = transform(np.array([x, y]), th)
        a = th + angles[ok]
        ex = x + ranges[ok] * np.cos(a)
        ey = y + ranges[ok] * np.sin(a)
        cells.update(zip(np.floor(ex / cell).astype(np.int64).tolist(),
                         np.floor(ey / cell).astype(np.int64).tolist()))
    return cells


def draw_pair(drawn, cell, window, path):
    """The cells of both trajectories near window = (x, y, half) side by side."""
    from PIL import Image
    x0, y0, half = window
    n = max(1, int(round(2 * half / cell)))
    lo_x, lo_y = math.floor((x0 - half) / cell), math.floor((y0 - half) / cell)
    panels = []
    for cells in drawn:
        img = np.full((n, n), 255, dtype=np.uint8)
        for cx, cy in cells:
            i, j = cx - lo_x, cy - lo_y
            if 0 <= i < n and 0 <= j < n:
                img[n - 1 - j, i] = 0  # rows downwards, y upwards
        panels.append(img)
    gap = np.full((n, max(2, n // 100)), 128, dtype=np.uint8)
    try:
        Image.fromarray(np.hstack([panels[0], gap, panels[1]])).save(path)
    except OSError as e:
        fail(f"{path}: {e.strerror or e}")


def main(argv):
    opts = {"--cell": 0.05, "--max-range": 20.0, "--blocks": 0, "--png": "", "--window": "",
            "--offset": -1}
    args = []
    it = iter(argv[1:])
    for a in it:
        if a in opts:
            try:
                opts[a] = type(opts[a])(next(it))
            except (StopIteration, ValueError):
                print(f"map_sharpness.py: {a} needs a value", file=sys.stderr)
                return 2
        elif a != "--json":
            args.append(a)
    window = None
    if opts["--window"]:
        try:
            window = [float(v) for v in opts["--window"].split(",")]
        except ValueError:
            window = []
    if "--offset" in argv and opts["--offset"] < 0:
        print("map_sharpness.py: --offset needs a scan count >= 0", file=sys.stderr)
        return 2
    if (len(args) not in (2, 3) or opts["--cell"] <= 0 or opts["--max-range"] <= 0
            or bool(opts["--png"]) != (window is not None)
            or (window is not None and (len(window) != 3 or not window[2] > 0 or len(args) != 3))):
        print(__doc__, file=sys.stderr)
        return 2
    try:
        scans = load_scans(args[0])
        runs = []
        for k, path in enumerate(args[1:]):
            poses = load_poses(path)
            if k == 0 and opts["--offset"] >= 0:
                poses, index = offset_scans(poses, scans, opts["--offset"], path)
            else:
                poses, index = match_scans(poses, scans, path)
            runs.append((path, poses, index))
    except SystemExit as e:
        print(e, file=sys.stderr)
        return 4
    cell, max_range = opts["--cell"], opts["--max-range"]
    move = None
    if len(runs) == 2:
        # The trajectory in the reference's frame, fitted on the scans both have.
        (_, pe, ie), (_, pr, ir) = runs
        common = np.intersect1d(ie, ir)
        fe = pe[np.isin(ie, common)][np.argsort(ie[np.isin(ie, common)], kind="stable")]
        fr = pr[np.isin(ir, common)][np.argsort(ir[np.isin(ir, common)], kind="stable")]
        r, me, mr = rigid_fit(fe[:, 1:3], fr[:, 1:3])
        t = mr - r @ me
        rot = math.atan2(r[1, 0], r[0, 0])

        def move(p, th):
            return r @ p + t, th + rot
    drawn = [end_point_cells(runs[0][1], runs[0][2], scans, cell, max_range, move)]
    if len(runs) == 2:
        drawn.append(end_point_cells(runs[1][1], runs[1][2], scans, cell, max_range))
    counts = [len(c) for c in drawn]
    out = {"cell_m": cell, "max_range_m": max_range, "trajectory_cells": counts[0],
           "trajectory_poses": len(runs[0][1])}
    if len(runs) == 2:
        out["reference_cells"] = counts[1]
        out["ratio"] = counts[0] / counts[1]
    if len(runs) == 2 and opts["--blocks"] > 0:
        block = 4.0
        per = [Counter((int(cx * cell // block), int(cy * cell // block)) for cx, cy in s)
               for s in drawn]
        diff = sorted(((per[0][k] - per[1][k], k) for k in set(per[0]) | set(per[1])))
        k = opts["--blocks"]

        def centre(key):
            return [round(key[0] * block + block / 2, 1), round(key[1] * block + block / 2, 1)]
        out["blocks_m"] = block
        out["trajectory_worse"] = [{"centre": centre(b), "more_cells": d}
                                   for d, b in reversed(diff[-k:]) if d > 0]
        out["reference_worse"] = [{"centre": centre(b), "more_cells": -d}
                                  for d, b in diff[:k] if d < 0]
    if opts["--png"]:
        draw_pair(drawn, cell, window, opts["--png"])
    if "--json" in argv:
        print(json.dumps(out))
    else:
        print(f"{args[1]}: {counts[0]} cells of {cell} m")
        if len(runs) == 2:
            print(f"{args[2]}: {counts[1]} cells; ratio {out['ratio']:.3f} "
                  f"({'the trajectory' if counts[0] < counts[1] else 'the reference'} is sharper)")
        for key in ("trajectory_worse", "reference_worse"):
            for b in out.get(key, []):
                print(f"{key.replace('_', ' ')}: block at {b['centre']} +{b['more_cells']} cells")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
