"""docs/performance.md's acceptance table is written by benchmarks/acceptance.py, between marks."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))

import acceptance  # noqa: E402


def test_the_performance_page_has_the_marks_the_benchmark_writes_between():
    text = (ROOT / "docs" / "performance.md").read_text(encoding="utf-8")
    start, end = text.find(acceptance.DOCS_START), text.find(acceptance.DOCS_END)
    assert 0 <= start < end


def test_writing_the_figures_replaces_the_table_and_keeps_the_page(tmp_path):
    page = tmp_path / "performance.md"
    page.write_text(
        f"# Performance\n\nintro\n\n{acceptance.DOCS_START}\nold table\n{acceptance.DOCS_END}\n"
        "\nafter\n",
        encoding="utf-8",
    )
    rows = [("html / 2 x import", 3.0, 2.0), ("table monotone, runs of 10 / 10", 10, 10)]
    for _ in range(2):  # a second run replaces the first run's table
        acceptance.write_docs(page, "acceptance (2 cores)", rows, ["a note"])
    text = page.read_text(encoding="utf-8")
    assert "old table" not in text and text.count("| html / 2 x import |") == 1
    # 3.0 s against a 2.0 s goal: ratio 1.50, not met; ten monotone runs of ten: met
    assert "| html / 2 x import | 3.000 | 2.000 | 1.50 | NOT MET |" in text
    assert "| table monotone, runs of 10 / 10 | 10.000 | 10.000 | 1.00 | ok |" in text
    assert text.startswith("# Performance\n\nintro\n\n") and text.endswith("\nafter\n")


def test_the_figures_are_timed_in_turns_with_their_yardstick(tmp_path):
    log = tmp_path / "order"
    runs = [
        ([sys.executable, "-c", f"open({str(log)!r}, 'a').write('{name}')"], {}) for name in "ab"
    ]
    medians = acceptance.walls(runs, repeat=3)
    # a warm-up round, then three rounds, each command once a round
    assert log.read_text() == "ab" * 4
    assert len(medians) == 2 and all(m > 0 for m in medians)


def test_a_command_that_fails_stops_the_benchmark():
    failing = ([sys.executable, "-c", "raise SystemExit(3)"], {})
    with pytest.raises(SystemExit, match="exited with 3"):
        acceptance.walls([failing], repeat=1)
    assert acceptance.walls([failing], repeat=1, codes=(3,))[0] > 0
