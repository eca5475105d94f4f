"""The processes a process has started and not yet reaped, for the tests that fork (run in the
fresh interpreters of test_background and test_printer, which import this file)."""

import glob
import os


def children() -> list[str]:
    """The /proc stat files of this process's children (Linux)."""
    mine = str(os.getpid())
    found = []
    for path in glob.glob("/proc/[0-9]*/stat"):
        try:  # any process of the machine may end between the listing and the read
            with open(path) as fh:
                parent = fh.read().split(") ")[-1].split()[1]
        except (FileNotFoundError, ProcessLookupError, IndexError):
            continue
        if parent == mine:
            found.append(path)
    return found
