#!/usr/bin/python3
"""Tests of scripts/thin_log.py on small CARMEN logs.

Run directly or through ctest (thin_log_script).
"""
import gzip
import os
import tempfile
import unittest

from script_test_util import runner

run = runner("thin_log.py")


def flaser(i):
    return f"FLASER 2 1.0 {i}.5 0 0 0 {i} 0 0 {i}.0 host {i}.0\n"


ROBOTLASER = ("ROBOTLASER1 0 -3.141593 6.283185 1.570796 81.9 0.01 0 4 2.0 9.5 3.0 81.9 0"
              " 0 0 0 0 0 0 0 0 0 0 0 7.0 sim 7.0\n")


class ThinLog(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.log = self.path("in.log")
        self.ref = self.path("in.ref.gz")
        lines = ["PARAM robot_front_laser_max 81.9\n"]
        for i in range(7):
            lines += [flaser(i), f"ODOM {i} 0 0 0 0 0 {i}.2 host {i}.2\n"]
        lines.append(ROBOTLASER)
        with open(self.log, "w") as f:
            f.writelines(lines)
        with gzip.open(self.ref, "wt") as f:
            f.write("# timestamp x y theta\n")
            f.writelines(f"{i}.0 {i} 0 0\n" for i in range(8))

    def tearDown(self):
        self.dir.cleanup()

    def path(self, name):
        return os.path.join(self.dir.name, name)

    def read(self, path):
        with (gzip.open(path, "rt") if path.endswith(".gz") else open(path)) as f:
            return f.read().splitlines()

    def test_one_scan_in_k_from_the_first_and_every_other_line(self):
        out, ref = self.path("out.log.gz"), self.path("out.ref")
        r = run(self.log, out, "--every", "3", "--reference", self.ref, ref)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("3 of 8 scans", r.stdout)
        lines = self.read(out)
        scans = [s for s in lines if s.split()[0] in ("FLASER", "ROBOTLASER1")]
        self.assertEqual(scans, [flaser(0).strip(), flaser(3).strip(), flaser(6).strip()])
        self.assertEqual(lines[0], "PARAM robot_front_laser_max 81.9")
        self.assertEqual(sum(s.startswith("ODOM") for s in lines), 7)
        # The reference keeps its comment and the poses of the kept scans.
        self.assertEqual(self.read(ref), ["# timestamp x y theta", "0.0 0 0 0", "3.0 3 0 0",
                                          "6.0 6 0 0"])

    def test_every_one_copies_the_log(self):
        out = self.path("same.log")
        self.assertEqual(run(self.log, out, "--every", "1").returncode, 0)
        self.assertEqual(self.read(out), self.read(self.log))

    def test_a_reference_of_another_length_is_an_error_and_writes_nothing(self):
        with gzip.open(self.ref, "wt") as f:
            f.write("0.0 0 0 0\n1.0 1 0 0\n")
        out, ref = self.path("out.log"), self.path("out.ref")
        r = run(self.log, out, "--every", "2", "--reference", self.ref, ref)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("2 poses for the log's 8 scans", r.stderr)
        self.assertEqual(sorted(os.listdir(self.dir.name)), ["in.log", "in.ref.gz"])

    def test_bad_input_is_a_clear_error(self):
        r = run(self.path("missing.log"), self.path("o.log"), "--every", "2")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("missing.log", r.stderr)
        r = run(self.log, self.path("o.log"), "--every", "0")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--every must be at least 1", r.stderr)
        with open(self.path("empty.log"), "w") as f:
            f.write("PARAM x 1\n")
        r = run(self.path("empty.log"), self.path("o.log"), "--every", "2")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("no FLASER or ROBOTLASER1 line", r.stderr)
        self.assertFalse(os.path.exists(self.path("o.log")))


if __name__ == "__main__":
    unittest.main()
