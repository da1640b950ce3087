#!/usr/bin/python3
"""Figures and one HTML page from an output folder of `hmt-slam run`.

    python3 scripts/report.py OUT_DIR [--html-out DIR]

Reads from OUT_DIR (every file is optional: a missing one skips its figure or
table, and the page says which input was missing):

  summary.json         run totals                          -> table
  topology.json        areas and arcs                      -> two tables
  topological_pmf.csv  step,time,area,probability          -> report/pmf.png:
                       P(current area = a) per step (002 Eq. 14, Fig. 10) and
                       the most probable area per step
  tsbi_events.csv      step,time,hypothesis,hypothesis_probability,from_area,
                       outcome,area,log_f,probability,match_ratio,child,x,y,theta
                                                           -> report/tsbi_events.png
                       (P(new) vs P(known a) at every new-area event) and a
                       table of the loop-closure candidates (known, P > 0.01)
  process_times.csv    step,time,metric_slam_ms,aam_ms,tsbi_ms,tlca_ms
                                                           -> report/process_times.png
                       (per step, log scale, and cumulative; Fig. 9c) + totals
  ess.csv              step,time,hypothesis,probability,area,ess,particles
                                                           -> report/ess.png (ESS
                       of the most probable hypothesis, hypotheses alive)
  memory.csv           step,time,peak_rss_mb,map_memory_mb,hypotheses,areas
                                                           -> report/memory.png (Fig. 9e)
  map.png, map_topology.png, areas/area_<id>.png           shown as they are
  islands/islands.json, islands/distinctiveness.png, islands/islands.png
                       what `hmt-slam islands --map OUT_DIR/hmt_map.bin` writes
                       (its default folder): the distinctiveness heat map, the
                       islands on the map and a table of them; shown only when
                       present (the islands are not part of a run)

Writes DIR/report/<figure>.png and DIR/index.html, DIR being --html-out or
OUT_DIR; the page links every image by a relative path. Every input is read
and checked before anything is written, and each output goes to a temporary
file renamed over the old one, so a failed report leaves an earlier one
intact. The same inputs give the same bytes (the only times on the page are
those of summary.json).

Exit codes: 0 ok; 1 internal error (e.g. matplotlib missing); 2 bad command
line; 4 unreadable or malformed input (the message names the file and line);
5 an output could not be written.
"""
import argparse
import csv
import html
import json
import math
import os
import re
import sys
import tempfile
from urllib.parse import quote

EXIT_INTERNAL, EXIT_USAGE, EXIT_INPUT, EXIT_OUTPUT = 1, 2, 4, 5
PROG = "report.py"
DPI = 100
CANDIDATE_THRESHOLD = 0.01  # a known area above this is a loop-closure candidate
PMF_LABEL_THRESHOLD = 0.05  # areas that ever exceed this get a colour and a label
PMF_LEGEND_MAX = 24
PROB_FLOOR = 1e-12  # probabilities are clipped to this on log axes

PROCESSES = [
    ("metric_slam_ms", "metric SLAM"),
    ("aam_ms", "area abstraction (AAM)"),
    ("tsbi_ms", "topological inference (TSBI)"),
    ("tlca_ms", "loop-closure acceptance (TLCA)"),
]

# Summary keys (nested ones flattened with dots) shown first, in this order,
# with a description; other keys follow in the file's order.
SUMMARY_KEYS = [
    ("input", "input log"),
    ("scans", "scans processed"),
    ("particles", "particles"),
    ("wall_time_s", "wall time (s)"),
    ("peak_rss_mb", "peak resident memory (MB)"),
    ("peak_map_memory_mb", "peak map memory (MB)"),
    ("final_pose.x", "final pose, global frame: x (m)"),
    ("final_pose.y", "final pose, global frame: y (m)"),
    ("final_pose.theta", "final pose, global frame: theta (rad)"),
    ("areas", "areas"),
    ("arcs", "arcs"),
    ("keyframes", "keyframes"),
    ("new_area_events", "new-area events"),
    ("transitions_evaluated", "transitions evaluated (TSBI)"),
    ("loop_closures_accepted", "loop closures accepted (TLCA)"),
    ("loop_closures_inconsistent", "of which inconsistent with the grids or the map "
     "(fused with an inflated covariance)"),
    ("max_hypotheses_alive", "most hypotheses alive at once"),
    ("hypotheses_at_end", "hypotheses alive at the end"),
    ("global_poses.method", "global area poses: method"),
    ("global_poses.iterations", "global area poses: iterations"),
    ("global_poses.initial_chi2", "global area poses: initial chi2"),
    ("global_poses.final_chi2", "global area poses: final chi2"),
    ("global_poses.converged", "global area poses: converged"),
    ("global_poses.outlier_arcs", "global area poses: loop arcs switched off as gross errors"),
]


class ReportError(Exception):
    def __init__(self, code, message):
        super().__init__(message)
        self.code = code


# --------------------------------------------------------------------------
# Reading and checking the inputs
# --------------------------------------------------------------------------

def parse_int(text):
    if not re.fullmatch(r"\s*[+-]?\d+\s*", text):
        raise ValueError("an integer")
    return int(text)


def parse_float(text):
    # printf writes non-finite values as inf/-inf/nan: accept them, plots skip them.
    try:
        return float(text)
    except ValueError:
        raise ValueError("a number") from None


def parse_optional_int(text):
    return None if text.strip() == "" else parse_int(text)


def parse_optional_float(text):
    return None if text.strip() == "" else parse_float(text)


def parse_outcome(text):
    if text not in ("new", "known"):
        raise ValueError("'new' or 'known'")
    return text


I, F, OPT_I, OPT_F, OUTCOME = (parse_int, parse_float, parse_optional_int, parse_optional_float,
                               parse_outcome)

CSV_SPECS = {
    "topological_pmf.csv": [("step", I), ("time", F), ("area", I), ("probability", F)],
    "memory.csv": [("step", I), ("time", F), ("peak_rss_mb", F), ("map_memory_mb", F),
                   ("hypotheses", I), ("areas", I)],
    "tsbi_events.csv": [("step", I), ("time", F), ("hypothesis", I),
                        ("hypothesis_probability", F), ("from_area", I),
                        ("outcome", OUTCOME), ("area", OPT_I), ("log_f", F),
                        ("probability", F), ("match_ratio", F), ("child", OPT_I),
                        ("x", OPT_F), ("y", OPT_F), ("theta", OPT_F)],
    "process_times.csv": [("step", I), ("time", F)] + [(c, F) for c, _ in PROCESSES],
    "ess.csv": [("step", I), ("time", F), ("hypothesis", I), ("probability", F),
                ("area", I), ("ess", F), ("particles", I)],
}


def open_input(path):
    try:
        return open(path, newline="", encoding="utf-8")
    except OSError as e:
        raise ReportError(EXIT_INPUT, f"{path}: cannot read: {e.strerror}") from None


def read_csv(path, spec):
    """Rows of a CSV as dicts typed by spec, or None when the file is absent."""
    if not os.path.exists(path):
        return None
    names = [n for n, _ in spec]
    rows = []
    with open_input(path) as f:
        try:
            reader = csv.reader(f)
            header = next(reader, None)
            if header is None:
                raise ReportError(EXIT_INPUT, f"{path}:1: empty file, expected the header "
                                              f"'{','.join(names)}'")
            if [h.strip() for h in header] != names:
                raise ReportError(EXIT_INPUT, f"{path}:1: header is '{','.join(header)}', "
                                              f"expected '{','.join(names)}'")
            for fields in reader:
                if not fields:
                    continue
                rows.append(parse_row(path, reader.line_num, fields, spec))
        except UnicodeDecodeError:
            raise ReportError(EXIT_INPUT, f"{path}: not UTF-8 text") from None
        except csv.Error as e:
            raise ReportError(EXIT_INPUT, f"{path}:{reader.line_num}: {e}") from None
    return rows


def parse_row(path, line, fields, spec):
    if len(fields) != len(spec):
        raise ReportError(EXIT_INPUT, f"{path}:{line}: {len(fields)} fields, "
                                      f"expected {len(spec)}")
    row = {}
    for (name, parse), text in zip(spec, fields):
        try:
            row[name] = parse(text)
        except ValueError as e:
            raise ReportError(EXIT_INPUT, f"{path}:{line}: field '{name}' is '{text}', "
                                          f"expected {e}") from None
    if row.get("outcome") == "known" and row.get("area") is None:
        raise ReportError(EXIT_INPUT, f"{path}:{line}: a 'known' outcome without an area")
    return row


def read_json(path):
    if not os.path.exists(path):
        return None
    with open_input(path) as f:
        try:
            return json.load(f)
        except json.JSONDecodeError as e:
            raise ReportError(EXIT_INPUT, f"{path}:{e.lineno}:{e.colno}: malformed JSON: "
                                          f"{e.msg}") from None
        except UnicodeDecodeError:
            raise ReportError(EXIT_INPUT, f"{path}: not UTF-8 text") from None


def read_summary(path):
    summary = read_json(path)
    if summary is not None and not isinstance(summary, dict):
        raise ReportError(EXIT_INPUT, f"{path}:1: expected a JSON object")
    return summary


def read_topology(path):
    topo = read_json(path)
    if topo is None:
        return None
    if not isinstance(topo, dict):
        raise ReportError(EXIT_INPUT, f"{path}:1: expected a JSON object")
    for key in ("areas", "arcs"):
        items = topo.get(key, [])
        if not isinstance(items, list) or not all(isinstance(x, dict) for x in items):
            raise ReportError(EXIT_INPUT, f"{path}: '{key}' is not a list of objects")
    return topo


def find_images(out_dir):
    """Map images present in OUT_DIR, as paths relative to it."""
    maps = [name for name in ("map.png", "map_topology.png")
            if os.path.isfile(os.path.join(out_dir, name))]
    areas = []
    area_dir = os.path.join(out_dir, "areas")
    if os.path.isdir(area_dir):
        for name in os.listdir(area_dir):
            m = re.fullmatch(r"area_(\d+)\.png", name)
            if m:
                areas.append((int(m.group(1)), "areas/" + name))
    return maps, sorted(areas)


ISLAND_IMAGES = ("distinctiveness.png", "islands.png", "islands_check.png")


def read_islands(out_dir):
    """islands/islands.json and the images beside it, or None."""
    path = os.path.join(out_dir, "islands", "islands.json")
    doc = read_json(path)
    if doc is None:
        return None
    if not isinstance(doc, dict) or not isinstance(doc.get("islands"), list):
        raise ReportError(EXIT_INPUT, f"{path}: expected an object with an 'islands' list")
    for k, item in enumerate(doc["islands"]):
        if not isinstance(item, dict) or not all(
                isinstance(item.get(key), (int, float)) for key in ("id", "x", "y", "R")):
            raise ReportError(EXIT_INPUT, f"{path}: island {k} lacks a numeric id, x, y or R")
    images = [name for name in ISLAND_IMAGES
              if os.path.isfile(os.path.join(out_dir, "islands", name))]
    return {"doc": doc, "images": images}


def load_inputs(out_dir):
    data = {name: read_csv(os.path.join(out_dir, name), spec)
            for name, spec in CSV_SPECS.items()}
    data["summary.json"] = read_summary(os.path.join(out_dir, "summary.json"))
    data["topology.json"] = read_topology(os.path.join(out_dir, "topology.json"))
    data["maps"], data["area_images"] = find_images(out_dir)
    data["islands"] = read_islands(out_dir)
    return data


# --------------------------------------------------------------------------
# Figures: one function each, taking the rows and the pyplot module
# --------------------------------------------------------------------------

def area_color(area):
    """A colour per area id: tab20 without its greys, alternating dark and light
    halves so that consecutive ids get distinct hues."""
    import matplotlib
    order = [0, 2, 4, 6, 8, 10, 12, 16, 18, 1, 3, 5, 7, 9, 11, 13, 17, 19]
    return matplotlib.colormaps["tab20"](order[(area - 1) % len(order)])


OTHER_COLOR = "#c8c8c8"


def finite(values):
    return [v if math.isfinite(v) else float("nan") for v in values]


def plot_pmf(plt, rows):
    from matplotlib.patches import Patch
    steps = sorted({r["step"] for r in rows})
    col = {s: i for i, s in enumerate(steps)}
    areas = sorted({r["area"] for r in rows})
    prob = {a: [0.0] * len(steps) for a in areas}
    for r in rows:
        if math.isfinite(r["probability"]):
            prob[r["area"]][col[r["step"]]] += r["probability"]
    peak = {a: max(prob[a]) for a in areas}
    labelled = [a for a in areas if peak[a] > PMF_LABEL_THRESHOLD]
    colors = [area_color(a) if a in labelled else OTHER_COLOR for a in areas]

    fig, (ax, strip) = plt.subplots(
        2, 1, sharex=True, figsize=(11, 6.5), layout="constrained",
        gridspec_kw={"height_ratios": [7, 1]})
    ax.stackplot(steps, [prob[a] for a in areas], colors=colors,
                 edgecolor="white", linewidth=0.3)
    label_bands(ax, steps, areas, labelled, prob)
    top = max(1.0, max(sum(prob[a][i] for a in areas) for i in range(len(steps))))
    ax.set_ylim(0, top)
    ax.set_xlim(steps[0] - 0.5, steps[-1] + 0.5)
    ax.set_ylabel("P(current area = a)")
    ax.set_title("Topological PMF: probability of being in each area, per step "
                 "(002 Eq. 14, cf. Fig. 10)")
    shown = sorted(sorted(labelled, key=lambda a: (-peak[a], a))[:PMF_LEGEND_MAX])
    handles = [Patch(color=area_color(a), label=f"area {a}") for a in shown]
    if len(labelled) > len(shown):
        handles.append(Patch(color="white", label=f"... {len(labelled) - len(shown)} more"))
    if len(labelled) < len(areas):
        handles.append(Patch(color=OTHER_COLOR,
                             label=f"other areas (P <= {PMF_LABEL_THRESHOLD:g})"))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1),
              fontsize="small", title="area a", ncol=1 if len(handles) <= 16 else 2)

    best = [max(areas, key=lambda a: (prob[a][i], -a)) for i in range(len(steps))]
    draw_argmax_strip(strip, steps, best)
    strip.set_xlabel("step (scan index)")
    return fig


def label_bands(ax, steps, areas, labelled, prob):
    """Writes each labelled area's id inside its band, where the band is widest."""
    for a in labelled:
        i, width = widest_stretch(prob[a])
        if prob[a][i] < 0.12 or width < 0.015 * len(steps):
            continue
        below = sum(prob[b][i] for b in areas if b < a)
        ax.text(steps[i], below + prob[a][i] / 2, str(a), ha="center", va="center",
                fontsize=8, fontweight="bold", color="black",
                bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.7))


def widest_stretch(values):
    """The middle index and the length of the longest run of values at or above
    half their maximum."""
    high = 0.5 * max(values)
    best, start = (0, 0), None
    for k, v in enumerate(values + [float("-inf")]):
        if v >= high and start is None:
            start = k
        elif v < high and start is not None:
            if k - start > best[1] - best[0]:
                best = (start, k)
            start = None
    return (best[0] + best[1] - 1) // 2, best[1] - best[0]


def draw_argmax_strip(ax, steps, best):
    """A band coloured by the most probable area at each step, ids written on runs."""
    runs = []  # [first step, last step, area]
    for s, a in zip(steps, best):
        if runs and runs[-1][2] == a:
            runs[-1][1] = s
        else:
            runs.append([s, s, a])
    span = max(1, steps[-1] - steps[0] + 1)
    for first, last, a in runs:
        width = last - first + 1
        ax.broken_barh([(first - 0.5, width)], (0, 1), facecolors=area_color(a))
        if width >= 0.015 * span:
            ax.text(first - 0.5 + width / 2, 0.5, str(a), ha="center", va="center",
                    fontsize=7)
    ax.set_ylim(0, 1)
    ax.set_yticks([])
    ax.set_ylabel("most\nprobable", rotation=0, ha="right", va="center", fontsize="small")


def group_events(rows):
    """The TSBI rows grouped by (step, hypothesis), in that order."""
    events = {}
    for r in rows:
        events.setdefault((r["step"], r["hypothesis"]), []).append(r)
    return [(key, events[key]) for key in sorted(events)]


def plot_tsbi_events(plt, rows):
    from matplotlib.lines import Line2D
    events = group_events(rows)
    n = len(events)
    fig, (ax, hyp) = plt.subplots(
        2, 1, sharex=True, figsize=(max(8.0, min(20.0, 2.5 + 0.32 * n)), 6.5),
        layout="constrained", gridspec_kw={"height_ratios": [3, 1]})
    lowest = 1.0
    for x, (_, outcomes) in enumerate(events):
        for r in outcomes:
            if not math.isfinite(r["probability"]):
                continue
            p = max(r["probability"], PROB_FLOOR)
            lowest = min(lowest, p)
            if r["outcome"] == "new":  # new a little left, known a little right
                ax.plot(x - 0.12, p, "s", ms=7, mfc="white", mec="black", mew=1.2, zorder=3)
            else:
                ax.plot(x + 0.12, p, "o", ms=7, color=area_color(r["area"]), mec="black",
                        mew=0.5, zorder=4)
                ax.annotate(str(r["area"]), (x + 0.12, p), xytext=(5, 0),
                            textcoords="offset points", va="center", fontsize=7)
    ax.axhline(CANDIDATE_THRESHOLD, ls=":", lw=0.8, color="black")
    ax.set_yscale("log")
    ax.set_ylim(min(lowest, CANDIDATE_THRESHOLD) / 10, 3)
    ax.set_ylabel("P(outcome | hypothesis)")
    ax.set_title("TSBI: probability of 'new area' vs each known area, "
                 "at every new-area event")
    ax.legend(handles=[
        Line2D([], [], ls="", marker="s", mfc="white", mec="black", label="new area"),
        Line2D([], [], ls="", marker="o", color="tab:blue", mec="black",
               label="known area (id written beside it)"),
        Line2D([], [], ls=":", color="black",
               label=f"candidate threshold ({CANDIDATE_THRESHOLD:g})"),
    ], loc="lower left", fontsize="small", framealpha=0.9)
    ax.grid(axis="y", lw=0.3, alpha=0.5)

    hyp.bar(range(n), [o[0]["hypothesis_probability"] for _, o in events],
            color="#9e9e9e", width=0.6)
    hyp.set_ylim(0, 1.05)
    hyp.set_ylabel("P(hypothesis)")
    every = max(1, math.ceil(n / 60))
    hyp.set_xticks(range(0, n, every))
    hyp.set_xticklabels([f"{s}\nh{h}" for (s, h), _ in events][::every], fontsize=7)
    hyp.set_xlim(-0.7, n - 0.3)
    hyp.set_xlabel("new-area event: step (scan index) / hypothesis id")
    return fig


def plot_process_times(plt, rows):
    from matplotlib.ticker import FormatStrFormatter, LogLocator
    rows = sorted(rows, key=lambda r: r["step"])
    steps = [r["step"] for r in rows]
    fig, (per_step, cumulative) = plt.subplots(2, 1, sharex=True, figsize=(10, 7),
                                               layout="constrained")
    any_positive = False
    for column, label in PROCESSES:
        values = finite([r[column] for r in rows])
        positive = [v if v > 0 else float("nan") for v in values]
        any_positive |= any(v == v for v in positive)
        per_step.plot(steps, positive, marker=".", ms=4, lw=0.7, label=label)
        total, sums = 0.0, []
        for v in values:
            total += v if v == v else 0.0
            sums.append(total / 1000.0)
        cumulative.plot(steps, sums, lw=1.5, label=label)
    if any_positive:
        per_step.set_yscale("log")
        per_step.yaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
        per_step.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    per_step.set_ylabel("time per step (ms, log scale)")
    per_step.set_title("Time spent by each process on the work of each step (cf. 002 Fig. 9c)")
    per_step.legend(fontsize="small", loc="upper left", ncol=2)
    per_step.grid(lw=0.3, alpha=0.5)
    cumulative.set_ylabel("cumulative time (s)")
    cumulative.set_xlabel("step (scan index)")
    cumulative.set_ylim(bottom=0)
    cumulative.legend(fontsize="small", loc="upper left")
    cumulative.grid(lw=0.3, alpha=0.5)
    return fig


def most_probable_per_step(rows):
    """For each step: the row of its most probable hypothesis and how many are alive."""
    by_step = {}
    for r in rows:
        by_step.setdefault(r["step"], []).append(r)
    result = []
    for step in sorted(by_step):
        alive = by_step[step]
        best = max(alive, key=lambda r: (r["probability"], -r["hypothesis"]))
        result.append((step, best, len({r["hypothesis"] for r in alive})))
    return result


def plot_ess(plt, rows):
    from matplotlib.ticker import MaxNLocator
    per_step = most_probable_per_step(rows)
    steps = [s for s, _, _ in per_step]
    fig, (ax, alive) = plt.subplots(2, 1, sharex=True, figsize=(10, 6), layout="constrained",
                                    gridspec_kw={"height_ratios": [3, 1]})
    ax.plot(steps, finite([b["ess"] for _, b, _ in per_step]), lw=1.2,
            label="effective sample size (ESS)")
    ax.plot(steps, [b["particles"] for _, b, _ in per_step], ls="--", lw=1.0,
            color="black", label="particles in the hypothesis")
    ax.set_ylim(bottom=0)
    ax.set_ylabel("particles")
    ax.set_title("ESS of the most probable topological hypothesis, per step")
    ax.legend(fontsize="small", loc="lower left")
    ax.grid(lw=0.3, alpha=0.5)
    alive.step(steps, [n for _, _, n in per_step], where="mid", color="tab:purple")
    alive.set_ylim(0, max(n for _, _, n in per_step) + 0.5)
    alive.yaxis.set_major_locator(MaxNLocator(integer=True))
    alive.set_ylabel("hypotheses\nalive")
    alive.set_xlabel("step (scan index)")
    alive.grid(lw=0.3, alpha=0.5)
    return fig


def plot_memory(plt, rows):
    from matplotlib.ticker import MaxNLocator
    rows = sorted(rows, key=lambda r: r["step"])
    steps = [r["step"] for r in rows]
    fig, ax = plt.subplots(figsize=(10, 5), layout="constrained")
    lines = ax.plot(steps, finite([r["peak_rss_mb"] for r in rows]), "o-",
                    color="tab:blue", label="peak resident memory (MB)")
    lines += ax.plot(steps, finite([r["map_memory_mb"] for r in rows]), "s-",
                     color="tab:orange", label="map memory (MB)")
    ax.set_ylim(bottom=0)
    ax.set_ylabel("memory (MB)")
    ax.set_xlabel("step (scan index)")
    ax.grid(lw=0.3, alpha=0.5)
    counts = ax.twinx()
    lines += counts.plot(steps, [r["hypotheses"] for r in rows], "x--",
                         color="tab:purple", label="hypotheses alive (right axis)")
    lines += counts.plot(steps, [r["areas"] for r in rows], "^:", color="tab:green",
                         label="areas (right axis)")
    counts.set_ylim(0, max(max(r["areas"] for r in rows),
                           max(r["hypotheses"] for r in rows)) * 1.1 + 1)
    counts.yaxis.set_major_locator(MaxNLocator(integer=True))
    counts.set_ylabel("count")
    ax.set_title("Memory over the run (cf. 002 Fig. 9e)")
    ax.legend(handles=lines, loc="upper left", fontsize="small")
    return fig


# name of the PNG in report/, its input, the plotting function, the caption
FIGURES = [
    ("pmf.png", "topological_pmf.csv", plot_pmf,
     "P(current area = a) at each step, stacked over the areas (Eq. 14); areas that "
     "never exceed 0.05 are grey. The strip below gives the most probable area."),
    ("tsbi_events.png", "tsbi_events.csv", plot_tsbi_events,
     "Every new-area event of every hypothesis: the probability of a new area "
     "(square) against each known area (circle, its id beside it), log scale; below, "
     "the probability of the hypothesis in which the event happened."),
    ("process_times.png", "process_times.csv", plot_process_times,
     "Time spent by each concurrent process on the work attributed to each step "
     "(steps where a process did nothing are gaps), and the running totals."),
    ("ess.png", "ess.csv", plot_ess,
     "Effective sample size of the most probable hypothesis at each step, against its "
     "number of particles; below, the number of hypotheses alive."),
    ("memory.png", "memory.csv", plot_memory,
     "Peak resident memory of the process and memory of the maps (left), "
     "hypotheses alive and areas (right), at each sampled step."),
]


# --------------------------------------------------------------------------
# Writing files atomically
# --------------------------------------------------------------------------

def file_mode():
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def write_atomically(path, write):
    """Calls write(binary file) on a temporary file, then renames it to path."""
    directory = os.path.dirname(path) or "."
    try:
        fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".",
                                   suffix=".tmp", dir=directory)
    except OSError as e:
        raise ReportError(EXIT_OUTPUT, f"{path}: cannot write: {e.strerror}") from None
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, file_mode())
        os.replace(tmp, path)
    except OSError as e:
        os.unlink(tmp)
        raise ReportError(EXIT_OUTPUT, f"{path}: cannot write: {e.strerror}") from None
    except BaseException:
        os.unlink(tmp)
        raise


def load_pyplot():
    try:
        import matplotlib
    except ImportError:
        raise ReportError(EXIT_INTERNAL,
                          f"matplotlib is not installed for {sys.executable} "
                          "(Debian: apt-get install python3-matplotlib)") from None
    matplotlib.use("Agg")
    matplotlib.rcParams["svg.hashsalt"] = "hmt-slam-report"
    import matplotlib.pyplot as plt
    return plt


def save_figure(plt, fig, path):
    try:
        write_atomically(path, lambda f: fig.savefig(f, format="png", dpi=DPI,
                                                     metadata={"Software": None}))
    finally:
        plt.close(fig)


def render_figures(plt, data, report_dir):
    """Writes each figure whose input has rows; returns {png name: note} for the others."""
    skipped = {}
    for png, source, plot, _ in FIGURES:
        rows = data[source]
        if rows is None:
            skipped[png] = f"{source} is missing"
        elif not rows:
            skipped[png] = f"{source} has no data rows"
        else:
            save_figure(plt, plot(plt, rows), os.path.join(report_dir, png))
    return skipped


# --------------------------------------------------------------------------
# The page
# --------------------------------------------------------------------------

def fmt(value, digits=6):
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    if isinstance(value, (list, dict)):
        return json.dumps(value, sort_keys=True)
    return str(value)


def esc(value, digits=6):
    return html.escape(fmt(value, digits))


def table(header, rows, numeric_from=0):
    """An HTML table; rows are lists of already-escaped cell strings."""
    out = ['<table><tr>' + ''.join(f'<th>{html.escape(h)}</th>' for h in header) + '</tr>']
    for row in rows:
        cells = ''.join(f'<td class="num">{c}</td>' if i >= numeric_from else f'<td>{c}</td>'
                        for i, c in enumerate(row))
        out.append(f'<tr>{cells}</tr>')
    out.append('</table>')
    return '\n'.join(out)


def link(path, html_dir):
    rel = os.path.relpath(path, html_dir).replace(os.sep, "/")
    return html.escape(quote(rel), quote=True)


def flatten(prefix, value):
    if isinstance(value, dict):
        for key, sub in value.items():
            yield from flatten(f"{prefix}.{key}", sub)
    else:
        yield prefix, value


def summary_section(summary):
    values = dict(kv for key, value in summary.items() for kv in flatten(key, value))
    known = dict(SUMMARY_KEYS)
    names = [k for k, _ in SUMMARY_KEYS if k in values]
    names += [k for k in values if k not in known]
    rows = [[html.escape(n), html.escape(known.get(n, "")), esc(values[n])] for n in names]
    return table(["key", "meaning", "value"], rows, numeric_from=3)


def candidates_section(rows):
    events = group_events(rows)
    out = []
    for (step, hyp), outcomes in events:
        p_new = sum(r["probability"] for r in outcomes if r["outcome"] == "new")
        for r in sorted(outcomes, key=lambda r: r["area"] if r["area"] is not None else -1):
            if r["outcome"] == "known" and r["probability"] > CANDIDATE_THRESHOLD:
                out.append([esc(step), esc(hyp), esc(r["hypothesis_probability"]),
                            esc(r["from_area"]), esc(r["area"]), esc(r["log_f"]),
                            esc(r["probability"]), esc(p_new), esc(r["match_ratio"]),
                            esc(r["child"])])
    if not out:
        return f"<p>No known area reached P &gt; {CANDIDATE_THRESHOLD:g} at any event.</p>"
    return table(["step", "hypothesis", "P(hypothesis)", "from area", "candidate area",
                  "log F", "P(candidate)", "P(new)", "match ratio", "child hypothesis"], out)


def process_totals_section(rows):
    out = []
    for column, label in PROCESSES:
        values = [r[column] for r in rows if math.isfinite(r[column])]
        total = sum(values)
        out.append([html.escape(label), esc(total / 1000.0, 4),
                    esc(total / len(rows) if rows else 0.0, 4),
                    esc(max(values, default=0.0), 4),
                    esc(sum(1 for v in values if v > 0))])
    return table(["process", "total (s)", "mean per step (ms)", "max per step (ms)",
                  "steps with work"], out, numeric_from=1)


def pose_cells(pose):
    pose = pose if isinstance(pose, dict) else {}
    return [esc(pose.get("x"), 5), esc(pose.get("y"), 5), esc(pose.get("theta"), 5)]


def topology_section(topo, area_links):
    areas = []
    def area_id(a):
        return a["id"] if isinstance(a.get("id"), int) else -1
    for a in sorted(topo.get("areas", []), key=area_id):
        ident = esc(a.get("id"))
        if a.get("id") in area_links:
            ident = f'<a href="{area_links[a["id"]]}">{ident}</a>'
        parent = "root" if "parent" in a and a["parent"] is None else esc(a.get("parent"))
        areas.append([ident, esc(a.get("keyframes")), parent, esc(a.get("created_step"))]
                     + pose_cells(a.get("global_pose")))
    arcs = [[esc(c.get("from")), esc(c.get("to")), esc(c.get("measurements"))]
            + pose_cells(c.get("mean")) for c in topo.get("arcs", [])]
    return ("<h3>Areas</h3>\n" +
            table(["area", "keyframes", "parent", "created at step", "global x (m)",
                   "global y (m)", "global theta (rad)"], areas) +
            "\n<h3>Arcs</h3>\n" +
            table(["from", "to", "measurements fused", "x (m)", "y (m)", "theta (rad)"],
                  arcs))


CSS = """body{font-family:sans-serif;margin:1.5em auto;max-width:1200px;color:#222}
table{border-collapse:collapse;margin:0.5em 0 1em}
th,td{border:1px solid #ccc;padding:2px 8px;font-size:90%}
th{background:#eee}td.num{text-align:right;font-variant-numeric:tabular-nums}
img.fig{max-width:100%;border:1px solid #ddd}
.gallery{display:flex;flex-wrap:wrap;gap:10px}
.gallery figure{margin:0;text-align:center}
.gallery img{width:220px;border:1px solid #ddd}
.missing{color:#a33}"""


def islands_section(islands, out_dir, html_dir):
    doc = islands["doc"]
    parts = ['<h2>Islands of reliability <small>from islands/islands.json</small></h2>',
             f'<p>Distinctiveness R (Simhon &amp; Dudek, Eq. 4-12) of {esc(doc.get("map", ""))}: '
             f'mean {esc(doc.get("mean_r"), 3)}; islands where R &ge; '
             f'{esc(doc.get("threshold"), 3)}, at least {esc(doc.get("min_distance"), 3)} m '
             f'apart.</p>']
    for name in islands["images"]:
        src = link(os.path.join(out_dir, "islands", name), html_dir)
        parts.append(f'<h3>{html.escape(name)}</h3><a href="{src}">'
                     f'<img class="fig" src="{src}" alt="{html.escape(name)}"></a>')
    rows = [[esc(i["id"]), esc(i["x"], 4), esc(i["y"], 4), esc(i["R"], 3)] for i in doc["islands"]]
    parts.append(table(["island", "x (m)", "y (m)", "R"], rows) if rows
                 else '<p>No place reaches the threshold.</p>')
    return "\n".join(parts)


def build_page(data, skipped, out_dir, html_dir, report_dir):
    summary, topo = data["summary.json"], data["topology.json"]
    title = "HMT-SLAM report"
    if summary and "input" in summary:
        title += " - " + fmt(summary["input"])
    parts = [f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
             f'<title>{html.escape(title)}</title>\n<style>{CSS}</style></head><body>',
             f'<h1>{html.escape(title)}</h1>']

    missing = [n for n in ("summary.json", "topology.json", *CSV_SPECS) if data[n] is None]
    missing += [n for n in ("map.png", "map_topology.png") if n not in data["maps"]]
    if missing:
        parts.append('<h2>Missing inputs</h2><ul class="missing">' +
                     ''.join(f'<li>{html.escape(n)} was not found; what it would show '
                             f'is left out</li>' for n in missing) + '</ul>')

    parts.append('<h2>Summary</h2>')
    parts.append(summary_section(summary) if summary is not None
                 else '<p class="missing">summary.json is missing.</p>')

    if data["maps"]:
        parts.append('<h2>Maps</h2>')
        for name in data["maps"]:
            src = link(os.path.join(out_dir, name), html_dir)
            parts.append(f'<h3>{html.escape(name)}</h3><a href="{src}">'
                         f'<img class="fig" src="{src}" alt="{html.escape(name)}"></a>')

    for png, source, _, caption in FIGURES:
        parts.append(f'<h2>{html.escape(png)} <small>from {html.escape(source)}</small></h2>')
        if png in skipped:
            parts.append(f'<p class="missing">Not drawn: {html.escape(skipped[png])}.</p>')
            continue
        src = link(os.path.join(report_dir, png), html_dir)
        parts.append(f'<img class="fig" src="{src}" alt="{html.escape(png)}">'
                     f'<p>{html.escape(caption)}</p>')
        if source == "tsbi_events.csv":
            parts.append(f'<h3>Loop-closure candidates (known area with P &gt; '
                         f'{CANDIDATE_THRESHOLD:g})</h3>' + candidates_section(data[source]))
        elif source == "process_times.csv":
            parts.append('<h3>Time per process</h3>' + process_totals_section(data[source]))

    if data["islands"] is not None:
        parts.append(islands_section(data["islands"], out_dir, html_dir))

    area_links = {i: link(os.path.join(out_dir, p), html_dir) for i, p in data["area_images"]}
    if topo is not None:
        parts.append('<h2>Topology <small>from topology.json</small></h2>')
        parts.append(topology_section(topo, area_links))
    if data["area_images"]:
        parts.append('<h2>Area maps</h2><div class="gallery">')
        for i, _ in data["area_images"]:
            src = area_links[i]
            parts.append(f'<figure><a href="{src}"><img src="{src}" alt="area {i}"></a>'
                         f'<figcaption>area {i}</figcaption></figure>')
        parts.append('</div>')
    parts.append('</body></html>\n')
    return '\n'.join(parts)


# --------------------------------------------------------------------------

def parse_args(argv):
    parser = argparse.ArgumentParser(
        prog=PROG, description="Figures and an HTML page from an output folder of "
                               "`hmt-slam run`.")
    parser.add_argument("out_dir", metavar="OUT_DIR", help="the --out folder of hmt-slam run")
    parser.add_argument("--html-out", metavar="DIR",
                        help="where to write index.html and report/ (default: OUT_DIR)")
    args = parser.parse_args(argv)
    if not os.path.isdir(args.out_dir):
        parser.error(f"OUT_DIR {args.out_dir}: not a directory")
    return args


def run(args):
    out_dir = args.out_dir
    html_dir = args.html_out or out_dir
    report_dir = os.path.join(html_dir, "report")
    data = load_inputs(out_dir)  # every input is checked before anything is written
    plt = load_pyplot()
    try:
        os.makedirs(report_dir, exist_ok=True)
    except OSError as e:
        raise ReportError(EXIT_OUTPUT, f"{report_dir}: cannot create: {e.strerror}") from None
    skipped = render_figures(plt, data, report_dir)
    page = build_page(data, skipped, out_dir, html_dir, report_dir)
    index = os.path.join(html_dir, "index.html")
    write_atomically(index, lambda f: f.write(page.encode("utf-8")))
    for png in skipped:  # a figure of an earlier report whose input is gone
        stale = os.path.join(report_dir, png)
        if os.path.exists(stale):
            os.remove(stale)
    return index


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        index = run(args)
    except ReportError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return e.code
    print(index)
    return 0


if __name__ == "__main__":
    sys.exit(main())
