#!/usr/bin/python3
"""Plots an estimated trajectory over a reference one, after the best rigid
2D alignment (as scripts/ate.py computes it), with the per-pose error as
colour: where a map goes wrong shows where the error jumps.

Usage: plot_trajectory.py TRAJECTORY REFERENCE OUT.png [--title TEXT]
"""
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from ate import align, load_matched  # noqa: E402


def main(argv):
    title = None
    if "--title" in argv:
        i = argv.index("--title")
        title = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    if len(argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        est, ref = load_matched(argv[1], argv[2])
    except SystemExit as e:
        print(e, file=sys.stderr)
        return 4
    est = align(est, ref)
    err = np.linalg.norm(est - ref, axis=1)
    fig, ax = plt.subplots(figsize=(9, 8))
    ax.plot(ref[:, 0], ref[:, 1], "-", color="0.6", lw=1.5, label="reference")
    sc = ax.scatter(est[:, 0], est[:, 1], c=err, s=4, cmap="inferno_r", label="estimate")
    fig.colorbar(sc, ax=ax, label="position error (m)")
    ax.set_aspect("equal")
    ax.legend(loc="best")
    ax.set_title(title or f"RMSE {np.sqrt((err ** 2).mean()):.3f} m, max {err.max():.3f} m")
    fig.savefig(argv[3], dpi=110, bbox_inches="tight")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
