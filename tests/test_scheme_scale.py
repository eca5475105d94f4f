"""The kinematic scheme (Fig. 3.1) is drawn to the standard scale its caption states: a millimetre
on paper is 1/scale millimetres of the mechanism, and the figure fits the A4 text width, where the
PDF shows it at its own size."""

from __future__ import annotations

import pytest
from test_scheme_labels import _positions

from crankdyn.report import mechanism_drawing as md
from crankdyn.report.figures import FIXED_LAYOUT, to_svg

MM_PER_INCH = 25.4


@pytest.mark.parametrize(
    ("extent", "room", "scale"),
    [
        ((100.0, 100.0), (150.0, 150.0), 1.0),
        ((300.0, 100.0), (150.0, 150.0), 0.5),
        ((340.0, 100.0), (150.0, 150.0), 0.4),  # 1:2 gives 170 mm: 1:2,5
        ((10.0, 5.0), (150.0, 150.0), 10.0),  # 20:1 would give 200 mm
        ((2.0, 2.0), (150.0, 150.0), 50.0),
        ((14_000.0, 100.0), (150.0, 150.0), 1 / 100),
        ((16_000.0, 100.0), (150.0, 150.0), 1 / 200),
        ((50_000.0, 100.0), (150.0, 150.0), 1 / 500),
        ((80_000.0, 100.0), (150.0, 150.0), 1 / 1000),
    ],
)
def test_drawing_scale_is_the_largest_standard_one_that_fits(extent, room, scale):
    assert md.drawing_scale(extent, room) == pytest.approx(scale)


@pytest.mark.parametrize(
    "example",
    ["petrol-1cyl", "inline4-petrol", "v8-petrol", "radial9-aircraft", "offset-crank-engine"],
)
def test_scheme_is_drawn_at_its_scale_and_fits_the_page(example):
    positions = _positions(example)
    labels = {k: f"{k} = {value * 1e3:g} mm" for k, value in positions.dimensions.items()}
    fig, scale = md.scheme_figure(
        positions, 0, labels, "Crank star (at the TDC of cylinder 1)", "Firing order: 1"
    )
    assert any(abs(scale - s) < 1e-12 for s in md.DRAWING_SCALES)
    assert getattr(fig, FIXED_LAYOUT)
    to_svg(fig)  # drawn as the report draws it: the layout must not have moved the drawing
    ax = fig.axes[0]
    width_in, height_in = fig.get_size_inches()
    paper_mm = (
        ax.get_position().width * width_in * MM_PER_INCH,
        ax.get_position().height * height_in * MM_PER_INCH,
    )
    real_mm = (ax.get_xlim()[1] - ax.get_xlim()[0], ax.get_ylim()[1] - ax.get_ylim()[0])
    assert paper_mm[0] == pytest.approx(real_mm[0] * scale, rel=1e-9)
    assert paper_mm[1] == pytest.approx(real_mm[1] * scale, rel=1e-9)
    assert width_in * MM_PER_INCH <= md.PAGE_ROOM_MM[0]
    assert height_in * MM_PER_INCH <= md.PAGE_ROOM_MM[1]


def test_the_bore_is_drawn_at_scale():
    """Independent of the axes: the piston's width on paper, from the drawn liner, is D x scale."""
    positions = _positions("petrol-1cyl")
    fig, scale = md.scheme_figure(positions, 0, {}, "", "")
    ax = fig.axes[0]
    to_svg(fig)
    bore_mm = positions.dimensions["D"] * 1e3
    # the liner's two walls: the long vertical lines of at least 1 pt
    walls = sorted(
        {
            round(float(line.get_xdata()[0]), 6)
            for line in ax.lines
            if line.get_linewidth() >= 1.0
            and len(line.get_xdata()) == 2
            and line.get_xdata()[0] == line.get_xdata()[1]
            and abs(line.get_ydata()[1] - line.get_ydata()[0]) > bore_mm
        }
    )
    left, right = ax.transData.transform([(walls[0], 0.0), (walls[-1], 0.0)])[:, 0]
    on_paper_mm = (right - left) / fig.dpi * MM_PER_INCH
    assert on_paper_mm == pytest.approx(bore_mm * scale, rel=0.02)


@pytest.mark.parametrize(
    ("example", "cylinders", "links"),
    [
        ("inline4-petrol", ["1"], {"crank_1", "rod_1"}),
        ("inline6-diesel-trace", ["1"], {"crank_1", "rod_1"}),
        ("v8-petrol", ["1L", "1R"], {"crank_1", "rod_1L", "rod_1R"}),
    ],
)
def test_front_view_shows_the_first_cylinder_of_each_row(example, cylinders, links):
    """In front view an in-line engine's cylinders hide one another: one piston, its rod and its
    crank, not four rods meeting on one piston pin; a V shows both banks' first cylinders."""
    geometry = _positions(example)
    front = md.front_view(geometry)
    assert [g.label for g in front.guides] == cylinders
    assert {name for name, _, _ in front.links} == links
    assert front.cranks == geometry.cranks  # the crank star still shows every crank
    for _, a, b in front.links:
        assert a in front.joints and b in front.joints


def test_front_view_keeps_a_radial_engine_whole():
    geometry = _positions("radial9-aircraft")
    assert md.front_view(geometry) is geometry


MARKS = {"alpha": "α", "beta": "β", "omega": "ω", "tdc": "TDC", "bdc": "BDC"}


@pytest.mark.parametrize(
    ("example", "drawings"),
    [("petrol-1cyl", 1), ("kinematics-only", 3), ("v8-petrol", 3)],
)
def test_the_scheme_with_its_marks_takes_the_scale_the_search_without_them_finds(
    monkeypatch, example, drawings
):
    """A mechanism that fits at the first scale tried is drawn once, with its marks; one that
    does not gets the scale the search without the marks finds, as before it was tried."""
    positions = _positions(example)
    labels = {k: f"{k} = {value * 1e3:g} mm" for k, value in positions.dimensions.items()}
    args = (positions, 0, labels, "Crank star", "Firing order: 1", MARKS)
    made = []
    scheme_at = md._scheme_at

    def counted(*a, **k):
        made.append(bool(a[6]))
        return scheme_at(*a, **k)

    monkeypatch.setattr(md, "_scheme_at", counted)
    fig, scale = md.scheme_figure(*args)
    assert len(made) == drawings and made[0] and made[-1]  # the first and the kept one marked

    # the full search: at each scale the drawing without marks first, as the report made it
    geometry = md.upright(md.front_view(positions))
    (x0, x1), (y0, y1) = md._limits(geometry)
    room = md.SCHEME_ROOM_WITH_STAR_MM if len(geometry.cranks) > 1 else md.SCHEME_ROOM_MM
    searched = md.drawing_scale(
        (x1 - x0, y1 - y0), (room[0] * md._LIMITS_SLACK, room[1] * md._LIMITS_SLACK)
    )
    while not (
        md._fits(scheme_at(geometry, 0, *args[2:5], searched, {}), room[1], searched)
        and md._fits(scheme_at(geometry, 0, *args[2:5], searched, MARKS), room[1], searched)
    ):
        searched = md._smaller_scale(searched)
    assert scale == searched
