#!/usr/bin/python3
"""Tests of scripts/report.py on small synthetic output folders of `hmt-slam run`.

Run directly (python3 scripts/tests/report_test.py) or through ctest
(report_script). Needs python3-matplotlib, as report.py does.
"""
import json
import os
import shutil
import struct
import subprocess
import tempfile
import unittest
import zlib
from html.parser import HTMLParser

REPORT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "report.py")
FIGURES = ["pmf.png", "tsbi_events.png", "process_times.png", "ess.png", "memory.png"]
MAP_IMAGES = ["map.png", "map_topology.png", "areas/area_1.png", "areas/area_2.png",
              "areas/area_10.png"]


def tiny_png(width=4, height=3):
    """A valid grey PNG, built with the standard library."""
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    raw = b"".join(b"\x00" + bytes([128] * width) for _ in range(height))
    return (b"\x89PNG\r\n\x1a\n" +
            chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="") as f:
        f.write(text)


def make_output_folder(root):
    """A small, consistent output folder: 30 steps, three areas, one loop closure."""
    t0 = 1137834225.0
    pmf = ["step,time,area,probability"]
    ess = ["step,time,hypothesis,probability,area,ess,particles"]
    times = ["step,time,metric_slam_ms,aam_ms,tsbi_ms,tlca_ms"]
    for s in range(30):
        t = f"{t0 + 0.25 * s:.6f}"
        if s < 10:
            pmf.append(f"{s},{t},1,1")
            ess.append(f"{s},{t},0,1,1,{30 - s},30")
        elif s < 20:
            pmf += [f"{s},{t},2,0.7", f"{s},{t},1,0.3"]
            ess += [f"{s},{t},1,0.7,2,{20 + s % 3},21", f"{s},{t},2,0.3,1,{5 + s % 2},9"]
        else:
            pmf += [f"{s},{t},1,0.96", f"{s},{t},3,0.04"]
            ess.append(f"{s},{t},2,1,1,{40 - s},30")
        event = s in (10, 20)
        times.append(f"{s},{t},{20 + s % 4}.5,{3.25 if s % 5 == 0 else 0},"
                     f"{12.5 if event else 0},{40 if s == 20 else 0}")
    tsbi = ["step,time,hypothesis,hypothesis_probability,from_area,outcome,area,"
            "log_f,probability,match_ratio,child,x,y,theta",
            f"10,{t0 + 2.5:.6f},0,1,1,new,2,8.0000,0.7,0.0000,1,,,",
            f"10,{t0 + 2.5:.6f},0,1,1,known,3,8.1000,0.3,0.6000,2,1.5,-2.25,0.125",
            f"20,{t0 + 5:.6f},1,0.7,2,new,,8.0000,1e-06,0.0000,,,,",
            f"20,{t0 + 5:.6f},1,0.7,2,known,1,21.6613,0.999999,0.8471,3,0.5,0.25,-3.1"]
    memory = ["step,time,peak_rss_mb,map_memory_mb,hypotheses,areas",
              f"0,{t0:.6f},90.5,0.7,1,1", f"15,{t0 + 3.75:.6f},120.25,10.5,2,2",
              f"29,{t0 + 7.25:.6f},130,12,1,3"]
    for name, lines in [("topological_pmf.csv", pmf), ("ess.csv", ess),
                        ("process_times.csv", times), ("tsbi_events.csv", tsbi),
                        ("memory.csv", memory)]:
        write(os.path.join(root, name), "\n".join(lines) + "\n")
    summary = {"input": "datasets/synthetic.rawlog", "scans": 30, "particles": 30,
               "wall_time_s": 1.25, "peak_rss_mb": 130.0, "peak_map_memory_mb": 12.0,
               "final_pose": {"x": 0.5, "y": -1.0, "theta": 0.1}, "areas": 3, "arcs": 3,
               "keyframes": 9, "new_area_events": 2, "transitions_evaluated": 2,
               "loop_closures_accepted": 1, "max_hypotheses_alive": 2,
               "hypotheses_at_end": 1, "an_extra_key": [1, 2],
               "global_poses": {"method": "least_squares", "iterations": 3,
                                "initial_chi2": 5.2, "final_chi2": 0.1, "converged": True}}
    write(os.path.join(root, "summary.json"), json.dumps(summary, indent=2))
    pose = {"x": 1.0, "y": 2.0, "theta": 0.5}
    topology = {"root": 1,
                "areas": [{"id": i, "keyframes": 3, "parent": None if i == 1 else i - 1,
                           "created_step": 10 * (i - 1), "global_pose": pose}
                          for i in (1, 2, 3)],
                "arcs": [{"from": 1, "to": 2, "measurements": 1, "mean": pose},
                         {"from": 2, "to": 3, "measurements": 1, "mean": pose},
                         {"from": 1, "to": 3, "measurements": 2, "mean": pose}]}
    write(os.path.join(root, "topology.json"), json.dumps(topology, indent=2))
    for name in MAP_IMAGES:
        os.makedirs(os.path.dirname(os.path.join(root, name)), exist_ok=True)
        with open(os.path.join(root, name), "wb") as f:
            f.write(tiny_png())


def run_report(*args):
    # As a user runs it: by its shebang (Debian's /usr/bin/python3).
    return subprocess.run([REPORT, *args], capture_output=True, text=True, timeout=300)


def check_png(test, path):
    """Asserts that path is a non-empty PNG whose chunks are well formed."""
    with open(path, "rb") as f:
        data = f.read()
    test.assertTrue(data.startswith(b"\x89PNG\r\n\x1a\n"), path)
    pos, kinds = 8, []
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        test.assertEqual(zlib.crc32(kind + body) & 0xFFFFFFFF, crc, f"{path}: bad CRC")
        kinds.append(kind)
        pos += 12 + length
    test.assertEqual(kinds[0], b"IHDR", path)
    test.assertEqual(kinds[-1], b"IEND", path)
    width, height = struct.unpack(">II", data[16:24])
    test.assertGreater(width * height, 0, path)


class Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.links = []

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if name in ("src", "href"):
                self.links.append(value)


def links_of(path):
    parser = Links()
    with open(path, encoding="utf-8") as f:
        parser.feed(f.read())
    return parser.links


def read(path):
    with open(path, "rb") as f:
        return f.read()


class ReportTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="hmt-report-test-")
        self.out = os.path.join(self.tmp, "out")
        make_output_folder(self.out)

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def report(self, *extra, code=0):
        r = run_report(self.out, *extra)
        self.assertEqual(r.returncode, code, r.stderr)
        return r

    def test_writes_every_figure_and_page(self):
        self.report()
        for png in FIGURES:
            check_png(self, os.path.join(self.out, "report", png))
        links = links_of(os.path.join(self.out, "index.html"))
        for png in FIGURES:
            self.assertIn("report/" + png, links)
        for image in MAP_IMAGES:
            self.assertIn(image, links)
        # the gallery is sorted by numeric area id
        self.assertLess(links.index("areas/area_2.png"), links.index("areas/area_10.png"))
        for link in links:
            self.assertTrue(os.path.isfile(os.path.join(self.out, link)), link)
        page = read(os.path.join(self.out, "index.html")).decode()
        self.assertIn("datasets/synthetic.rawlog", page)  # summary table
        self.assertIn("an_extra_key", page)               # extra keys are kept
        self.assertIn("Loop-closure candidates", page)
        self.assertIn("21.6613", page)                    # the closure at step 20
        self.assertIn("topological inference (TSBI)", page)  # process totals
        self.assertNotIn("Missing inputs", page)

    def test_islands_are_shown_when_present(self):
        self.report()
        self.assertNotIn("Islands of reliability", read(os.path.join(self.out, "index.html")).decode())
        write(os.path.join(self.out, "islands", "islands.json"), json.dumps(
            {"map": "HMT map hmt_map.bin", "mean_r": 0.31, "threshold": 0.5, "min_distance": 3,
             "islands": [{"id": 1, "x": 2.5, "y": -1.25, "R": 0.875}]}))
        with open(os.path.join(self.out, "islands", "distinctiveness.png"), "wb") as f:
            f.write(tiny_png())
        self.report()
        page = read(os.path.join(self.out, "index.html")).decode()
        self.assertIn("Islands of reliability", page)
        self.assertIn("0.875", page)
        self.assertIn("islands/distinctiveness.png", links_of(os.path.join(self.out, "index.html")))
        write(os.path.join(self.out, "islands", "islands.json"), '{"islands": [{"id": 1}]}')
        r = self.report(code=4)
        self.assertIn("islands.json", r.stderr)

    def test_html_out_links_back_to_the_maps(self):
        html_dir = os.path.join(self.tmp, "site", "run1")
        self.report("--html-out", html_dir)
        self.assertFalse(os.path.exists(os.path.join(self.out, "index.html")))
        for png in FIGURES:
            check_png(self, os.path.join(html_dir, "report", png))
        links = links_of(os.path.join(html_dir, "index.html"))
        self.assertIn("../../out/map.png", links)
        for link in links:
            self.assertTrue(os.path.isfile(os.path.join(html_dir, link)), link)

    def test_same_inputs_give_the_same_bytes(self):
        self.report()
        first = {n: read(os.path.join(self.out, n))
                 for n in ["index.html"] + ["report/" + p for p in FIGURES]}
        self.report()
        for name, data in first.items():
            self.assertEqual(read(os.path.join(self.out, name)), data, name)

    def test_wrong_header_fails_and_keeps_the_earlier_report(self):
        self.report()
        before = read(os.path.join(self.out, "index.html"))
        write(os.path.join(self.out, "memory.csv"),
              "step,time,rss_mb,map_memory_mb,hypotheses,areas\n0,1,2,3,1,1\n")
        r = self.report(code=4)
        self.assertIn("memory.csv:1", r.stderr)
        self.assertEqual(read(os.path.join(self.out, "index.html")), before)
        check_png(self, os.path.join(self.out, "report", "memory.png"))

    def test_non_numeric_field_names_file_and_line(self):
        path = os.path.join(self.out, "process_times.csv")
        with open(path) as f:
            lines = f.read().splitlines()
        lines[3] = "2,1137834225.500000,fast,0,0,0"  # the file's line 4
        write(path, "\n".join(lines) + "\n")
        r = self.report(code=4)
        self.assertIn("process_times.csv:4", r.stderr)
        self.assertIn("metric_slam_ms", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.out, "index.html")))

    def test_malformed_json_names_the_file(self):
        write(os.path.join(self.out, "summary.json"), '{"scans": 3,\n')
        r = self.report(code=4)
        self.assertIn("summary.json:2", r.stderr)

    def test_missing_csv_is_reported_and_skipped(self):
        os.remove(os.path.join(self.out, "ess.csv"))
        os.remove(os.path.join(self.out, "map_topology.png"))
        self.report()
        page = read(os.path.join(self.out, "index.html")).decode()
        self.assertIn("Missing inputs", page)
        self.assertIn("ess.csv was not found", page)
        self.assertIn("map_topology.png was not found", page)
        self.assertFalse(os.path.exists(os.path.join(self.out, "report", "ess.png")))
        links = links_of(os.path.join(self.out, "index.html"))
        self.assertNotIn("report/ess.png", links)
        for png in FIGURES:
            if png != "ess.png":
                check_png(self, os.path.join(self.out, "report", png))

    def test_empty_folder_gives_a_page(self):
        empty = os.path.join(self.tmp, "empty")
        os.makedirs(empty)
        r = run_report(empty)
        self.assertEqual(r.returncode, 0, r.stderr)
        page = read(os.path.join(empty, "index.html")).decode()
        for name in ["summary.json", "topological_pmf.csv", "process_times.csv", "ess.csv"]:
            self.assertIn(name + " was not found", page)

    def test_bad_command_line(self):
        self.assertEqual(run_report().returncode, 2)
        r = run_report(os.path.join(self.tmp, "no-such-folder"))
        self.assertEqual(r.returncode, 2)
        self.assertIn("no-such-folder", r.stderr)

    def test_unwritable_output_exits_5(self):
        write(os.path.join(self.out, "report"), "a file where the folder should be")
        r = self.report(code=5)
        self.assertIn("report", r.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)
