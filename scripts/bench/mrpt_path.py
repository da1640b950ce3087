#!/usr/bin/env python3
"""Per-scan trajectory of an MRPT rbpf-slam run, as TUM lines.

Usage: mrpt_path.py OUT_DIR [--mean] [--localize LIN_M ANG_DEG] > trajectory.tum

OUT_DIR is rbpf-slam's logOutput_dir. rbpf-slam always writes, whatever the
logging options (these files cost a few hundred bytes per scan):
  log_estimated_path.txt  step x y z yaw pitch roll timestamp  (one per scan:
                          the weighted mean of the particles at that time,
                          i.e. the on-line filter estimate)
  log_odometry_path.txt   step x y z yaw pitch roll            (one per scan)
  log_times.txt           step ms map_size inserted?           (one per scan)
  most_likely_path.txt    x y yaw (%.3f) of the final most likely particle:
                          its initial pose, then one entry per particle-filter
                          update (no timestamps)

The filter only runs when the robot has moved localizeLinDistance /
localizeAngDistance since its last update; in between, the pose is the last
filtered pose composed with the odometry since then (as MRPT's own
getCurrentPoseEstimation() does). Which scans were filter updates is not
logged: with --localize (the ini's localizeLinDistance and
localizeAngDistance_deg) they are found by MRPT's own rule on the odometry
(the first scan, then each scan whose odometry since the last update moved
more than LIN_M or turned more than ANG_DEG); without it, localize* must
equal insertion*, and they are the steps with inserted? = 1. Either way
their count must match most_likely_path.txt, or nothing is printed.

Default output: the final most likely particle's path (the smoothed estimate
a particle filter delivers at the end, like GMapping's best particle),
expanded to every scan by odometry between filter updates.
--mean: the on-line mean estimate of log_estimated_path.txt instead.
"""
import math
import os
import sys


def rows(path):
    out = []
    with open(path) as f:
        for line in f:
            s = line.split()
            if not s or s[0].startswith("%") or s[0].startswith("#"):
                continue
            out.append([float(x) for x in s])
    return out


def compose(a, b):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1],
            math.atan2(math.sin(a[2] + b[2]), math.cos(a[2] + b[2])))


def relative(a, b):
    """a^-1 (+) b."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    c, s = math.cos(a[2]), math.sin(a[2])
    return (c * dx + s * dy, -s * dx + c * dy,
            math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2])))


def tum(t, p):
    return "%.6f %.6f %.6f 0 0 0 %.9f %.9f" % (
        t, p[0], p[1], math.sin(p[2] / 2), math.cos(p[2] / 2))


def filter_updates(odo, lin, ang_deg):
    """MRPT's localize rule (CMetricMapBuilderRBPF) replayed on the odometry."""
    ang = math.radians(ang_deg)
    out = [0]
    for i in range(1, len(odo)):
        d = relative(odo[out[-1]], odo[i])
        if math.hypot(d[0], d[1]) > lin or abs(d[2]) > ang:
            out.append(i)
    return out


def main():
    argv = sys.argv[1:]
    localize = None
    if "--localize" in argv:
        k = argv.index("--localize")
        try:
            localize = (float(argv[k + 1]), float(argv[k + 2]))
        except (IndexError, ValueError):
            raise SystemExit("--localize needs LIN_M ANG_DEG")
        del argv[k:k + 3]
    args = [a for a in argv if not a.startswith("--")]
    if len(args) != 1:
        raise SystemExit(__doc__)
    d = args[0]
    est = rows(os.path.join(d, "log_estimated_path.txt"))
    if not est:
        raise SystemExit(f"{d}: log_estimated_path.txt is empty")
    # step x y z yaw pitch roll timestamp
    times = [r[7] for r in est]
    if "--mean" in argv:
        for r in est:
            print(tum(r[7], (r[1], r[2], r[4])))
        return
    odo = [(r[1], r[2], r[4]) for r in rows(os.path.join(d, "log_odometry_path.txt"))]
    inserted = [int(r[3]) for r in rows(os.path.join(d, "log_times.txt"))]
    ml = [tuple(r[:3]) for r in rows(os.path.join(d, "most_likely_path.txt"))]
    n = len(est)
    if len(odo) != n or len(inserted) != n:
        raise SystemExit(f"{d}: {n} estimated poses but {len(odo)} odometry "
                         f"poses and {len(inserted)} timing lines")
    if localize:
        updates = filter_updates(odo, *localize)
        hint = "the odometry replay of --localize disagrees with the run"
    else:
        updates = [i for i in range(n) if inserted[i]]
        hint = ("are localizeLinDistance/AngDistance equal to insertionLin/AngDistance? "
                "If not, pass --localize")
    if not updates or updates[0] != 0 or len(ml) != len(updates) + 1:
        raise SystemExit(
            f"{d}: most_likely_path.txt has {len(ml)} poses for "
            f"{len(updates)} filter updates (expected one more: {hint})")
    j = 0  # index of the last filter update at or before scan i
    for i in range(n):
        if j + 1 < len(updates) and updates[j + 1] <= i:
            j += 1
        s = updates[j]
        pose = compose(ml[j + 1], relative(odo[s], odo[i]))
        print(tum(times[i], pose))


if __name__ == "__main__":
    main()
