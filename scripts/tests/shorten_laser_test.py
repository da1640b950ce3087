#!/usr/bin/python3
"""Tests of scripts/shorten_laser.py on small CARMEN logs.

Run directly or through ctest (shorten_laser_script).
"""
import gzip
import os
import tempfile
import unittest

from script_test_util import runner

run = runner("shorten_laser.py")

FLASER = "FLASER 4 1.5 3.99 4.01 81.91 0 0 0 0 0 0 1.0 host 1.0\n"
# One beam per quarter turn, two remissions, then the poses and safety fields.
ROBOTLASER = ("ROBOTLASER1 0 -3.141593 6.283185 1.570796 81.9 0.01 0 4 2.0 9.5 3.0 81.9 2 7 8"
              " 0 0 0 0 0 0 0 0 0 0 0 2.0 sim 2.0\n")


class ShortenLaser(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.log = os.path.join(self.dir.name, "in.log")
        with open(self.log, "w") as f:
            f.write("PARAM robot_front_laser_max 81.9\n")
            f.write(FLASER)
            f.write(ROBOTLASER)

    def tearDown(self):
        self.dir.cleanup()

    def lines(self, *args):
        out = os.path.join(self.dir.name, "out.log.gz")
        r = run(self.log, out, *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        with gzip.open(out, "rt") as f:
            return f.read().splitlines(), r.stdout

    def test_readings_beyond_the_range_become_the_no_return_code(self):
        lines, report = self.lines("--range", "4")
        self.assertEqual(lines[0], "PARAM robot_front_laser_max 81.9")
        # 4.01 and 81.91 lie beyond 4 m; 3.99 and 1.5 are kept as written.
        self.assertEqual(lines[1], "FLASER 4 1.5 3.99 5 5 0 0 0 0 0 0 1.0 host 1.0")
        self.assertIn("4 of 8 readings", report)

    def test_robotlaser_ranges_and_max_range_field_change_remissions_do_not(self):
        lines, _ = self.lines("--range", "4")
        f = lines[2].split()
        self.assertEqual(f[5], "5")                           # max_range
        self.assertEqual(f[9:13], ["2.0", "5", "3.0", "5"])   # the four beams
        self.assertEqual(f[13:16], ["2", "7", "8"])           # remissions untouched
        self.assertEqual(len(f), len(ROBOTLASER.split()))

    def test_a_range_beyond_every_reading_changes_nothing(self):
        lines, report = self.lines("--range", "100")
        self.assertEqual(lines[1] + "\n", FLASER)
        self.assertEqual(lines[2].split()[9:13], ["2.0", "9.5", "3.0", "81.9"])
        self.assertIn("0 of 8 readings", report)

    def test_readings_that_are_no_number_stay_as_written(self):
        with open(self.log, "w") as f:
            f.write("FLASER 3 nan 9.0 inf 0 0 0 0 0 0 1.0 host 1.0\n")
        lines, report = self.lines("--range", "4")
        self.assertEqual(lines[0].split()[2:5], ["nan", "5", "inf"])
        self.assertIn("1 of 3 readings", report)

    def test_a_log_that_fails_half_way_leaves_the_output_as_it_was(self):
        out = os.path.join(self.dir.name, "kept.log")
        with open(out, "w") as f:
            f.write("an earlier output\n")
        with open(self.log, "a") as f:
            f.write("FLASER 3 1.0\n")
        r = run(self.log, out, "--range", "4")
        self.assertNotEqual(r.returncode, 0)
        with open(out) as f:
            self.assertEqual(f.read(), "an earlier output\n")
        self.assertEqual(sorted(os.listdir(self.dir.name)), ["in.log", "kept.log"])

    def test_bad_input_is_refused(self):
        r = run(os.path.join(self.dir.name, "missing.log"), os.path.join(self.dir.name, "m.log"),
                "--range", "4")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("missing.log", r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        for bad in (["--range", "0"], ["--range", "-2"], ["--range", "nan"], []):
            r = run(self.log, os.path.join(self.dir.name, "x.log"), *bad)
            self.assertNotEqual(r.returncode, 0, bad)
        short = os.path.join(self.dir.name, "short.log")
        with open(short, "w") as f:
            f.write(FLASER)
            f.write("FLASER 3 1.0\n")
        r = run(short, os.path.join(self.dir.name, "y.log"), "--range", "4")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("short.log:2", r.stderr)
        word = os.path.join(self.dir.name, "word.log")
        with open(word, "w") as f:
            f.write("FLASER 2 1.0 far 0 0 0 0 0 0 1.0 host 1.0\n")
        r = run(word, os.path.join(self.dir.name, "z.log"), "--range", "4")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("word.log:1", r.stderr)


if __name__ == "__main__":
    unittest.main()
