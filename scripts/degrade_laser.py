#!/usr/bin/python3
"""Makes a CARMEN log's laser worse, as a smaller robot's would be: shorter
(a Hokuyo URG reaches 4-5.6 m, many planar lidars 8-12 m) or narrower (a
laser behind a bumper, a depth camera's slice). With --range M every
reading beyond M metres becomes a no-return; with --fov DEG every beam more
than DEG/2 degrees from the scan's middle bearing does. No-returns are
written as M + 1 m with --range (above every kept reading by more than the
0.3 m band in which a CARMEN reader takes the log's largest value for its
no-return code), else as the log's largest reading (its own no-return
code). FLASER and ROBOTLASER1 lines are both changed (ROBOTLASER1's
max_range field becomes the code); the poses, timestamps and every other
line are kept.

A robustness benchmark for logs one does not have: the same path seen by a
worse laser. The reference trajectory of the original log still scores the
result (the scans are the same, one for one).

Usage: degrade_laser.py IN.log[.gz] OUT.log[.gz] [--range M] [--fov DEG]
"""
import argparse
import math
import sys

# A laser line's readings, and the beams' bearings as hmt-slam's CARMEN
# reader takes them.
sys.path.insert(0, __file__.rsplit("/", 1)[0])
from log_files import open_text, replaced_at_end  # noqa: E402
from map_sharpness import laser_readings  # noqa: E402


def laser_fields(s):
    """(field of the first reading, readings, bearings in rad) of a FLASER or
    ROBOTLASER1 line; ValueError or IndexError if it does not parse or is
    short of its beams."""
    first, n, readings, bearings = laser_readings(s)
    if n < 0 or len(readings) != n:
        raise IndexError
    return first, readings, bearings


def laser_lines(path):
    """(line number, fields or None, line) for every line; fields only for a
    FLASER or ROBOTLASER1 line."""
    with open_text(path, "r") as f:
        for n, line in enumerate(f, 1):
            s = line.split()
            yield n, (s if s and s[0] in ("FLASER", "ROBOTLASER1") else None), line


def fail_line(path, n, kind):
    raise SystemExit(f"{path}:{n}: a {kind} line whose beam count or readings do not "
                     "parse, or too short for its beams")


def largest_reading(path):
    top = None
    for n, s, _ in laser_lines(path):
        if s is None:
            continue
        try:
            _, readings, _ = laser_fields(s)
        except (ValueError, IndexError):
            fail_line(path, n, s[0])
        for r in readings:
            if math.isfinite(r) and (top is None or r > top):
                top = r
    if top is None:
        raise SystemExit(f"{path}: no FLASER or ROBOTLASER1 reading to take the no-return code from")
    return top


def write_degraded(inp, out, reach, fov, code):
    """Copies inp to out, degraded; (scans, readings changed, readings)."""
    half = math.radians(fov) / 2 if fov is not None else None
    scans = changed = readings = 0
    with open_text(out, "w") as g:
        for n, s, line in laser_lines(inp):
            if s is None:
                g.write(line)
                continue
            try:
                first, values, bearings = laser_fields(s)
            except (ValueError, IndexError):
                fail_line(inp, n, s[0])
            if s[0] == "ROBOTLASER1":
                s[5] = code
            count = len(values)
            middle = (bearings[0] + bearings[-1]) / 2 if count else 0.0
            for i, r in enumerate(values):
                if not math.isfinite(r):  # nan and inf stay as written: no reading either way
                    continue
                beyond = reach is not None and r > reach
                aside = half is not None and abs(bearings[i] - middle) > half + 1e-9
                if beyond or aside:
                    if s[first + i] != code:
                        changed += 1
                    s[first + i] = code
            readings += count
            scans += 1
            g.write(" ".join(s) + "\n")
    return scans, changed, readings


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("inp")
    ap.add_argument("out")
    ap.add_argument("--range", dest="reach", type=float, help="the laser's reach (m)")
    ap.add_argument("--fov", type=float, help="the laser's field of view (degrees)")
    a = ap.parse_args()
    if a.reach is None and a.fov is None:
        ap.error("give --range, --fov or both")
    if a.reach is not None and not (a.reach > 0 and math.isfinite(a.reach)):
        ap.error("--range must be a positive number of metres")
    if a.fov is not None and not (0 < a.fov <= 360):
        ap.error("--fov must be in (0, 360] degrees")
    try:
        code = f"{a.reach + 1.0:g}" if a.reach is not None else f"{largest_reading(a.inp):g}"
        with replaced_at_end(a.out) as tmp:
            scans, changed, readings = write_degraded(a.inp, tmp, a.reach, a.fov, code)
    except (OSError, EOFError) as e:  # a missing, unreadable or damaged (gzip) log
        raise SystemExit(f"{a.inp}: {e}")
    share = 100.0 * changed / readings if readings else 0.0
    print(f"{a.out}: {scans} scans, {changed} of {readings} readings ({share:.1f} %) "
          f"made no-returns ({code} m)")


if __name__ == "__main__":
    main()
