"""The lint and the static types of pyproject.toml hold: ``ruff check`` ([tool.ruff]) on the whole
repository and ``mypy`` ([tool.mypy]: the core and the built-in plugins), each also shown to fail
on a file that breaks its rules."""

from __future__ import annotations

import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Unsorted imports (I001), an unused one (F401), a zip without strict= (B905), typing.List (UP006).
BAD_LINT = """import sys
import os
from typing import List


def pairs(a: List[int], b: List[int]):
    return list(zip(a, b))
"""

#: A str returned where an int is promised, and an int passed where a str is expected.
BAD_TYPES = """def length(text: str) -> int:
    return text


length(3)
"""


def _tool(module: str, *args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    if importlib.util.find_spec(module) is None:
        pytest.skip(f"{module} is not importable (requirements/lock.txt's test extra has it)")
    return subprocess.run(
        [sys.executable, "-m", module, *args], cwd=cwd, capture_output=True, text=True, timeout=600
    )


def test_ruff_finds_nothing():
    done = _tool("ruff", "check", "--no-cache", ".")
    assert done.returncode == 0, done.stdout + done.stderr


def test_ruff_with_the_repositorys_rules_refuses_a_bad_file(tmp_path):
    (tmp_path / "bad.py").write_text(BAD_LINT, encoding="utf-8")
    done = _tool(
        "ruff",
        "check",
        "--no-cache",
        "--config",
        str(ROOT / "pyproject.toml"),
        "--output-format",
        "concise",
        str(tmp_path / "bad.py"),
    )
    assert done.returncode == 1
    codes = set(re.findall(r": ([A-Z]+[0-9]+) ", done.stdout))
    assert {"I001", "F401", "B905", "UP006"} <= codes, done.stdout


@pytest.mark.slow  # the whole tree, 10 s without its cache: in the slow tier, which CI runs
@pytest.mark.long
def test_mypy_finds_nothing():
    """The files, the per-module exceptions and the cache folder (.mypy_cache, kept between runs:
    a warm run checks only what changed) are [tool.mypy]'s."""
    done = _tool("mypy")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Success: no issues found" in done.stdout


def test_mypy_refuses_a_bad_file(tmp_path):
    (tmp_path / "bad.py").write_text(BAD_TYPES, encoding="utf-8")
    done = _tool(
        "mypy",
        "--config-file",
        str(ROOT / "pyproject.toml"),
        "--cache-dir",
        str(ROOT / ".mypy_cache" / "refused"),
        str(tmp_path / "bad.py"),
    )
    assert done.returncode == 1
    assert "bad.py:2: error: Incompatible return value type" in done.stdout, done.stdout
    wrong_argument = 'bad.py:5: error: Argument 1 to "length" has incompatible type'
    assert wrong_argument in done.stdout, done.stdout
