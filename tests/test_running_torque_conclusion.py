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
