#!/usr/bin/python3
"""Makes a CARMEN log's odometry worse, as another robot's would be: each
step's motion (in the robot frame of the step's start) has its translation
scaled by --trans and its rotation by --rot, then Gaussian noise of --sxy m
(per axis) and --sth rad added; the poses are integrated again from the first
one. Scans, timestamps and every other line are kept. Both pose fields of a
FLASER line (x y theta and odom_x odom_y odom_theta) get the new odometry.

A robustness benchmark for logs one does not have: the same scans with a
robot whose wheels slip, whose gyro is off by a few percent, or whose
encoders are noisy. The reference trajectory of the original log still
scores the result (the scans are the same, one for one).

Usage: perturb_odometry.py IN.log[.gz] OUT.log[.gz] [--trans F] [--rot F]
                           [--sxy M] [--sth RAD] [--seed N]
"""
import argparse
import math
import random
import sys

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from log_files import open_text, replaced_at_end  # noqa: E402


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


def write_perturbed(inp, out, a):
    """Copies inp to out with the odometry of the options `a`; the scans written."""
    rnd = random.Random(a.seed)
    prev = cur = None
    scans = 0
    with open_text(inp, "r") as f, open_text(out, "w") as g:
        for n, line in enumerate(f, 1):
            s = line.split()
            if not s or s[0] != "FLASER":
                g.write(line)
                continue
            try:
                k = 2 + int(s[1])
                ox, oy, oth = float(s[k + 3]), float(s[k + 4]), float(s[k + 5])
            except (ValueError, IndexError):
                raise SystemExit(f"{inp}:{n}: not a FLASER line with odometry")
            if prev is None:
                cur = (ox, oy, oth)
            else:
                px, py, pth = prev
                c, sn = math.cos(pth), math.sin(pth)
                lx, ly = c * (ox - px) + sn * (oy - py), -sn * (ox - px) + c * (oy - py)
                dth = wrap(oth - pth)
                lx = lx * a.trans + rnd.gauss(0.0, a.sxy)
                ly = ly * a.trans + rnd.gauss(0.0, a.sxy)
                dth = dth * a.rot + rnd.gauss(0.0, a.sth)
                cx, cy, cth = cur
                c, sn = math.cos(cth), math.sin(cth)
                cur = (cx + c * lx - sn * ly, cy + sn * lx + c * ly, wrap(cth + dth))
            prev = (ox, oy, oth)
            for off in (0, 3):
                s[k + off], s[k + off + 1], s[k + off + 2] = (f"{v:.6f}" for v in cur)
            g.write(" ".join(s) + "\n")
            scans += 1
    return scans


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("inp")
    ap.add_argument("out")
    ap.add_argument("--trans", type=float, default=1.0, help="translation scale [1]")
    ap.add_argument("--rot", type=float, default=1.0, help="rotation scale [1]")
    ap.add_argument("--sxy", type=float, default=0.0, help="translation noise per step, m [0]")
    ap.add_argument("--sth", type=float, default=0.0, help="rotation noise per step, rad [0]")
    ap.add_argument("--seed", type=int, default=1, help="noise seed [1]")
    a = ap.parse_args()
    if a.sxy < 0 or a.sth < 0:
        ap.error("noise must be >= 0")
    try:
        with replaced_at_end(a.out) as tmp:
            scans = write_perturbed(a.inp, tmp, a)
    except (OSError, EOFError, UnicodeDecodeError) as e:  # missing, unreadable, damaged
        raise SystemExit(f"{a.inp}: {e}")
    print(f"{a.out}: {scans} scans")


if __name__ == "__main__":
    main()
