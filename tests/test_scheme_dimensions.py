"""The schemes' dimensions follow ГОСТ 2.307: two extension lines from the feature, square to the
dimension line and running past it, the dimension line with its arrows between them, the text
beside the dimension line; and a V engine's scheme names its points and angles as a single
cylinder's does (O, U, each bank's A and β with the bank's letter, α, ω)."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import shared_run

from crankdyn.report import mechanism_drawing as md

ENGINES = {
    "v8": ("v8-petrol", {}),
    "single": ("petrol-1cyl", {}),
    "offset": ("offset-crank-engine", {}),
    "radial9": ("radial9-aircraft", {}),
    "inline4": ("inline4-petrol", {}),
    # the V8's cylinders in three banks at 60° and in four at 90°, firing evenly
    "w12": (
        "v8-petrol",
        {
            "engine": {
                "layout": "W",
                "cylinders": 12,
                "bank_angle_deg": 60,
                "crank_angles_deg": None,
                "firing_order": [f"{k}{bank}" for k in range(1, 5) for bank in "LCR"],
            }
        },
    ),
    "x16": (
        "v8-petrol",
        {
            "engine": {
                "layout": "X",
                "cylinders": 16,
                "bank_angle_deg": 90,
                "crank_angles_deg": None,
                "firing_order": [
                    f"{k}{bank}" for pair in (1, 3) for bank in "ABCD" for k in (pair, pair + 1)
                ],
            }
        },
    ),
}
MARKS = {"alpha": "α", "beta": "β", "omega": "ω", "tdc": "TDC", "bdc": "BDC"}


def _scheme(engine: str):
    name, changes = ENGINES[engine]
    output = shared_run(name, changes, stages=("drawing",)).outputs["drawing"]
    positions = output.artifacts["positions"]
    labels = {k: f"{k} = {value * 1e3:g} mm" for k, value in positions.dimensions.items()}
    frame = len(output.results["crank_angles_deg"])
    fig, _ = md.scheme_figure(positions, frame, labels, "Crank star", "Firing order: 1", MARKS)
    fig.canvas.draw()
    return fig, md.upright(md.front_view(positions)), frame


def _by_gid(ax) -> dict:
    found = {}
    for artist in ax.get_children():
        gid = artist.get_gid()
        if gid:
            found.setdefault(gid, []).append(artist)
    return found


def _dimensions(ax) -> dict:
    """{key: (dimension line's ends, [extension lines' ends], text or None)} in mm."""
    found = _by_gid(ax)
    dimensions = {}
    for gid, (arrow,) in ((g, a) for g, a in found.items() if g.endswith("-line")):
        key = gid.removeprefix("dimension-").removesuffix("-line")
        extensions = [
            np.asarray(found[f"dimension-{key}-extension-{k}"][0].get_xydata(), float)
            for k in (1, 2)
            if f"dimension-{key}-extension-{k}" in found
        ]
        text = found.get(f"dimension-{key}-text", [None])[0]
        ends = np.array([arrow.xyann, arrow.xy], dtype=float)
        dimensions[key] = (ends, extensions, text)
    return dimensions


@pytest.mark.parametrize("engine", list(ENGINES))
def test_each_dimension_has_two_extension_lines_past_its_arrows(engine):
    fig, geometry, _ = _scheme(engine)
    dimensions = _dimensions(fig.axes[0])
    assert {"R", "D"} <= set(dimensions)
    for key, (ends, extensions, text) in dimensions.items():
        assert len(extensions) == 2, key
        along = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
        extent = md._extent_mm(geometry)
        for end, line in zip(ends, extensions, strict=True):
            square = (line[1] - line[0]) / np.linalg.norm(line[1] - line[0])
            assert abs(float(square @ along)) < 1e-6, key  # at right angles to the dimension
            # the arrow's point lies on the extension line, which runs on past it
            t = float((end - line[0]) @ square)
            assert np.linalg.norm(line[0] + square * t - end) < 1e-6 * extent, key
            assert 0.0 < t < float(np.linalg.norm(line[1] - line[0])) - 0.005 * extent, key
        assert text is not None and text.get_text().startswith(f"{key} ="), key


@pytest.mark.parametrize("engine", ["v8", "single", "radial9"])
def test_the_bore_is_dimensioned_from_the_liners_wall_ends(engine):
    """D's extension lines start at the ends of the liner's walls (not in the air above them) and
    its text stands over the dimension line, away from the cylinder."""
    fig, geometry, frame = _scheme(engine)
    ends, extensions, text = _dimensions(fig.axes[0])["D"]
    guide = geometry.guides[0]
    o, d, n = md._guide_frame(geometry, guide, frame)
    top = md.liner_ends_mm(guide, geometry)[1]
    half = guide.bore_m * 1e3 / 2
    walls = [o + d * top - n * half, o + d * top + n * half]
    for wall, line in zip(walls, extensions, strict=True):
        assert np.allclose(line[0], wall, atol=1e-9)
        assert float((line[1] - line[0]) @ d) > 0  # away from the cylinder's head
    box = text.get_window_extent(fig.canvas.get_renderer())
    centre = (
        fig.axes[0].transData.inverted().transform([(box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2])
    )
    assert float((centre - ends.mean(axis=0)) @ d) > 0  # beyond the dimension line


def test_a_v_engines_scheme_names_its_points_and_angles():
    fig, geometry, _ = _scheme("v8")
    found = _by_gid(fig.axes[0])
    texts = {
        gid: [a.get_text() for a in artists]
        for gid, artists in found.items()
        if gid.startswith("mark-")
    }
    assert texts["mark-O"] == ["O"] and texts["mark-U"] == ["U"]
    assert texts["mark-α"] == ["α"] and texts["mark-ω"] == ["ω"]
    banks = sorted(md.bank_letter(g.label) for g in geometry.guides)
    assert banks == ["L", "R"]
    for letter in banks:  # each bank's piston pin and rod angle indexed with its letter
        assert texts[f"mark-A_{letter}"] == ["A"] and texts[f"mark-A_{letter}-index"] == [letter]
        assert texts[f"mark-β_{letter}"] == ["β"] and texts[f"mark-β_{letter}-index"] == [letter]
    # one id per mark in the drawing's SVG
    assert all(len(artists) == 1 for gid, artists in found.items() if gid.startswith("mark-"))
    # no dead centres beside one bank's liner
    assert not any(t.get_text() in ("TDC", "BDC") for t in fig.axes[0].texts)


def test_each_piston_pin_letter_is_by_its_own_pin():
    """A with L stands nearer the left bank's piston pin than the right one's."""
    fig, geometry, frame = _scheme("v8")
    ax = fig.axes[0]
    found = _by_gid(ax)
    renderer = fig.canvas.get_renderer()
    for letter in ("L", "R"):
        (sub,) = found[f"mark-A_{letter}-index"]
        box = sub.get_window_extent(renderer)
        at = ax.transData.inverted().transform([(box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2])
        pins = {
            md.bank_letter(g.label): geometry.joints[g.joint][frame] * 1e3 for g in geometry.guides
        }
        nearest = min(pins, key=lambda k: np.linalg.norm(pins[k] - at))
        assert nearest == letter


def test_bank_letter():
    assert md.bank_letter("1L") == "L"
    assert md.bank_letter("12Л") == "Л"
    assert md.bank_letter("3") == "3"


def _centre_mm(ax, artist, renderer) -> np.ndarray:
    box = artist.get_window_extent(renderer)
    return ax.transData.inverted().transform([(box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2])


@pytest.mark.parametrize(
    "engine, indices, rod_angles",
    [
        ("w12", ["L", "C", "R"], True),
        ("x16", ["A", "B", "C", "D"], True),
        ("radial9", [str(k) for k in range(1, 10)], False),
    ],
)
def test_a_w_an_x_and_a_radial_mark_every_banks_piston_pin(engine, indices, rod_angles):
    """O, U, ω and one A per cylinder axis, indexed with its bank's letter (a radial's: the
    cylinder's number), each A nearer its own piston pin than any other joint; β per bank where
    the rods are on the crank pin (a radial's slave rods are on the master rod's knuckle pins);
    no two letters overprint one another."""
    fig, geometry, frame = _scheme(engine)
    ax = fig.axes[0]
    renderer = fig.canvas.get_renderer()
    found = _by_gid(ax)
    assert [g.label for g in geometry.guides] == [f"1{k}" for k in indices] or engine == "radial9"
    for mark in ("mark-O", "mark-U", "mark-ω"):
        assert len(found.get(mark, [])) == 1, mark
    pins = {md.bank_letter(g.label): geometry.joints[g.joint][frame] * 1e3 for g in geometry.guides}
    joints = {name: p[frame] * 1e3 for name, p in geometry.joints.items()}
    for index in indices:
        (letter,) = found[f"mark-A_{index}"]
        (sub,) = found[f"mark-A_{index}-index"]
        assert (letter.get_text(), sub.get_text()) == ("A", index)
        at = _centre_mm(ax, letter, renderer)
        nearest = min(joints, key=lambda k: np.linalg.norm(joints[k] - at))
        assert np.allclose(joints[nearest], pins[index]), (index, nearest)
        assert (f"mark-β_{index}" in found) is rod_angles
    # U by the crank pin, O by the shaft's axis: of the points the scheme names, the nearest
    named = {k: joints[k] for k in ("crank_pin_1", "crank_centre")}
    named.update({g.joint: joints[g.joint] for g in geometry.guides})
    for mark, joint in (("mark-U", "crank_pin_1"), ("mark-O", "crank_centre")):
        at = _centre_mm(ax, found[mark][0], renderer)
        assert min(named, key=lambda k: np.linalg.norm(named[k] - at)) == joint, mark
    marks = [a for gid, artists in found.items() if gid.startswith("mark-") for a in artists]
    boxes = [a.get_window_extent(renderer).padded(-0.5) for a in marks]
    for k, box in enumerate(boxes):
        for other in boxes[k + 1 :]:
            assert not box.overlaps(other)


def test_the_schemes_alpha_has_its_arc_unless_the_crank_is_on_its_zero_line():
    """α is drawn where the crank stands at 45° from cylinder 1's TDC (W, X); a radial's scheme
    shows cylinder 1 at TDC, where the crank lies on the line α counts from: no arc, no α."""
    for engine, drawn in (("w12", True), ("x16", True), ("radial9", False)):
        fig, _, _ = _scheme(engine)
        assert any(t.get_text() == "α" for t in fig.axes[0].texts) is drawn, engine


def test_a_wide_scheme_puts_its_crank_star_below_rather_than_halve_its_scale():
    """A W12's banks at 60° make a drawing too wide for the crank star beside it at 1:4 (beside
    it, at half that scale or less): it is drawn at 1:4 with the star below it; a V8 keeps its
    star beside it at 1:5 (below, one step larger, 1:4, is not worth the height)."""
    for engine, expected_scale, below in (("w12", 1 / 4, True), ("v8", 1 / 5, False)):
        name, changes = ENGINES[engine]
        output = shared_run(name, changes, stages=("drawing",)).outputs["drawing"]
        positions = output.artifacts["positions"]
        labels = {k: f"{k} = {value * 1e3:g} mm" for k, value in positions.dimensions.items()}
        frame = len(output.results["crank_angles_deg"])
        fig, scale = md.scheme_figure(positions, frame, labels, "Crank star", "Firing order")
        assert scale == pytest.approx(expected_scale)
        width_mm, height_mm = (size * 25.4 for size in fig.get_size_inches())
        assert width_mm <= md.PAGE_ROOM_MM[0] and height_mm <= md.SCHEME_ROOM_MM[1]
        drawing, star = fig.axes
        under = bool(star.get_position().y1 <= drawing.get_position().y0)
        assert under is below, engine
        beside = md._scheme_at(
            md.upright(md.front_view(positions)), frame, labels, "", "", scale, {}
        )
        if below:  # at this scale the star beside the drawing makes the figure too wide
            assert beside.get_size_inches()[0] * 25.4 > md.PAGE_ROOM_MM[0]


@pytest.mark.parametrize("engine", ["single", "offset", "inline4"])
def test_a_tall_mechanisms_positions_are_half_the_text_width(engine):
    """A cylinder above its crank: two panels in a row, each half the text width (the figure as
    high as the print style lets it be), the page filled by one row."""
    name, changes = ENGINES[engine]
    output = shared_run(name, changes, stages=("drawing",)).outputs["drawing"]
    positions = output.artifacts["positions"]
    frames = [(k, f"position {k}\nα = {k}°") for k in range(5)]
    sheets = md.positions_sheets(positions, frames)
    assert [len(sheet) for sheet in sheets] == [2, 2, 1]
    fig = md.positions_figure(positions, sheets[0])
    width_mm, height_mm = (size * 25.4 for size in fig.get_size_inches())
    assert height_mm <= md.FIGURE_HEIGHT_MM + 1e-9
    assert width_mm == pytest.approx(md.TEXT_WIDTH_MM, abs=1e-6)
    for ax in fig.axes:
        assert ax.get_position().width * width_mm == pytest.approx(md.TEXT_WIDTH_MM / 2, abs=1e-6)
        # a lone cylinder's number tells nothing beside its position: not written
        assert [t.get_text() for t in ax.texts] == []


@pytest.mark.parametrize(
    "engine, count, expected",
    [("radial9", 5, [3, 2]), ("radial9", 9, [4, 3, 2]), ("v8", 13, [8, 5])],
)
def test_no_positions_figure_holds_a_lone_panel(engine, count, expected):
    """Panels about as high as wide (a radial: two rows of two a figure; a V: six rows) fill
    whole rows, but the last figure takes a panel from the one before rather than hold a lone
    one: five of a radial as three and two; each panel half the text width, a last row's
    single panel centred under the two above it."""
    name, changes = ENGINES[engine]
    positions = shared_run(name, changes, stages=("drawing",)).outputs["drawing"]
    positions = positions.artifacts["positions"]
    frames = [(k % 5, f"position {k}\nα = {k}°") for k in range(count)]
    cols, per_sheet = md.positions_layout(positions, count)
    assert cols == 2 and per_sheet == {"radial9": 4, "v8": 12}[engine]
    sheets = md.positions_sheets(positions, frames)
    assert [len(sheet) for sheet in sheets] == expected
    assert [f for sheet in sheets for f in sheet] == frames  # in order, each once
    fig = md.positions_figure(positions, sheets[0])
    width_mm = fig.get_size_inches()[0] * 25.4
    lefts = []
    for ax in fig.axes:
        box = ax.get_position()
        assert box.width * width_mm == pytest.approx(md.TEXT_WIDTH_MM / 2, abs=1e-6)
        lefts.append(box.x0 * width_mm)
    if len(sheets[0]) % 2:  # the last row's panel centred: a quarter of the text width in
        assert lefts[-1] == pytest.approx(md.TEXT_WIDTH_MM / 4, abs=1e-6)
        assert lefts[:2] == pytest.approx([0.0, md.TEXT_WIDTH_MM / 2], abs=1e-6)


def test_the_print_style_lets_the_positions_figure_be_as_high_as_it_is_drawn():
    """The page's style shrinks a figure higher than 175 mm, but not the positions figure, drawn
    up to FIGURE_HEIGHT_MM high so that its panels are half the text width."""
    import re

    from crankdyn.report.document import report_css

    css = report_css("en")
    rule = re.search(r'img\[src\$="_positions\.svg"\][^{]*\{\s*max-height:\s*([\d.]+)mm', css)
    assert rule is not None
    assert float(rule.group(1)) == md.FIGURE_HEIGHT_MM


def test_a_slanted_text_is_checked_in_its_own_frame():
    """A segment below the foot of a text at 45°, inside the text's upright box but clear of the
    text itself, does not count (the upright box would); one across the text does."""
    from matplotlib.transforms import Bbox

    width, height = 40.0, 10.0
    beside = np.array([[[10.0, -5.0], [14.0, -2.0]]])
    through = np.array([[[-5.0, 12.0], [5.0, 2.0]]])  # across the text's middle
    assert not md._slanted_text_crosses((0.0, 0.0), 45.0, width, height, 0.0, beside)
    assert md._slanted_text_crosses((0.0, 0.0), 45.0, width, height, 0.0, through)
    # the upright box of that text: its corners at ±20 along the slant and 10 up from its foot
    half, rise = width / 2 / np.sqrt(2), height / np.sqrt(2)
    upright = Bbox.from_extents(-half - rise, -half, half, half + rise)
    assert md.text_crosses(upright, beside)


@pytest.mark.parametrize(
    "direction_deg, text_deg",
    [
        (0, 0),
        (45, 45),
        (90, 90),
        (100, 100),
        (120, 120),
        (150, -30),
        (180, 0),
        (-45, -45),
        (-60, 120),
        (-80, 100),
        (-90, 90),
        (-135, 45),
    ],
)
def test_a_dimension_text_reads_from_the_bottom_or_the_right(direction_deg, text_deg):
    """ГОСТ 2.307 / ISO 129-1: a text along a steep line reads upwards (from the right), never
    downwards; along a shallower one, from the bottom."""
    d = (np.cos(np.radians(direction_deg)), np.sin(np.radians(direction_deg)))
    assert md._readable_rotation_deg(d) == pytest.approx(text_deg, abs=1e-9)
