#!/usr/bin/python3
"""Tests of scripts/relation_error.py on small trajectories and relations.

Run directly or through ctest (relation_error_script).
"""
import gzip
import os
import shutil
import tempfile
import unittest

from script_test_util import runner, write_rows

run = runner("relation_error.py")


class RelationError(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        d = self.dir.name
        # Four poses 1 m apart along x ("t x y theta").
        self.truth = [(10.0 + k, float(k), 0.0, 0.0) for k in range(4)]
        # The estimate: right but for a 0.3 m slip in y at the last pose.
        est = [list(p) for p in self.truth]
        est[3][2] = 0.3
        # The other trajectory: the same slip, 0.02 m more.
        other = [list(p) for p in self.truth]
        other[3][2] = 0.32
        self.est, self.other = f"{d}/est.txt", f"{d}/other.txt"
        write_rows(self.est, est)
        write_rows(self.other, other)
        # Relations (t1 t2 x y z roll pitch yaw): 0-1, 1-2 (exact), 2-3
        # (the slip), and one whose two ends match one pose (skipped).
        self.rel = f"{d}/rel.txt"
        write_rows(self.rel, [(10, 11, 1, 0, 0, 0, 0, 0), (11, 12, 1, 0, 0, 0, 0, 0),
                              (12, 13, 1, 0, 0, 0, 0, 0), (12.001, 12.002, 0.3, 0, 0, 0, 0, 0)])

    def tearDown(self):
        self.dir.cleanup()

    def test_mean_error_counts_the_usable_relations(self):
        r = run(self.est, self.rel)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("relations: 3", r.stdout)
        self.assertIn("translational 0.1000", r.stdout)

    def test_worst_lists_the_slip_and_the_other_trajectorys_errors(self):
        r = run(self.est, self.rel, "--worst", "1", "--against", self.other)
        self.assertEqual(r.returncode, 0, r.stderr)
        lines = r.stdout.splitlines()
        self.assertRegex(lines[1], r"scans\s+2\s+3 .*error 0\.300 m")
        self.assertIn("other 0.320 m", lines[1])
        self.assertIn("between them 0.020 m", lines[1])
        self.assertIn("without these 1: 0.0000 m over 2", lines[2])

    def test_a_gzipped_other_trajectory_is_read(self):
        # The datasets' references are gzipped (NAME.reference.txt.gz).
        gz = self.other + ".gz"
        with open(self.other, "rb") as src, gzip.open(gz, "wb") as dst:
            shutil.copyfileobj(src, dst)
        r = run(self.est, self.rel, "--worst", "1", "--against", gz)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("other 0.320 m", r.stdout.splitlines()[1])

    def test_a_malformed_trajectory_is_a_clear_error(self):
        bad = os.path.join(self.dir.name, "bad.txt")
        with open(bad, "w") as f:
            f.write("10 0 0\n")
        r = run(bad, self.rel)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("expected 4 or 8 fields", r.stderr)

    def test_bad_options_are_refused(self):
        self.assertNotEqual(run(self.est, self.rel, "--worst", "x").returncode, 0)
        self.assertNotEqual(run(self.est, self.rel, "--against", self.other).returncode, 0)
        self.assertNotEqual(run(self.est, self.rel, "--worst").returncode, 0)


if __name__ == "__main__":
    unittest.main()
