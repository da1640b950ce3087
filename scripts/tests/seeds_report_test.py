#!/usr/bin/python3
"""Tests of scripts/seeds_report.py (the table of scripts/bench_seeds.sh) on
synthetic benchmark folders.

Run directly or through ctest (seeds_report_script).
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPORT = os.path.join(HERE, "..", "seeds_report.py")

TIME_TXT = """\tCommand being timed: "hmt-slam run"
\tElapsed (wall clock) time (h:mm:ss or m:ss): {wall}
\tMaximum resident set size (kbytes): {rss_kb}
"""


def run(*args):
    return subprocess.run([sys.executable, REPORT, *args], capture_output=True, text=True)


class SeedsReport(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.out = self.dir.name

    def tearDown(self):
        self.dir.cleanup()

    def add(self, log, seed, rmse=None, relations=None, wall=None, rss_mb=None, areas=None,
            closures=None, loops=None, checked=None, error=None):
        d = os.path.join(self.out, log, f"seed{seed}")
        os.makedirs(d)
        if rmse is not None:
            with open(os.path.join(d, "ate.json"), "w") as f:
                json.dump({"count": 10, "rmse_m": rmse, "max_m": 2 * rmse}, f)
        if relations is not None:
            with open(os.path.join(d, "relations.json"), "w") as f:
                json.dump({"count": 116, "trans_mean_m": relations}, f)
        if wall is not None:
            with open(os.path.join(d, "time.txt"), "w") as f:
                f.write(TIME_TXT.format(wall=wall, rss_kb=int(rss_mb * 1024)))
        if areas is not None:
            with open(os.path.join(d, "summary.json"), "w") as f:
                json.dump({"areas": areas, "loop_closures_accepted": closures}, f)
        if loops is not None:  # [(median error, closed), ...]
            with open(os.path.join(d, "loops.json"), "w") as f:
                json.dump({"loops": len(loops), "closed": sum(c for _, c in loops),
                           "each": [{"first_pair": [10 * k, 10 * k + 300], "path_m": 40.0 + k,
                                     "pairs": 3, "median_error_m": e, "max_error_m": 2 * e,
                                     "closed": c} for k, (e, c) in enumerate(loops)]}, f)
        if checked is not None:  # (counts, first wrong closure or None)
            with open(os.path.join(d, "closures.json"), "w") as f:
                json.dump({"decisions": [], "counts": checked[0],
                           "first_wrong_closure": checked[1]}, f)
        if error is not None:
            with open(os.path.join(d, "error.txt"), "w") as f:
                f.write(error)

    def rows(self, text):
        return {line.split("|")[1].strip(): [c.strip() for c in line.split("|")[2:-1]]
                for line in text.splitlines() if line.startswith("| ") and "---" not in line}

    def test_means_worst_and_count_above_threshold(self):
        self.add("intel", 1, rmse=0.08, relations=0.05, wall="0:08.50", rss_mb=57, areas=16,
                 closures=10, loops=[(0.05, True), (0.1, True)])
        self.add("intel", 2, rmse=0.20, relations=0.04, wall="0:09.50", rss_mb=59, areas=18,
                 closures=12, loops=[(0.05, True), (0.45, False)])
        self.add("seattle", 1, rmse=0.05, wall="0:01.80", rss_mb=28, areas=5, closures=3)
        self.add("seattle", 2, rmse=0.11, wall="0:02.20", rss_mb=30, areas=7, closures=5)
        with open(os.path.join(self.out, "logs.txt"), "w") as f:
            f.write("seattle intel\n")
        r = run(self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = self.rows(r.stdout)
        self.assertEqual(list(rows), ["log", "seattle", "intel"])  # the benchmark's order
        self.assertEqual(rows["intel"][:4], ["0.080 (rel. 0.0500)", "0.200 (rel. 0.0400)",
                                             "0.140", "0.200"])
        self.assertEqual(rows["intel"][4:], ["9.0", "58", "17.0", "11.0", "-", "3/4"])
        self.assertEqual(rows["seattle"][-1], "-")  # no loops.json
        self.assertIn("loops of the references left open: 1\n"
                      "  - intel seed 2: steps 10 -> 310 (41 m of path), error median 0.450 m",
                      r.stdout)
        self.assertEqual(rows["seattle"][:4], ["0.050", "0.110", "0.080", "0.110"])
        self.assertIn("runs: 4; position RMSE mean 0.110 m, worst 0.200 m (intel seed 2); "
                      "above 0.15 m: 1", r.stdout)
        self.assertIn("relation error: mean 0.0450 m over 2 runs, worst 0.0500 m", r.stdout)
        self.assertIn("failed runs: 0", r.stdout)
        # A stricter threshold counts more runs.
        self.assertIn("above 0.06 m: 3", run(self.out, "--threshold", "0.06").stdout)

    def test_many_open_loops_are_summed_up_a_run_a_line(self):
        self.add("office1", 1, rmse=6.0, loops=[(4.0, False)] * 20 + [(0.1, True)])
        self.add("office1", 2, rmse=5.0, loops=[(2.5, False)] * 11 + [(9.0, False)])
        r = run(self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.rows(r.stdout)["office1"][-1], "1/33")
        self.assertIn("loops of the references left open: 32\n"
                      "  - office1 seed 1: 20 open, error median up to 4.000 m "
                      "(office1/seed1/loops.json)\n"
                      "  - office1 seed 2: 12 open, error median up to 9.000 m "
                      "(office1/seed2/loops.json)\n"
                      "- failed runs: 0", r.stdout)
        self.assertNotIn("steps 0 -> 300", r.stdout)

    def test_closures_the_reference_disagrees_with(self):
        first = {"step": 836, "from_area": 8, "area": 2, "verdict": "elsewhere"}
        self.add("office4", 1, rmse=10.1,
                 checked=({"new": 9, "right": 20, "elsewhere": 5, "wrong_place": 2,
                           "unknown": 1}, first))
        self.add("office4", 2, rmse=0.3, checked=({"new": 9, "right": 25}, None))
        self.add("office4", 3, rmse=0.4)  # no closures.json
        r = run(self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.rows(r.stdout)["office4"][-2], "45/52")
        self.assertIn("- closures the references disagree with: 7\n"
                      "  - office4 seed 1: 7, the first at step 836 (8 -> 2, elsewhere)\n"
                      "- loops of the references left open", r.stdout)

    def test_failed_run_is_counted_not_dropped(self):
        self.add("csail", 1, rmse=0.13)
        self.add("csail", 2, error="timeout: still running")
        self.add("csail", 3)  # neither figures nor an error: it failed too
        r = run(self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.rows(r.stdout)["csail"][:5], ["0.130", "failed", "failed", "0.130",
                                                            "0.130"])
        self.assertIn("runs: 3;", r.stdout)
        self.assertIn("failed runs: 2", r.stdout)
        self.assertIn("csail seed 2: timeout: still running", r.stdout)
        self.assertIn("csail seed 3: no ate.json", r.stdout)

    def test_only_the_logs_of_logs_txt(self):
        self.add("intel", 1, rmse=0.08)
        self.add("aces", 1, rmse=0.5)  # left from another benchmark
        with open(os.path.join(self.out, "logs.txt"), "w") as f:
            f.write("intel\n")
        r = run(self.out)
        self.assertEqual(list(self.rows(r.stdout)), ["log", "intel"])
        self.assertIn("worst 0.080 m", r.stdout)

    def test_bad_input(self):
        r = run(os.path.join(self.out, "missing"))
        self.assertEqual(r.returncode, 4)
        self.assertIn("not a folder", r.stderr)
        r = run(self.out)  # empty
        self.assertEqual(r.returncode, 4)
        self.assertIn("no LOG/seedS runs", r.stderr)
        self.add("intel", 1, rmse=0.08)
        r = run(self.out, "--threshold", "nan")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--threshold", r.stderr)


if __name__ == "__main__":
    unittest.main()
