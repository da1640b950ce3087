#!/usr/bin/python3
"""What the tests of the trajectory scripts share: running a script of
scripts/ under this Python, and writing trajectory files."""
import os
import subprocess
import sys

SCRIPTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def runner(name):
    """A function that runs scripts/NAME with its arguments, output captured."""
    path = os.path.join(SCRIPTS, name)

    def run(*args):
        return subprocess.run([sys.executable, path, *args], capture_output=True, text=True)
    return run


def write_rows(path, rows, digits=6):
    """One line of space-separated numbers per row."""
    with open(path, "w") as f:
        for r in rows:
            f.write(" ".join(f"{v:.{digits}f}" for v in r) + "\n")
