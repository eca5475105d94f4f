"""The engine's plan in the engine layout section (ГОСТ 2.770): every cylinder drawn once with its
printed label, crank spacing a dimensioned, a V's banks on either side with the rods' offset; a
one-crank engine has none; the kinematic scheme's crank star names the cylinder whose TDC it
shows (1Л of a V in a Russian note).

Independent values: the example scenes' cylinder counts, bore and cylinder_spacing, the typical
proportions of a big-end bearing (0.45 of the pin's diameter, the pin 0.63 of the bore)."""

from __future__ import annotations

import re
import tomllib

import pytest
from conftest import shared_html, shared_run

from crankdyn.cli import examples_dir
from crankdyn.plugin.registry import default_registry
from crankdyn.report.i18n import translator
from crankdyn_builtin.bays.plan import PlanTexts, plan_figure, row_centres, row_sides
from crankdyn_builtin.bays.section import plan_texts
from crankdyn_builtin.drawing.section import _first_cylinder, _labelled


def _scene(example: str) -> dict:
    return tomllib.loads((examples_dir() / f"{example}.toml").read_text(encoding="utf-8"))


def _mm(text: str) -> float:
    return float(re.match(r"\s*([0-9.]+)\s*mm", text).group(1))


def _t(language: str):
    return translator(language, default_registry().catalogs)


def _drawn(example: str, language: str):
    plan = shared_run(example).outputs["bays"].results["plan"]
    t = _t(language)
    printed = dict(
        plan, cylinders=[dict(c, label=t.cylinder(c["label"])) for c in plan["cylinders"]]
    )
    fig = plan_figure(printed, plan_texts(plan, t))
    fig.canvas.draw()
    return plan, fig.axes[0]


@pytest.mark.parametrize(
    ("example", "language", "labels"),
    [
        ("v8-petrol", "ru", [f"{k}{b}" for k in range(1, 5) for b in "ЛП"]),
        ("inline4-petrol", "en", ["1", "2", "3", "4"]),
    ],
)
def test_every_cylinder_is_drawn_once_and_the_crank_spacing_is_dimensioned(
    example, language, labels
):
    scene = _scene(example)
    assert len(labels) == scene["engine"]["cylinders"]
    _, ax = _drawn(example, language)
    drawn = [x.get_text() for x in ax.texts if x.get_gid() == "plan-cylinder"]
    assert sorted(drawn) == sorted(labels)
    (arrow,) = [x for x in ax.texts if x.get_gid() == "plan-spacing"]
    spacing = _mm(scene["engine"]["cylinder_spacing"])
    assert abs(arrow.xy[0] - arrow.xyann[0]) == pytest.approx(spacing)
    (text,) = [x for x in ax.texts if x.get_gid() == "plan-spacing-text"]
    assert text.get_text().startswith("a = ") and f"{spacing:g}" in text.get_text()
    cranks = [x.get_text() for x in ax.texts if x.get_gid() == "plan-crank"]
    assert len(cranks) == scene["engine"]["cylinders"] // (2 if "Л" in labels[0] else 1)


def test_a_vs_banks_lie_either_side_and_one_rod_width_apart_along_the_shaft():
    scene = _scene("v8-petrol")
    plan, _ = _drawn("v8-petrol", "ru")
    assert row_sides(plan["bank_axes_deg"]) == {0: 1.0, 1: -1.0}
    bore = _mm(scene["engine"]["bore"]) / 1e3
    # one big-end bearing's width: half a pin 2 × 0.45 of a diameter 0.63 of the bore, each to
    # 0.1 mm as the bearings section takes them
    diameter = round(0.63 * bore * 1e4) / 1e4
    assert plan["rod_offset_m"] == pytest.approx(round(2 * 0.45 * diameter * 1e4) / 1e4 / 2)
    places = {c["label"]: c["position_m"] for c in plan["cylinders"]}
    assert places["1R"] - places["1L"] == pytest.approx(
        plan["rod_offset_m"]
    )  # L nearer the free end
    assert places["2L"] - places["1L"] == pytest.approx(
        _mm(scene["engine"]["cylinder_spacing"]) / 1e3
    )


def test_a_boxers_banks_are_opposite_and_an_inline_row_above_the_shaft():
    assert row_sides({"0": 0.0, "1": 180.0}) == pytest.approx({0: 1.0, 1: -1.0})
    assert row_sides({"0": 0.0}) == {0: 1.0}


def test_a_ws_middle_bank_is_stacked_above_the_shaft_under_its_left_bank():
    centres = row_centres({"0": 0.0, "1": 60.0, "2": 120.0}, 100.0, 50.0)
    assert centres == pytest.approx({1: 100.0, 0: 150.0, 2: -100.0})


def test_a_one_crank_engine_has_no_plan():
    assert "plan" not in shared_run("radial9-aircraft").outputs["bays"].results


def test_the_plan_is_announced_before_it_appears():
    html = re.sub(r"<[^>]+>", "", shared_html("v8-petrol").linked_html)
    caption = html.index("Plan of the engine")
    number = re.search(r"Figure\s(\d+\.\d+) \W Plan of the engine", html[caption - 30 :])
    assert number is not None
    announced = html.index(f"crankshaft are shown in figure\xa0{number.group(1)}")
    assert announced < caption


def test_a_v_engines_crank_star_names_cylinder_1L_in_russian():
    t = _t("ru")
    positions = _labelled(shared_run("v8-petrol").outputs["drawing"].artifacts["positions"], t)
    assert _first_cylinder(positions) == "1Л"
    assert t("drawing.crank_star", cylinder="1Л").endswith("цилиндра 1Л)")
    inline = _labelled(shared_run("inline4-petrol").outputs["drawing"].artifacts["positions"], t)
    assert _first_cylinder(inline) == "1"


@pytest.mark.parametrize("application", ["marine", "outboard", "motorcycle"])
def test_a_boat_or_motorcycle_engines_take_off_end_is_its_drive_not_a_flywheel(application):
    """An outboard motor's flywheel sits at the other end from its drive, and a motorcycle's
    alternator rotor at the other end from its primary drive: their journals name the power
    take-off end; a car's keep the flywheel's."""
    from conftest import shared_html

    other = shared_html("inline3-petrol", {"engine": {"application": application}}, "en")
    assert "power take-off end" in other.linked_html
    assert "flywheel end" not in other.linked_html
    car = shared_html("inline3-petrol", None, "en").linked_html
    assert "its flywheel end" in car or "towards the flywheel" in car


def test_each_throw_is_drawn_on_its_side_of_the_axis():
    from crankdyn_builtin.bays.plan import throw_heights

    # cos 0 = 1, cos 180° = -1, cos 120° = -1/2; a crank at 90° or 270° keeps a third of the throw
    assert throw_heights([0, 180, 120, 90, 270], 3.0) == pytest.approx([3.0, -3.0, -1.5, 1.0, -1.0])


def _boxer_four() -> dict:
    cylinders = [
        {"label": str(k + 1), "bank": k % 2, "crank": k, "position_m": 0.098 * k} for k in range(4)
    ]
    return {
        "layout": "boxer",
        "cranks": 4,
        "crank_lags_deg": [0.0, 180.0, 180.0, 0.0],
        "spacing_m": 0.098,
        "bore_m": 0.0795,
        "rod_offset_m": 0.0,
        "bank_axes_deg": {"0": 0.0, "1": 180.0},
        "cylinders": cylinders,
    }


def test_a_boxers_cylinders_are_outlines_either_side_and_the_crank_numbers_clear_of_the_rest():
    texts = PlanTexts("колено", "свободный конец", "воздушный винт", "", ("", ""), "a", "")
    fig = plan_figure(_boxer_four(), texts)
    fig.canvas.draw()
    ax = fig.axes[0]
    outlines = [p for p in ax.patches if p.get_gid() == "plan-cylinder-outline"]
    assert not [p for p in ax.patches if p.get_gid() == "plan-bore"]
    assert len(outlines) == 4 and sorted(p.get_width() for p in outlines) == [79.5] * 4
    # cylinders 1 and 3 above the shaft, 2 and 4 below, each deeper than wide (horizontal)
    above = sorted(round(p.get_x() + 0.5 * p.get_width()) for p in outlines if p.get_y() > 0)
    assert above == [0, 196] and all(p.get_height() > p.get_width() for p in outlines)
    renderer = fig.canvas.get_renderer()
    labels = [t.get_window_extent(renderer) for t in ax.texts if t.get_gid() == "plan-crank"]
    assert len(labels) == 4
    # the numbers overlap neither each other, nor a cylinder, nor a throw of the shaft
    for k, box in enumerate(labels):
        assert not any(box.overlaps(other) for other in labels[k + 1 :])
        assert not any(box.overlaps(p.get_window_extent(renderer)) for p in outlines)
    shaft = ax.lines[0].get_xydata()
    pins = ax.transData.transform(shaft[shaft[:, 1] != 0.0])
    assert not any(box.contains(x, y) for box in labels for x, y in pins)


def test_the_layout_section_says_how_many_main_supports_the_shaft_has():
    # a support between neighbouring cranks and at both ends: cranks + 1, as the plan draws them
    text = re.sub(r"<[^>]+>", "", shared_html("inline4-petrol", None, "ru").linked_html)
    # a count below ten in words (ГОСТ 2.105), its noun agreeing with it
    assert "Коленчатый вал принят полноопорным: пять коренных опор" in text


def test_a_straight_eights_plan_keeps_its_words_apart():
    """Eight cranks on the sheet's width leave no room for "колено k" under every crank, for the
    free end's name beside crank 1's throw or for a's text between its extension lines: crank 1
    keeps the word, the others their numbers, and no two words of the plan overlap."""
    eight = {"engine": {"cylinders": 8, "firing_order": [1, 6, 2, 5, 8, 3, 7, 4]}}
    plan = shared_run("inline4-petrol", eight, stages=["bays"]).outputs["bays"].results["plan"]
    t = _t("ru")
    fig = plan_figure(plan, plan_texts(plan, t))
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    cranks = [x.get_text().split("\n")[0] for x in ax.texts if x.get_gid() == "plan-crank"]
    assert cranks == ["колено 1", *map(str, range(2, 9))]
    words = [x for x in ax.texts if x.get_text().strip() and x.get_gid() != "plan-cylinder"]
    boxes = [x.get_window_extent(renderer) for x in words]
    for i, first in enumerate(boxes):
        for j in range(i + 1, len(boxes)):
            assert not first.overlaps(boxes[j]), (words[i].get_text(), words[j].get_text())
    # and the four cranks of an in-line four each keep the word
    four = shared_run("inline4-petrol").outputs["bays"].results["plan"]
    fig = plan_figure(four, plan_texts(four, t))
    fig.canvas.draw()
    cranks = [x.get_text().split("\n")[0] for x in fig.axes[0].texts if x.get_gid() == "plan-crank"]
    assert cranks == [f"колено {k}" for k in range(1, 5)]


def test_an_angle_column_prints_each_angle_as_it_is():
    """A V16 two-stroke's cranks lie at 22.5° steps: whole degrees would print them as 22, 68, 112,
    158 (round half to even) beside the text's 22.5; a column gets the fewest decimals that print
    every angle exactly, at most three."""
    from crankdyn.report.context import exact_decimals

    assert exact_decimals([0.0, 90.0, 270.0]) == 0
    assert exact_decimals([0.0, 22.5, 67.5, 112.5]) == 1
    assert exact_decimals([0.0, 8.4375]) == 3  # at most three, the nearest then
    assert exact_decimals([53.4375, 202.5], most=1) == 1
    assert exact_decimals([1.0 / 3.0]) == 3


def test_the_bank_letters_say_from_which_end_left_and_right_are_seen():
    """ "Л – лівий ряд" means nothing without the end it is seen from (manuals name banks from
    either end). The shaft turns clockwise seen from its free end, and a crank reaches bank L's
    axis first: L's axis lies the bank angle before R's in the turning sense, so with the V's
    bisector up the L bank is on the left seen from the free end, which the sentence says."""
    from crankdyn.plugin.scene_inputs import engine_layout

    result = shared_run("v8-petrol")
    layout = engine_layout(result.scene)
    axes = {c.label[-1]: c.axis_deg for c in layout.cylinders}
    bank_angle = result.scene.engine.bank_angle_deg
    assert axes["L"] == 0 and axes["R"] == pytest.approx(bank_angle)  # clockwise from L
    text = re.sub(r"<[^>]+>", "", shared_html("v8-petrol", None, "uk", ("bays",)).linked_html)
    assert "Л – лівий ряд, П – правий ряд (якщо дивитися з боку вільного кінця колінчастого" in text
