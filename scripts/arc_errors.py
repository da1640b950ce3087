#!/usr/bin/python3
"""How far an area's creating arc is off, against its length: the data
behind the arcs' floors of `[hmt]` (arc_std_theta + arc_std_theta_per_metre
d up to arc_std_theta_max, arc_std_xy + arc_std_xy_per_metre d).

An area's frame is the robot's pose at the step it was created, and its
creating arc is that pose in its parent's frame: the parent's keyframe pose
at the same step (topology.json holds every area's parent, creation step and
keyframe poses). Its error is the difference from the reference's relative
pose between the parent's creation step and the child's (the same error as
a ground-truth relation's, scripts/relation_error.py). An area whose parent
holds no keyframe at its creation step is left out and counted.

drift.py measures the open-loop drift of one map along its path; this
measures the arcs the run actually made, closures and all, per bin of the
straight-line distance between the two origins (the distance the floors
grow with): 0-5, 5-10, 10-20, 20-40, 40-80 and 80 m or more.

Usage: arc_errors.py RUN_DIR REFERENCE [--json]
RUN_DIR: an `hmt-slam run` output folder (topology.json; its
config_effective.ini, when present, gives the floors to print beside).
REFERENCE: TUM ("t x y z qx qy qz qw") or "t x y theta" per line, one per
scan of the log (gzip when the name ends in .gz).
Exit 4 on a missing or malformed file.
"""
import configparser
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ate import load_poses  # noqa: E402
from drift import error_stats  # noqa: E402
from relation_error import errors, relative  # noqa: E402

BINS = [(0, 5), (5, 10), (10, 20), (20, 40), (40, 80), (80, math.inf)]


def arcs(topology, ref):
    """(length m, heading error rad, position error m) per creating arc,
    and the number of areas left out."""
    areas = {a["id"]: a for a in topology["areas"]}
    out, skipped = [], 0
    for a in topology["areas"]:
        parent = areas.get(a.get("parent"))
        if parent is None:
            continue  # the root
        step, from_step = a["created_step"], parent["created_step"]
        steps = parent["keyframe_steps"]
        if step not in steps or max(step, from_step) >= len(ref):
            skipped += 1
            continue
        _, x, y, th = parent["keyframe_poses"][steps.index(step)]
        e_xy, e_th = errors(relative(ref[from_step, 1:], ref[step, 1:]), np.array([x, y, th]))
        out.append((math.hypot(x, y), e_th, e_xy))
    return out, skipped


def floors(run_dir):
    """The heading floor of `[hmt]` as a function of the length, or None."""
    path = os.path.join(run_dir, "config_effective.ini")
    if not os.path.exists(path):
        return None
    cfg = configparser.ConfigParser(inline_comment_prefixes=(";", "#"))
    cfg.read(path)
    h = cfg["hmt"] if cfg.has_section("hmt") else {}
    try:
        c = float(h.get("arc_std_theta", "nan"))
        k = float(h.get("arc_std_theta_per_metre", "nan"))
        cap = float(h.get("arc_std_theta_max", "0"))
    except ValueError:
        return None
    if math.isnan(c) or math.isnan(k):
        return None
    return lambda d: max(c, min(c + k * d, cap)) if cap > 0 else c + k * d


def table(rows, floor):
    out = []
    for lo, hi in BINS:
        sel = [r for r in rows if lo <= r[0] < hi]
        row = {"from_m": lo, "to_m": None if math.isinf(hi) else hi, "arcs": len(sel)}
        if sel:
            d = np.array([r[0] for r in sel])
            th = np.array([r[1] for r in sel])
            row.update(mean_length_m=float(d.mean()), heading_max_rad=float(th.max()),
                       **error_stats(th, [r[2] for r in sel]))
            if floor:
                row["heading_floor_rad"] = floor(float(d.mean()))
        out.append(row)
    return out


def main(argv):
    args = [a for a in argv[1:] if a != "--json"]
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    run_dir, ref_path = args
    try:
        with open(os.path.join(run_dir, "topology.json")) as f:
            topology = json.load(f)
        ref = load_poses(ref_path)
        rows, skipped = arcs(topology, ref)
    except SystemExit as e:  # the reference's reader says what is wrong
        print(e, file=sys.stderr)
        return 4
    except OSError as e:
        print(f"arc_errors.py: {e.filename}: {e.strerror}", file=sys.stderr)
        return 4
    except (ValueError, KeyError, TypeError, IndexError) as e:
        print(f"arc_errors.py: {run_dir}/topology.json: not a run's topology ({e!r})",
              file=sys.stderr)
        return 4
    result = table(rows, floors(run_dir))
    if "--json" in argv:
        print(json.dumps({"bins": result, "skipped": skipped}, indent=1))
        return 0
    print(f"{len(rows)} creating arcs ({skipped} left out: no parent keyframe at the step)")
    print("length (m)  arcs  heading rms / p95 / max (rad)  position rms / p95 (m)  floor (rad)")
    for r in result:
        span = f"{r['from_m']:>3}-{r['to_m'] if r['to_m'] is not None else '':<5}"
        if not r["arcs"]:
            print(f"{span}  {0:>6}")
            continue
        floor = f"{r['heading_floor_rad']:.3f}" if "heading_floor_rad" in r else "-"
        print(f"{span}  {r['arcs']:>6}  {r['heading_rms_rad']:.4f} / {r['heading_p95_rad']:.4f} / "
              f"{r['heading_max_rad']:.4f}   {r['position_rms_m']:.3f} / "
              f"{r['position_p95_m']:.3f}           {floor}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
