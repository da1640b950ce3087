#!/usr/bin/python3
"""Which of a run's topological decisions a reference trajectory agrees with.

A map breaks at a wrong loop closure: the robot is placed in a known area
it is not in, or at the wrong place of the right one. Position RMSE and
loops_closed.py say that the map is bent; this says at which new-area event
it was bent. It follows the decisions the final map rests on (the outcome
taken at each event on the line of ancestors of the most probable
hypothesis at the end: summary.json's best_hypothesis, then back through
tsbi_events.csv's `child` column) and judges each one
against the reference, using where the areas' keyframes were taken
(topology.json's keyframe_poses: each keyframe's time and pose in its
area's frame; keyframe_steps: its log step, by which the reference is
read when it holds one pose per scan).

A closure into known area A (its best mode: the robot in A's frame) is
  right        the mode lies within --tolerance of where the reference puts
               the robot in A's frame, through the keyframe of A nearest to
               the robot (its pose in A composed with the reference's motion
               from it to the event);
  wrong_place  the mode is farther off, and a keyframe of A lies within
               --near metres of the robot: the wrong place of the right area;
  elsewhere    the mode is farther off, and no keyframe of A lies within
               --near of the robot: the robot was not in A at all (a
               look-alike area);
  unknown      A had no keyframe before the event, or the reference has no
               pose at a time needed. Times are needed only where steps are
               not known (an output of an older hmt-slam, a reference with
               other poses than the log's scans) and then fail on logs whose
               timestamps repeat: csail's are rounded to 10 s, the infinite
               corridor's broken.
A new area is
  new          no older area had a keyframe within --revisit of the robot;
  revisit      one did (the nearest is named): that place is now in two
               areas' maps. The area the robot leaves does not count: the
               event's own arc joins the new area to it. Harmless where a
               later closure joins the two (a new area begun at a doorway of
               a room mapped before); in a broken map, a loop left open
               there.
Only the keyframes taken before the robot entered the area it left at the
event count: later ones may sit where a wrong closure put them. By step, a
keyframe of the entering step itself counts too (it was taken, in the area
then left, before that event was decided); by time it does not (another
scan may share the time).

Usage: closure_check.py OUT_DIR REFERENCE [--near M] [--tolerance M]
                        [--revisit M] [--json]
  OUT_DIR: an hmt-slam run's output folder; REFERENCE: TUM or
  "t x y theta" per line (gzip if .gz), the log's timestamps.
  --near: how far from an area's keyframes the robot may be and still be
     in that area [8 m]
  --tolerance: the largest error of a right closure's mode [1.5 m]
  --revisit: how near an older keyframe makes a new area a revisit [1 m]
Prints every decision with its verdict, the counts, and the first closure
that was not right (where the map broke). Exit 4 on a missing or malformed
file, 2 on bad arguments.
"""
import argparse
import csv
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from ate import load_poses  # noqa: E402
from relation_error import relative, wrap  # noqa: E402

SCRIPT = "closure_check.py"


def fail(msg):
    print(f"{SCRIPT}: {msg}", file=sys.stderr)
    sys.exit(4)


def read_rows(path, columns):
    """A CSV's rows as dicts, checking that `columns` are in its header."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f)
            missing = [c for c in columns if c not in (reader.fieldnames or [])]
            if missing:
                fail(f"{path}: no column {', '.join(missing)} (an output of an older "
                     f"hmt-slam, or not one at all)")
            return list(reader)
    except OSError as e:
        fail(f"{path}: cannot read: {e.strerror}")


def number(text, path, what):
    try:
        v = float(text)
    except (TypeError, ValueError):
        fail(f"{path}: {what} is '{text}', not a number")
    if not math.isfinite(v):
        fail(f"{path}: {what} is not finite")
    return v


def final_line(events, best):
    """The decisions the final map rests on, oldest first: the event row
    that created hypothesis `best` (summary.json's best_hypothesis, whose
    map the outputs draw), then the one that created its parent, and so
    on."""
    created = {r["child"].strip(): r for r in events if r["child"].strip()}
    line, seen, h = [], set(), str(best)
    while h in created and h not in seen:
        seen.add(h)
        line.append(created[h])
        h = created[h]["hypothesis"].strip()
    return line[::-1]


def read_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except OSError as e:
        fail(f"{path}: cannot read: {e.strerror}")
    except json.JSONDecodeError as e:
        fail(f"{path}: not JSON: {e}")


def best_hypothesis(path):
    summary = read_json(path)
    best = summary.get("best_hypothesis") if isinstance(summary, dict) else None
    if not isinstance(best, int) or isinstance(best, bool) or best < 0:
        fail(f"{path}: no best_hypothesis (an output of an older hmt-slam, or a run that "
             f"ended without one)")
    return best


def compose(a, b):
    """Pose a (x, y, theta) composed with pose b."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


class Reference:
    """The reference's poses looked up by time. Timestamps may repeat or
    lie milliseconds apart (Intel), or be rounded (csail's to 10 s): a time
    is looked up as the nearest pose within TIME_TOL, and is unknown (None)
    only when the poses within 2 TIME_TOL of it lie more than SPREAD_M
    apart, so that the time cannot say where the robot was."""
    TIME_TOL = 0.01
    SPREAD_M = 0.3

    def __init__(self, poses):
        order = np.argsort(poses[:, 0], kind="stable")
        self.t = poses[order, 0]
        self.p = poses[order, 1:4]
        self.by_index = poses[:, 1:4]

    def at(self, times):
        out = []
        for q in times:
            lo = np.searchsorted(self.t, q - 2 * self.TIME_TOL, side="left")
            hi = np.searchsorted(self.t, q + 2 * self.TIME_TOL, side="right")
            if lo == hi:
                out.append(None)
                continue
            i = lo + int(np.argmin(np.abs(self.t[lo:hi] - q)))
            xy = self.p[lo:hi, :2]
            if abs(self.t[i] - q) > self.TIME_TOL or np.ptp(xy, axis=0).max() > self.SPREAD_M:
                out.append(None)
            else:
                out.append(tuple(self.p[i]))
        return out

    def at_step(self, step, time, scans):
        """The pose at a log step: by index when the step is known (not None)
        and the reference holds one pose per scan of the run (as many as
        `scans`), else by time."""
        if step is not None and scans == len(self.by_index) and 0 <= step < scans:
            return tuple(self.by_index[step])
        return self.at([time])[0]


def placed_keyframes(areas, ref, scans):
    """{area: [(time, step, pose in the area's frame, reference pose)]} for
    the keyframes the reference can place: by step where known, else by
    time."""
    out = {}
    for aid, kfs in areas.items():
        placed = []
        for time, x, y, theta, step in kfs:
            p = ref.at_step(step, time, scans)
            if p is not None:
                placed.append((time, step, (x, y, theta), p))
        out[aid] = placed
    return out


def nearest_before(placed, t, step, now):
    """(distance, pose in the area, reference pose) of the keyframe nearest
    to `now` among those taken up to step `step` (before time t, for a
    keyframe whose step is not known), or None."""
    best = None
    for time, kf_step, pose, p in placed:
        if (kf_step <= step) if kf_step is not None else (time < t):
            dist = math.hypot(p[0] - now[0], p[1] - now[1])
            if best is None or dist < best[0]:
                best = (dist, pose, p)
    return best


def judge(line, placed, ref, scans, near, tolerance, revisit):
    out = []
    # When (time, step) the robot entered the area it leaves at a decision.
    entered = (-math.inf, -math.inf)
    for r in line:
        t = float(r["time"])
        d = {"step": int(r["step"]), "time": t, "from_area": int(r["from_area"]),
             "outcome": r["outcome"], "area": int(r["area"]) if r["area"].strip() else None,
             "probability": float(r["probability"])}
        out.append(d)
        before, entered = entered, (t, d["step"])
        now = ref.at_step(d["step"], t, scans)
        if now is None:
            d["verdict"] = "unknown"
            continue
        if r["outcome"] == "new":
            found = [(n[0], aid) for aid, n in ((aid, nearest_before(kfs, *before, now))
                                                for aid, kfs in sorted(placed.items())
                                                if aid != d["from_area"]) if n]
            nearest = min(found) if found else (None, None)
            d["nearest_keyframe_m"], d["nearest_area"] = nearest
            d["verdict"] = "revisit" if found and nearest[0] <= revisit else "new"
            continue
        found = nearest_before(placed.get(d["area"], []), *before, now)
        if found is None:
            d["verdict"] = "unknown"
            continue
        dist, pose, p = found
        d["nearest_keyframe_m"] = dist
        truth = compose(pose, relative(p, now))
        mode = (float(r["x"]), float(r["y"]), float(r["theta"]))
        d["mode_error_m"] = math.hypot(mode[0] - truth[0], mode[1] - truth[1])
        d["mode_error_deg"] = abs(math.degrees(wrap(mode[2] - truth[2])))
        if d["mode_error_m"] <= tolerance:
            d["verdict"] = "right"
        else:
            d["verdict"] = "elsewhere" if dist > near else "wrong_place"
    return out


def count_scans(path):
    """The run's scans: trajectory.tum holds one line per scan."""
    try:
        with open(path, encoding="utf-8") as f:
            return sum(1 for ln in f if ln.strip() and not ln.startswith("#"))
    except OSError as e:
        fail(f"{path}: cannot read: {e.strerror}")


def load_areas(path):
    topo = read_json(path)
    areas = {}
    for a in (topo.get("areas", []) if isinstance(topo, dict) else []):
        if "keyframe_poses" not in a:
            fail(f"{path}: area {a.get('id')} has no keyframe_poses (an output of an older "
                 f"hmt-slam)")
        poses = a["keyframe_poses"]
        # Steps: none from an older hmt-slam; null where a resumed map's
        # older file did not hold them.
        steps = a.get("keyframe_steps", [None] * len(poses))
        if not isinstance(steps, list) or len(steps) != len(poses):
            fail(f"{path}: area {a.get('id')}: keyframe_steps does not hold one step per "
                 f"keyframe pose")
        kfs = []
        for k, step in zip(poses, steps):
            if len(k) != 4 or not all(isinstance(v, (int, float)) and math.isfinite(v) for v in k):
                fail(f"{path}: area {a.get('id')}: a keyframe pose is not [time, x, y, theta]")
            if step is not None and (not isinstance(step, int) or isinstance(step, bool)
                                     or step < 0):
                fail(f"{path}: area {a.get('id')}: a keyframe step is '{step}', not a count")
            kfs.append(tuple(float(v) for v in k) + (step,))
        areas[int(a["id"])] = kfs
    return areas


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("reference")
    ap.add_argument("--near", type=float, default=8.0)
    ap.add_argument("--tolerance", type=float, default=1.5)
    ap.add_argument("--revisit", type=float, default=1.0)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    for name in ("near", "tolerance", "revisit"):
        v = getattr(a, name)
        if not (math.isfinite(v) and v > 0):
            ap.error(f"--{name} must be a positive number, not {v}")
    events_path = os.path.join(a.out_dir, "tsbi_events.csv")
    events = read_rows(events_path, ["step", "time", "hypothesis", "from_area", "outcome",
                                     "area", "probability", "child", "x", "y", "theta"])
    for i, r in enumerate(events, start=2):
        for c in ("step", "time", "from_area", "probability"):
            number(r[c], events_path, f"line {i}: {c}")
        for c in ("step", "from_area", "hypothesis") + (("area",) if r["area"].strip() else ()):
            if not r[c].strip().isdigit():
                fail(f"{events_path}: line {i}: {c} is '{r[c]}', not a count")
        if r["outcome"] not in ("new", "known"):
            fail(f"{events_path}: line {i}: outcome is '{r['outcome']}', not new or known")
        if r["outcome"] == "known" and r["child"].strip():
            for c in ("x", "y", "theta"):
                number(r[c], events_path, f"line {i}: {c}")
    areas = load_areas(os.path.join(a.out_dir, "topology.json"))
    try:
        ref = Reference(load_poses(a.reference))
    except SystemExit as e:  # ate.py's clear message for a bad file
        fail(str(e))
    line = final_line(events, best_hypothesis(os.path.join(a.out_dir, "summary.json")))
    scans = count_scans(os.path.join(a.out_dir, "trajectory.tum"))
    decisions = judge(line, placed_keyframes(areas, ref, scans), ref, scans, a.near,
                      a.tolerance, a.revisit)
    counts = {}
    for d in decisions:
        counts[d["verdict"]] = counts.get(d["verdict"], 0) + 1
    first_bad = next((d for d in decisions
                      if d["outcome"] == "known" and d["verdict"] in ("elsewhere", "wrong_place")),
                     None)
    if a.json:
        print(json.dumps({"decisions": decisions, "counts": counts,
                          "first_wrong_closure": first_bad}))
        return 0
    if not decisions:
        print("no new-area event on the final hypothesis's line: nothing to judge")
        return 0
    for d in decisions:
        to = d["area"] if d["area"] is not None else "-"
        extra = ""
        if d.get("nearest_keyframe_m") is not None:
            extra += f"  nearest keyframe {d['nearest_keyframe_m']:.2f} m"
            if d.get("nearest_area") is not None:
                extra += f" (area {d['nearest_area']})"
        if "mode_error_m" in d:
            extra += f"  mode off {d['mode_error_m']:.2f} m {d['mode_error_deg']:.1f} deg"
        print(f"step {d['step']:6d}  t {d['time']:.3f}  {d['from_area']} -> {to} "
              f"({d['outcome']}, p {d['probability']:.3g})  {d['verdict']}{extra}")
    print("decisions: " + ", ".join(f"{v} {n}" for v, n in sorted(counts.items())))
    if first_bad:
        print(f"first closure not right: step {first_bad['step']} "
              f"({first_bad['from_area']} -> {first_bad['area']}, {first_bad['verdict']})")
    else:
        print("every closure judged is right")
    return 0


if __name__ == "__main__":
    sys.exit(main())
