#!/usr/bin/python3
"""Tests of scripts/degrade_laser.py on small CARMEN logs.

Run directly or through ctest (degrade_laser_script).
"""
import gzip
import os
import tempfile
import unittest

from script_test_util import runner

run = runner("degrade_laser.py")

FLASER = "FLASER 4 1.5 3.99 4.01 81.91 0 0 0 0 0 0 1.0 host 1.0\n"
# Four beams a quarter turn apart from -180 degrees, two remissions, then the
# poses and safety fields.
ROBOTLASER = ("ROBOTLASER1 0 -3.141593 6.283185 1.570796 81.9 0.01 0 4 2.0 9.5 3.0 81.9 2 7 8"
              " 0 0 0 0 0 0 0 0 0 0 0 2.0 sim 2.0\n")


def flaser(ranges):
    return f"FLASER {len(ranges)} {' '.join(ranges)} 0 0 0 0 0 0 1.0 host 1.0\n"


class DegradeLaser(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.log = os.path.join(self.dir.name, "in.log")
        self.write(["PARAM robot_front_laser_max 81.9\n", FLASER, ROBOTLASER])

    def tearDown(self):
        self.dir.cleanup()

    def write(self, lines):
        with open(self.log, "w") as f:
            f.writelines(lines)

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

    def test_beams_outside_the_field_of_view_take_the_logs_own_no_return_code(self):
        # 181 beams a degree apart from -90: a 90 degree view keeps beams
        # 45-135 (bearings -45..+45), the log's largest reading (81.91) is
        # the code.
        ranges = ["2.5"] * 181
        ranges[100] = "81.91"
        self.write([flaser(ranges)])
        lines, report = self.lines("--fov", "90")
        got = lines[0].split()[2:183]
        self.assertEqual(got[:45], ["81.91"] * 45)
        self.assertEqual(got[45:136], ranges[45:136])
        self.assertEqual(got[136:], ["81.91"] * 45)
        self.assertIn("90 of 181 readings", report)

    def test_range_and_field_of_view_together(self):
        ranges = ["2.5"] * 181
        ranges[90] = "30"
        self.write([flaser(ranges)])
        lines, _ = self.lines("--fov", "120", "--range", "8")
        got = lines[0].split()[2:183]
        self.assertEqual(got[:30], ["9"] * 30)
        self.assertEqual(got[30], "2.5")
        self.assertEqual(got[90], "9")      # straight ahead, beyond 8 m
        self.assertEqual(got[150], "2.5")
        self.assertEqual(got[151:], ["9"] * 30)

    def test_robotlaser_field_of_view_is_about_its_middle_bearing(self):
        # Bearings -180, -90, 0, +90: the middle is -45, so a 100 degree view
        # keeps -90 and 0 only.
        self.write([ROBOTLASER])
        lines, _ = self.lines("--fov", "100")
        self.assertEqual(lines[0].split()[9:13], ["81.9", "9.5", "3.0", "81.9"])

    def test_readings_that_are_no_number_stay_as_written(self):
        self.write(["FLASER 3 nan 9.0 inf 0 0 0 0 0 0 1.0 host 1.0\n"])
        lines, report = self.lines("--range", "4")
        self.assertEqual(lines[0].split()[2:5], ["nan", "5", "inf"])
        self.assertIn("1 of 3 readings", report)

    def test_a_log_that_fails_half_way_leaves_the_output_as_it_was(self):
        out = os.path.join(self.dir.name, "kept.log")
        with open(out, "w") as f:
            f.write("an earlier output\n")
        with open(self.log, "a") as f:
            f.write("FLASER 3 1.0\n")
        for args in (["--range", "4"], ["--fov", "90"]):
            r = run(self.log, out, *args)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("in.log:4", r.stderr)
            with open(out) as f:
                self.assertEqual(f.read(), "an earlier output\n")
            self.assertEqual(sorted(os.listdir(self.dir.name)), ["in.log", "kept.log"])

    def test_bad_input_is_refused(self):
        r = run(os.path.join(self.dir.name, "missing.log"), os.path.join(self.dir.name, "m.log"),
                "--range", "4")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("missing.log", r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        for bad in (["--range", "0"], ["--range", "-2"], ["--range", "nan"], ["--fov", "0"],
                    ["--fov", "400"], []):
            r = run(self.log, os.path.join(self.dir.name, "x.log"), *bad)
            self.assertNotEqual(r.returncode, 0, bad)
        for text, args, message in (
                ("FLASER 2 1.0 far 0 0 0 0 0 0 1.0 host 1.0\n", ["--range", "4"], "in.log:1"),
                ("PARAM robot_front_laser_max 81.9\n", ["--fov", "90"], "no FLASER or ROBOTLASER1")):
            self.write([text])
            r = run(self.log, os.path.join(self.dir.name, "z.log"), *args)
            self.assertNotEqual(r.returncode, 0, text)
            self.assertIn(message, r.stderr)


if __name__ == "__main__":
    unittest.main()
