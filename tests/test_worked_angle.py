"""The worked substitutions' crank angle: taken at its point of each table's period."""

from __future__ import annotations

import re

from crankdyn.report.worked import snapped, worked_row


def test_an_angle_past_a_tables_span_is_taken_at_its_point_of_the_period():
    """[report] worked_angle_deg = 390 (30° into the cycle's second turn): the cycle's tables
    (0…720°) take 390°, a one-turn table (0…360°) its 30°, not its nearest row 360°, where
    every term of the kinematics is zero and the check shows nothing."""
    turn = [float(a) for a in range(0, 361, 30)]
    cycle = [float(a) for a in range(0, 721, 30)]
    assert turn[worked_row(turn, 390.0)] == 30.0
    assert cycle[worked_row(cycle, 390.0)] == 390.0
    assert turn[worked_row(turn, -30.0)] == 330.0
    open_turn = [float(a) for a in range(0, 331, 30)]  # a table of one turn without its 360° row
    assert open_turn[worked_row(open_turn, 365.0)] == 0.0
    assert turn[worked_row(turn, 44.0)] == 30.0  # inside the span: the nearest row, as before


def test_rounding_noise_is_substituted_as_zero():
    assert snapped(-3.852e-15, 90.0) == 0.0
    assert snapped(1e-6, 90.0) == 1e-6


def test_a_worked_angle_in_the_second_turn_gives_the_kinematics_check_at_30_degrees():
    from conftest import shared_html

    page = shared_html("petrol-1cyl", {"report": {"worked_angle_deg": 390}}, "ru", ("kinematics",))
    text = re.sub(r"<[^>]+>", "", page.linked_html)
    assert "10⁻¹⁵" not in text and "+ −" not in text
    assert "α = 30°" in text.replace("\u2009", " ").replace("\xa0", " ")
