"""Rows added to the printed tables at the extremes the table step misses: a 30° table of an
engine whose pressure peaks at 372° would otherwise show a p_г of 2,9 MPa where the cylinder sees
5 MPa, and the largest tangential force of the cycle not at all."""

from __future__ import annotations

import re

import numpy as np
from conftest import as_read

from crankdyn.report.context import add_extreme_rows, sample_rows


def _grid(step_deg: float = 1.0, cycle_deg: float = 720.0) -> np.ndarray:
    return np.arange(0.0, cycle_deg, step_deg)


def test_a_peak_between_the_rows_gets_a_row_in_angle_order():
    angle = _grid()
    values = np.exp(-(((angle - 372.0) / 8.0) ** 2))  # a combustion-like peak at 372°
    rows, labels = sample_rows(angle, 30.0)
    rows2, labels2, marks = add_extreme_rows(angle, rows, labels, [(values, "max", "peak")])
    assert len(rows2) == len(rows) + 1
    assert list(labels2) == sorted(labels2)
    (mark,) = marks
    assert (
        mark.crank_angle_deg == 372.0
        and labels2[mark.position] == 372.0
        and rows2[mark.position] == 372
    )
    assert mark.what == "peak"
    assert values[rows2].max() == values.max()  # the table now shows the true largest value


def test_an_extreme_on_a_row_or_within_the_resolution_adds_nothing():
    angle = _grid()
    rows, labels = sample_rows(angle, 30.0)
    on_row = np.cos(
        np.radians(angle)
    )  # largest at 0° and 360°, least at 180° and 540°: rows already
    _, labels2, marks = add_extreme_rows(
        angle, rows, labels, [(on_row, "max", "a"), (on_row, "min", "b")]
    )
    assert marks == [] and list(labels2) == list(labels)
    # 1° off a row, a hair above it: a row would repeat the same printed number
    nearly = np.cos(np.radians(angle - 1.0))
    assert add_extreme_rows(angle, rows, labels, [(nearly, "max", "c")])[2] == []
    assert (
        len(add_extreme_rows(angle, rows, labels, [(nearly, "max", "c")], resolution=0.0)[2]) == 1
    )


def test_extremes_at_one_angle_share_a_row_and_the_least_is_found_too():
    angle = _grid(0.5)
    # a narrow peak at 127.5° and a narrow trough at 307.5°, both between the 30° rows
    values = np.exp(-(((angle - 127.5) / 5.0) ** 2)) - np.exp(-(((angle - 307.5) / 5.0) ** 2))
    rows, labels = sample_rows(angle, 30.0)
    rows2, labels2, marks = add_extreme_rows(
        angle,
        rows,
        labels,
        [
            (values, "max", "largest"),
            (2 * values, "max", "twice as large"),
            (values, "min", "least"),
        ],
    )
    assert [(m.crank_angle_deg, m.what) for m in marks] == [
        (127.5, "largest, twice as large"),
        (307.5, "least"),
    ]
    assert len(rows2) == len(rows) + 2


def test_the_report_shows_the_peak_pressure_row_in_bold_and_names_it(shared_report):
    out = shared_report(
        "petrol-1cyl-uk"
    )  # the HTML report, shared with other test files (read only)
    html = as_read((out / "report.html").read_text(encoding="utf-8"))
    tables = re.findall(
        r'<table class="data[^"]*" data-number="([^"]+)".*?</table>\s*(<p class="table-note">.*?</p>)?',
        html,
        re.S,
    )
    notes = {
        number: note.replace("<i>", "").replace("</i>", "") for number, note in tables
    }  # letters in italics
    assert "α = 372° – найбільший тиск у циліндрі" in notes["4.1"]
    # each table names the extremes of its own columns: p_г and n in 5.1, q in 5.2, t in both
    assert (
        "найбільша тангенціальна сила" in notes["5.1"]
        and "найбільша тангенціальна сила" in notes["5.2"]
    )
    assert (
        "тиск газів" in notes["5.1"]
        and "тиск газів" not in notes["5.2"]
        and "бокова сила" in notes["5.1"]
    )
    assert (
        "α = 1° – найбільша рівнодійна сила q" in notes["5.2"]
    )  # the conclusions' angle has its row
    assert "Примітка. Крім рядків із кроком 30°" in notes["4.1"]
    table_41 = html[html.index('data-number="4.1"') :]
    table_41 = table_41[: table_41.index("</table>")]
    assert re.search(
        r'<tr(?: data-continued="[^"]*")? class="extremum"><td><b>372</b></td>', table_41
    )


def test_a_curve_over_the_whole_cycle_is_drawn_to_the_cycle_end():
    """Fig. 5.2 ended at 719° about 8 N·m above the table's 0,0 at 720°: a periodic curve on the
    cycle's grid (which has no end point) is closed with its first value; others are left alone."""
    from crankdyn.report.figures import crank_angle_axis, new_figure

    angle = _grid(1.0)
    fig, axes = new_figure(16, 10, nrows=2, sharex=True)
    whole = axes[0].plot(angle, np.sin(np.radians(angle)) + 2.0)[0]
    half = axes[1].plot(angle[:360], np.cos(np.radians(angle[:360])))[
        0
    ]  # one revolution of a 720° cycle
    crank_angle_axis(axes[1], 720.0, "α, °")
    x, y = whole.get_xdata(), whole.get_ydata()
    assert x[-1] == 720.0 and y[-1] == y[0] == 2.0 and len(x) == len(angle) + 1
    assert len(half.get_xdata()) == 360 and half.get_xdata()[-1] == 359.0


def test_of_equal_peaks_in_every_period_the_first_in_the_cycle_gets_the_row():
    """A torque repeating every 240°: its peaks differ by rounding only, and the row (as the
    conclusions, which name the first such angle) is at the first, not at a later one a hair
    higher."""
    angle = _grid()
    values = np.cos(np.radians(3 * (angle - 224.0)))  # peaks at 104°, 224°, 344°, ... (period 120°)
    values[np.flatnonzero(angle == 464.0)] += 1e-13  # a later peak higher by rounding only
    rows, labels = sample_rows(angle, 30.0)
    _, _, marks = add_extreme_rows(angle, rows, labels, [(values, "max", "M_d max")])
    (mark,) = marks
    assert mark.crank_angle_deg == 104.0
