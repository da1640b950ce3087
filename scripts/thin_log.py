#!/usr/bin/python3
"""Keeps one laser scan in K of a CARMEN log, as the classic logs were
thinned from their robots' recordings: FLASER and ROBOTLASER1 lines 1, K + 1,
2K + 1, ... are kept, with every other line (PARAM, ODOM, ...). With
--reference, the log's reference trajectory (one pose line per scan, as
scripts/ate.py reads them) is thinned alike, so that it still scores the
thinned log pose for pose.

With scripts/sim_office.py --step it measures what a log's scan spacing
does to a run: the same walk recorded every 5 cm, and thinned to 0.3 m or
0.5 m.

Usage: thin_log.py IN.log[.gz] OUT.log[.gz] --every K
                   [--reference IN_REF[.gz] OUT_REF[.gz]]
"""
import argparse
import gzip
import os
import tempfile

LASER = ("FLASER", "ROBOTLASER1")


def open_text(path, mode):
    return gzip.open(path, mode + "t") if path.endswith(".gz") else open(path, mode)


def is_pose(line):
    s = line.split()
    return bool(s) and not s[0].startswith("#")


def thin(inp, out, every, keep):
    """Copies inp to out with one line in `every` of those keep(line) holds;
    (lines kept, lines seen) of them."""
    kept = seen = 0
    with open_text(inp, "r") as f, open_text(out, "w") as g:
        for line in f:
            if keep(line):
                seen += 1
                if (seen - 1) % every:
                    continue
                kept += 1
            g.write(line)
    return kept, seen


def atomic(inp, out, every, keep):
    """thin() into a file beside OUT, renamed at the end: a run that fails
    half way leaves no truncated OUT (nor spoils one already there)."""
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(out)),
                               suffix=".gz" if out.endswith(".gz") else "")
    os.close(fd)
    try:
        counts = thin(inp, tmp, every, keep)
        return counts, tmp
    except (OSError, EOFError, UnicodeDecodeError) as e:  # missing, unreadable, damaged
        os.remove(tmp)
        raise SystemExit(f"{inp}: {e}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("inp")
    ap.add_argument("out")
    ap.add_argument("--every", type=int, required=True, help="keep one scan in this many")
    ap.add_argument("--reference", nargs=2, metavar=("IN_REF", "OUT_REF"))
    a = ap.parse_args()
    if a.every < 1:
        ap.error("--every must be at least 1")
    done = []
    try:
        (kept, scans), tmp = atomic(a.inp, a.out, a.every,
                                    lambda line: line.split(" ", 1)[0] in LASER)
        done.append((tmp, a.out))
        if scans == 0:
            raise SystemExit(f"{a.inp}: no FLASER or ROBOTLASER1 line")
        if a.reference:
            (_, poses), tmp = atomic(a.reference[0], a.reference[1], a.every, is_pose)
            done.append((tmp, a.reference[1]))
            if poses != scans:
                raise SystemExit(f"{a.reference[0]}: {poses} poses for the log's {scans} scans")
        for tmp, out in done:
            os.replace(tmp, out)
    finally:
        for tmp, _ in done:
            if os.path.exists(tmp):
                os.remove(tmp)
    print(f"{a.out}: {kept} of {scans} scans")


if __name__ == "__main__":
    main()
