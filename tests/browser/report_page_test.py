#!/usr/bin/python3
"""The report of `hmt-slam run --report` in a real browser.

    report_page_test.py HMT_SLAM_BIN SOURCE_DIR WORK_DIR

Maps the embedded Malaga log (config/default.ini) with --report into
WORK_DIR/malaga, checks what the report holds (every step, the trajectory,
the loop-closure candidates with their grids and points) and that a second
run writes the same bytes, then loads report/index.html in headless
Chromium (scripts/check_report.py): no console message, no error on the
page, the page says it drew everything, and a 1280x900 screenshot that is
not blank (WORK_DIR/screenshot.png). Opened at
index.html#step=100 the page must show step 100; a copy of the report whose
map image is gone must fail the check; --report without map.png is refused.
"""
import importlib.util
import json
import os
import shutil
import subprocess
import sys

TIMEOUT_RUN = 240


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def load_checker(source_dir):
    path = os.path.join(source_dir, "scripts", "check_report.py")
    spec = importlib.util.spec_from_file_location("check_report", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_app(binary, source_dir, args):
    return subprocess.run([binary, *args], cwd=source_dir, stdin=subprocess.DEVNULL,
                          capture_output=True, text=True, timeout=TIMEOUT_RUN)


def read_data(report_dir):
    with open(os.path.join(report_dir, "data.js"), encoding="utf-8") as f:
        text = f.read()
    prefix, suffix = "window.HMT_REPORT = ", ";\n"
    if not (text.startswith(prefix) and text.endswith(suffix)):
        fail("data.js is not 'window.HMT_REPORT = {...};'")
    return json.loads(text[len(prefix):-len(suffix)])


def tree(directory):
    """{relative path: bytes} of every file under directory."""
    files = {}
    for root, _, names in os.walk(directory):
        for name in names:
            path = os.path.join(root, name)
            with open(path, "rb") as f:
                files[os.path.relpath(path, directory)] = f.read()
    return files


def check_data(data, out_dir, report_dir):
    summary = data["summary"]
    steps = data["steps"]
    if len(steps) != summary["scans"] or len(data["trajectory"]) != len(steps):
        fail(f"{len(steps)} steps and {len(data['trajectory'])} poses for "
             f"{summary['scans']} scans")
    if [s["step"] for s in steps] != list(range(len(steps))):
        fail("the steps are not 0, 1, 2, ...")
    for s in steps:
        total = sum(p for _, p in s["pmf"])
        if abs(total - 1.0) > 1e-3:
            fail(f"P(current area) sums to {total} at step {s['step']}")
        if not 0 < s["ess"] <= s["particles"] + 1e-9:
            fail(f"ESS {s['ess']} of {s['particles']} particles at step {s['step']}")
    if len(data["areas"]) != summary["areas"] or summary["areas"] < 2:
        fail(f"{len(data['areas'])} areas in the report, {summary['areas']} in the summary")
    frame = data["map"]
    if not os.path.isfile(os.path.join(report_dir, frame["image"])):
        fail(f"the map image {frame['image']} is not beside the report")
    # The Malaga loop closes: a known area weighed, both poses, its grid drawn.
    views = [(ev, o) for ev in data["events"] for o in ev["outcomes"]
             if o["area"] is not None and "grid" in o]
    if not views:
        fail("no loop-closure candidate with a drawn grid")
    for ev, o in views:
        if len(ev.get("points", [])) < 50:
            fail(f"step {ev['step']}: {len(ev.get('points', []))} observed points")
        if not os.path.isfile(os.path.join(report_dir, o["grid"]["image"])):
            fail(f"{o['grid']['image']} is missing")
        if len(o["prior"]) != 3 or len(o["match"]) != 3:
            fail(f"step {ev['step']}: the two poses of area {o['area']} are not (x, y, theta)")
    if summary["loop_closures_accepted"] < 1 or not data["closures"]:
        fail("the Malaga loop closed no loop")


def main():
    if len(sys.argv) != 4:
        fail("usage: report_page_test.py HMT_SLAM_BIN SOURCE_DIR WORK_DIR")
    binary, source_dir, work_dir = sys.argv[1:4]
    checker = load_checker(source_dir)
    try:
        run_checks(checker, binary, source_dir, work_dir)
    except checker.Missing as e:  # chromium or PIL: what to install
        fail(str(e))


def run_checks(checker, binary, source_dir, work_dir):
    shutil.rmtree(work_dir, ignore_errors=True)
    os.makedirs(work_dir)
    out_dir = os.path.join(work_dir, "malaga")

    r = run_app(binary, source_dir, ["run", "--config", "config/default.ini", "--out", out_dir,
                                     "--quiet", "--report"])
    if r.returncode != 0:
        fail(f"hmt-slam run --report exited with {r.returncode}: {r.stderr}")
    report_dir = os.path.join(out_dir, "report")
    index = os.path.join(report_dir, "index.html")
    if f"report: {index}" not in r.stdout:
        fail(f"hmt-slam did not say where the report is: {r.stdout}")
    for name in ("index.html", "report.js", "report.css", "data.js"):
        if not os.path.isfile(os.path.join(report_dir, name)):
            fail(f"report/{name} was not written")
    check_data(read_data(report_dir), out_dir, report_dir)

    # The same run gives the same report, byte for byte.
    again = os.path.join(work_dir, "malaga_again")
    r = run_app(binary, source_dir, ["run", "--config", "config/default.ini", "--out", again,
                                     "--quiet", "--report"])
    if r.returncode != 0:
        fail(f"the second run exited with {r.returncode}: {r.stderr}")
    first, second = tree(report_dir), tree(os.path.join(again, "report"))
    if first != second:
        differ = sorted(k for k in first.keys() | second.keys() if first.get(k) != second.get(k))
        fail(f"two runs wrote different reports: {differ}")

    shot = os.path.join(work_dir, "screenshot.png")
    problems = checker.check(index, shot, 1280, 900, 90)
    if problems:
        fail("the report page in Chromium:\n  " + "\n  ".join(problems))
    # Opened at a step (index.html#step=100), the page shows that step.
    problems = checker.check(index, os.path.join(work_dir, "screenshot_step100.png"),
                             1280, 900, 90, step=100)
    if problems:
        fail("the report page at step 100:\n  " + "\n  ".join(problems))

    # The check can fail: the same page without its map image does.
    broken = os.path.join(work_dir, "broken")
    shutil.copytree(report_dir, os.path.join(broken, "report"))
    problems = checker.check(os.path.join(broken, "report", "index.html"),
                             os.path.join(work_dir, "broken.png"), 1280, 900, 90)
    if not any("map image ../map.png did not load" in p for p in problems):
        fail(f"a report without its map image passed the check: {problems}")

    r = run_app(binary, source_dir, ["run", "--config", "config/default.ini", "--out",
                                     os.path.join(work_dir, "nopng"), "--quiet", "--report",
                                     "--set", "output.png=false"])
    if r.returncode != 2 or "[output] png = false" not in r.stderr:
        fail(f"--report without map.png: exit {r.returncode}, {r.stderr}")
    print(f"ok: {index} drawn in Chromium; screenshot {shot}")


if __name__ == "__main__":
    main()
