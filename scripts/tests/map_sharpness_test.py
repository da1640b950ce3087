#!/usr/bin/python3
"""Tests of scripts/map_sharpness.py on a small synthetic CARMEN log.

Run directly or through ctest (map_sharpness_script).
"""
import gzip
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "map_sharpness.py")


def wall_ranges(x, y, theta, wall_x=5.0):
    """181 FLASER beams (1 degree apart from -90) of a robot at (x, y,
    theta) facing a straight wall x = wall_x; beams missing it read 30 m."""
    out = []
    for k in range(181):
        a = theta + math.radians(k - 90)
        c = math.cos(a)
        r = (wall_x - x) / c if c > 1e-6 else 30.0
        out.append(r if 0 < r < 30 else 30.0)
    return out


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


class MapSharpness(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        d = self.dir.name
        # The robot drives along y facing the wall, ten scans.
        self.truth = [(100.0 + k, 0.0, 0.4 * k, 0.0) for k in range(10)]
        self.log = f"{d}/wall.log.gz"
        with gzip.open(self.log, "wt") as f:
            f.write("PARAM robot_frontlaser_offset 0.0\n")
            for t, x, y, th in self.truth:
                r = " ".join(f"{v:.3f}" for v in wall_ranges(x, y, th))
                f.write(f"FLASER 181 {r} {x} {y} {th} {x} {y} {th} {t} host {t}\n")
        self.true_path = f"{d}/true.txt"
        self.bent_path = f"{d}/bent.txt"
        with open(self.true_path, "w") as f:
            f.writelines(f"{t} {x} {y} {th}\n" for t, x, y, th in self.truth)
        # Half the scans 0.3 m and 2 degrees off: the wall is drawn twice.
        with open(self.bent_path, "w") as f:
            for k, (t, x, y, th) in enumerate(self.truth):
                if k >= 5:
                    x, th = x + 0.3, th + math.radians(2)
                f.write(f"{t} {x} {y} {th}\n")

    def tearDown(self):
        self.dir.cleanup()

    def test_the_consistent_trajectory_draws_fewer_cells(self):
        r = run(self.log, self.true_path, self.bent_path, "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        out = json.loads(r.stdout)
        self.assertLess(out["trajectory_cells"], out["reference_cells"])
        self.assertLess(out["ratio"], 0.9)
        # The other way round (each drawn in the other's frame), the same verdict.
        back = json.loads(run(self.log, self.bent_path, self.true_path, "--json").stdout)
        self.assertGreater(back["ratio"], 1.1)

    def test_the_trajectory_is_drawn_in_the_references_frame(self):
        moved = f"{self.dir.name}/moved.txt"
        a = 0.7
        with open(moved, "w") as f:
            for t, x, y, th in self.truth:
                f.write(f"{t} {math.cos(a) * x - math.sin(a) * y + 3} "
                        f"{math.sin(a) * x + math.cos(a) * y - 1} {th + a}\n")
        # Against the reference it is moved into the reference's frame first:
        # the same poses there, the same cells.
        both = json.loads(run(self.log, moved, self.true_path, "--json").stdout)
        self.assertEqual(both["trajectory_cells"], both["reference_cells"])

    def test_blocks_point_at_the_doubled_wall(self):
        r = run(self.log, self.bent_path, self.true_path, "--blocks", "2", "--json")
        out = json.loads(r.stdout)
        self.assertTrue(out["trajectory_worse"])
        # The doubled stretch is the wall (x = 5) beside the last five scans
        # (y from 2 m on).
        cx, cy = out["trajectory_worse"][0]["centre"]
        self.assertLess(abs(cx - 5.0), 4.0)
        self.assertGreater(cy, 0.0)

    def test_png_shows_the_doubled_wall_on_the_left_only(self):
        png = f"{self.dir.name}/pair.png"
        r = run(self.log, self.bent_path, self.true_path, "--png", png, "--window", "5,2,3")
        self.assertEqual(r.returncode, 0, r.stderr)
        from PIL import Image
        import numpy as np
        img = np.asarray(Image.open(png))
        n = img.shape[0]
        left, right = img[:, :n], img[:, -n:]
        # Columns holding wall cells: the wall x = 5 is one column on the
        # right; on the left its second copy 0.3 m away adds more.
        def wall_columns(panel):
            return int(((panel == 0).sum(axis=0) > 5).sum())
        self.assertGreater(wall_columns(left), wall_columns(right))
        self.assertGreaterEqual(wall_columns(right), 1)

    def test_png_needs_a_window_and_a_reference(self):
        png = f"{self.dir.name}/pair.png"
        self.assertEqual(run(self.log, self.bent_path, self.true_path, "--png", png).returncode, 2)
        self.assertEqual(run(self.log, self.bent_path, "--png", png, "--window", "5,2,3").returncode, 2)
        self.assertEqual(run(self.log, self.bent_path, self.true_path, "--png", png,
                             "--window", "5,2").returncode, 2)
        self.assertFalse(os.path.exists(png))

    def test_poses_that_match_no_scan_are_an_error(self):
        other = f"{self.dir.name}/other.txt"
        with open(other, "w") as f:
            f.writelines(f"{t + 50} {x} {y} {th}\n" for t, x, y, th in self.truth[:7])
        r = run(self.log, other)
        self.assertEqual(r.returncode, 4)
        self.assertIn("match a scan", r.stderr)

    def test_a_timestamp_several_scans_share_matches_none(self):
        # Nine of the ten poses (one dropped, so matched by time), the log's
        # timestamps rounded so that scans 4-9 share one: those poses could
        # be any of six scans, and only scans 0-3 are left, under half.
        rounded = f"{self.dir.name}/rounded.log"
        with open(rounded, "w") as f, gzip.open(self.log, "rt") as g:
            for line in g:
                s = line.split()
                if s[0] == "FLASER" and float(s[-1]) >= 104:
                    s[-1] = s[-3] = "104"
                f.write(" ".join(s) + "\n")
        nine = f"{self.dir.name}/nine.txt"
        with open(nine, "w") as f:
            f.writelines(f"{min(t, 104)} {x} {y} {th}\n" for t, x, y, th in self.truth[1:])
        r = run(rounded, nine)
        self.assertEqual(r.returncode, 4)
        self.assertIn("no other scan shares", r.stderr)
        # Matched by index from scan 1 instead, they draw the wall once.
        r = run(rounded, nine, "--offset", "1", "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(json.loads(r.stdout)["trajectory_poses"], 9)
        self.assertEqual(run(rounded, nine, "--offset", "x").returncode, 2)
        # From scan 6, only four of the nine poses fall on the log's ten
        # scans: under half, refused as matching by time is.
        r = run(rounded, nine, "--offset", "6")
        self.assertEqual(r.returncode, 4)
        self.assertIn("only 4 of 9 poses", r.stderr)

    def test_ate_offset_and_ambiguous_times(self):
        ate = os.path.join(HERE, "..", "ate.py")
        # A curve (a shift along it is no rigid motion), the estimate moved
        # by 1 m and without its first pose.
        curve = [(100.0 + k, float(k), 0.1 * k * k, 0.0) for k in range(10)]
        ref, nine = f"{self.dir.name}/curve.txt", f"{self.dir.name}/nine.txt"
        with open(ref, "w") as f:
            f.writelines(f"{t} {x} {y} {th}\n" for t, x, y, th in curve)
        with open(nine, "w") as f:
            f.writelines(f"{t} {x + 1} {y} {th}\n" for t, x, y, th in curve[1:])
        def ate_run(*args):
            return subprocess.run([sys.executable, ate, *args, "--json"], capture_output=True,
                                  text=True)
        # By time and by index from pose 1 alike: the same poses, shifted.
        for extra in ([], ["--offset", "1"]):
            r = ate_run(nine, ref, *extra)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(json.loads(r.stdout)["count"], 9)
            self.assertLess(json.loads(r.stdout)["rmse_m"], 1e-9)
        # From pose 0 instead, every pose is one scan off along the curve.
        r = ate_run(nine, ref, "--offset", "0")
        self.assertGreater(json.loads(r.stdout)["rmse_m"], 0.01)
        # A reference whose times all coincide matches nothing by time.
        same = f"{self.dir.name}/same.txt"
        with open(same, "w") as f:
            f.writelines(f"100 {x} {y} {th}\n" for t, x, y, th in curve)
        r = ate_run(nine, same)
        self.assertEqual(r.returncode, 4)
        self.assertIn("no other pose of the reference shares", r.stderr)

    def test_a_malformed_heading_is_an_error(self):
        tum = f"{self.dir.name}/bad.tum"
        with open(tum, "w") as f:
            f.write("100.0 0.0 0.0 0.0 0.0 0.0 oops 1.0\n")
        r = run(self.log, tum)
        self.assertEqual(r.returncode, 4)
        self.assertIn("bad.tum:1: not a number", r.stderr)

    def assert_log_refused(self, name, text, message):
        path = f"{self.dir.name}/{name}"
        with open(path, "w") as f:
            f.write(text)
        r = run(path, self.true_path)
        self.assertEqual(r.returncode, 4)
        self.assertIn(message, r.stderr)

    def test_a_malformed_scan_line_is_an_error(self):
        self.assert_log_refused("bad.log", "FLASER 181 1.0 2.0 oops\n", "bad.log:1")

    def test_a_log_without_scans_is_an_error(self):
        self.assert_log_refused("empty.log", "PARAM x 1\n", "no FLASER")


if __name__ == "__main__":
    unittest.main()
