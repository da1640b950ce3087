#!/usr/bin/python3
"""Tests of scripts/perturb_odometry.py on small CARMEN logs.

Run directly or through ctest (perturb_odometry_script).
"""
import gzip
import math
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "perturb_odometry.py")


def flaser(ranges, pose, t):
    p = " ".join(f"{v:.6f}" for v in pose)
    return f"FLASER {len(ranges)} {' '.join(map(str, ranges))} {p} {p} {t:.6f} host {t:.6f}\n"


def poses_of(path):
    out = []
    with gzip.open(path, "rt") as f:
        for line in f:
            s = line.split()
            if s and s[0] == "FLASER":
                k = 2 + int(s[1])
                first = [float(v) for v in s[k:k + 3]]
                second = [float(v) for v in s[k + 3:k + 6]]
                assert first == second, line
                out.append(first)
    return out


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


class PerturbOdometry(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.log = os.path.join(self.dir.name, "in.log")
        # Forward 1 m, then a quarter turn in place, then forward 1 m.
        with open(self.log, "w") as f:
            f.write("PARAM robot_front_laser_max 81.9\n")
            f.write(flaser([1.0, 2.0], (0, 0, 0), 1))
            f.write(flaser([1.5, 2.5], (1, 0, 0), 2))
            f.write(flaser([1.0, 2.0], (1, 0, math.pi / 2), 3))
            f.write(flaser([1.5, 2.5], (1, 1, math.pi / 2), 4))

    def tearDown(self):
        self.dir.cleanup()

    def out(self, *args):
        path = os.path.join(self.dir.name, "out.log.gz")
        r = run(self.log, path, *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        return path

    def test_defaults_keep_the_odometry_and_every_other_field(self):
        path = self.out()
        got = poses_of(path)
        want = [(0, 0, 0), (1, 0, 0), (1, 0, math.pi / 2), (1, 1, math.pi / 2)]
        for g, w in zip(got, want):
            for a, b in zip(g, w):
                self.assertAlmostEqual(a, b, places=5)
        with gzip.open(path, "rt") as f:
            lines = f.read().splitlines()
        self.assertEqual(lines[0], "PARAM robot_front_laser_max 81.9")
        self.assertTrue(lines[2].startswith("FLASER 2 1.5 2.5 "))
        self.assertTrue(lines[2].endswith(" 2.000000 host 2.000000"))

    def test_scales_compose_in_the_robot_frame(self):
        # Half the translation, turns doubled: the last step heads along -x.
        got = poses_of(self.out("--trans", "0.5", "--rot", "2"))
        self.assertAlmostEqual(got[1][0], 0.5, places=5)
        self.assertAlmostEqual(abs(got[2][2]), math.pi, places=5)
        self.assertAlmostEqual(got[3][0], 0.0, places=5)
        self.assertAlmostEqual(got[3][1], 0.0, places=5)

    def test_noise_is_seeded(self):
        a = poses_of(self.out("--sxy", "0.1", "--sth", "0.1", "--seed", "7"))
        b = poses_of(self.out("--sxy", "0.1", "--sth", "0.1", "--seed", "7"))
        c = poses_of(self.out("--sxy", "0.1", "--sth", "0.1", "--seed", "8"))
        self.assertEqual(a, b)
        self.assertNotEqual(a, c)
        self.assertEqual(a[0], [0.0, 0.0, 0.0])  # the start is kept

    def test_bad_input_is_refused(self):
        self.assertNotEqual(run(self.log, os.path.join(self.dir.name, "x"), "--sxy", "-1").returncode, 0)
        bad = os.path.join(self.dir.name, "bad.log")
        with open(bad, "w") as f:
            f.write("FLASER 3 1.0\n")
        r = run(bad, os.path.join(self.dir.name, "y"))
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("bad.log:1", r.stderr)
        r = run(os.path.join(self.dir.name, "missing.log"), os.path.join(self.dir.name, "z"))
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("missing.log", r.stderr)
        self.assertNotIn("Traceback", r.stderr)

    def test_a_log_that_fails_half_way_leaves_the_output_as_it_was(self):
        out = os.path.join(self.dir.name, "kept.log")
        with open(out, "w") as f:
            f.write("an earlier output\n")
        with open(self.log, "a") as f:
            f.write("FLASER 2 1.0 2.0 0 0\n")  # line 6: no odometry
        r = run(self.log, out, "--sxy", "0.1")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("in.log:6", r.stderr)
        with open(out) as f:
            self.assertEqual(f.read(), "an earlier output\n")
        self.assertEqual(sorted(os.listdir(self.dir.name)), ["in.log", "kept.log"])


if __name__ == "__main__":
    unittest.main()
