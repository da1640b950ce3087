#!/usr/bin/python3
"""The paper's check of the distinctiveness measure (Simhon & Dudek, 003
section 8.1, Fig. 2-3) from the output folder of `hmt-slam islands --check`.

    python3 scripts/plot_islands_check.py ISLANDS_DIR [--out FILE]

Reads distinctiveness.pgm/.yaml (R per cell), localization_check.csv (per
sample: x,y,heading,R,error_xy,error_theta) and islands.json (the offsets the
check used). Writes FILE (default ISLANDS_DIR/islands_check.png) with three
panels: R over the map (Fig. 3a); the localization confidence at each sample
(Fig. 3c), here 1 - error / offset_max clipped to [0, 1] (the paper's c -
error, scaled so that an error as large as the starting offset -- the
matcher did not improve on its start -- is 0 and a perfect match 1); and the
accumulated residual plot (Fig. 2): how many samples differ from R by more
than each residual. Prints Spearman's rank correlation of R and the error
and the share of samples with a residual above 0.4 (the paper's figure is
about 25 %).

Exit codes: 0 ok; 1 internal error (e.g. matplotlib missing); 2 bad command
line; 4 unreadable or malformed input.
"""
import argparse
import csv
import json
import os
import sys


def fail(code, message):
    print(f"plot_islands_check.py: {message}", file=sys.stderr)
    sys.exit(code)


def read_pgm(path):
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        fail(4, f"{path}: {e.strerror}")
    tokens, pos = [], 0
    while len(tokens) < 4:
        while pos < len(data) and data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            while pos < len(data) and data[pos:pos + 1] != b"\n":
                pos += 1
            continue
        start = pos
        while pos < len(data) and not data[pos:pos + 1].isspace():
            pos += 1
        if start == pos:
            fail(4, f"{path}: truncated PGM header")
        tokens.append(data[start:pos])
    if tokens[0] != b"P5":
        fail(4, f"{path}: not a binary PGM")
    w, h = int(tokens[1]), int(tokens[2])
    pixels = data[pos + 1:pos + 1 + w * h]
    if len(pixels) != w * h:
        fail(4, f"{path}: truncated PGM")
    return w, h, pixels


def read_yaml_frame(path):
    frame = {}
    try:
        with open(path) as f:
            for line in f:
                if ":" in line:
                    key, value = line.split(":", 1)
                    frame[key.strip()] = value.strip()
        res = float(frame["resolution"])
        ox, oy = [float(v) for v in frame["origin"].strip("[]").split(",")[:2]]
    except (OSError, KeyError, ValueError) as e:
        fail(4, f"{path}: no resolution or origin ({e})")
    return res, ox, oy


def read_samples(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        return [(float(r["x"]), float(r["y"]), float(r["R"]), float(r["error_xy"]))
                for r in rows]
    except (OSError, KeyError, ValueError) as e:
        fail(4, f"{path}: malformed localization check ({e}); run hmt-slam islands --check")


def ranks(values):
    order = sorted(range(len(values)), key=lambda k: values[k])
    r = [0.0] * len(values)
    k = 0
    while k < len(order):
        e = k
        while e + 1 < len(order) and values[order[e + 1]] == values[order[k]]:
            e += 1
        for m in range(k, e + 1):
            r[order[m]] = (k + e) / 2 + 1
        k = e + 1
    return r


def spearman(a, b):
    ra, rb = ranks(a), ranks(b)
    n = len(a)
    mean = (n + 1) / 2
    sab = sum((x - mean) * (y - mean) for x, y in zip(ra, rb))
    saa = sum((x - mean) ** 2 for x in ra)
    sbb = sum((y - mean) ** 2 for y in rb)
    return sab / (saa * sbb) ** 0.5 if saa > 0 and sbb > 0 else 0.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("islands_dir", help="the --out folder of hmt-slam islands --check")
    parser.add_argument("--out", help="the PNG to write [ISLANDS_DIR/islands_check.png]")
    args = parser.parse_args()
    d = args.islands_dir
    if not os.path.isdir(d):
        parser.error(f"{d}: not a directory")
    w, h, pixels = read_pgm(os.path.join(d, "distinctiveness.pgm"))
    res, ox, oy = read_yaml_frame(os.path.join(d, "distinctiveness.yaml"))
    samples = read_samples(os.path.join(d, "localization_check.csv"))
    if len(samples) < 2:
        fail(4, f"{d}/localization_check.csv: fewer than two samples")
    try:
        with open(os.path.join(d, "islands.json")) as f:
            check = json.load(f).get("check", {})
        offset_max = float(check["offset_max"])
    except (OSError, ValueError, KeyError, TypeError) as e:
        fail(4, f"{d}/islands.json: no check offsets ({e})")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np
    except ImportError as e:
        fail(1, f"matplotlib is needed (apt-get install python3-matplotlib): {e}")

    grid = np.frombuffer(pixels, dtype=np.uint8).reshape(h, w).astype(float)
    r_map = np.ma.masked_where(grid == 255, grid / 254.0)
    extent = [ox, ox + w * res, oy, oy + h * res]
    xs, ys, rs, es = zip(*samples)
    conf = [min(1.0, max(0.0, 1.0 - e / offset_max)) for e in es]
    resid = sorted(abs(r - c) for r, c in zip(rs, conf))
    rho = spearman(list(rs), list(es))
    above = sum(1 for v in resid if v > 0.4) / len(resid)

    fig, (a, b, c) = plt.subplots(1, 3, figsize=(18, 6), layout="constrained")
    im = a.imshow(r_map, extent=extent, origin="upper", cmap="viridis", vmin=0, vmax=1)
    a.set_title("distinctiveness R (Fig. 3a)")
    fig.colorbar(im, ax=a, shrink=0.8)
    b.imshow(np.ma.masked_where(grid != 255, np.zeros_like(grid)), extent=extent, origin="upper",
             cmap="Greys", vmin=0, vmax=4)
    sc = b.scatter(xs, ys, c=conf, s=8, cmap="viridis", vmin=0, vmax=1)
    b.set_xlim(extent[0], extent[1])
    b.set_ylim(extent[2], extent[3])
    b.set_aspect("equal")
    b.set_title(f"localization confidence 1 - error / {offset_max:g} m (Fig. 3c)")
    fig.colorbar(sc, ax=b, shrink=0.8)
    levels = np.linspace(0, 1, 101)
    counts = [sum(1 for v in resid if v > t) for t in levels]
    c.plot(levels, counts)
    c.axvline(0.4, color="grey", linestyle=":")
    c.set_xlabel("residual |R - confidence|")
    c.set_ylabel("samples with a larger residual")
    c.set_title(f"residuals (Fig. 2): {100 * above:.0f} % above 0.4\n"
                f"Spearman(R, error) = {rho:.3f}")
    c.grid(True, alpha=0.3)
    out = args.out or os.path.join(d, "islands_check.png")
    fig.savefig(out, dpi=100)
    print(f"{out}: {len(samples)} samples, Spearman(R, error) = {rho:.3f}, "
          f"{100 * above:.1f} % residuals above 0.4")
    return 0


if __name__ == "__main__":
    sys.exit(main())
