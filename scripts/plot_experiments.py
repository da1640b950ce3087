#!/usr/bin/python3
"""Plots of the area-abstraction experiments (paper 000, Sec. 6) from the
outputs of `hmt-experiments`.

  plot_experiments.py --info-loss DIR   Fig. 8 from DIR/info_loss_summary.csv and
                                        DIR/info_loss_example.json:
                                        fig8a_map.png, fig8b_loss_vs_k.png,
                                        fig8c_loss_vs_tau.png
  plot_experiments.py --fov DIR         from DIR/field_of_view.json:
                                        fov_areas_tau<T>.png for every --fov-tau T
                                        (the areas on the map, one panel per
                                        sensor) and, when several thresholds were
                                        computed, fov_areas_vs_tau.png

Both options may be repeated; the PNGs are written into each DIR.
"""
import argparse
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Ellipse  # noqa: E402


def read_summary(path):
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            rows.append(
                {
                    "method": r["method"],
                    "param": float(r["param"]),
                    "groups": float(r["mean_groups"]),
                    "mean": 100 * float(r["e_mean"]),
                    "std": 100 * float(r["e_std"]),
                    "p16": 100 * float(r["e_p16"]),
                    "p84": 100 * float(r["e_p84"]),
                    "runs": int(r["runs"]),
                }
            )
    return rows


def interval(rows):
    lo = [r["mean"] - r["p16"] for r in rows]
    hi = [r["p84"] - r["mean"] for r in rows]
    return [max(0.0, v) for v in lo], [max(0.0, v) for v in hi]


def plot_loss_vs_k(rows, out):
    main = [r for r in rows if r["method"] == "spectral_main"]
    even = [r for r in rows if r["method"] == "even_same_count"]
    fixed = sorted((r for r in rows if r["method"] == "fixed"), key=lambda r: r["param"])
    if not main or not fixed:
        raise SystemExit("info_loss_summary.csv lacks the spectral or fixed rows")
    m = main[0]
    fig, ax = plt.subplots(figsize=(10, 4.5))
    x0 = fixed[0]["param"] - 3
    lo, hi = interval([m])
    ax.errorbar([x0], [m["mean"]], yerr=[lo, hi], fmt="o", color="tab:red", capsize=5,
                markersize=7, label="spectral, tau = %.2f (%.1f sub-maps)" % (m["param"], m["groups"]))
    if even:
        e = even[0]
        lo, hi = interval([e])
        ax.errorbar([x0 + 1], [e["mean"]], yerr=[lo, hi], fmt="s", color="tab:green",
                    capsize=4, markersize=5,
                    label="same number of evenly spaced groups (control)")
    lo, hi = interval(fixed)
    ax.errorbar([r["param"] for r in fixed], [r["mean"] for r in fixed], yerr=[lo, hi],
                fmt="o", color="tab:blue", capsize=2, markersize=3,
                label="fixed size: a new sub-map every k observations")
    ticks = [x0] + [k for k in range(int(fixed[0]["param"]), int(fixed[-1]["param"]) + 1, 5)]
    ax.set_xticks(ticks)
    ax.set_xticklabels(["spectral"] + [str(k) for k in ticks[1:]])
    ax.set_xlabel("k (observations per sub-map)")
    ax.set_ylabel("information loss e [%]")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.set_title("Information loss (Eq. 22): mean and 68%% interval (16th-84th percentile), %d runs"
                 % m["runs"])
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120, bbox_inches="tight")
    plt.close(fig)


def plot_loss_vs_tau(rows, out):
    sp = sorted((r for r in rows if r["method"] == "spectral"), key=lambda r: r["param"])
    if not sp:
        raise SystemExit("info_loss_summary.csv lacks the tau sweep")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    taus = [r["param"] for r in sp]
    ax.fill_between(taus, [r["p16"] for r in sp], [r["p84"] for r in sp], color="tab:red",
                    alpha=0.2, label="68% interval (16th-84th percentile)")
    ax.plot(taus, [r["mean"] for r in sp], "o-", color="tab:red", markersize=4, label="mean")
    ax.set_xlabel("tau (Ncut threshold of the recursive partition)")
    ax.set_ylabel("information loss e [%]")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax2 = ax.twinx()
    ax2.plot(taus, [r["groups"] for r in sp], "s--", color="tab:gray", markersize=3,
             label="sub-maps (mean)")
    ax2.set_ylabel("sub-maps per run (mean)", color="tab:gray")
    ax2.set_ylim(bottom=0)
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, loc="upper left", fontsize=8)
    ax.set_title("Spectral partition: e against tau, %d runs" % sp[0]["runs"])
    fig.tight_layout()
    fig.savefig(out, dpi=120, bbox_inches="tight")
    plt.close(fig)


def plot_example_map(example, out):
    steps = example["steps"]
    groups = sorted({s["group"] for s in steps})
    cmap = plt.get_cmap("tab10")
    colour = {g: cmap(i % 10) for i, g in enumerate(groups)}
    fig, ax = plt.subplots(figsize=(12, 3.8))
    tx = [p[0] for p in example["landmarks_true"]]
    ty = [p[1] for p in example["landmarks_true"]]
    ax.plot(tx, ty, "k+", markersize=6, label="true landmarks")
    for lm in example["map"]:
        (x, y), (cxx, cxy, cyy) = lm["mean"], lm["cov"]
        tr, det = cxx + cyy, cxx * cyy - cxy * cxy
        l1 = tr / 2 + math.sqrt(max(tr * tr / 4 - det, 0.0))
        l2 = max(tr / 2 - math.sqrt(max(tr * tr / 4 - det, 0.0)), 0.0)
        ang = math.degrees(0.5 * math.atan2(2 * cxy, cxx - cyy))
        ax.add_patch(Ellipse((x, y), 6 * math.sqrt(l1), 6 * math.sqrt(l2), angle=ang,
                             fill=False, color="tab:blue", lw=0.8))
    ax.plot([], [], color="tab:blue", lw=0.8, label="EKF landmarks (3 sigma)")
    ax.plot([s["true_pose"][0] for s in steps], [s["true_pose"][1] for s in steps], "-",
            color="0.6", lw=1, label="true path")
    # Observation poses coloured by their group; only groups that sensed something.
    sensing = {s["group"] for s in steps if s["ids"]}
    for g in groups:
        if g not in sensing:
            continue
        pts = [s["pose"] for s in steps if s["group"] == g]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], ".", color=colour[g], markersize=5)
    ax.plot([], [], ".", color="0.3", label="estimated poses, coloured by sub-map")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("One run: final EKF map and the %d sub-maps of the spectral partition (tau = %.2f)"
                 % (len(sensing), example["tau"]))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.22), ncol=4, fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120, bbox_inches="tight")
    plt.close(fig)


def info_loss(d):
    rows = read_summary(os.path.join(d, "info_loss_summary.csv"))
    outs = [os.path.join(d, "fig8b_loss_vs_k.png"), os.path.join(d, "fig8c_loss_vs_tau.png")]
    plot_loss_vs_k(rows, outs[0])
    plot_loss_vs_tau(rows, outs[1])
    ex = os.path.join(d, "info_loss_example.json")
    if os.path.exists(ex):
        with open(ex) as f:
            outs.append(os.path.join(d, "fig8a_map.png"))
            plot_example_map(json.load(f), outs[-1])
    return outs


def fov(d, fov_taus):
    with open(os.path.join(d, "field_of_view.json")) as f:
        j = json.load(f)
    results = j["results"]
    taus = sorted({r["tau"] for r in results})
    sensors = []
    for r in results:
        if r["sensor"] not in sensors:
            sensors.append(r["sensor"])
    outs = []
    cmap = plt.get_cmap("tab20")
    poses = j["poses"]
    for tau in fov_taus:
        pick = min(taus, key=lambda t: abs(t - tau))
        fig, axes = plt.subplots(1, len(sensors), figsize=(6 * len(sensors), 3.8))
        if len(sensors) == 1:
            axes = [axes]
        for ax, name in zip(axes, sensors):
            r = next(r for r in results if r["sensor"] == name and r["tau"] == pick)
            for w in j["walls"]:
                ax.plot([w[0], w[2]], [w[1], w[3]], "k-", lw=0.6)
            ax.scatter([p[0] for p in poses], [p[1] for p in poses], s=6,
                       c=[cmap(l % 20) for l in r["labels"]])
            ax.set_aspect("equal")
            ax.set_title("%s: %d areas (tau = %.2f)" % (name, r["areas"], pick))
            ax.set_xticks([])
            ax.set_yticks([])
        fig.tight_layout()
        outs.append(os.path.join(d, "fov_areas_tau%.2f.png" % pick))
        fig.savefig(outs[-1], dpi=110, bbox_inches="tight")
        plt.close(fig)
    if len(taus) > 1:
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for name in sensors:
            rs = sorted((r for r in results if r["sensor"] == name), key=lambda r: r["tau"])
            ax.plot([r["tau"] for r in rs], [r["areas"] for r in rs], "o-", markersize=4,
                    label="%s (%.0f deg)" % (name, rs[0]["fov_deg"]))
        ax.set_yscale("log")
        ax.set_xlabel("tau")
        ax.set_ylabel("areas")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        ax.set_title("Areas of the route against tau, per sensor")
        fig.tight_layout()
        outs.append(os.path.join(d, "fov_areas_vs_tau.png"))
        fig.savefig(outs[-1], dpi=120, bbox_inches="tight")
        plt.close(fig)
    return outs


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--info-loss", action="append", default=[], metavar="DIR")
    ap.add_argument("--fov", action="append", default=[], metavar="DIR")
    ap.add_argument("--fov-tau", type=float, action="append", default=[],
                    help="threshold whose areas to draw on the map (nearest computed; "
                         "repeatable; default 1)")
    a = ap.parse_args()
    if not a.info_loss and not a.fov:
        ap.error("give --info-loss DIR and/or --fov DIR")
    for d in a.info_loss:
        for p in info_loss(d):
            print(p)
    for d in a.fov:
        for p in fov(d, a.fov_tau or [1.0]):
            print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
