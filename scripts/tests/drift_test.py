#!/usr/bin/python3
"""Tests of scripts/drift.py on trajectories whose drift is known.

Run directly or through ctest (drift_script).
"""
import json
import math
import tempfile
import unittest

from script_test_util import runner, write_rows

run = runner("drift.py")


class Drift(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        d = self.dir.name
        # The reference: 200 poses 1 m apart along x. The estimate turns by
        # K rad more than the truth every metre, and walks its own heading.
        self.k = 0.001
        ref = [(float(i), float(i), 0.0, 0.0) for i in range(200)]
        est = self.walk(self.k)
        self.ref, self.est = f"{d}/ref.txt", f"{d}/est.txt"
        write_rows(self.ref, ref, 9)
        write_rows(self.est, est, 9)

    @staticmethod
    def walk(k):
        """200 steps of 1 m, turning by k rad each."""
        est, x, y, th = [], 0.0, 0.0, 0.0
        for i in range(200):
            est.append((float(i), x, y, th))
            x, y, th = x + math.cos(th), y + math.sin(th), th + k
        return est

    def tearDown(self):
        self.dir.cleanup()

    def test_heading_error_grows_as_the_drift_per_metre(self):
        r = run(self.est, self.ref, "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = json.loads(r.stdout)
        self.assertEqual([(b["from_m"], b["to_m"]) for b in rows],
                         [(2, 5), (5, 10), (10, 20), (20, 40), (40, 80), (80, 160)])
        for b in rows:
            self.assertGreater(b["pairs"], 0)
            # A pair d metres (steps) apart is K d off in heading, and the
            # walk bends its end sideways by about K d (d - 1) / 2. Near the
            # log's end a bin holds shorter pairs than elsewhere, so d varies
            # a little within it: 10 % of slack.
            d = b["mean_distance_m"]
            self.assertTrue(b["from_m"] <= d < b["to_m"])
            self.assertAlmostEqual(b["heading_rms_rad"] / (self.k * d), 1.0, delta=0.1)
            self.assertLessEqual(b["heading_p95_rad"], self.k * b["to_m"])
            self.assertAlmostEqual(b["position_rms_m"] / (self.k * d * (d - 1) / 2), 1.0, delta=0.1)
        # And ten times the drift reads ten times the error.
        write_rows(self.est, self.walk(10 * self.k), 9)
        rows10 = json.loads(run(self.est, self.ref, "--json").stdout)
        self.assertAlmostEqual(rows10[3]["heading_rms_rad"] / rows[3]["heading_rms_rad"], 10.0,
                               delta=1e-6)

    def test_itself_has_no_drift(self):
        rows = json.loads(run(self.ref, self.ref, "--json").stdout)
        for b in rows:
            self.assertEqual(b["heading_rms_rad"], 0.0)
            self.assertEqual(b["position_rms_m"], 0.0)

    def test_trajectories_of_other_lengths_are_refused(self):
        short = f"{self.dir.name}/short.txt"
        with open(self.ref) as f, open(short, "w") as g:
            g.writelines(f.readlines()[:150])
        r = run(short, self.ref)
        self.assertEqual(r.returncode, 4)
        self.assertIn("150 poses", r.stderr)
        self.assertEqual(run(f"{self.dir.name}/missing.txt", self.ref).returncode, 4)
        self.assertEqual(run(self.ref).returncode, 2)


if __name__ == "__main__":
    unittest.main()
