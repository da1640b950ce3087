#!/usr/bin/python3
"""How square a trajectory's straight legs are to one another: a check of
heading error that needs no alignment and no ground truth, for buildings
whose corridors meet at right angles.

The legs are the straight runs of the reference's path (of the trajectory's
own when no reference is given): maximal runs of poses that all lie within
--tolerance metres of the chord between the run's two ends, at least
--min-length metres long. Each leg's direction in a trajectory is taken from
that trajectory's poses at the leg's two ends, and compared, modulo 90
degrees, with the trajectory's own grid axis (the length-weighted circular
mean of four times the legs' directions, divided by four). In a building
laid out on a grid the legs of a trajectory without heading error all lie on
its axis, so where a leg deviates, and by how much, shows where a map is
turned (a block of corridors drawn a few degrees off the rest), and which of
two trajectories keeps its corridors square. Legs within 10 degrees of a
diagonal of the grid are left out of the RMS (a corridor off the grid).

With a reference, the turns too: runs of steps where the reference turns
faster than 0.04 rad a step, widened by 3 steps each side, that turn by at
least 0.8 rad in all. For each, the trajectory's heading change across it
minus the reference's; their RMS is the heading error a turn adds (a
trajectory of the log's own odometry gives the wheels' figure to compare).

Usage: leg_headings.py TRAJECTORY [REFERENCE] [--min-length M] [--tolerance T] [--json]
Poses are matched by index (one line per scan in both files; TUM or
"t x y theta", gzip when the name ends in .gz). Exit 2 on bad arguments,
4 on a malformed or empty file or when the two differ in length.
"""
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ate import load_by_index  # noqa: E402

OFF_GRID_DEG = 35.0  # |deviation| above this: a corridor off the grid, not an error


def straight_legs(xy, min_length, tolerance):
    """(first, last) index pairs of the path's maximal straight runs."""
    legs = []
    i, n = 0, len(xy)
    while i < n - 1:
        last = None
        for j in range(i + 1, n):
            chord = xy[j] - xy[i]
            length = math.hypot(chord[0], chord[1])
            if length < 1e-9:
                continue
            normal = np.array([-chord[1], chord[0]]) / length
            if np.abs((xy[i:j + 1] - xy[i]) @ normal).max() > tolerance:
                break
            last = j
        if last is not None and math.hypot(*(xy[last] - xy[i])) >= min_length:
            legs.append((i, last))
            i = last
        else:
            i += 1
    return legs


def deviations(xy, legs):
    """Each leg's direction minus the grid axis, in degrees in [-45, 45)."""
    d = np.array([xy[j] - xy[i] for i, j in legs])
    angle = np.arctan2(d[:, 1], d[:, 0])
    length = np.hypot(d[:, 0], d[:, 1])
    axis = math.atan2(np.sum(length * np.sin(4 * angle)),
                      np.sum(length * np.cos(4 * angle))) / 4
    dev = np.degrees(angle - axis)
    return (dev + 45.0) % 90.0 - 45.0, math.degrees(axis), length


def rms(dev, length):
    """Length-weighted RMS over the legs on the grid (None if there are none)."""
    on = np.abs(dev) <= OFF_GRID_DEG
    if not on.any():
        return None
    return float(math.sqrt(np.sum(length[on] * dev[on] ** 2) / np.sum(length[on])))


TURN_RATE = 0.04   # rad a step: the reference is turning
TURN_MARGIN = 3    # steps added either side of a turn
TURN_MIN = 0.8     # rad: a turn, not a wiggle


def turns(theta):
    """(first, last) index pairs of the turns of an unwrapped heading."""
    fast = np.abs(np.diff(theta)) > TURN_RATE
    out, i, n = [], 0, len(theta)
    while i < n - 1:
        if not fast[i]:
            i += 1
            continue
        j = i
        while j < n - 1 and fast[j]:
            j += 1
        a, b = max(0, i - TURN_MARGIN), min(n - 1, j + TURN_MARGIN)
        if abs(theta[b] - theta[a]) >= TURN_MIN:
            out.append((a, b))
        i = j
    return out


def option(args, name, default):
    if name not in args:
        return default
    i = args.index(name)
    try:
        value = float(args[i + 1])
    except (IndexError, ValueError):
        raise SystemExit(f"leg_headings.py: {name} needs a number")
    if not value > 0:
        raise SystemExit(f"leg_headings.py: {name} must be > 0")
    del args[i:i + 2]
    return value


def main(argv):
    args = [a for a in argv[1:] if a != "--json"]
    try:
        min_length = option(args, "--min-length", 25.0)
        tolerance = option(args, "--tolerance", 0.3)
    except SystemExit as e:
        print(e, file=sys.stderr)
        return 2
    if len(args) not in (1, 2) or any(a.startswith("--") for a in args):
        print(__doc__, file=sys.stderr)
        return 2
    try:
        poses = load_by_index(args, "leg_headings.py")
    except SystemExit as e:
        print(e, file=sys.stderr)
        return 4
    legs = straight_legs(poses[-1][:, 1:3], min_length, tolerance)
    out = {"min_length_m": min_length, "tolerance_m": tolerance, "legs": [],
           "axis_deg": [], "rms_deg": []}
    per = []
    length = np.zeros(0)  # the legs' lengths in the last file (the reference)
    for p in poses:
        dev, axis = np.zeros(0), None
        if legs:
            dev, axis, length = deviations(p[:, 1:3], legs)
        per.append(dev)
        out["axis_deg"].append(axis)
        out["rms_deg"].append(rms(dev, length))
    if len(poses) == 2:
        ref_theta = np.unwrap(poses[1][:, 3])
        est_theta = np.unwrap(poses[0][:, 3])
        found = turns(ref_theta)
        err = np.array([(est_theta[b] - est_theta[a]) - (ref_theta[b] - ref_theta[a])
                        for a, b in found])
        out["turns"] = len(found)
        out["turn_error_rms_deg"] = (float(np.degrees(np.sqrt(np.mean(err ** 2))))
                                     if len(found) else None)
    for k, (i, j) in enumerate(legs):
        out["legs"].append({"first": i, "last": j, "length_m": float(length[k]),
                            "deviation_deg": [float(d[k]) for d in per]})
    if "--json" in argv:
        print(json.dumps(out, indent=1))
        return 0
    names = ["trajectory", "reference"][:len(poses)]
    print(f"{len(legs)} straight legs of at least {min_length:g} m (within {tolerance:g} m of "
          f"a line) in the {names[-1]}")
    if "turns" in out:
        t = out["turn_error_rms_deg"]
        print(f"{out['turns']} turns of the reference; heading error a turn adds: "
              + ("-" if t is None else f"{t:.2f} deg RMS"))
    if not legs:
        return 0
    print("poses          length   deviation from the grid (deg): " + "  ".join(names))
    for leg in out["legs"]:
        devs = "  ".join(f"{d:+10.2f}" for d in leg["deviation_deg"])
        print(f"{leg['first']:>5}-{leg['last']:<5}  {leg['length_m']:7.1f} m  {devs}")
    for name, axis, r in zip(names, out["axis_deg"], out["rms_deg"]):
        r = "-" if r is None else f"{r:.2f} deg"
        print(f"{name}: grid axis {axis:.2f} deg, RMS deviation of the legs {r}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
