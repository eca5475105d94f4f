"""The table of strokes (crankdyn.physics.layout.stroke_sequence, the bays section's table):
which stroke each cylinder is in over cylinder 1's crank angle."""

from __future__ import annotations

import pytest

from crankdyn.physics.layout import stroke_sequence


def _expanded(runs):
    return [stroke for stroke, span in runs for _ in range(span)]


def test_an_in_line_four_firing_1_3_4_2_is_the_textbooks_table():
    """Cylinders 1…4 with cycle delays 0, 540, 180, 360° (firing 1–3–4–2, 180° apart): the table
    every textbook prints, each stroke once in every half turn."""
    step, rows = stroke_sequence([0.0, 540.0, 180.0, 360.0])
    assert step == 180.0
    assert [_expanded(r) for r in rows] == [
        ["intake", "compression", "expansion", "exhaust"],
        ["compression", "expansion", "exhaust", "intake"],
        ["exhaust", "intake", "compression", "expansion"],
        ["expansion", "exhaust", "intake", "compression"],
    ]
    for column in zip(*(_expanded(r) for r in rows), strict=True):
        assert sorted(column) == sorted(["intake", "compression", "expansion", "exhaust"])


def test_a_v8_firing_every_90_degrees_has_90_degree_columns_and_strokes_spanning_two():
    delays = [0.0, 90.0, 450.0, 540.0, 270.0, 360.0, 180.0, 630.0]
    step, rows = stroke_sequence(delays)
    assert step == 90.0
    for delay, runs in zip(delays, rows, strict=True):
        strokes = _expanded(runs)
        assert len(strokes) == 8
        # cylinder i is in stroke floor(((a - delay) mod 720) / 180) at the column's start a
        assert strokes == [
            ("intake", "compression", "expansion", "exhaust")[int(((c * 90 - delay) % 720) // 180)]
            for c in range(8)
        ]
        assert sum(span for _, span in runs) == 8 and all(
            a[0] != b[0] for a, b in zip(runs, runs[1:], strict=False)
        )
    for column in zip(
        *(_expanded(r) for r in rows), strict=True
    ):  # two cylinders in each stroke at any moment
        assert all(column.count(s) == 2 for s in set(column))


@pytest.mark.parametrize("delays", [[0.0, 45.5], [0.0, 10.0, 370.0]])
def test_no_table_where_the_strokes_begin_between_whole_degrees_or_too_often(delays):
    assert stroke_sequence(delays) is None


def test_the_bays_section_prints_the_table_with_strokes_spanning_their_columns():
    from conftest import shared_html

    html = shared_html("v8-petrol", language="uk").linked_html
    import re

    assert re.search(
        r"Таблиця \d+\.2 – Чергування тактів у циліндрах за кутом повороту колінчастого вала, °",
        html,
    )
    table = html[html.index("Чергування тактів у циліндрах за кутом") :]
    table = table[: table.index("</table>")]
    assert "<th>630–720</th>" in table and table.count('colspan="2">робочий хід<') >= 6


def test_an_offset_fours_stroke_table_says_its_strokes_are_not_half_turns():
    """With the cylinder axis offset the piston reaches BDC 183.2° after TDC (e = 12 mm, R = 39 mm,
    L = 139.3 mm: φ from sin φ = e/(L ± R)): the table of strokes by half-turns says how long
    the strokes really are; a central engine's says nothing of it."""
    import math

    from conftest import shared_html, shared_run

    offset = {"engine": {"mechanism": "offset_crank_slider"}, "mechanism": {"offset": "12 mm"}}
    r = shared_run("inline4-petrol", offset).outputs["bays"].results
    radius = 0.039
    rod = radius / 0.28
    tdc = math.asin(0.012 / (rod + radius))
    bdc = math.pi + math.asin(0.012 / (rod - radius))
    assert r["bdc_crank_angle_deg"] == pytest.approx(math.degrees(bdc - tdc), abs=1e-6)
    page = shared_html("inline4-petrol", offset, "en", ("bays",)).linked_html
    outward = f"{r['bdc_crank_angle_deg']:.4g}"
    assert f"strokes away from the crankshaft and towards it take {outward}°" in page
    central = shared_html("inline4-petrol", None, "en", ("bays",)).linked_html
    assert "strokes away from the crankshaft and towards it" not in central
