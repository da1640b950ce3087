#!/usr/bin/python3
"""Writes a simulated indoor log of the kind the shared logs are too short
to test: a long run (about 2 km, 4 000-5 000 scans) through a large office
floor whose corridors all look alike.

The floor: a grid of corridors 2.4 m wide (NX + 1 across, NY + 1 along,
the outer ones a ring along the building's walls), about 130 x 40 m; the
blocks between them hold two rows of rooms 4-7 m wide, each opening on its
corridor by a door 1 m wide (a quarter of them closed), with 0-3 pieces of
furniture. Cabinets stand here and there against the corridors' walls.
A corridor is then a long run of doors a few metres apart, as in most
office buildings: the aliasing a loop closure must not fall for.

The robot walks the corridors from crossing to crossing (never straight
back), looks into a passing room now and then (drives in, turns round, and
out again), and stops after --length metres. A scan every 0.5 m or 0.25 rad
of turn (--step M: every M metres or M / 2 rad, e.g. 0.05 for a log recorded
as a robot's laser runs, not thinned; one scan every 0.1 s of the log's
clock then, else 0.5 s); the laser, the odometry's noise and the files
written are those of scripts/sim_campus.py (a 180 degree laser of 181 beams
reaching 80 m, range noise 2 cm; fair or harsh odometry, its per-step noise
scaled by sqrt(M / 0.5) so that a metre of it is as noisy at any step).

Outputs OUT.log.gz (CARMEN FLASER lines) and OUT.reference.txt.gz (the true
poses, "t x y theta" per scan, for scripts/ate.py).

Usage: sim_office.py OUT [--seed N] [--odometry fair|harsh] [--length M]
                     [--beams-per-degree N] [--step M]
"""
import argparse
import math
import sys

import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from sim_campus import odometry, write_log  # noqa: E402

NX, NY = 4, 2        # blocks across and along
BLOCK_W = 30.0       # a block's width (m)
BLOCK_H = 16.0       # a block's depth: two rows of 8 m rooms
CORRIDOR = 2.4       # corridor width (m)
DOOR = 1.0           # door width (m)
STEP = 0.5  # a scan per this much travel (m), or half as many radians of turn


def corridor_x(i):
    return i * (BLOCK_W + CORRIDOR)


def corridor_y(j):
    return j * (BLOCK_H + CORRIDOR)


class Floor:
    """Wall segments, and the doors a robot may look through."""

    def __init__(self, rng):
        self.segs = []
        self.doors = {}  # (corridor index, door's x) -> the room's centre
        self.rng = rng
        h = CORRIDOR / 2
        x_end, y_end = corridor_x(NX), corridor_y(NY)
        self.box(-h, -h, x_end + h, y_end + h)  # the building's outer walls
        for i in range(NX):
            for j in range(NY):
                self.block(corridor_x(i) + h, corridor_y(j) + h,
                           corridor_x(i + 1) - h, corridor_y(j + 1) - h, i, j)
        self.cabinets(x_end)
        self.segs = np.array(self.segs)

    def wall(self, x0, y0, x1, y1):
        self.segs.append((x0, y0, x1, y1))

    def box(self, x0, y0, x1, y1):
        self.wall(x0, y0, x1, y0)
        self.wall(x1, y0, x1, y1)
        self.wall(x1, y1, x0, y1)
        self.wall(x0, y1, x0, y0)

    def block(self, x0, y0, x1, y1, i, j):
        rng = self.rng
        ym = 0.5 * (y0 + y1)
        self.wall(x0, ym, x1, ym)  # the rows' back wall
        self.wall(x0, y0, x0, y1)  # the block's ends, on the cross corridors
        self.wall(x1, y0, x1, y1)
        # Room partitions: widths 4-7 m, the last room taking what is left.
        cuts = [x0]
        while x1 - cuts[-1] > 11:
            cuts.append(cuts[-1] + rng.uniform(4, 7))
        cuts.append(x1)
        for c in cuts[1:-1]:
            self.wall(c, y0, c, y1)
        for y_face, y_back, row in ((y0, ym, j), (y1, ym, j + 1)):
            # Each room's door on the corridor side; a wall around the gaps.
            x = x0
            for a, b in zip(cuts[:-1], cuts[1:]):
                d = rng.uniform(a + 0.5, b - 0.5 - DOOR)
                if rng.random() < 0.25:  # a closed door: wall on
                    continue
                self.wall(x, y_face, d, y_face)
                x = d + DOOR
                self.doors[(row, d + DOOR / 2)] = (0.5 * (a + b), 0.5 * (y_face + y_back))
                # In the half away from the door, where the robot never goes.
                y_mid = 0.5 * (y_face + y_back)
                self.furniture(a, min(y_mid, y_back), b, max(y_mid, y_back))
            self.wall(x, y_face, x1, y_face)

    def furniture(self, x0, y0, x1, y1):
        rng = self.rng
        for _ in range(rng.integers(0, 4)):
            w, d = rng.uniform(0.5, 1.8), rng.uniform(0.4, 0.9)
            if x1 - x0 < w + 0.6 or y1 - y0 < d + 0.6:
                continue
            cx = rng.uniform(x0 + 0.3 + w / 2, x1 - 0.3 - w / 2)
            cy = rng.uniform(y0 + 0.3 + d / 2, y1 - 0.3 - d / 2)
            self.box(cx - w / 2, cy - d / 2, cx + w / 2, cy + d / 2)

    def cabinets(self, x_end):
        # Against the corridors' walls every 10-30 m, 0.4 m deep, away from
        # the crossings; a door a cabinet stands in front of is not used.
        rng = self.rng
        h = CORRIDOR / 2
        for j in range(NY + 1):
            t = rng.uniform(0, 15)
            while t < x_end - 2:
                side = 1 if rng.random() < 0.5 else -1
                y = corridor_y(j) + side * (h - 0.2)
                if all(abs(t - corridor_x(i)) > 2 for i in range(NX + 1)):
                    self.box(t - 0.5, y - 0.2, t + 0.5, y + 0.2)
                    for key in [k for k in self.doors if k[0] == j and abs(k[1] - t) < 1.5]:
                        del self.doors[key]
                t += rng.uniform(10, 30)


def walk(floor, rng, length, step=STEP):
    """True poses: crossing to crossing, now and then into a room and out; a
    pose every `step` metres, or step / 2 rad of turn on the spot."""
    turn_step = step / 2
    poses = [(0.0, 0.0, 0.0)]
    node, prev = (0, 0), None
    travelled = 0.0

    def go_to(x, y):
        nonlocal travelled
        px, py, th = poses[-1]
        want = math.atan2(y - py, x - px)
        turn = math.atan2(math.sin(want - th), math.cos(want - th))
        for k in range(1, int(abs(turn) / turn_step) + 1):  # turn on the spot
            poses.append((px, py, th + math.copysign(k * turn_step, turn)))
        d = math.hypot(x - px, y - py)
        n = max(1, math.ceil(d / step))
        for k in range(1, n + 1):
            poses.append((px + (x - px) * k / n, py + (y - py) * k / n,
                          want + rng.normal(0, 0.01)))
        poses[-1] = (x, y, want)
        travelled += d

    while travelled < length:
        i, j = node
        nbrs = [(i + di, j + dj) for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1))
                if 0 <= i + di <= NX and 0 <= j + dj <= NY and (i + di, j + dj) != prev]
        nxt = nbrs[rng.integers(len(nbrs))]
        x0, y0 = corridor_x(i), corridor_y(j)
        x1, y1 = corridor_x(nxt[0]), corridor_y(nxt[1])
        if y0 == y1:  # along a corridor with rooms: perhaps look into one
            lo, hi = sorted((x0, x1))
            doors = sorted((x, c) for (row, x), c in floor.doors.items()
                           if row == j and lo < x < hi)
            if x1 < x0:
                doors.reverse()
            for x, (cx, cy) in doors:
                if rng.random() < 0.12:
                    go_to(x, y0)
                    go_to(x, y0 + 0.6 * (cy - y0))
                    go_to(x, y0)
        go_to(x1, y1)
        prev, node = node, nxt
    return np.array(poses)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--odometry", choices=("fair", "harsh"), default="fair")
    ap.add_argument("--length", type=float, default=2000.0,
                    help="the walk's length (m) before it stops, at the next crossing")
    ap.add_argument("--beams-per-degree", type=int, default=1,
                    help="the laser's beams a degree (4: a 0.25 degree scanner)")
    ap.add_argument("--step", type=float, default=STEP,
                    help="a scan every this many metres (or half as many radians of turn)")
    a = ap.parse_args()
    if a.beams_per_degree < 1:
        ap.error("--beams-per-degree must be at least 1")
    if not a.length > 0:
        ap.error("--length must be positive")
    if not 0.01 <= a.step <= 2.0:
        ap.error("--step must lie in [0.01, 2] m")
    rng = np.random.default_rng(a.seed)
    floor = Floor(rng)
    poses = walk(floor, rng, a.length, a.step)
    odo = odometry(poses, rng, a.odometry == "harsh", math.sqrt(a.step / 0.5))
    period = 0.5 if a.step >= 0.5 else 0.1
    path = write_log(a.out, floor.segs, poses, odo, rng, 180, period, a.beams_per_degree)
    print("%d scans, %d wall segments, %d open doors, path %.0f m: %s.log.gz, %s.reference.txt.gz"
          % (len(poses), len(floor.segs), len(floor.doors), path, a.out, a.out))


if __name__ == "__main__":
    main()
