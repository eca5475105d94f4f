"""The conclusions name the main journal of the largest running torque, with the section's value."""

from __future__ import annotations

import pytest
from test_plausibility_in_report import Note


def test_the_last_journal_of_an_inline_four_carries_the_engines_torque_and_is_concluded():
    # the journal after the last crank passes the torque of every crank: the engine's torque
    note = Note("inline4-petrol", {}, ("torque",), "en")
    r = note.result.outputs["torque"].results
    engine_largest = max(abs(r["max_Nm"]), abs(r["min_Nm"]))
    assert r["journals"][-1]["max_abs_Nm"] == pytest.approx(engine_largest, rel=1e-9)
    assert max(j["max_abs_Nm"] for j in r["journals"]) == pytest.approx(engine_largest, rel=1e-9)
    value = f"{engine_largest:.1f}"
    sentence = f"carried by main journal 4–5 (after crank 4): {value} N·m."
    assert sentence in note.conclusions
    assert f"on the journal after crank 4: {value} N·m" in note.section("torque")


def test_an_inner_journal_of_the_largest_running_torque_is_concluded_in_the_notes_language():
    # a crank arrangement whose cranks' torques partly cancel: the largest is not on the last
    changes = {"engine": {"cylinders": 5, "firing_order": None}}
    note = Note("inline4-petrol", changes, ("torque",), "uk")
    journals = note.result.outputs["torque"].results["journals"]
    peaks = [j["max_abs_Nm"] for j in journals]
    k = max(range(len(peaks)), key=lambda i: (peaks[i], i)) + 1
    assert k < len(peaks)
    assert f"корінна шийка {k}–{k + 1} (за коліном {k})" in note.conclusions


def test_no_running_torque_conclusion_for_one_crank():
    note = Note("petrol-1cyl", {}, ("torque",), "ru")
    assert "набегающий момент передаёт" not in note.conclusions


def test_the_journals_names_are_explained_before_the_figure_that_first_uses_them():
    """The journals' running-torque figure labels its curves "0–1" … "4–5": how a journal is
    named stands in the sentence that announces that figure, not only later at the table."""
    import re

    from conftest import shared_html

    html = shared_html("inline4-petrol", None, "en").linked_html
    text = re.sub(r"<[^>]+>", "", html).replace("&#39;", "'")
    named = text.index("a journal is named by the cranks it lies between")
    figure = text.index("— Running torques on the main journals")
    table = text.index("The largest and smallest running torques on the main journals")
    assert named < figure < table
    assert text.count("a journal is named by the cranks it lies between") == 1
