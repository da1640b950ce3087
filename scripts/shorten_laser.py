#!/usr/bin/python3
"""Makes a CARMEN log's laser shorter, as a smaller robot's would be (a
Hokuyo URG reaches 4-5.6 m, many planar lidars 8-12 m): every reading
beyond --range metres becomes a no-return, written as --range + 1 m, above
every kept reading by more than the 0.3 m band in which a CARMEN reader
takes the log's largest value for its no-return code. FLASER and
ROBOTLASER1 lines are both shortened (ROBOTLASER1's max_range field becomes
the same code); the poses, timestamps and every other line are kept.

A robustness benchmark for logs one does not have: the same path seen by a
laser of shorter reach. The reference trajectory of the original log still
scores the result (the scans are the same, one for one).

Usage: shorten_laser.py IN.log[.gz] OUT.log[.gz] --range M
"""
import argparse
import gzip
import math
import os
import tempfile


def open_text(path, mode):
    return gzip.open(path, mode + "t") if path.endswith(".gz") else open(path, mode)


def shorten(fields, first, count, reach, code):
    """Readings fields[first:first+count] beyond `reach` become `code`; the
    number of them changed."""
    changed = 0
    for i in range(first, first + count):
        r = float(fields[i])  # nan and inf stay as written: no reading either way
        if math.isfinite(r) and r > reach:
            fields[i] = code
            changed += 1
    return changed


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("inp")
    ap.add_argument("out")
    ap.add_argument("--range", dest="reach", type=float, required=True,
                    help="the shorter laser's reach (m)")
    a = ap.parse_args()
    if not (a.reach > 0 and math.isfinite(a.reach)):
        ap.error("--range must be a positive number of metres")
    code = f"{a.reach + 1.0:g}"
    # Written beside OUT and renamed at the end: a log that fails half way
    # leaves no truncated OUT (nor spoils one already there).
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(a.out)),
                               suffix=".gz" if a.out.endswith(".gz") else "")
    os.close(fd)
    try:
        scans, changed, readings = write_shortened(a.inp, tmp, a.reach, code)
        os.replace(tmp, a.out)
    except (OSError, EOFError) as e:  # a missing, unreadable or damaged (gzip) log
        raise SystemExit(f"{a.inp}: {e}")
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    share = 100.0 * changed / readings if readings else 0.0
    print(f"{a.out}: {scans} scans, {changed} of {readings} readings ({share:.1f} %) "
          f"beyond {a.reach:g} m now no-returns ({code} m)")


def write_shortened(inp, out, reach, code):
    """Copies inp to out, shortened; (scans, readings changed, readings)."""
    scans = changed = readings = 0
    with open_text(inp, "r") as f, open_text(out, "w") as g:
        for n, line in enumerate(f, 1):
            s = line.split()
            kind = s[0] if s else ""
            if kind not in ("FLASER", "ROBOTLASER1"):
                g.write(line)
                continue
            try:
                if kind == "FLASER":
                    first, count = 2, int(s[1])
                else:  # ROBOTLASER1 type start fov resolution max_range accuracy mode n ...
                    first, count = 9, int(s[8])
                    s[5] = code
                if count < 0 or len(s) < first + count:
                    raise IndexError
                changed += shorten(s, first, count, reach, code)
            except (ValueError, IndexError):
                raise SystemExit(f"{inp}:{n}: a {kind} line whose beam count or readings "
                                 "do not parse, or too short for its beams")
            readings += count
            scans += 1
            g.write(" ".join(s) + "\n")
    return scans, changed, readings


if __name__ == "__main__":
    main()
