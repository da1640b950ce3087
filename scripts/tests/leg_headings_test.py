#!/usr/bin/python3
"""Tests of scripts/leg_headings.py on paths whose legs are known.

Run directly or through ctest (leg_headings_script).
"""
import json
import math
import tempfile
import unittest

from script_test_util import runner, write_rows

run = runner("leg_headings.py")


def walk(headings_deg, leg_m=40):
    """A path of 1 m steps: leg_m steps along each heading in turn."""
    rows, x, y, i = [], 0.0, 0.0, 0
    for h in headings_deg:
        for _ in range(leg_m):
            rows.append((float(i), x, y, math.radians(h)))
            x += math.cos(math.radians(h))
            y += math.sin(math.radians(h))
            i += 1
    rows.append((float(i), x, y, math.radians(headings_deg[-1])))
    return rows


class LegHeadings(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        d = self.dir.name
        self.ref, self.est = f"{d}/ref.txt", f"{d}/est.txt"
        # A square block walked once round; the estimate turns the last
        # three legs 2 degrees too far, as a map turned at its first corner.
        write_rows(self.ref, walk([0, 90, 180, 270]), 9)
        write_rows(self.est, walk([0, 92, 182, 272]), 9)

    def tearDown(self):
        self.dir.cleanup()

    def json_of(self, *args):
        r = run(*args, "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        return json.loads(r.stdout)

    def test_finds_the_legs_of_the_reference(self):
        out = self.json_of(self.est, self.ref)
        self.assertEqual([(g["first"], g["last"]) for g in out["legs"]],
                         [(0, 40), (40, 80), (80, 120), (120, 160)])
        for g in out["legs"]:
            self.assertAlmostEqual(g["length_m"], 40.0, places=6)

    def test_a_square_path_lies_on_its_grid(self):
        out = self.json_of(self.est, self.ref)
        self.assertAlmostEqual(out["rms_deg"][1], 0.0, places=6)
        self.assertAlmostEqual(out["axis_deg"][1], 0.0, places=6)
        for g in out["legs"]:
            self.assertAlmostEqual(g["deviation_deg"][1], 0.0, places=6)

    def test_a_turned_block_shows_as_its_turn(self):
        out = self.json_of(self.est, self.ref)
        dev = [g["deviation_deg"][0] for g in out["legs"]]
        # Whatever the axis, the first leg is 2 degrees off the other three.
        for d in dev[1:]:
            self.assertAlmostEqual(d - dev[0], 2.0, places=6)
        # The axis is the legs' mean (1.5 degrees): deviations -1.5, +0.5 x 3.
        self.assertAlmostEqual(out["axis_deg"][0], 1.5, delta=0.01)
        self.assertAlmostEqual(out["rms_deg"][0], math.sqrt((1.5 ** 2 + 3 * 0.5 ** 2) / 4),
                               delta=0.01)

    def test_the_trajectory_alone_uses_its_own_legs(self):
        out = self.json_of(self.est)
        self.assertEqual(len(out["legs"]), 4)
        self.assertEqual(len(out["rms_deg"]), 1)
        self.assertGreater(out["rms_deg"][0], 0.8)

    def test_legs_shorter_than_the_minimum_are_not_legs(self):
        out = self.json_of(self.est, self.ref, "--min-length", "50")
        self.assertEqual(out["legs"], [])
        r = run(self.est, self.ref, "--min-length", "50")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("0 straight legs", r.stdout)

    def test_a_leg_off_the_grid_is_left_out_of_the_rms(self):
        # A diagonal leg between two square ones: listed, not counted.
        write_rows(self.ref, walk([0, 45, 90]), 9)
        out = self.json_of(self.ref)
        self.assertEqual(len(out["legs"]), 3)
        self.assertAlmostEqual(abs(out["legs"][1]["deviation_deg"][0]), 45.0, delta=1e-6)
        self.assertAlmostEqual(out["rms_deg"][0], 0.0, places=6)

    def test_the_turns_and_what_each_adds(self):
        out = self.json_of(self.est, self.ref)
        # Three corners of 90 degrees; the estimate turns 2 too far at the
        # first only.
        self.assertEqual(out["turns"], 3)
        self.assertAlmostEqual(out["turn_error_rms_deg"], 2.0 / math.sqrt(3), places=6)
        write_rows(self.est, walk([0, 90, 180, 270]), 9)
        self.assertAlmostEqual(self.json_of(self.est, self.ref)["turn_error_rms_deg"], 0.0,
                               places=6)
        # Alone, a trajectory has no reference to count turns by.
        self.assertNotIn("turns", self.json_of(self.est))

    def test_bad_input_is_refused(self):
        write_rows(self.est, walk([0, 90]), 9)
        r = run(self.est, self.ref)
        self.assertEqual(r.returncode, 4)
        self.assertIn("must be as many", r.stderr)
        with open(self.est, "w") as f:
            f.write("1 2 x 4\n")
        r = run(self.est, self.ref)
        self.assertEqual(r.returncode, 4)
        self.assertIn("not a number", r.stderr)
        r = run(self.ref, "--min-length", "-3")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--min-length", r.stderr)
        r = run(self.ref, "--tolerance")
        self.assertEqual(r.returncode, 2)
        r = run()
        self.assertEqual(r.returncode, 2)


if __name__ == "__main__":
    unittest.main()
