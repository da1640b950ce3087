#!/usr/bin/python3
"""What the log-rewriting scripts (thin_log.py, degrade_laser.py,
perturb_odometry.py) share: opening a log or reference as text, gzipped or
not, and writing an output that is either whole or not there at all."""
import contextlib
import gzip
import os
import tempfile


def open_text(path, mode):
    """PATH opened as text for mode "r" or "w", through gzip if it ends in .gz."""
    return gzip.open(path, mode + "t") if path.endswith(".gz") else open(path, mode)


@contextlib.contextmanager
def replaced_at_end(out):
    """Yields a temporary path beside OUT (gzipped if OUT is) and renames it
    to OUT when the block ends without an exception; otherwise removes it.
    So a script that fails half way leaves no truncated OUT, nor spoils one
    already there."""
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(out)),
                               suffix=".gz" if out.endswith(".gz") else "")
    os.close(fd)
    try:
        yield tmp
        os.replace(tmp, out)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
