"""Helpers of the tests that fork: the processes a process has started and not yet reaped, and
running a test in a pytest process of its own (test_aside, test_background, test_printer,
test_study_worker)."""

import functools
import glob
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# Set to a test's node id in the pytest process that runs it alone (``in_fresh_process``).
FRESH_PROCESS_ENV = "CRANKDYN_TEST_FRESH_PROCESS"


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


def in_fresh_process(test):
    """Run the decorated test in a fresh pytest process of its own: an interpreter with no thread
    but its own (a pytest-xdist worker has some, and the code under test forks only without), in
    which nothing of another test was imported or started. Its assertions stay in the test
    function, and a failure shows that process's pytest report."""

    @functools.wraps(test)
    def wrapper(*args, **kwargs):
        node = os.environ["PYTEST_CURRENT_TEST"].rsplit(" ", 1)[0]
        if os.environ.get(FRESH_PROCESS_ENV) == node:
            return test(*args, **kwargs)
        env = {
            k: v
            for k, v in os.environ.items()
            if not k.startswith(("PYTEST_XDIST", "PYTEST_CURRENT_TEST")) and k != FRESH_PROCESS_ENV
        }
        env[FRESH_PROCESS_ENV] = node
        # No plugin of another package (no xdist workers, so no execnet threads; importing the
        # plugins, anyio's among them, is a third of pytest's start) and so no addopts (its -n is
        # xdist's); -m "": the node runs whatever its marks; without the cache and conftest.py the
        # test does not use (such a test takes its fixtures from pytest itself).
        env["PYTEST_DISABLE_PLUGIN_AUTOLOAD"] = "1"
        done = subprocess.run(
            [
                sys.executable,
                "-m",
                "pytest",
                "-q",
                "-o",
                "addopts=",
                "-p",
                "no:cacheprovider",
                "--noconftest",
                "-m",
                "",
                node,
            ],
            cwd=ROOT,
            env=env,
            capture_output=True,
            text=True,
            timeout=600,
            check=False,
        )
        report = done.stdout[-6000:] + done.stderr[-2000:]
        assert done.returncode == 0, f"{node} failed in its own process:\n{report}"
        assert re.search(r"\b1 passed\b", done.stdout), (
            f"{node} did not run in its own process:\n{report}"
        )

    return wrapper
