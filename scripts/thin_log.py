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
import contextlib
import sys

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from log_files import open_text, replaced_at_end  # noqa: E402

LASER = ("FLASER", "ROBOTLASER1")


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


def thin_or_exit(inp, out, every, keep):
    """thin(), a missing, unreadable or damaged input a clear error."""
    try:
        return thin(inp, out, every, keep)
    except (OSError, EOFError, UnicodeDecodeError) as e:
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
    # Both outputs are written beside their names and renamed only once both
    # are whole: a run that fails leaves neither changed.
    with contextlib.ExitStack() as outputs:
        tmp = outputs.enter_context(replaced_at_end(a.out))
        kept, scans = thin_or_exit(a.inp, tmp, a.every,
                                   lambda line: line.split(" ", 1)[0] in LASER)
        if scans == 0:
            raise SystemExit(f"{a.inp}: no FLASER or ROBOTLASER1 line")
        if a.reference:
            tmp = outputs.enter_context(replaced_at_end(a.reference[1]))
            _, poses = thin_or_exit(a.reference[0], tmp, a.every, is_pose)
            if poses != scans:
                raise SystemExit(f"{a.reference[0]}: {poses} poses for the log's {scans} scans")
    print(f"{a.out}: {kept} of {scans} scans")


if __name__ == "__main__":
    main()
