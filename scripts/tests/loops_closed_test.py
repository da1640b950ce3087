#!/usr/bin/python3
"""Tests of scripts/loops_closed.py on synthetic trajectories.

Run directly or through ctest (loops_closed_script).
"""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "loops_closed.py")


def square_laps(laps, side=10.0, step=0.5):
    """(t, x, y, theta) around a square of `side` metres, `laps` times,
    anticlockwise from the origin: 40 m of path a lap."""
    poses, t = [], 0.0
    per_side = int(round(side / step))
    for _ in range(laps):
        for k, (dx, dy) in enumerate([(1, 0), (0, 1), (-1, 0), (0, -1)]):
            x0 = [0, side, side, 0][k]
            y0 = [0, 0, side, side][k]
            for i in range(per_side):
                poses.append((t, x0 + dx * step * i, y0 + dy * step * i, math.atan2(dy, dx)))
                t += 1.0
    return poses


def write(path, poses):
    with open(path, "w") as f:
        for t, x, y, th in poses:
            f.write(f"{t:.3f} {x:.6f} {y:.6f} {th:.6f}\n")


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


class LoopsClosed(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.ref = os.path.join(self.dir.name, "ref.txt")
        self.ref_poses = square_laps(2)
        write(self.ref, self.ref_poses)

    def tearDown(self):
        self.dir.cleanup()

    def check(self, poses, *args):
        path = os.path.join(self.dir.name, "est.txt")
        write(path, poses)
        r = run(path, self.ref, "--json", *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        return json.loads(r.stdout)

    def test_the_reference_closes_its_own_loop(self):
        out = self.check(self.ref_poses)
        # The robot comes within 1 m of its start 39 m on (step 78) and drives
        # the square again: one loop of 82 returns.
        self.assertEqual(out["loops"], 1)
        self.assertEqual(out["closed"], 1)
        loop = out["each"][0]
        self.assertEqual(loop["pairs"], 82)
        self.assertEqual(loop["first_pair"], [0, 78])
        self.assertAlmostEqual(loop["path_m"], 39.0)
        self.assertAlmostEqual(loop["max_error_m"], 0.0, places=9)

    def test_a_rigid_motion_of_the_whole_estimate_changes_nothing(self):
        c, s = math.cos(0.7), math.sin(0.7)
        moved = [(t, 3 + c * x - s * y, -2 + s * x + c * y, th + 0.7)
                 for t, x, y, th in self.ref_poses]
        out = self.check(moved)
        self.assertEqual(out["closed"], 1)
        self.assertLess(out["each"][0]["max_error_m"], 1e-5)  # files hold 6 decimals

    def test_a_second_lap_beside_the_first_is_open(self):
        # The second lap drawn 0.8 m to the side: the loop was not closed.
        est = [(t, x + (0.8 if k >= 80 else 0.0), y, th)
               for k, (t, x, y, th) in enumerate(self.ref_poses)]
        out = self.check(est)
        self.assertEqual((out["loops"], out["closed"]), (1, 0))
        self.assertAlmostEqual(out["each"][0]["median_error_m"], 0.8, places=6)
        # A looser tolerance counts it closed; the text names the open loop.
        self.assertEqual(self.check(est, "--tolerance", "1.0")["closed"], 1)
        path = os.path.join(self.dir.name, "est.txt")
        r = run(path, self.ref)
        self.assertIn("0 of 1 loops of the reference closed", r.stdout)
        self.assertIn("OPEN   steps 0 -> 78: 39 m of path, 82 pairs, error median 0.800 m",
                      r.stdout)

    def test_short_returns_are_not_loops(self):
        # One lap: back near the start after 39.5 m of path, a loop unless
        # loops must be longer.
        one = square_laps(1)
        write(self.ref, one)
        self.assertEqual(self.check(one)["loops"], 1)
        self.assertEqual(self.check(one, "--min-path", "45")["loops"], 0)
        self.assertEqual(self.check(one, "--radius", "0.4")["loops"], 0)

    def test_matched_by_timestamp(self):
        # The estimate lacks every third pose: matched by time, still closed.
        est = [p for k, p in enumerate(self.ref_poses) if k % 3]
        out = self.check(est)
        self.assertEqual((out["loops"], out["closed"]), (1, 1))

    def test_bad_input(self):
        r = run(os.path.join(self.dir.name, "missing.txt"), self.ref)
        self.assertEqual(r.returncode, 4)
        self.assertIn("missing.txt", r.stderr)
        bad = os.path.join(self.dir.name, "bad.txt")
        with open(bad, "w") as f:
            f.write("1 2 3\n")
        r = run(bad, self.ref)
        self.assertEqual(r.returncode, 4)
        self.assertIn("expected 4 or 8 fields", r.stderr)
        few = os.path.join(self.dir.name, "few.txt")
        write(few, [(1000.0 + k, 0, 0, 0) for k in range(10)])
        r = run(few, self.ref)
        self.assertEqual(r.returncode, 4)
        self.assertIn("match a pose", r.stderr)
        r = run(self.ref, self.ref, "--radius", "nan")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--radius", r.stderr)


if __name__ == "__main__":
    unittest.main()
