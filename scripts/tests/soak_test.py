#!/usr/bin/python3
"""Tests of scripts/soak_log.py and scripts/soak_report.py on small logs.

Run directly or through ctest (soak_scripts).
"""
import csv
import gzip
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SOAK_LOG = os.path.join(HERE, "..", "soak_log.py")
SOAK_REPORT = os.path.join(HERE, "..", "soak_report.py")


def flaser(ranges, pose, t):
    p = " ".join(f"{v:.6f}" for v in pose)
    return f"FLASER {len(ranges)} {' '.join(map(str, ranges))} {p} {p} {t:.6f} host {t:.6f}\n"


def fields_of(line):
    f = line.split()
    n = int(f[1])
    return [float(v) for v in f[n + 5:n + 8]], float(f[n + 8])


class SoakLog(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        d = self.dir.name
        # A square driven once: odometry that drifted 0.5 m and 0.1 rad; the
        # reference says the last scan is 1 m before the first, facing it.
        self.odom = [(0, 0, 0), (1, 0, 0), (1, 1, 1.6), (0.5, 1.2, 3.1), (-0.5, 0.3, -1.5)]
        self.ref = [(0, 0, 0), (1, 0, 0), (1, 1, 1.57), (0, 1, 3.14), (-1, 0, 0)]
        with open(f"{d}/log", "w") as f:
            f.write("PARAM robot_front_laser_max 30\n")
            for i, p in enumerate(self.odom):
                f.write(flaser([1.0, 2.0, 3.0], p, 10.0 + i))
        with open(f"{d}/ref", "w") as f:
            for i, p in enumerate(self.ref):
                f.write(f"{10.0 + i} {p[0]} {p[1]} {p[2]}\n")

    def tearDown(self):
        self.dir.cleanup()

    def build(self, laps, out="soak.log.gz"):
        d = self.dir.name
        return subprocess.run([sys.executable, SOAK_LOG, f"{d}/log", f"{d}/ref", str(laps), f"{d}/{out}"],
                              capture_output=True, text=True)

    def test_laps_continue_the_odometry_by_the_reference_seam(self):
        r = self.build(3)
        self.assertEqual(r.returncode, 0, r.stderr)
        with gzip.open(f"{self.dir.name}/soak.log.gz", "rt") as f:
            lines = f.readlines()
        self.assertEqual(lines[0], "PARAM robot_front_laser_max 30\n")
        scans = [fields_of(l) for l in lines if l.startswith("FLASER")]
        self.assertEqual(len(scans), 15)
        # The first lap is the log itself.
        for (o, _), p in zip(scans[:5], self.odom):
            self.assertAlmostEqual(o[0], p[0], places=5)
            self.assertAlmostEqual(o[1], p[1], places=5)
        # Across each seam the odometry moves as the reference moves from the
        # last scan to the first: 1 m straight ahead of a robot facing 0 rad.
        for seam in (5, 10):
            (a, _), (b, _) = scans[seam - 1], scans[seam]
            c, s = math.cos(a[2]), math.sin(a[2])
            dx, dy = b[0] - a[0], b[1] - a[1]
            self.assertAlmostEqual(c * dx + s * dy, 1.0, places=4)
            self.assertAlmostEqual(-s * dx + c * dy, 0.0, places=4)
            self.assertAlmostEqual(math.remainder(b[2] - a[2], 2 * math.pi), 0.0, places=4)
        # Within a lap the motion is the log's own.
        for lap in (1, 2):
            for i in range(1, 5):
                (a, _), (b, _) = scans[lap * 5 + i - 1], scans[lap * 5 + i]
                self.assertAlmostEqual(math.hypot(b[0] - a[0], b[1] - a[1]),
                                       math.hypot(self.odom[i][0] - self.odom[i - 1][0],
                                                  self.odom[i][1] - self.odom[i - 1][1]), places=4)
        times = [t for _, t in scans]
        self.assertEqual(times, sorted(times))
        self.assertEqual(len(set(times)), len(times))

    def test_a_reference_of_another_length_is_refused(self):
        with open(f"{self.dir.name}/ref", "a") as f:
            f.write("15 0 0 0\n")
        r = self.build(2)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("6 poses for 5 FLASER lines", r.stderr)


class SoakReport(unittest.TestCase):
    def test_laps_memory_times_and_closures(self):
        with tempfile.TemporaryDirectory() as d:
            def write(name, header, rows):
                with open(f"{d}/{name}", "w", newline="") as f:
                    w = csv.writer(f)
                    w.writerow(header)
                    w.writerows(rows)
            write("memory.csv", ["step", "time", "peak_rss_mb", "map_memory_mb", "hypotheses", "areas"],
                  [[0, 0, 10, 1, 1, 1], [3, 0, 50, 5, 1, 2], [7, 0, 52, 4, 1, 2]])
            write("process_times.csv", ["step", "time", "metric_slam_ms", "aam_ms", "tsbi_ms", "tlca_ms"],
                  [[s, 0, 2.0 * (s + 1), 0, 0, 0] for s in range(8)])
            # Lap 2 (steps 4-7): three scans back in area 1, one in its own area 3.
            write("topological_pmf.csv", ["step", "time", "area", "probability"],
                  [[0, 0, 1, 1], [1, 0, 1, 1], [2, 0, 2, 1], [3, 0, 2, 1], [4, 0, 1, 0.9], [4, 0, 3, 0.1],
                   [5, 0, 1, 1], [6, 0, 1, 1], [7, 0, 3, 1]])
            with open(f"{d}/topology.json", "w") as f:
                json.dump({"areas": [{"id": 1, "created_step": 0}, {"id": 2, "created_step": 2},
                                     {"id": 3, "created_step": 7}]}, f)
            r = subprocess.run([sys.executable, SOAK_REPORT, d, "4", "--json"], capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stderr)
            laps = json.loads(r.stdout)
            self.assertEqual([l["lap"] for l in laps], [1, 2])
            self.assertEqual([l["peak_rss_mb"] for l in laps], [50, 52])
            self.assertEqual([l["ms_per_scan"][0] for l in laps], [5.0, 13.0])
            self.assertEqual([l["areas_created"] for l in laps], [2, 1])
            self.assertEqual([l["share_in_first_lap_areas"] for l in laps], [1.0, 0.75])

    def test_a_missing_output_is_an_error(self):
        with tempfile.TemporaryDirectory() as d:
            r = subprocess.run([sys.executable, SOAK_REPORT, d, "4"], capture_output=True, text=True)
            self.assertEqual(r.returncode, 4)
            self.assertIn("memory.csv", r.stderr)


if __name__ == "__main__":
    unittest.main()
