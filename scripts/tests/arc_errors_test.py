#!/usr/bin/python3
"""Tests of scripts/arc_errors.py on a run whose arcs' errors are known.

Run directly or through ctest (arc_errors_script).
"""
import json
import math
import os
import tempfile
import unittest

from script_test_util import runner, write_rows

run = runner("arc_errors.py")


def area(id_, created, parent, keyframes):
    a = {"id": id_, "created_step": created,
         "keyframe_steps": [k[0] for k in keyframes],
         "keyframe_poses": [[float(k[0])] + list(k[1:]) for k in keyframes]}
    if parent is not None:
        a["parent"] = parent
    return a


class ArcErrors(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        d = self.dir.name
        # The reference: 30 poses 1 m apart along x, heading 0.
        self.ref = f"{d}/ref.txt"
        write_rows(self.ref, [(float(i), float(i), 0.0, 0.0) for i in range(30)])
        # Area 1 begins at step 0, area 2 at step 4 (4 m on), area 3 at step
        # 24 (20 m on from area 2's origin). Area 1 holds area 2's origin
        # 0.1 m and 0.01 rad off; area 2 holds area 3's 0.5 m and 0.03 rad
        # off; area 4's parent holds no keyframe at its step.
        topology = {"root": 1, "arcs": [], "areas": [
            area(1, 0, None, [(0, 0.0, 0.0, 0.0), (4, 4.1, 0.0, 0.01)]),
            area(2, 4, 1, [(5, 1.0, 0.0, 0.0), (24, 20.0, 0.5, -0.03)]),
            area(3, 24, 2, [(25, 1.0, 0.0, 0.0)]),
            area(4, 28, 3, [(29, 1.0, 0.0, 0.0)]),
        ]}
        with open(f"{d}/topology.json", "w") as f:
            json.dump(topology, f)
        with open(f"{d}/config_effective.ini", "w") as f:
            f.write("[hmt]\narc_std_theta = 0.02 ; rad\narc_std_theta_per_metre = 0.002\n"
                    "arc_std_theta_max = 0.1\n")

    def tearDown(self):
        self.dir.cleanup()

    def test_each_creating_arc_against_the_reference(self):
        r = run(self.dir.name, self.ref, "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        out = json.loads(r.stdout)
        self.assertEqual(out["skipped"], 1)  # area 4
        bins = {b["from_m"]: b for b in out["bins"]}
        self.assertEqual(bins[0]["arcs"], 1)     # 4.1 m
        self.assertAlmostEqual(bins[0]["heading_rms_rad"], 0.01, places=6)
        self.assertAlmostEqual(bins[0]["position_rms_m"], 0.1, places=6)
        self.assertEqual(bins[20]["arcs"], 1)    # 20.006 m
        self.assertAlmostEqual(bins[20]["heading_max_rad"], 0.03, places=6)
        self.assertAlmostEqual(bins[20]["position_rms_m"], 0.5, places=6)
        self.assertEqual(bins[5]["arcs"], 0)
        # The floor the run's configuration gives at the bin's length.
        self.assertAlmostEqual(bins[0]["heading_floor_rad"], 0.02 + 0.002 * 4.1, places=6)
        self.assertAlmostEqual(bins[20]["heading_floor_rad"],
                               0.02 + 0.002 * math.hypot(20.0, 0.5), places=6)

    def test_the_text_table(self):
        r = run(self.dir.name, self.ref)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("2 creating arcs (1 left out", r.stdout)

    def test_bad_input_exits_4_naming_the_file(self):
        r = run(os.path.join(self.dir.name, "nowhere"), self.ref)
        self.assertEqual(r.returncode, 4)
        self.assertIn("topology.json", r.stderr)
        r = run(self.dir.name, os.path.join(self.dir.name, "missing.txt"))
        self.assertEqual(r.returncode, 4)
        self.assertIn("missing.txt", r.stderr)
        with open(os.path.join(self.dir.name, "topology.json"), "w") as f:
            f.write('{"areas": 3}')
        r = run(self.dir.name, self.ref)
        self.assertEqual(r.returncode, 4)
        self.assertIn("not a run's topology", r.stderr)


if __name__ == "__main__":
    unittest.main()
