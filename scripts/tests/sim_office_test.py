#!/usr/bin/python3
"""Tests of scripts/sim_office.py: the log it writes is a CARMEN log whose
scans agree with its reference poses, of a walk that stays inside the
corridors and rooms.

Run directly or through ctest (sim_office_script).
"""
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.join(HERE, "..")
SCRIPT = os.path.join(SCRIPTS, "sim_office.py")
sys.path.insert(0, SCRIPTS)
import sim_office  # noqa: E402
from sim_campus_test import assert_steps_refused, read, read_robotlaser  # noqa: E402

LENGTH = 300  # metres: enough for crossings, doors and a room or two


def crosses(p, q, segs):
    """Whether the move p -> q crosses any wall segment."""
    d = q - p
    e = segs[:, 2:4] - segs[:, 0:2]
    w = segs[:, 0:2] - p
    den = d[0] * e[:, 1] - d[1] * e[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0]) / den
        u = (w[:, 0] * d[1] - w[:, 1] * d[0]) / den
    return bool(np.any((np.abs(den) > 1e-12) & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)))


class SimOffice(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.prefix = os.path.join(cls.dir.name, "office")
        r = subprocess.run([sys.executable, SCRIPT, cls.prefix, "--seed", "2",
                            "--length", str(LENGTH)], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        cls.scans, cls.odo, cls.stamps, cls.ref = read(cls.prefix)

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_a_scan_per_reference_pose_on_one_clock(self):
        self.assertEqual(len(self.scans), len(self.ref))
        self.assertTrue(all(len(s) == 181 for s in self.scans))
        self.assertEqual(self.stamps, [r[0] for r in self.ref])
        self.assertEqual(self.odo[0], [0.0, 0.0, 0.0])
        steps = [math.hypot(b[1] - a[1], b[2] - a[2]) for a, b in zip(self.ref, self.ref[1:])]
        self.assertGreaterEqual(sum(steps), LENGTH)
        self.assertLessEqual(max(steps), sim_office.STEP + 1e-6)

    def test_the_walk_never_passes_through_a_wall(self):
        segs = sim_office.Floor(np.random.default_rng(2)).segs
        poses = np.array([r[1:3] for r in self.ref])
        for p, q in zip(poses, poses[1:]):
            self.assertFalse(crosses(p, q, segs), f"{p} -> {q}")
        # Nor stands next to one: every scan's nearest return is 0.3 m off or more.
        self.assertGreater(min(min(s) for s in self.scans), 0.3)

    def test_an_indoor_scene_and_rooms_looked_into(self):
        r = [v for s in self.scans for v in s if v < 81.0]
        self.assertLess(float(np.median(r)), 10.0)
        # Poses more than half a metre past a corridor's walls: inside a room.
        inside = [p for p in self.ref
                  if min(abs(p[2] - sim_office.corridor_y(j)) for j in range(sim_office.NY + 1))
                  > sim_office.CORRIDOR / 2 + 0.5]
        self.assertGreater(len(inside), 0)

    def test_the_same_seed_writes_the_same_log(self):
        prefix = os.path.join(self.dir.name, "again")
        subprocess.run([sys.executable, SCRIPT, prefix, "--seed", "2", "--length", str(LENGTH)],
                       check=True, capture_output=True)
        self.assertEqual(read(prefix), (self.scans, self.odo, self.stamps, self.ref))

    def test_a_length_that_is_not_positive_is_refused(self):
        r = subprocess.run([sys.executable, SCRIPT, os.path.join(self.dir.name, "x"),
                            "--length", "0"], capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--length", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir.name, "x.log.gz")))

    def test_a_finer_laser_writes_robotlaser_lines_of_the_same_walk(self):
        prefix = os.path.join(self.dir.name, "fine")
        subprocess.run([sys.executable, SCRIPT, prefix, "--seed", "2", "--length", str(LENGTH),
                        "--beams-per-degree", "4"], check=True, capture_output=True)
        # -90..90 degrees, a quarter of a degree apart.
        scans, odo, ref = read_robotlaser(prefix, -math.pi / 2, math.pi, math.radians(0.25))
        self.assertTrue(all(len(s) == 721 for s in scans))
        # The same walk and odometry; every fourth beam is the 1 degree laser's.
        self.assertEqual(odo, self.odo)
        self.assertEqual(ref, self.ref)
        agree = total = 0
        for fine, coarse in zip(scans, self.scans):
            for k in range(181):
                a, b = fine[4 * k], coarse[k]
                if a < 81 and b < 81:
                    total += 1
                    agree += abs(a - b) < 0.15
        self.assertGreater(agree, 0.99 * total)

    def test_a_finer_step_records_a_scan_every_step_on_a_finer_clock(self):
        prefix = os.path.join(self.dir.name, "dense")
        subprocess.run([sys.executable, SCRIPT, prefix, "--seed", "2", "--length", "60",
                        "--step", "0.1"], check=True, capture_output=True)
        scans, odo, stamps, ref = read(prefix)
        self.assertEqual(len(scans), len(ref))
        steps = [math.hypot(b[1] - a[1], b[2] - a[2]) for a, b in zip(ref, ref[1:])]
        self.assertLessEqual(max(steps), 0.1 + 1e-6)
        self.assertGreater(float(np.median([d for d in steps if d > 0])), 0.09)
        self.assertAlmostEqual(stamps[1] - stamps[0], 0.1)
        # The odometry's error over the walk is of the 0.5 m log's size, not
        # sqrt(5) times it: its per-step noise is scaled down.
        end = np.array(odo[-1][:2]) - np.array(ref[-1][1:3]) + np.array(ref[0][1:3])
        self.assertLess(float(np.hypot(*end)), 3.0)

    def test_a_step_out_of_range_is_refused(self):
        assert_steps_refused(self, SCRIPT, self.dir.name, ("0", "5"))

    def test_fewer_than_one_beam_a_degree_is_refused(self):
        r = subprocess.run([sys.executable, SCRIPT, os.path.join(self.dir.name, "y"),
                            "--beams-per-degree", "0"], capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--beams-per-degree", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir.name, "y.log.gz")))


if __name__ == "__main__":
    unittest.main()
