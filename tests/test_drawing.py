"""Mechanism drawings: geometry against the kinematics, the report's scheme and
positions figure, and the animation driven in headless Chromium."""

from __future__ import annotations

import base64
import inspect
import io
import re
import sys
import time
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from conftest import ARTIFACTS, modified

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import plan, run_scene
from crankdyn.plugin.registry import collect, default_registry, plugin_manager
from crankdyn.scene.model import load_scene

EXAMPLES = sorted(p.stem for p in examples_dir().glob("*.toml"))
# The example plugin lives in the repository (it is not package data of crankdyn).
PLUGIN_DIR = Path(__file__).resolve().parent.parent / "examples" / "plugin-example"
PLUGIN_SRC = PLUGIN_DIR / "src"


@cache
def _registry():
    return default_registry()


@cache
def _run(example: str):
    """Kinematics and the drawing only (the cheapest run that draws)."""
    scene = load_scene(examples_dir() / f"{example}.toml", registry=_registry())
    wanted = [
        s.name for s in plan(scene, _registry()).order if s.name in ("drawing", "drawing_linkage")
    ]
    kin = [s.name for s in plan(scene, _registry()).order if "kinematics" in s.provides]
    return run_scene(
        scene,
        _registry(),
        kin + wanted + (["vane"] if scene.engine.mechanism == "vane_crank_rocker" else []),
    )


def _geometry(scene, angle_deg):
    return _registry().mechanisms[scene.engine.mechanism].geometry(scene, np.radians(angle_deg))


def _link_spread(geometry) -> float:
    """Largest change of any link's length over the frames (m)."""
    worst = 0.0
    for _, a, b in geometry.links:
        length = np.hypot(*(geometry.joints[a] - geometry.joints[b]).T)
        worst = max(worst, float(np.ptp(length)))
    return worst


@pytest.mark.parametrize("example", EXAMPLES)
def test_every_example_is_drawn_with_rigid_links(example):
    """Every bundled example has a geometry; over a cycle no link changes length (1e-9 m)."""
    scene = load_scene(examples_dir() / f"{example}.toml", registry=_registry())
    the_plan = plan(scene, _registry())
    assert {"drawing", "drawing_linkage"} & {s.name for s in the_plan.order}, the_plan.skipped
    geometry = _geometry(scene, np.arange(0.0, 360.0, 1.0))
    assert geometry.links and _link_spread(geometry) < 1e-9


def test_scotch_yoke_plugin_geometry_is_rigid_and_matches_its_physics():
    sys.path.insert(0, str(PLUGIN_SRC))
    try:
        from crankdyn_scotch_yoke import physics, plugin
    finally:
        sys.path.pop(0)
    scene = load_scene(PLUGIN_DIR / "scotch-yoke.toml")
    alpha = np.radians(np.arange(0.0, 360.0, 1.0))
    geometry = plugin.geometry(scene, alpha)
    assert _link_spread(geometry) < 1e-9
    wrist = geometry.joints["wrist_pin"]
    # The piston pin falls by s from TDC; s from the plugin's kinematics (R(1 - cos a), its table).
    assert np.allclose(
        wrist[0, 1] - wrist[:, 1], physics.piston_displacement_m(alpha, 0.04), atol=1e-12
    )
    # The crank pin stays in the yoke's slot: on the slot's line at every angle.
    assert np.allclose(
        geometry.joints["crank_pin"][:, 1], geometry.joints["yoke_centre"][:, 1], atol=1e-12
    )
    manager = plugin_manager()
    manager.register(plugin)
    assert inspect.unwrap(collect(manager).mechanisms["scotch_yoke"].geometry) is plugin.geometry


@pytest.mark.parametrize(
    "example", ["petrol-1cyl", "v8-petrol", "offset-crank-engine", "planetary-kinematics"]
)
def test_piston_pin_follows_the_kinematics_table(example):
    """Cylinder 1's piston pin in the drawing sits where the kinematics table puts it: its height
    falls by s_p from TDC, it stays on the cylinder axis, and its rod keeps its length to the pin."""
    result = _run(example)
    kin = result.outputs[result.stages_run[0]]
    frame = next(iter(kin.tables.values()))
    angle = frame["crank_angle_deg"].to_numpy()
    s = frame["piston_displacement_m"].to_numpy()
    geometry = _geometry(result.scene, angle)
    wrist = geometry.joints.get("wrist_pin", geometry.joints.get("wrist_pin_1L"))
    tdc_height = geometry.guides[0].travel_m[1]
    direction = np.asarray(geometry.guides[0].direction)
    origin = np.asarray(geometry.guides[0].origin_m)
    along = (wrist - origin) @ direction
    assert np.allclose(tdc_height - along, s, rtol=0, atol=1e-12)
    across = (wrist - origin) @ np.array([direction[1], -direction[0]])
    assert np.allclose(across, 0.0, atol=1e-15)
    assert (
        np.ptp(
            np.hypot(
                *(wrist - geometry.joints.get("crank_pin", geometry.joints.get("crank_pin_1"))).T
            )
        )
        < 1e-12
    )


@pytest.mark.parametrize("example", ["petrol-1cyl", "offset-crank-engine", "planetary-kinematics"])
def test_positions_are_the_kinematics_extremes(example):
    """The positions figure's angles are the extremes the kinematics results report (to 1e-3 deg);
    the central mechanism reports v_max and j_min and is symmetric, so v_min = 360 - v_max there."""
    result = _run(example)
    kin = result.outputs[result.stages_run[0]].results
    drawn = result.outputs["drawing"].results["crank_angles_deg"]
    assert drawn["tdc"] == 0.0
    reported = {
        k: kin[f"{k}_crank_angle_deg"]
        for k in ("bdc", "v_max", "v_min", "j_max", "j_min")
        if f"{k}_crank_angle_deg" in kin
    }
    if example == "petrol-1cyl":
        reported.update(bdc=180.0, v_min=360.0 - kin["v_max_crank_angle_deg"], j_max=0.0)
    assert set(reported) == {"bdc", "v_max", "v_min", "j_max", "j_min"}
    for key, angle in reported.items():
        assert abs((drawn[key] - angle + 180.0) % 360.0 - 180.0) < 1e-3, (key, drawn[key], angle)


@pytest.mark.parametrize("example", ["petrol-1cyl", "offset-crank-engine"])
def test_speed_extremes_are_named_by_the_stroke_they_lie_on(example):
    """v_max lies on the stroke towards BDC, v_min (the largest speed back) on the stroke towards
    TDC: the piston's travel rises from TDC to BDC and falls after, so the angles' order says it;
    the panels say it in words ("v_min" alone reads as the slowest piston)."""
    import crankdyn_builtin.drawing
    from crankdyn.report.i18n import load_catalog_file

    drawn = _run(example).outputs["drawing"].results["crank_angles_deg"]
    assert drawn["tdc"] < drawn["v_max"] < drawn["bdc"] < drawn["v_min"] < 360.0
    words = {
        "uk": ("до НМТ", "до ВМТ"),
        "ru": ("к НМТ", "к ВМТ"),
        "en": ("towards BDC", "towards TDC"),
    }
    for language, (down, up) in words.items():
        catalog = load_catalog_file(
            Path(crankdyn_builtin.drawing.__file__).parent / "i18n" / f"drawing.{language}.toml"
        )
        assert down in catalog["drawing.position_v_max"] and up in catalog["drawing.position_v_min"]
        # the return stroke's is its largest speed too, not a "v_min" (read as the slowest piston)
        assert catalog["drawing.position_v_min"].startswith("v_max")


def test_vane_engine_drawn_from_its_geometry():
    """No stage provides a piston motion for the vane engine: drawing_linkage takes the slider's
    travel along the slot from the geometry; it is the source's y_po, so its extremes are known."""
    result = _run("vane-engine-kinematics")
    assert "drawing_linkage" in result.stages_run and "drawing" not in result.stages_run
    drawn = result.outputs["drawing_linkage"].results["crank_angles_deg"]
    # y_po = r[(1 - cos a) + (1 - chi)/lambda] is the central crank-slider's displacement: BDC at 180 deg.
    assert drawn["tdc"] == 0.0 and drawn["bdc"] == pytest.approx(180.0, abs=1e-3)
    assert drawn["v_min"] == pytest.approx(360.0 - drawn["v_max"], abs=1e-3)


# ----------------------------------------------------------------------------- HTML


@cache
def _html(example: str, language: str = "en") -> str:
    """The report of ``example`` with the drawing's section only (the other sections are tested
    elsewhere; rendering them here would only cost time)."""
    return _rendered(example, language).html


@pytest.mark.parametrize("example", EXAMPLES)
def test_report_has_scheme_positions_and_animation(example):
    html = _html(example)
    assert html.count('class="mech-animation"') == 1
    angle = (
        0 if example == "radial9-aircraft" else 45
    )  # a master rod's knuckle pins clear of the shaft at TDC
    assert re.search(
        rf"Kinematic diagram of the mechanism at α = {angle}° \(scale (1:[0-9.]+|[0-9.]+:1)\)", html
    )
    assert "The mechanism at its characteristic positions" in html
    assert html.count('<img alt="') >= 2  # the scheme and the positions figure (static: they print)
    assert "@media print { .mech-animation { display: none !important; } }" in html
    assert 'type="range"' in html and "requestAnimationFrame" in html
    block = html.split('class="mech-animation"')[1]
    assert "http://" not in block.replace("http://www.w3.org/2000/svg", "")  # nothing fetched
    assert "src=" not in block.split("</script>\n</div>")[0].replace('src="data:', "")


@pytest.mark.parametrize(
    "language, title",
    [
        ("uk", "Кінематична схема механізму за кута α = 45°"),
        ("ru", "Кинематическая схема механизма при угле α = 45°"),
    ],
)
def test_drawing_texts_are_translated(language, title):
    html = _html("v8-petrol", language)
    assert title in html
    for english in (
        "Kinematic diagram",
        "characteristic positions",
        "Firing order",
        "Crank star",
        "Drag the slider",
    ):
        assert english not in html


@pytest.mark.parametrize(
    "example, marked",
    [
        ("petrol-1cyl", True),
        ("inline4-petrol", True),
        ("offset-crank-engine", True),
        ("v8-petrol", "banks"),
        ("radial9-aircraft", "radial"),
        ("vane-engine-kinematics", False),
        ("planetary-kinematics", False),
    ],
)
def test_scheme_is_drawn_at_its_angle_with_the_angles_marked(example, marked):
    """The scheme shows the crank at α = 45° (the crank pin where the geometry puts it at 45° from
    the cylinder axis, clockwise), and, where one cylinder axis is drawn, the angles α and β, the
    sense of rotation ω and the dead centres, named in the text; a V marks O, U, each bank's A and
    β (indexed with the bank's letter), α and ω, not the dead centres (beside one bank's liner
    they would meet the other's); a radial marks O, U, each cylinder's A (indexed with its number)
    and ω, not β (its slave rods hang on the master rod) nor α (drawn at cylinder 1's TDC, its
    crank lies on the line α counts from), and its text says so."""
    from crankdyn.report import mechanism_drawing as md

    result = _run(example)
    stage = "drawing" if "drawing" in result.outputs else "drawing_linkage"
    output = result.outputs[stage]
    positions = output.artifacts["positions"]
    frame = len(output.results["crank_angles_deg"])  # the scheme's frame follows the six positions
    # an engine with a master rod is drawn at cylinder 1's TDC, where its knuckle pins clear the shaft
    expected_angle = 0.0 if example == "radial9-aircraft" else 45.0
    assert output.results["scheme_angle_deg"] == expected_angle
    crank = next((l for l in positions.links if l[0] in ("crank", "crank_1", "carrier")), None)
    if crank is not None and stage == "drawing":
        pin, at_tdc = (
            positions.joints[crank[2]][k] - positions.joints[crank[1]][k] for k in (frame, 0)
        )
        # 45° clockwise from the crank at TDC (frame 0), which an offset cylinder's is not along +y
        turn = np.degrees(
            np.arctan2(at_tdc[1] * pin[0] - at_tdc[0] * pin[1], at_tdc @ pin)
        )  # clockwise
        assert turn == pytest.approx(expected_angle, abs=1e-9)
    figure = next(f for f in _rendered(example).figures if f.key == "scheme")
    svg = figure.svg.decode("utf-8")
    html = _html(example)
    banks = marked == "banks"
    if example == "planetary-kinematics":
        # its own letters: the carrier angle, the rotation, O, C, B, A and the pitch point K on the
        # hatched sun gear, the carrier's radius a = (60 + 20)/2 mm
        for mark in ("α", "ω", ">O<", ">A<", ">B<", ">C<", ">K<", ">a = 40 mm<"):
            assert mark in svg, mark
    elif marked == "radial":
        for mark in ("ω", ">O<", ">A<", ">U<", ">1<", ">9<"):
            assert mark in svg, mark
        assert "α" not in svg and "β" not in svg and ">B<" not in svg
        assert "indexed with the cylinder&#39;s number" in html
        assert "counted from the TDC of cylinder 1 " in html
    else:
        for mark in ("α", "β", "ω", ">O<", ">A<", ">U<"):
            assert (mark in svg) is bool(marked), mark
        # the crank pin's axis is U: B is the bearing width
        assert ">B<" not in svg
    for mark in (">TDC<", ">BDC<", ">S = 78"):
        assert (mark in svg) is (marked is True), mark
    assert ("α is the crank angle from the crank&#39;s position at TDC" in html) is (marked is True)
    assert ("S is the stroke" in html) is (marked is True)
    assert ("indexed with the bank&#39;s letter (L, R)" in html) is banks
    assert ("α is the crank angle from the TDC of cylinder 1L" in html) is banks
    if banks:  # each bank's piston pin and rod angle carry the bank's letter as their index
        assert svg.count(">L<") >= 2 and svg.count(">R<") >= 2
    if (
        marked is True
    ):  # the stroke between the dead centres: 2R of a central crank-slider, longer with an offset
        stroke = positions.dimensions["S"]
        expected = (
            2 * positions.dimensions["R"]
            if "e" not in positions.dimensions
            else np.sqrt(
                (positions.dimensions["L"] + positions.dimensions["R"]) ** 2
                - positions.dimensions["e"] ** 2
            )
            - np.sqrt(
                (positions.dimensions["L"] - positions.dimensions["R"]) ** 2
                - positions.dimensions["e"] ** 2
            )
        )
        assert stroke == pytest.approx(expected, rel=1e-12)
    assert (md.angle_mark_parts(md.front_view(positions)) is not None) is (marked is True)
    assert (md.bank_mark_parts(md.front_view(positions)) is not None) is banks
    assert (md.radial_mark_parts(md.front_view(positions)) is not None) is (marked == "radial")
    if (
        marked is not True and "L" in positions.dimensions and positions.links
    ):  # its rod's length is drawn as before
        assert ">L = " in svg


@cache
def _rendered(example: str, language: str = "en"):
    from dataclasses import replace

    from crankdyn.report.document import render_html

    result = _run(example)
    drawing_only = replace(
        result.plan, order=[s for s in result.plan.order if s.name.startswith("drawing")]
    )
    return render_html(replace(result, plan=drawing_only), _registry(), language)


# ----------------------------------------------------------------------------- browser


def _png_pixels(png: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("L"), dtype=float)


@pytest.mark.slow  # drives Chromium: in the slow tier, which CI runs
def test_animation_moves_in_chromium(tmp_path):
    """Headless Chromium: moving the slider redraws the mechanism (screenshots differ) and moves
    the cursor; playing advances frames (the rate is reported, not asserted)."""
    from test_serve import BASH, CHROMIUM, DevTools

    if CHROMIUM is None or BASH is None:
        pytest.skip("Debian's chromium package is not installed (.ci/setup.sh installs it)")
    page = tmp_path / "v8.html"
    page.write_text(_html("v8-petrol"), encoding="utf-8")
    browser = DevTools(page.as_uri(), tmp_path / "profile")
    ARTIFACTS.mkdir(exist_ok=True)
    try:
        browser.attach("file://")
        root = "document.querySelector('.mech-animation')"
        for _ in range(300):
            if browser.evaluate(
                f"document.readyState === 'complete' && !!{root} && !!{root}.dataset.drawn",
                tolerant=True,
            ):
                break
            time.sleep(0.1)
        else:
            raise AssertionError("the animation did not draw its first frame")
        browser.evaluate(f"{root}.scrollIntoView()")

        def shot(name: str) -> bytes:
            box = browser.evaluate(
                f"(() => {{ const r = {root}.querySelector('svg.mech-anim').getBoundingClientRect();"
                " return [r.x + scrollX, r.y + scrollY, r.width, r.height]; })()"
            )
            data = browser.call(
                "Page.captureScreenshot",
                {
                    "format": "png",
                    "captureBeyondViewport": True,
                    "clip": {
                        "x": box[0],
                        "y": box[1],
                        "width": box[2],
                        "height": box[3],
                        "scale": 1,
                    },
                },
            )["data"]
            png = base64.b64decode(data)
            (ARTIFACTS / name).write_bytes(png)
            return png

        before = shot("animation-v8-0deg.png")
        cursor_before = browser.evaluate(f"{root}.querySelector('.cursor').getAttribute('x1')")
        browser.evaluate(
            f"(() => {{ const s = {root}.querySelector('.mech-angle'); s.value = 30;"
            " s.dispatchEvent(new Event('input')); })()"
        )
        assert browser.evaluate(f"{root}.dataset.frame") == "30"
        assert browser.evaluate(f"{root}.querySelector('.mech-readout').textContent") == "α = 60°"
        after = shot("animation-v8-60deg.png")
        changed = np.mean(np.abs(_png_pixels(before) - _png_pixels(after)) > 32)
        assert changed > 0.002, changed
        assert (
            browser.evaluate(f"{root}.querySelector('.cursor').getAttribute('x1')") != cursor_before
        )

        start = browser.evaluate(f"[+{root}.dataset.drawn, performance.now()]")
        browser.evaluate(f"{root}.querySelector('.mech-play').click()")
        # playing draws frames one after the other: wait for a few (a generous deadline)
        for _ in range(600):
            end = browser.evaluate(f"[+{root}.dataset.drawn, performance.now()]")
            if end[0] - start[0] >= 10:
                break
            time.sleep(0.05)
        browser.evaluate(f"{root}.querySelector('.mech-play').click()")
        frames = end[0] - start[0]
        fps = frames / ((end[1] - start[1]) / 1000.0)
        (ARTIFACTS / "animation-v8-fps.txt").write_text(
            f"{fps:.1f} frames per second (V8, headless Chromium)\n"
        )
        print(f"V8 animation: {fps:.1f} frames per second in headless Chromium")
        assert frames > 0, "pressing play did not animate"
    finally:
        browser.close()


def test_positions_at_one_angle_share_a_panel():
    """A central crank-slider's largest acceleration is at TDC: one panel "ВМТ, j_max", not two
    identical ones; a position 0.05° or more away keeps its own (360° is the same as 0°)."""
    from crankdyn_builtin.drawing.section import _merged_frames

    frames = [
        (0, "ВМТ\nα = 0°", 0.0),
        (1, "НМТ\nα = 180°", 180.0),
        (2, "v_max\nα = 75,4°", 75.4),
        (4, "j_max\nα = 0°", 359.99),
        (5, "j_min\nα = 158,2°", 158.2),
    ]
    assert _merged_frames(frames) == [
        (0, "ВМТ, j_max\nα = 0°"),
        (1, "НМТ\nα = 180°"),
        (2, "v_max\nα = 75,4°"),
        (5, "j_min\nα = 158,2°"),
    ]


def test_positions_are_drawn_in_the_order_the_crank_reaches_them():
    """The uk check: j_min at 158,2° stood after v_min at 284,6°. Panels follow the crank angle;
    TDC and j_max at 359,99° still share the first panel."""
    from crankdyn_builtin.drawing.section import position_frames

    angles = {
        "tdc": 0.0,
        "bdc": 180.0,
        "v_max": 75.4,
        "v_min": 284.6,
        "j_max": 359.99,
        "j_min": 158.2,
    }
    frames = position_frames(angles, lambda k: f"{k}\nα = {angles[k]}°")
    assert [caption.split("\n")[0] for _, caption in frames] == [
        "tdc, j_max",
        "v_max",
        "j_min",
        "bdc",
        "v_min",
    ]
    assert [i for i, _ in frames] == [0, 2, 5, 1, 3]


@pytest.mark.parametrize("language", ["ru", "en"])
def test_an_articulated_v_scheme_hangs_the_slave_rod_on_the_master_rods_lug(tmp_path, language):
    """A V's master rod with one slave is drawn as one plate through its big end, the slave's pin
    and its own piston pin (ГОСТ 2.770: a link of three joints), in any language: the slave rod's
    big end is a corner of that plate, not a free end of a bar."""
    from crankdyn import api
    from crankdyn.report import mechanism_drawing as md

    data = modified(
        "v8-petrol",
        {
            "engine": {"rod_type": "articulated"},
            "articulated": {"pin_radius": "45 mm", "slave_rod": "0.7 kg"},
            "report": {"language": language},
        },
    )
    result = api.run(data, stages=["drawing"])  # and the kinematics it draws from
    positions = result.run_result.outputs["drawing"].artifacts["positions"]
    bodies = md.master_rod_joints(md.front_view(positions))
    assert bodies and all(len(b) == 3 and b[1].startswith("slave_pin_") for b in bodies)
    result.write(tmp_path, formats=["html"])
    scheme = next((tmp_path / "figures").glob("fig_3_1_scheme.svg")).read_text(encoding="utf-8")
    # the plate's fill (0.86 grey), as the radial's master rod has it
    assert "#dbdbdb" in scheme
