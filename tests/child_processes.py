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


def run_fresh(setup: str, code: str, timeout: float = 120, says_ok: bool = True):
    """Run ``setup`` and the (dedented) ``code`` in a fresh interpreter, which then has no thread
    but its own (a pytest-xdist worker has some, and the code under test forks only without);
    it must exit 0 and, with ``says_ok``, print "ok" last. Returns the finished process."""
    import subprocess
    import sys
    import textwrap

    done = subprocess.run([sys.executable, "-c", setup + textwrap.dedent(code)], capture_output=True, text=True,
                          timeout=timeout)
    assert done.returncode == 0, done.stdout + done.stderr
    if says_ok:
        assert done.stdout.strip().endswith("ok"), done.stdout
    return done
