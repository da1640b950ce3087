#!/usr/bin/python3
"""Loads a report page of `hmt-slam run --report` in headless Chromium, checks
that it drew without an error, and saves a screenshot of it.

    scripts/check_report.py OUT/report/index.html --screenshot PNG
        [--width 1280] [--height 900] [--timeout 90] [--step N]

The page is loaded twice by a fresh browser profile (Debian's chromium, run
with --no-sandbox so it works as root): once to dump its DOM after its
scripts ran, once to take the screenshot. It passes when

  - the page says it drew everything (<body data-report="ready">, set by
    report.js once the map image loaded and the plots were drawn) and its
    error box (#errors, where window.onerror writes) is empty;
  - the browser printed no console message (the page logs none: any is an
    error, a failed image or script load included);
  - the screenshot is a PNG of the window's size with more than a few
    colours (not a blank or error page);
  - with --step N, the page opened at that step (index.html#step=N) and
    says so.

Each browser run is killed after --timeout seconds. Exit codes: 0 the page
is good, 1 it is not (every problem is printed), 2 bad command line, 3
chromium or python3-pil is missing (the message says what to install).
"""
import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
from urllib.parse import quote

PROG = "check_report.py"
EXIT_BAD_PAGE, EXIT_USAGE, EXIT_MISSING = 1, 2, 3
MIN_COLOURS = 50  # a blank page has 1, an error page a handful


class Missing(Exception):
    pass


def find_chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    raise Missing("chromium is not installed (Debian: apt-get install chromium, "
                  "or bash scripts/setup.sh)")


def run_browser(chromium, profile, args, url, timeout):
    """Runs headless Chromium on url; returns (stdout, stderr) as text. Its
    own process group, killed whole on timeout (the browser forks helpers)."""
    cmd = [chromium, "--headless=new", "--no-sandbox", "--disable-gpu",
           "--disable-dev-shm-usage", "--no-first-run", "--disable-extensions",
           "--hide-scrollbars", "--enable-logging=stderr", "--v=0",
           f"--user-data-dir={profile}", *args, url]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        raise TimeoutError(f"chromium did not finish within {timeout} s") from None
    if proc.returncode != 0:
        raise RuntimeError(f"chromium exited with {proc.returncode}: "
                           f"{err.decode(errors='replace').strip()[-600:]}")
    return out.decode("utf-8", errors="replace"), err.decode("utf-8", errors="replace")


def console_messages(stderr):
    """The page's console messages in Chromium's log: lines like
    [pid:tid:date:INFO:CONSOLE:12] "message", source: file:///... (12)."""
    return [line for line in stderr.splitlines() if re.search(r":CONSOLE[:(]", line)]


def check_dom(dom, step=None):
    problems = []
    if step is not None:
        m = re.search(r'<span id="readout"[^>]*>step (\d+) /', dom)
        shown = int(m.group(1)) if m else None
        if shown != step:
            problems.append(f"the page shows step {shown}, expected {step}")
    m = re.search(r'<body[^>]*\bdata-report="([^"]*)"', dom)
    state = m.group(1) if m else None
    if state != "ready":
        problems.append(f"the page did not finish drawing: <body data-report={state!r}>, "
                        "expected 'ready'")
    m = re.search(r'<div id="errors"[^>]*>(.*?)</div>', dom, re.S)
    if m is None:
        problems.append("the page has no #errors element: not a report page")
    elif m.group(1).strip():
        problems.append("the page reported errors: " + m.group(1).strip())
    return problems


def check_screenshot(path, width, height):
    try:
        from PIL import Image
    except ImportError:
        raise Missing("python3-pil is not installed (Debian: apt-get install python3-pil)")
    if not os.path.isfile(path):
        return [f"{path}: chromium wrote no screenshot"]
    with open(path, "rb") as f:
        if f.read(8) != b"\x89PNG\r\n\x1a\n":
            return [f"{path}: not a PNG file"]
    with Image.open(path) as img:
        img.load()
        if img.size != (width, height):
            return [f"{path}: {img.size[0]}x{img.size[1]} pixels, expected {width}x{height}"]
        colours = img.convert("RGB").getcolors(maxcolors=1 << 20)
    distinct = len(colours) if colours is not None else 1 << 20
    if distinct < MIN_COLOURS:
        return [f"{path}: only {distinct} distinct colours: a blank page"]
    return []


def check(index, screenshot, width, height, timeout, step=None):
    """The problems found with the page (an empty list when it is good),
    opened at `step` if given."""
    chromium = find_chromium()
    url = "file://" + quote(os.path.abspath(index))
    if step is not None:
        url += f"#step={step}"
    problems = []
    with tempfile.TemporaryDirectory(prefix="hmt-report-browser.") as profile:
        # A virtual-time budget lets the page's loads and scripts finish
        # before the DOM is dumped or the screenshot taken.
        budget = "--virtual-time-budget=10000"
        dom, err = run_browser(chromium, os.path.join(profile, "dom"),
                               [budget, "--dump-dom"], url, timeout)
        problems += check_dom(dom, step)
        problems += [f"console: {line}" for line in console_messages(err)]
        shot_dir = os.path.dirname(os.path.abspath(screenshot))
        os.makedirs(shot_dir, exist_ok=True)
        tmp = os.path.join(shot_dir, "." + os.path.basename(screenshot) + ".tmp.png")
        try:
            _, err = run_browser(chromium, os.path.join(profile, "shot"),
                                 [budget, f"--window-size={width},{height}",
                                  f"--screenshot={tmp}"], url, timeout)
            problems += [f"console (screenshot run): {line}" for line in console_messages(err)]
            shot_problems = check_screenshot(tmp, width, height)
            problems += shot_problems
            if not shot_problems:
                os.replace(tmp, screenshot)
        finally:
            if os.path.exists(tmp):
                os.remove(tmp)
    return problems


def main(argv=None):
    parser = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0])
    parser.add_argument("index", help="report/index.html written by hmt-slam run --report")
    parser.add_argument("--screenshot", required=True, help="where to write the PNG")
    parser.add_argument("--width", type=int, default=1280)
    parser.add_argument("--height", type=int, default=900)
    parser.add_argument("--timeout", type=float, default=90.0,
                        help="seconds each browser run may take (default 90)")
    parser.add_argument("--step", type=int, help="open the page at this step")
    args = parser.parse_args(argv)
    if not os.path.isfile(args.index):
        parser.error(f"{args.index}: no such file (run hmt-slam run ... --report first)")
    if args.width < 100 or args.height < 100 or args.timeout <= 0:
        parser.error("--width and --height must be >= 100, --timeout > 0")
    if args.step is not None and args.step < 0:
        parser.error("--step must be >= 0")
    try:
        problems = check(args.index, args.screenshot, args.width, args.height, args.timeout,
                         args.step)
    except Missing as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return EXIT_MISSING
    except (TimeoutError, RuntimeError, OSError) as e:
        print(f"{PROG}: {args.index}: {e}", file=sys.stderr)
        return EXIT_BAD_PAGE
    for p in problems:
        print(f"{PROG}: {args.index}: {p}", file=sys.stderr)
    if problems:
        return EXIT_BAD_PAGE
    print(f"{args.index}: drawn without errors; screenshot {args.screenshot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
