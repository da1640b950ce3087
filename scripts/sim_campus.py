#!/usr/bin/python3
"""Writes a simulated outdoor log, for what the shared logs (all indoors) do
not test: a campus of 5 x 4 blocks (80 x 60 m, streets 16 m wide) with one
to three buildings per block set back from the street, lawns between them,
and trees along the kerbs; a robot drives a 1.6 km tour along the streets
with two loops (it comes back along its first street at the end), one scan
per metre or so, a 180 degree laser of 181 beams (--fov 360: a full turn of
360) reaching 80 m (no return written as 81.91, as CARMEN logs do), range
noise 2 cm.

Odometry: each step's motion with its translation scaled by 1 + s + noise
(s = 1 % fair, 2 % harsh), lateral noise, heading noise, and a heading drift
of 0.001 (fair) or 0.004 (harsh) rad per metre.

--beams-per-degree N: N beams a degree instead of one (4: a 0.25 degree
scanner).

--step M: a scan every M metres or less (e.g. 0.1: a 10 Hz laser at 1 m/s),
the same drive with each of its steps cut into equal parts, on a clock of
2 M seconds; the odometry's per-step noise is scaled by sqrt(M), so that a
metre of it is as noisy at any step.

Outputs OUT.log.gz (CARMEN FLASER lines; ROBOTLASER1 with --fov 360 or
more than a beam a degree) and OUT.reference.txt.gz (the true poses,
"t x y theta" per scan, for scripts/ate.py).

Usage: sim_campus.py OUT [--seed N] [--odometry fair|harsh] [--fov 180|360]
                     [--beams-per-degree N] [--step M]
"""
import argparse
import gzip
import math

import numpy as np

BX, BY, ST = 80.0, 60.0, 16.0  # block size, street width (m)
NX, NY = 5, 4
MAX_RANGE, NO_RETURN = 80.0, 81.91


def world(rng, harsh):
    segs = []

    def poly(pts):
        for i in range(len(pts)):
            a, b = pts[i], pts[(i + 1) % len(pts)]
            segs.append((a[0], a[1], b[0], b[1]))

    for i in range(NX):
        for j in range(NY):
            x0, y0 = i * (BX + ST), j * (BY + ST)
            n = rng.integers(1, 4) if harsh else rng.integers(2, 4)
            xs = np.sort(rng.uniform(x0 + 3, x0 + BX - 3, 2 * n))
            for k in range(n):
                a, b = xs[2 * k], xs[2 * k + 1]
                if b - a < 8:
                    continue
                c, d = rng.uniform(y0 + 2, y0 + 12), rng.uniform(y0 + BY - 12, y0 + BY - 2)
                if rng.random() < 0.5:  # an L-shaped building
                    m, h = rng.uniform(a + 3, b - 3), rng.uniform(c + 3, d - 3)
                    poly([(a, c), (b, c), (b, h), (m, h), (m, d), (a, d)])
                else:
                    poly([(a, c), (b, c), (b, d), (a, d)])

    def tree(cx, cy, r):
        poly([(cx + r * math.cos(math.pi * t / 3), cy + r * math.sin(math.pi * t / 3))
              for t in range(6)])

    def kerbs(centre, length, vertical):
        # Trees along both kerbs of a street, every 8-20 m, each side 60 % of the time.
        t = -ST
        while t < length + ST:
            t += rng.uniform(8, 20)
            for side in (-1, 1):
                if rng.random() < 0.6:
                    along, across = t + rng.normal(0, 1), centre + side * (ST / 2 - 1)
                    r = rng.uniform(0.15, 0.4)
                    tree(across, along, r) if vertical else tree(along, across, r)

    W, H = NX * (BX + ST) - ST, NY * (BY + ST) - ST
    for j in range(NY + 1):
        kerbs(j * (BY + ST) - ST / 2, W, False)
    for i in range(NX + 1):
        kerbs(i * (BX + ST) - ST / 2, H, True)
    return np.array(segs)


def drive(rng):
    def node(i, j):
        return np.array([i * (BX + ST) - ST / 2, j * (BY + ST) - ST / 2])

    route = [(0, 0), (5, 0), (5, 4), (2, 4), (2, 0), (0, 0), (0, 1)]
    wps = [node(*r) for r in route]
    poses = []
    p = wps[0].copy()
    th = math.atan2(*(wps[1] - wps[0])[::-1])
    for w in wps[1:]:
        while True:
            d = w - p
            if np.hypot(*d) < 1.2:
                break
            err = math.atan2(math.sin(math.atan2(d[1], d[0]) - th), math.cos(math.atan2(d[1], d[0]) - th))
            step = rng.uniform(0.8, 1.2) if abs(err) < 0.3 else 0.5
            th += max(-0.35, min(0.35, err)) + rng.normal(0, 0.01)
            p = p + step * np.array([math.cos(th), math.sin(th)])
            poses.append((p[0], p[1], th))
    return np.array(poses)


def densify(poses, step):
    """`poses` with each step cut into ceil(length / step) equal parts, the
    heading turning evenly along it (the drive's steps turn as they go)."""
    out = [poses[0]]
    for a, b in zip(poses[:-1], poses[1:]):
        n = max(1, math.ceil(math.hypot(b[0] - a[0], b[1] - a[1]) / step - 1e-9))
        turn = math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2]))
        for k in range(1, n + 1):
            f = k / n
            out.append((a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * turn))
    return np.array(out)


def bearings(fov, per_degree=1):
    """The beams' bearings in the sensor frame (rad), `per_degree` a degree:
    from -90 to +90 degrees both included (fov 180), or a full turn from
    -180 (fov 360)."""
    if fov == 180:
        return np.radians(np.arange(180 * per_degree + 1) / per_degree - 90.0)
    return np.radians(np.arange(360 * per_degree) / per_degree - 180.0)


def raycast(S, x, y, th, rng, fov, per_degree=1):
    ang = th + bearings(fov, per_degree)
    dx, dy = np.cos(ang), np.sin(ang)
    near = np.minimum(np.hypot(S[:, 0] - x, S[:, 1] - y), np.hypot(S[:, 2] - x, S[:, 3] - y)) < MAX_RANGE + 100
    s = S[near]
    ex, ey = s[:, 2] - s[:, 0], s[:, 3] - s[:, 1]
    wx, wy = s[:, 0] - x, s[:, 1] - y
    den = dx[:, None] * ey[None, :] - dy[:, None] * ex[None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (wx[None, :] * ey[None, :] - wy[None, :] * ex[None, :]) / den
        u = (wx[None, :] * dy[:, None] - wy[None, :] * dx[:, None]) / den
    ok = (np.abs(den) > 1e-12) & (t > 0.05) & (u >= 0) & (u <= 1)
    t = np.where(ok, t, np.inf).min(axis=1)
    r = t + rng.normal(0, 0.02, t.shape)
    r[~np.isfinite(t) | (t > MAX_RANGE)] = NO_RETURN
    return r


def odometry(poses, rng, harsh, per_step=1.0):
    """Odometry along `poses`. `per_step` scales the noise each step adds
    whatever its length (the scale noise, the constant part of the heading
    noise): sqrt(step / nominal step) keeps their sum over a metre as it is
    when the scans are denser than the nominal step."""
    scale, drift = (0.02, 0.004) if harsh else (0.01, 0.001)
    odo = [np.zeros(3)]
    for k in range(1, len(poses)):
        a, b = poses[k - 1], poses[k]
        c, s = math.cos(a[2]), math.sin(a[2])
        dx, dy = b[0] - a[0], b[1] - a[1]
        lx, ly = c * dx + s * dy, -s * dx + c * dy
        dth = math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2]))
        d = math.hypot(lx, ly)
        lx *= 1 + scale + rng.normal(0, (0.02 + 0.01 * harsh) * per_step)
        ly += rng.normal(0, (0.01 + 0.01 * harsh) * d)
        dth += rng.normal(0, (0.005 + 0.005 * harsh) * per_step + (0.03 + 0.02 * harsh) * abs(dth)) + drift * d
        o = odo[-1]
        co, so = math.cos(o[2]), math.sin(o[2])
        odo.append(np.array([o[0] + co * lx - so * ly, o[1] + so * lx + co * ly, o[2] + dth]))
    return odo


def write_log(out, segs, poses, odo, rng, fov, period, per_degree=1):
    """Writes OUT.log.gz (a scan of `segs` from each true pose, with its
    odometry, `per_degree` beams a degree; FLASER lines for fov 180 at one a
    degree, else ROBOTLASER1) and OUT.reference.txt.gz (the true poses), one
    scan every `period` seconds; returns the path's length (m)."""
    with gzip.open(out + ".log.gz", "wt") as f, gzip.open(out + ".reference.txt.gz", "wt") as g:
        for k, (x, y, th) in enumerate(poses):
            r = raycast(segs, x, y, th, rng, fov, per_degree)
            o = odo[k]
            ot = math.atan2(math.sin(o[2]), math.cos(o[2]))
            t = 100.0 + period * k
            ranges = " ".join("%.3f" % v for v in r)
            if fov == 180 and per_degree == 1:
                f.write("FLASER 181 " + ranges +
                        " %.4f %.4f %.5f %.4f %.4f %.5f %.3f sim %.3f\n" % (o[0], o[1], ot, o[0], o[1], ot, t, t))
            else:  # ROBOTLASER1, which states its first bearing and step
                f.write("ROBOTLASER1 0 %.6f %.6f %.6f %.1f 0.01 0 %d %s 0"
                        " %.4f %.4f %.5f %.4f %.4f %.5f 0 0 0 0 0 %.3f sim %.3f\n"
                        % (-math.radians(fov / 2), math.radians(fov),
                           math.radians(1.0 / per_degree), MAX_RANGE, len(r), ranges,
                           o[0], o[1], ot, o[0], o[1], ot, t, t))
            g.write("%.3f %.4f %.4f %.5f\n" % (t, x, y, math.atan2(math.sin(th), math.cos(th))))
    return float(np.sum(np.hypot(*np.diff(poses[:, :2], axis=0).T)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--odometry", choices=("fair", "harsh"), default="fair")
    ap.add_argument("--fov", type=int, choices=(180, 360), default=180,
                    help="the laser's field of view (degrees): 180 (FLASER lines) or "
                         "360 (ROBOTLASER1 lines), a beam a degree")
    ap.add_argument("--beams-per-degree", type=int, default=1,
                    help="the laser's beams a degree (4: a 0.25 degree scanner)")
    ap.add_argument("--step", type=float, default=None,
                    help="a scan every this many metres or less (default: the drive's "
                         "own steps, 0.5-1.2 m)")
    a = ap.parse_args()
    if a.beams_per_degree < 1:
        ap.error("--beams-per-degree must be at least 1")
    if a.step is not None and not 0.01 <= a.step <= 1.0:
        ap.error("--step must lie in [0.01, 1] m")
    rng = np.random.default_rng(a.seed)
    harsh = a.odometry == "harsh"
    S = world(rng, harsh)
    poses = drive(rng)
    per_step, period = 1.0, 2.0
    if a.step is not None:
        poses = densify(poses, a.step)
        per_step, period = math.sqrt(a.step), 2.0 * a.step
    odo = odometry(poses, rng, harsh, per_step)
    length = write_log(a.out, S, poses, odo, rng, a.fov, period, a.beams_per_degree)
    print("%d scans, %d wall segments, path %.0f m: %s.log.gz, %s.reference.txt.gz"
          % (len(poses), len(S), length, a.out, a.out))


if __name__ == "__main__":
    main()
