#!/usr/bin/python3
"""Tests of scripts/sim_campus.py: the log it writes is a CARMEN log of the
README's format whose scans agree with its reference poses.

Run directly or through ctest (sim_campus_script).
"""
import gzip
import math
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "sim_campus.py")


def read(prefix):
    scans, odo, stamps = [], [], []
    with gzip.open(prefix + ".log.gz", "rt") as f:
        for line in f:
            s = line.split()
            assert s[0] == "FLASER", line[:40]
            n = int(s[1])
            assert len(s) == n + 11, len(s)
            scans.append([float(v) for v in s[2:2 + n]])
            odo.append([float(v) for v in s[2 + n + 3:2 + n + 6]])
            stamps.append(float(s[2 + n + 6]))
    with gzip.open(prefix + ".reference.txt.gz", "rt") as f:
        ref = [[float(v) for v in line.split()] for line in f]
    return scans, odo, stamps, ref


def read_robotlaser(prefix, first, fov, spacing):
    """The scans and odometry of a ROBOTLASER1 log (each line's first bearing,
    field of view and beam spacing checked, in radians to the 6 decimals
    written, and the laser at the robot), and the reference poses."""
    scans, odo = [], []
    with gzip.open(prefix + ".log.gz", "rt") as f:
        for line in f:
            s = line.split()
            assert s[0] == "ROBOTLASER1", line[:40]
            n = int(s[8])
            assert len(s) == n + 24, len(s)  # no remissions
            for k, want in ((2, first), (3, fov), (4, spacing)):
                assert round(float(s[k]) - want, 6) == 0, (k, s[k], want)
            scans.append([float(v) for v in s[9:9 + n]])
            o = 10 + n
            assert s[o:o + 3] == s[o + 3:o + 6], line[:40]  # the laser at the robot
            odo.append([float(v) for v in s[o + 3:o + 6]])
    with gzip.open(prefix + ".reference.txt.gz", "rt") as f:
        ref = [[float(v) for v in line.split()] for line in f]
    return scans, odo, ref


def assert_steps_refused(test, script, out_dir, steps):
    """`script OUT --step S` exits non-zero for each S of `steps`, naming the
    option, and writes no log."""
    for step in steps:
        r = subprocess.run([sys.executable, script, os.path.join(out_dir, "z"), "--step", step],
                           capture_output=True, text=True)
        test.assertNotEqual(r.returncode, 0)
        test.assertIn("--step", r.stderr)
        test.assertFalse(os.path.exists(os.path.join(out_dir, "z.log.gz")))


class SimCampus(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.out = {}
        for kind in ("fair", "harsh"):
            prefix = os.path.join(cls.dir.name, kind)
            r = subprocess.run([sys.executable, SCRIPT, prefix, "--seed", "3", "--odometry", kind],
                               capture_output=True, text=True)
            assert r.returncode == 0, r.stderr
            cls.out[kind] = read(prefix)

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_a_scan_per_reference_pose_on_one_clock(self):
        scans, odo, stamps, ref = self.out["fair"]
        self.assertGreater(len(scans), 1500)
        self.assertEqual(len(scans), len(ref))
        self.assertTrue(all(len(s) == 181 for s in scans))
        self.assertEqual(stamps, [r[0] for r in ref])
        self.assertEqual(odo[0], [0.0, 0.0, 0.0])

    def test_an_outdoor_scene_far_returns_and_no_returns(self):
        scans = self.out["fair"][0]
        r = [v for s in scans for v in s]
        valid = [v for v in r if v < 81.0]
        self.assertGreater(r.count(81.91), 0.3 * len(r))  # open space
        far = sum(1 for v in valid if v > 20.0) / len(valid)
        self.assertGreater(far, 0.5)  # most returns beyond 20 m
        self.assertLessEqual(max(valid), 80.5)

    def test_the_tour_is_long_and_closes_on_its_first_street(self):
        ref = self.out["fair"][3]
        length = sum(math.hypot(b[1] - a[1], b[2] - a[2]) for a, b in zip(ref, ref[1:]))
        self.assertGreater(length, 1500)
        # The last stretch drives back along the first street (y = -8).
        near_start = [p for p in ref[-300:] if abs(p[2] - ref[0][2]) < 1.0 and p[1] < 150]
        self.assertGreater(len(near_start), 50)

    def test_harsh_odometry_drifts_more_than_fair(self):
        def heading_drift(kind):
            # Unwrapped heading of the odometry minus that of the truth, at the end.
            _, odo, _, ref = self.out[kind]
            def turned(th):
                return sum(math.atan2(math.sin(b - a), math.cos(b - a)) for a, b in zip(th, th[1:]))
            return turned([o[2] for o in odo]) - turned([r[3] for r in ref])
        fair, harsh = heading_drift("fair"), heading_drift("harsh")
        self.assertGreater(fair, 1.0)  # 0.001 rad per metre over 1.6 km, worth correcting
        self.assertGreater(harsh, 3.0 * fair)

    def test_a_full_turn_laser_writes_robotlaser_lines_of_the_same_tour(self):
        prefix = os.path.join(self.dir.name, "wide")
        subprocess.run([sys.executable, SCRIPT, prefix, "--seed", "3", "--fov", "360"],
                       check=True, capture_output=True)
        # A full turn from -180 degrees, a beam a degree.
        scans, odo, ref = read_robotlaser(prefix, -math.pi, 2 * math.pi, math.radians(1))
        fair_scans, fair_odo, _, fair_ref = self.out["fair"]
        self.assertTrue(all(len(s) == 360 for s in scans))
        # The same tour and odometry; only the range noise is drawn anew.
        self.assertEqual(odo, fair_odo)
        self.assertEqual(ref, fair_ref)
        # Beams at bearings -90..90 degrees are the 180 degree log's.
        agree = total = 0
        for wide, front in zip(scans[::10], fair_scans[::10]):
            for k in range(181):
                a, b = wide[90 + k], front[k]
                if a < 81 and b < 81:
                    total += 1
                    agree += abs(a - b) < 0.15
        self.assertGreater(agree, 0.99 * total)
        # And the other half sees what a forward laser cannot.
        behind = [v for s in scans for v in s[:90] + s[271:] if v < 81]
        self.assertGreater(len(behind), 0.2 * len(scans) * 180)

    def test_a_finer_step_cuts_the_same_drive_on_a_finer_clock(self):
        prefix = os.path.join(self.dir.name, "dense")
        subprocess.run([sys.executable, SCRIPT, prefix, "--seed", "3", "--step", "0.5"],
                       check=True, capture_output=True)
        scans, odo, stamps, ref = read(prefix)
        _, _, _, coarse = self.out["fair"]
        self.assertEqual(len(scans), len(ref))
        self.assertGreater(len(ref), 1.5 * len(coarse))
        steps = [math.hypot(b[1] - a[1], b[2] - a[2]) for a, b in zip(ref, ref[1:])]
        self.assertLessEqual(max(steps), 0.5 + 1e-3)
        self.assertAlmostEqual(stamps[1] - stamps[0], 1.0)
        # Every pose of the drive is one of the finer log's, in order.
        fine = {(round(r[1], 3), round(r[2], 3)) for r in ref}
        self.assertTrue(all((round(r[1], 3), round(r[2], 3)) in fine for r in coarse))
        self.assertEqual(ref[-1][1:3], coarse[-1][1:3])
        # The odometry's heading drifts as the drive's does (0.001 rad a metre;
        # seeds 3-6: 1.2-1.9 rad both ways), the per-step noise scaled down.
        def drift(odo, ref):
            def turned(th):
                return sum(math.atan2(math.sin(b - a), math.cos(b - a)) for a, b in zip(th, th[1:]))
            return turned([o[2] for o in odo]) - turned([r[3] for r in ref])
        fine_drift, coarse_drift = drift(odo, ref), drift(self.out["fair"][1], coarse)
        self.assertGreater(fine_drift, 1.0)
        self.assertLess(abs(fine_drift - coarse_drift), 0.5)

    def test_a_step_out_of_range_is_refused(self):
        assert_steps_refused(self, SCRIPT, self.dir.name, ("0", "1.5"))

    def test_the_same_seed_writes_the_same_log(self):
        prefix = os.path.join(self.dir.name, "again")
        subprocess.run([sys.executable, SCRIPT, prefix, "--seed", "3"], check=True, capture_output=True)
        self.assertEqual(read(prefix), self.out["fair"])


if __name__ == "__main__":
    unittest.main()
