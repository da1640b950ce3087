#!/usr/bin/python3
"""Tests of scripts/closure_check.py on a constructed run.

The robot drives 30 m east and back (one pose a second, 0.5 m a step).
Area 1 is the first 10 m, area 2 the next 10 m (its frame at x = 10.5 m),
area 3 the last 10 m. On the way back the final line of hypotheses closes
into area 2 where the robot is (right), then into area 3 while the robot is
back at x = 10 m, 12 m from any of area 3's keyframes (elsewhere). A dead
branch's event (hypothesis 4's, at step 90) must not be judged.

Run directly or through ctest (closure_check_script).
"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "closure_check.py")
T0 = 100.0
STEPS = 121


def truth(step):
    """(x, y, theta) of the reference at a step."""
    if step <= 60:
        return (0.5 * step, 0.0, 0.0)
    return (30.0 - 0.5 * (step - 60), 0.0, math.pi)


ORIGIN = {1: 0.0, 2: 10.5, 3: 20.5}  # each area's frame: x of its origin, heading 0


def keyframe(area, step):
    x, y, th = truth(step)
    return [T0 + step, x - ORIGIN[area], y, th]


EVENT_COLUMNS = ["step", "time", "hypothesis", "hypothesis_probability", "from_area", "outcome",
                 "area", "log_f", "probability", "match_ratio", "child", "x", "y", "theta"]


def event(step, parent, from_area, outcome, area, p, child, mode=None):
    x, y, th = mode if mode else ("", "", "")
    return [step, f"{T0 + step:.6f}", parent, 1, from_area, outcome, area, 8.0, p, 0.7,
            child, x, y, th]


class ClosureCheck(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.out = os.path.join(self.dir.name, "out")
        os.makedirs(self.out)
        self.ref = os.path.join(self.dir.name, "ref.txt")
        self.write_ref(lambda s: T0 + s)
        self.best = 5
        self.right_mode = (19.5 - ORIGIN[2], 0.0, math.pi)  # step 81, in area 2's frame
        self.events = [
            event(21, 0, 1, "new", 2, 1, 1),
            event(41, 1, 2, "new", 3, 1, 2),
            event(81, 2, 3, "known", 2, 0.8, 3, self.right_mode),
            event(81, 2, 3, "new", 4, 0.2, 4),
            event(90, 4, 4, "known", 1, 1, 6, (15.0, 0.0, math.pi)),  # the dead branch
            event(100, 3, 2, "known", 3, 1, 5, (0.0, 0.0, math.pi)),
        ]
        self.areas = {
            1: [keyframe(1, s) for s in range(0, 21, 4)],
            2: [keyframe(2, s) for s in range(24, 41, 4)] + [keyframe(2, s) for s in (84, 92)],
            # Kept after the wrong closure, where the robot really was.
            3: [keyframe(3, s) for s in range(44, 61, 4)] + [[T0 + 104, -10.0, 0.0, math.pi]],
        }
        self.write_all()

    def tearDown(self):
        self.dir.cleanup()

    def write_ref(self, time_of):
        with open(self.ref, "w") as f:
            for s in range(STEPS):
                x, y, th = truth(s)
                f.write(f"{time_of(s):.3f} {x:.4f} {y:.4f} {th:.6f}\n")

    def write_all(self, keyframe_key="keyframe_poses", steps=None):
        """steps: {area: keyframe_steps}; None writes none (an older
        hmt-slam's output)."""
        with open(os.path.join(self.out, "tsbi_events.csv"), "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(EVENT_COLUMNS)
            w.writerows(self.events)
        with open(os.path.join(self.out, "summary.json"), "w") as f:
            json.dump({"hypotheses_at_end": 2, "best_hypothesis": self.best}, f)
        topo = {"root": 1, "arcs": [],
                "areas": [{"id": a, "keyframes": len(k), keyframe_key: k}
                          for a, k in self.areas.items()]}
        for area in topo["areas"]:
            if steps is not None:
                area["keyframe_steps"] = steps[area["id"]]
        with open(os.path.join(self.out, "topology.json"), "w") as f:
            json.dump(topo, f)
        with open(os.path.join(self.out, "trajectory.tum"), "w") as f:
            for s in range(STEPS):
                f.write(f"{T0 + s:.6f} 0 0 0 0 0 0 1\n")

    def run_script(self, *args):
        return subprocess.run([sys.executable, SCRIPT, self.out, self.ref, *args],
                              capture_output=True, text=True)

    def expect_error(self, text):
        """The script fails on the files as written, naming `text`."""
        r = self.run_script()
        self.assertEqual(r.returncode, 4, r.stdout)
        self.assertIn(text, r.stderr)

    def judged(self, *args):
        r = self.run_script("--json", *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        return json.loads(r.stdout)

    def test_the_final_line_is_judged_and_the_first_wrong_closure_named(self):
        j = self.judged()
        self.assertEqual([(d["step"], d["verdict"]) for d in j["decisions"]],
                         [(21, "new"), (41, "new"), (81, "right"), (100, "elsewhere")])
        right = j["decisions"][2]
        self.assertLess(right["mode_error_m"], 1e-6)
        self.assertAlmostEqual(right["nearest_keyframe_m"], 0.5, places=6)
        # Area 3's keyframe taken after the wrong closure sits where the
        # robot was; only those before it count: the nearest is 12 m away.
        self.assertAlmostEqual(j["decisions"][3]["nearest_keyframe_m"], 12.0, places=6)
        self.assertEqual(j["first_wrong_closure"]["step"], 100)
        self.assertEqual(j["counts"], {"new": 2, "right": 1, "elsewhere": 1})

    def test_a_mode_off_the_true_pose_is_the_wrong_place(self):
        self.events[2] = event(81, 2, 3, "known", 2, 0.8, 3, (5.0, 0.0, math.pi))
        self.write_all()
        d = self.judged()["decisions"][2]
        self.assertEqual(d["verdict"], "wrong_place")
        self.assertAlmostEqual(d["mode_error_m"], 4.0, places=6)
        # A looser tolerance takes it.
        self.assertEqual(self.judged("--tolerance", "4.5")["decisions"][2]["verdict"], "right")

    def test_a_right_closure_far_from_the_areas_keyframes_is_right(self):
        # A wide laser sees area 3 from 12 m away: the mode at the true pose
        # in area 3's frame is right, however far its keyframes.
        self.events[5] = event(100, 3, 2, "known", 3, 1, 5, (10.0 - ORIGIN[3], 0.0, math.pi))
        self.write_all()
        d = self.judged()["decisions"][3]
        self.assertEqual(d["verdict"], "right")
        self.assertAlmostEqual(d["nearest_keyframe_m"], 12.0, places=6)

    def test_a_new_area_where_an_older_one_was_mapped_is_a_revisit(self):
        self.events[2] = event(81, 2, 3, "new", 4, 0.8, 3)
        self.write_all()
        d = self.judged()["decisions"][2]
        self.assertEqual(d["verdict"], "revisit")
        # Area 2's keyframe of step 40 is 0.5 m away; area 3's nearest, 2.5 m.
        self.assertEqual((d["nearest_area"], d["nearest_keyframe_m"]), (2, 0.5))
        self.assertEqual(self.judged("--revisit", "0.25")["decisions"][2]["verdict"], "new")

    def test_rounded_timestamps_judge_nothing_they_cannot_place(self):
        # Every pose's time rounded to 10 s: a keyframe's time matches poses
        # metres apart. The events are placed by step (one pose per scan).
        self.write_ref(lambda s: T0 + 10 * round(s / 10))
        j = self.judged()
        self.assertEqual([d["verdict"] for d in j["decisions"]], ["new", "new", "unknown",
                                                                   "unknown"])

    def true_steps(self):
        """Each keyframe's step: its time less T0."""
        return {a: [round(k[0] - T0) for k in kfs] for a, kfs in self.areas.items()}

    def test_keyframe_steps_place_keyframes_the_times_cannot(self):
        self.write_ref(lambda s: T0 + 10 * round(s / 10))
        self.write_all(steps=self.true_steps())
        j = self.judged()
        self.assertEqual([d["verdict"] for d in j["decisions"]], ["new", "new", "right",
                                                                   "elsewhere"])
        # Only area 3's keyframes up to step 81 count: not the one at 104.
        self.assertAlmostEqual(j["decisions"][3]["nearest_keyframe_m"], 12.0, places=6)
        # A step not known (null) falls back to the keyframe's time.
        steps = self.true_steps()
        steps[3] = [None] * len(steps[3])
        self.write_all(steps=steps)
        self.assertEqual([d["verdict"] for d in self.judged()["decisions"]],
                         ["new", "new", "right", "unknown"])

    def test_a_keyframe_of_the_entering_step_counts_by_step_not_by_time(self):
        # Area 3's keyframe of step 81, taken there before the event of step
        # 81 took the robot into area 2: 9.5 m from the robot at step 100.
        self.areas[3].insert(5, keyframe(3, 81))
        self.write_all(steps=self.true_steps())
        self.assertAlmostEqual(self.judged()["decisions"][3]["nearest_keyframe_m"], 9.5, places=6)
        # Its time is the event's: by time it does not count.
        self.write_all()
        self.assertAlmostEqual(self.judged()["decisions"][3]["nearest_keyframe_m"], 12.0,
                               places=6)

    def test_malformed_keyframe_steps_are_errors(self):
        steps = self.true_steps()
        steps[2] = steps[2][1:]
        self.write_all(steps=steps)
        self.expect_error("area 2: keyframe_steps does not hold one step per keyframe pose")
        for bad in (-3, 2.5, True, "7"):
            steps = self.true_steps()
            steps[1][2] = bad
            self.write_all(steps=steps)
            self.expect_error("area 1: a keyframe step is")

    def test_a_new_area_beside_the_area_left_is_no_revisit(self):
        # At step 90 the robot (x = 15 m) is 1 m from area 2's keyframes of
        # the first pass, and leaves area 2: the event's arc joins the two.
        # The nearest other area's keyframe is area 1's, 5 m away.
        self.events[5] = event(90, 3, 2, "new", 5, 1, 5)
        self.write_all()
        d = self.judged()["decisions"][3]
        self.assertEqual((d["verdict"], d["nearest_area"], d["nearest_keyframe_m"]),
                         ("new", 1, 5.0))

    def test_the_dead_branch_is_judged_when_its_hypothesis_is_the_best(self):
        self.best = 6
        self.write_all()
        j = self.judged()
        self.assertEqual([(d["step"], d["verdict"]) for d in j["decisions"]],
                         [(21, "new"), (41, "new"), (81, "revisit"), (90, "right")])

    def test_bad_inputs_are_named_errors(self):
        self.write_all(keyframe_key="kf")
        self.expect_error("keyframe_poses")
        os.remove(os.path.join(self.out, "tsbi_events.csv"))
        self.expect_error("tsbi_events.csv")
        self.write_all()
        with open(os.path.join(self.out, "summary.json"), "w") as f:
            json.dump({"hypotheses_at_end": 0}, f)
        self.expect_error("best_hypothesis")

    def test_a_malformed_mode_or_reference_is_an_error(self):
        self.events[2][11] = "nan"
        self.write_all()
        self.expect_error("line 4: x")
        self.events[2][11] = self.right_mode[0]
        self.write_all()
        with open(self.ref, "w") as f:
            f.write("1.0 2.0\n")
        self.expect_error(self.ref)

    def test_a_run_without_events_has_nothing_to_judge(self):
        self.events = []
        self.write_all()
        r = self.run_script()
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("nothing to judge", r.stdout)
        self.assertEqual(self.judged()["decisions"], [])

    def test_a_malformed_count_is_an_error(self):
        self.events[1][4] = "2.5"
        self.write_all()
        self.expect_error("line 3: from_area is '2.5', not a count")

    def test_bad_arguments(self):
        for args in (["--near", "-1"], ["--tolerance", "nan"], ["--revisit", "0"]):
            r = self.run_script(*args)
            self.assertEqual(r.returncode, 2, args)

    def test_text_output_names_the_first_wrong_closure(self):
        r = self.run_script()
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("first closure not right: step 100 (2 -> 3, elsewhere)", r.stdout)


if __name__ == "__main__":
    unittest.main()
