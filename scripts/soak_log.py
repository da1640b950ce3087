#!/usr/bin/python3
"""Builds a long CARMEN log by driving one log's loop several times.

Usage: soak_log.py LOG REFERENCE LAPS OUT

LOG is a CARMEN log (FLASER lines, gzip when it ends in .gz) whose robot
comes back near its start; REFERENCE its reference trajectory ("t x y
theta" per FLASER line). OUT (gzip when it ends in .gz) holds the PARAM
lines once and then the FLASER lines LAPS times. Each lap's odometry is
moved rigidly so that it continues where the previous lap ended: its first
pose is the previous lap's last pose composed with the motion that the
reference says separates the log's last scan from its first. So the seam
looks to the filter like any other step of the robot (as if it had driven
on), and every lap after the first passes through the first lap's places
again. Timestamps are shifted by whole laps, so they keep their order
within a lap and never repeat across laps. Deterministic: no randomness.
"""
import gzip
import math
import sys


def opener(path, mode):
    return gzip.open(path, mode) if path.endswith(".gz") else open(path, mode)


def compose(a, b):
    """a (+) b for 2D poses (x, y, theta)."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


def inverse(a):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (-c * a[0] - s * a[1], s * a[0] - c * a[1], -a[2])


def fail(message):
    sys.exit(f"soak_log.py: {message}")


def read_log(path):
    params, scans = [], []
    try:
        with opener(path, "rt") as f:
            for n, line in enumerate(f, 1):
                fields = line.split()
                if not fields:
                    continue
                if fields[0] == "PARAM":
                    params.append(line.rstrip("\n"))
                elif fields[0] == "FLASER":
                    try:
                        beams = int(fields[1])
                        if len(fields) < beams + 11:
                            raise ValueError
                        odom = tuple(float(v) for v in fields[beams + 5:beams + 8])
                        times = (float(fields[beams + 8]), float(fields[beams + 10]))
                    except (ValueError, IndexError):
                        fail(f"{path}:{n}: malformed FLASER line")
                    scans.append((fields, beams, odom, times))
    except OSError as e:
        fail(f"cannot read {path}: {e.strerror}")
    if len(scans) < 2:
        fail(f"{path}: fewer than two FLASER lines")
    return params, scans


def read_reference(path, expected):
    poses = []
    try:
        with opener(path, "rt") as f:
            for line in f:
                fields = line.split()
                if not fields or fields[0].startswith("#"):
                    continue
                poses.append(tuple(float(v) for v in fields[1:4]))
    except (OSError, ValueError) as e:
        fail(f"cannot read {path}: {e}")
    if len(poses) != expected:
        fail(f"{path}: {len(poses)} poses for {expected} FLASER lines")
    return poses


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__.strip().splitlines()[2])
    log, reference, laps, out = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
    if laps < 1:
        fail("LAPS must be at least 1")
    params, scans = read_log(log)
    ref = read_reference(reference, len(scans))
    # The motion from the last scan's true pose to the first scan's.
    seam = compose(inverse(ref[-1]), ref[0])
    first_odom, last_odom = scans[0][2], scans[-1][2]
    times = [t for s in scans for t in s[3]]
    period = max(times) - min(times) + 1.0
    shift = (0.0, 0.0, 0.0)  # odometry frame of the current lap in the log's
    with opener(out, "wt") as f:
        for line in params:
            f.write(line + "\n")
        lap_end = None
        for lap in range(laps):
            if lap_end is not None:
                start = compose(lap_end, seam)
                shift = compose(start, inverse(first_odom))
            for fields, beams, odom, (t, logger_t) in scans:
                o = compose(shift, odom)
                o = (o[0], o[1], math.atan2(math.sin(o[2]), math.cos(o[2])))
                pose = " ".join(f"{v:.6f}" for v in o)
                out_fields = fields[:beams + 2] + [pose, pose,
                                                   f"{t + lap * period:.6f}", fields[beams + 9],
                                                   f"{logger_t + lap * period:.6f}"]
                f.write(" ".join(out_fields) + "\n")
            lap_end = compose(shift, last_odom)
    print(f"{out}: {laps} laps of {len(scans)} scans")


if __name__ == "__main__":
    main()
