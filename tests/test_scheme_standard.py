"""The kinematic schemes read as ГОСТ 2.770 draws them: cylinders that do not cross, solid
pistons, a master rod as one rigid body with its knuckle pins, a crank with its counterweight,
dimension texts clear of the links, and characteristic positions large enough to read on A4."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import shared_run
from matplotlib import path as mpl_path

from crankdyn.report import mechanism_drawing as md

MM_PER_INCH = 25.4
#: Radials of 5, 7 and 9 cylinders (the default step of each), a V8 and in-line and offset engines.
ENGINES = {
    "radial5": (
        "radial9-aircraft",
        {"engine": {"cylinders": 5}, "analysis": {"angle_step_deg": None}},
    ),
    "radial7": (
        "radial9-aircraft",
        {"engine": {"cylinders": 7}, "analysis": {"angle_step_deg": None}},
    ),
    "radial9": ("radial9-aircraft", {}),
    # a short rod and a wide bore: the liners converge steeply near the shaft
    "radial9-wide": (
        "radial9-aircraft",
        {
            "engine": {"bore": "105 mm", "stroke": "130 mm", "rod_length": "235 mm"},
            "articulated": {"pin_radius": "52 mm"},
        },
    ),
    "v8": ("v8-petrol", {}),
    # a flat four: two letters U with indices beside the shaft's O
    "boxer": (
        "inline4-petrol",
        {
            "engine": {
                "layout": "boxer",
                "firing_order": [1, 3, 2, 4],
                "bore": "79.5 mm",
                "stroke": "61 mm",
                "rod_ratio": 0.299,
            }
        },
    ),
    "inline4": ("inline4-petrol", {}),
    "offset": ("offset-crank-engine", {}),
    # a long stroke and rod under a narrow bore: a panel as tall as a figure allows, narrower
    # than half the text width
    "tall-single": (
        "diesel-1cyl",
        {"engine": {"bore": "105 mm", "stroke": "120 mm", "rod_length": "215 mm"}},
    ),
}


def _drawing(engine: str):
    name, changes = ENGINES[engine]
    return shared_run(name, changes, stages=("drawing",)).outputs["drawing"]


def _positions(engine: str):
    return md.upright(md.front_view(_drawing(engine).artifacts["positions"]))


def _outline(o, d, n, low, high, half) -> np.ndarray:
    return np.array(
        [
            o + d * low - n * half,
            o + d * high - n * half,
            o + d * high + n * half,
            o + d * low + n * half,
        ]
    )


def _liners_mm(geometry) -> list[np.ndarray]:
    """Each cylinder's outline as drawn (mm): its walls from the liner's end to its head."""
    liners = []
    for guide in md._one_per_axis(geometry.guides):
        o, d, n = md._guide_frame(geometry, guide, 0)
        liners.append(_outline(o, d, n, *md.liner_ends_mm(guide, geometry), guide.bore_m * 1e3 / 2))
    return liners


def _pistons_mm(geometry, i: int) -> list[np.ndarray]:
    pistons = []
    for guide in md._one_per_axis(geometry.guides):
        o, d, n = md._guide_frame(geometry, guide, i)
        at = float(np.dot(geometry.joints[guide.joint][i] * 1e3 - o, d))
        pistons.append(
            _outline(
                o,
                d,
                n,
                at - md.piston_skirt_mm(guide, geometry),
                at + md.CROWN * guide.bore_m * 1e3,
                0.97 * guide.bore_m * 1e3 / 2,
            )
        )
    return pistons


def _overlap(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two convex polygons overlap by more than a touch (separating axis theorem)."""
    for polygon in (a, b):
        for p, q in zip(polygon, np.roll(polygon, -1, axis=0), strict=False):
            normal = np.array([q[1] - p[1], p[0] - q[0]])
            pa, pb = a @ normal, b @ normal
            if (
                pa.max() <= pb.min() + 1e-6 * np.abs(normal).sum()
                or pb.max() <= pa.min() + 1e-6 * np.abs(normal).sum()
            ):
                return False
    return True


@pytest.mark.parametrize("engine", ["radial5", "radial7", "radial9", "v8"])
def test_no_two_cylinders_cross(engine):
    geometry = _positions(engine)
    liners = _liners_mm(geometry)
    assert len(liners) > 1
    crossing = [
        (i, k)
        for i in range(len(liners))
        for k in range(i + 1, len(liners))
        if _overlap(liners[i], liners[k])
    ]
    assert not crossing


def test_the_overlap_check_finds_crossing_cylinders():
    """The check above can fail: two liners of a nine-cylinder radial, were they drawn down to
    their pistons' full skirts at BDC, would cross."""
    geometry = _positions("radial9")
    full = [
        _outline(
            *md._guide_frame(geometry, g, 0),
            g.travel_m[0] * 1e3 - md.SKIRT * g.bore_m * 1e3,
            md.liner_ends_mm(g)[1],
            g.bore_m * 1e3 / 2,
        )
        for g in geometry.guides
    ]
    assert _overlap(full[0], full[1])


@pytest.mark.parametrize("engine", ["radial5", "radial7", "radial9"])
def test_the_pistons_of_a_radial_never_overlap(engine):
    geometry = _positions(engine)
    frames = len(next(iter(geometry.joints.values())))
    for i in range(frames):
        pistons = _pistons_mm(geometry, i)
        assert not [
            (a, b)
            for a in range(len(pistons))
            for b in range(a + 1, len(pistons))
            if _overlap(pistons[a], pistons[b])
        ], i


def test_the_master_rod_is_one_body_with_its_knuckle_pins():
    geometry = _positions("radial9")
    bodies = md.master_rod_bodies(geometry, 0)
    assert len(bodies) == 1 and len(bodies[0]) == 8  # the eight slave rods' pins
    knuckles = {
        tuple(np.round(geometry.joints[f"slave_pin_{k}"][0] * 1e3, 6)) for k in range(2, 10)
    }
    assert {tuple(np.round(p, 6)) for p in bodies[0]} == knuckles
    assert not [name for name, _, _ in md.drawn_links(geometry) if name.startswith("master_")]


@pytest.mark.parametrize("engine", ["radial9", "inline4", "offset"])
def test_a_crank_is_drawn_with_its_counterweight_opposite_its_pin(engine):
    geometry = _positions(engine)
    (outline,) = md.counterweights(geometry, 0)
    crank = next(link for link in geometry.links if link[0] in ("crank", "crank_1"))
    pin = (geometry.joints[crank[2]][0] - geometry.joints[crank[1]][0]) * 1e3
    assert float(np.mean(outline, axis=0) @ pin) < 0


def _scheme(engine: str):
    output = _drawing(engine)
    positions = output.artifacts["positions"]
    labels = {k: f"{k} = {value * 1e3:g} mm" for k, value in positions.dimensions.items()}
    marks = {"alpha": "α", "beta": "β", "omega": "ω", "tdc": "TDC", "bdc": "BDC"}
    fig, _ = md.scheme_figure(
        positions,
        len(output.results["crank_angles_deg"]),
        labels,
        "Crank star",
        "Firing order: 1",
        marks,
    )
    fig.canvas.draw()
    return fig, md.upright(md.front_view(positions)), len(output.results["crank_angles_deg"])


@pytest.mark.parametrize("engine", ["radial5", "radial7", "radial9", "v8", "inline4", "offset"])
def test_no_dimension_text_crosses_a_link(engine):
    fig, geometry, frame = _scheme(engine)
    ax = fig.axes[0]
    renderer = fig.canvas.get_renderer()
    links = np.array(
        [
            (geometry.joints[a][frame] * 1e3, geometry.joints[b][frame] * 1e3)
            for _, a, b in md.drawn_links(geometry)
        ]
    )
    links = ax.transData.transform(links.reshape(-1, 2)).reshape(-1, 2, 2)
    texts = [t for t in ax.texts if t.get_text()[:4] in ("R = ", "L = ", "D = ", "S = ", "e = ")]
    assert {t.get_text()[0] for t in texts} >= {"R", "L", "D"}
    for text in texts:
        assert not md.text_crosses(text.get_window_extent(renderer).padded(-1.0), links), (
            text.get_text()
        )


def test_the_text_check_finds_a_text_on_a_link():
    from matplotlib.transforms import Bbox

    # a rod from (0, 0) to (100, 50) on the page, a label's box over its middle and one beside it
    rod = np.array([[[0.0, 0.0], [100.0, 50.0]]])
    assert md.text_crosses(Bbox([[40.0, 15.0], [60.0, 30.0]]), rod)
    assert not md.text_crosses(Bbox([[40.0, 30.0], [60.0, 45.0]]), rod)
    assert not md.text_crosses(Bbox([[40.0, 15.0], [60.0, 30.0]]), np.empty((0, 2, 2)))


def _panels_mm(fig) -> list[float]:
    width_mm = fig.get_size_inches()[0] * MM_PER_INCH
    return [ax.get_position().width * width_mm for ax in fig.axes]


@pytest.mark.parametrize("engine", ["radial9", "radial7", "v8"])
def test_each_position_of_a_radial_or_v_is_half_the_text_width(engine):
    """Two in a row, each half the A4 text width, on as many figures as the page's figure height
    needs, none taller (the printed page would shrink it)."""
    output = _drawing(engine)
    positions = output.artifacts["positions"]
    # Five positions: a full sheet of two rows and a sheet with one left over.
    frames = [(k, f"position {k}\nα = {k}°") for k in range(5)]
    sheets = md.positions_sheets(positions, frames)
    assert sum(len(sheet) for sheet in sheets) == len(frames)
    for sheet in sheets:
        fig = md.positions_figure(positions, sheet)
        width_mm, height_mm = (size * MM_PER_INCH for size in fig.get_size_inches())
        assert height_mm <= md.FIGURE_HEIGHT_MM + 1e-9 and width_mm <= md.TEXT_WIDTH_MM + 1e-9
        assert min(_panels_mm(fig)) >= md.TEXT_WIDTH_MM / 2 - 1e-9


@pytest.mark.parametrize("engine", ["inline4", "offset"])
def test_a_tall_mechanisms_positions_are_two_in_a_row_as_high_as_a_figure(engine):
    """A cylinder above its crank: two panels in a row, wider than a third of the text width,
    each only as high as the mechanism at its standard scale (no bands of paper above and
    below it) and no higher than a figure may be."""
    output = _drawing(engine)
    positions = output.artifacts["positions"]
    frames = [(k, f"position {k}\nα = {k}°") for k in range(6)]
    sheets = md.positions_sheets(positions, frames)
    assert [len(sheet) for sheet in sheets] == [2, 2, 2]
    for sheet in sheets:
        fig = md.positions_figure(positions, sheet)
        assert min(_panels_mm(fig)) >= md.TEXT_WIDTH_MM / 3 - 1e-9
        height_mm = fig.get_size_inches()[1] * MM_PER_INCH
        assert height_mm <= md.FIGURE_HEIGHT_MM + 1e-9
    panel = md._panel_geometry(positions)
    (_, _), (low, high) = md._panel_limits(panel)
    (_, _), (content_low, content_high) = md._content_limits(panel)
    assert (low, high) == pytest.approx((content_low, content_high), rel=1e-12)


def _hatchings_mm(geometry) -> list[list[np.ndarray]]:
    """Each cylinder's two hatched bands as drawn (mm): outside each wall, as deep as the hatching's
    strokes, from the first stroke's inner end to the head."""
    extent = md._extent_mm(geometry)
    depth = md.HATCH * extent * md.HATCH_SLANT
    bands = []
    for guide in md._one_per_axis(geometry.guides):
        o, d, n = md._guide_frame(geometry, guide, 0)
        bottom, top = md.liner_ends_mm(guide, geometry)
        start = max(bottom, md.hatch_start_mm(geometry, guide)) - depth
        half = guide.bore_m * 1e3 / 2
        bands.append(
            [
                _outline(o + n * side * (half + depth / 2), d, n, start, top, depth / 2)
                for side in (-1, 1)
            ]
        )
    return bands


@pytest.mark.parametrize("engine", ["radial5", "radial7", "radial9", "radial9-wide"])
def test_the_hatching_of_neighbouring_cylinders_does_not_cross(engine):
    """ГОСТ 2.770: cylinders do not cross, nor do their walls' hatchings near the shaft, where the
    liners of a radial converge (a nine-cylinder radial of a wide bore the most)."""
    geometry = _positions(engine)
    bands = _hatchings_mm(geometry)
    crossing = [
        (i, k)
        for i in range(len(bands))
        for k in range(i + 1, len(bands))
        if any(_overlap(a, b) for a in bands[i] for b in bands[k])
    ]
    assert not crossing


def _mark_boxes(fig) -> dict:
    """Each lettered mark's box on the page (the letter with its index), by its SVG id."""
    renderer = fig.canvas.get_renderer()
    boxes: dict = {}
    for text in fig.axes[0].texts:
        gid = text.get_gid() or ""
        if gid.startswith("mark-"):
            box = text.get_window_extent(renderer)
            name = gid.removesuffix("-index")
            boxes[name] = box if name not in boxes else type(box).union([boxes[name], box])
    return boxes


@pytest.mark.parametrize("engine", ["boxer", "v8", "inline4", "offset"])
def test_no_two_letters_of_a_scheme_overlap(engine):
    fig, _, _ = _scheme(engine)
    boxes = _mark_boxes(fig)
    assert {"mark-O", "mark-ω"} <= set(boxes) or "mark-O" in boxes
    names = sorted(boxes)
    for k, a in enumerate(names):
        for b in names[k + 1 :]:
            assert not boxes[a].padded(-0.5).overlaps(boxes[b].padded(-0.5)), (a, b)


@pytest.mark.parametrize("engine", ["boxer", "v8"])
def test_no_letter_stands_on_a_piston(engine):
    """A short rod's β arc ends over its piston: its letter moves off it (ГОСТ 2.770: a
    designation is read against the white of the sheet, not on a shaded link); only the piston
    pin's A, which lies in its piston, stands on one."""
    fig, geometry, frame = _scheme(engine)
    ax = fig.axes[0]
    pistons = [ax.transData.transform(p) for p in _pistons_mm(geometry, frame)]
    for name, box in _mark_boxes(fig).items():
        if name.startswith("mark-A"):
            continue
        corners = box.padded(-0.5).corners()
        centre = np.mean(corners, axis=0, keepdims=True)
        for piston in pistons:
            assert not _overlap(corners[[0, 1, 3, 2]], piston), name
            assert not mpl_path.Path(piston).contains_points(centre).any(), name


@pytest.mark.parametrize("engine", ["tall-single", "inline4", "v8", "radial9", "offset"])
def test_a_position_panel_is_drawn_at_the_scale_its_caption_names(engine):
    """A millimetre of the mechanism is the scale's millimetres of paper in every panel, also
    where the panel is narrower than half the text width (its height bound by the figure's):
    its width follows from its limits at that scale, not from its shape alone."""
    positions = _drawing(engine).artifacts["positions"]
    scale = md.positions_scale(positions)
    fig = md.positions_figure(positions, [(k, f"position {k}") for k in range(2)])
    fig.dpi = 72.0
    for ax in fig.axes:
        (x0, y0), (x1, y1) = ax.transData.transform([(0.0, 0.0), (100.0, 100.0)])
        paper_mm = np.array([x1 - x0, y1 - y0]) / 72.0 * MM_PER_INCH
        assert paper_mm == pytest.approx([100.0 * scale, 100.0 * scale], rel=1e-9)
