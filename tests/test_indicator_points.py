"""The characteristic points marked on the p–V diagram (r, a, c, c′, f, c″, z, z′, b′, b, b″), each
checked against where it is by definition: the crank angle of its event on the grid, the
volume there, and the pressure of the curve it belongs to."""

from __future__ import annotations

import re
from types import SimpleNamespace

import numpy as np
import pytest

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.contracts import GAS_PRESSURE
from crankdyn.plugin.registry import default_registry
from crankdyn.plugin.scene_inputs import rounding_parameters
from crankdyn.scene.model import load_scene
from crankdyn_builtin.indicator.section import _characteristic_points

REGISTRY = default_registry()


@pytest.fixture(scope="module", params=["petrol-1cyl-uk", "diesel-1cyl"])
def marked(request):
    scene = load_scene(examples_dir() / f"{request.param}.toml")
    output = run_scene(scene, REGISTRY, ["indicator"]).outputs["indicator"]
    frame, r = output.tables.arrays("indicator"), output.results
    points = {
        label: (v, p)
        for label, v, p, _ in _characteristic_points(SimpleNamespace(scene=scene), frame, r)
    }
    return scene, frame, r, points


def _at(frame, angle_deg):
    i = int(np.argmin(np.abs(frame["crank_angle_deg"] - angle_deg % 720.0)))
    return (
        frame["cylinder_volume_m3"][i] * 1e3,
        frame["pressure_Pa"][i] / 1e6,
        frame["pressure_theoretical_Pa"][i] / 1e6,
    )


def test_every_point_is_where_its_event_is(marked):
    scene, frame, r, points = marked
    rounding = rounding_parameters(scene)
    v_c = r["clearance_volume_m3"] * 1e3
    v_a = v_c + r["swept_volume_m3"] * 1e3
    assert set(points) == {"r", "a", "c", "c′", "f", "c″", "z", "z′", "b′", "b", "b″"}
    assert points["r"][0] == pytest.approx(v_c) and points["c″"][0] == pytest.approx(v_c)
    assert points["a"][0] == pytest.approx(v_a) and points["b"][0] == pytest.approx(v_a)
    assert points["c"] == pytest.approx((v_c, r["compression_end_pressure_Pa"] / 1e6))
    assert points["c″"][1] == pytest.approx(_at(frame, 360.0)[1])
    assert points["c′"] == pytest.approx(
        _at(frame, 360.0 - rounding.ignition_advance_deg)[:2], rel=1e-9
    )
    visible = 360.0 - rounding.ignition_advance_deg + rounding.combustion_delay_deg
    assert points["f"] == pytest.approx(_at(frame, visible)[:2], rel=1e-9)
    assert points["z′"][1] == pytest.approx(frame["pressure_Pa"].max() / 1e6)
    assert points["z"][1] == pytest.approx(scene.cycle.max_pressure / 1e6)
    assert points["b′"] == pytest.approx(
        _at(frame, 540.0 - rounding.exhaust_opens_before_bdc_deg)[:2], rel=1e-9
    )
    assert points["b"][1] == pytest.approx(r["expansion_end_pressure_Pa"] / 1e6, rel=1e-6)
    assert points["b″"][1] == pytest.approx(_at(frame, 540.0)[1])


def test_a_diesel_z_ends_the_heat_addition_at_rho_times_v_c(marked):
    scene, frame, r, points = marked
    rho = scene.cycle.pre_expansion_ratio
    assert points["z"][0] == pytest.approx(rho * r["clearance_volume_m3"] * 1e3, rel=2e-2)


def test_the_pumping_loop_is_enlarged_in_an_inset_with_locale_ticks(shared_report):
    """At the scale of a 5 MPa peak the intake and exhaust lines (0,1 MPa) are one line: an inset
    shows them, its ticks written as the report writes numbers (decimal comma in uk)."""
    out = shared_report(
        "petrol-1cyl-uk"
    )  # the HTML report, shared with other test files (read only)
    svg = next((out / "figures").glob("fig_*_pV.svg")).read_text(encoding="utf-8")
    assert "впуск і випуск (збільшено)" in svg
    assert ">0,05<" in svg and ">0.05<" not in svg


def test_each_label_at_bdc_is_nearest_its_own_point():
    """b, b″ and a stand one above the other at BDC (0,36, 0,24 and 0,085 МПа in the in-line four):
    each label's centre is nearer its own point than the others' (b″'s label set under its point
    would read as a's)."""
    from crankdyn.report.figures import to_svg
    from crankdyn_builtin.indicator.figures import _pv_figure
    from crankdyn_builtin.indicator.section import _POINTS

    offsets = {label: offset for label, _, _, offset in _POINTS}
    heights = {"b": 0.36, "b″": 0.239, "a": 0.085}
    points = [(label, 0.46, p, offsets[label]) for label, p in heights.items()]
    volume = np.linspace(0.05, 0.46, 50)
    pressure = 0.1 + 5.0 * np.exp(-30 * (volume - 0.05))
    fig = _pv_figure(volume, pressure, None, points, lambda key, **kw: key)
    to_svg(fig)  # laid out and drawn as in the report
    ax = fig.axes[0]
    renderer = fig.canvas.get_renderer()
    where = {label: ax.transData.transform((0.46, p)) for label, p in heights.items()}
    for text in ax.texts:
        box = text.get_window_extent(renderer)
        centre = np.array([(box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2])
        nearest = min(where, key=lambda label: np.hypot(*(centre - where[label])))
        assert nearest == text.get_text(), (text.get_text(), nearest)


def test_the_labels_at_tdc_keep_their_points_order_from_the_top():
    """A diesel's c″ (4,41 МПа at TDC), c (p_c = 3,91 МПа) and f (3,80 МПа, a hair before TDC)
    stand one above the other in a 4-МПа-high diagram: their labels read in the same order from
    the top, and each label's centre is nearer its own point than the others'."""
    from crankdyn.report.figures import to_svg
    from crankdyn_builtin.indicator.figures import _pv_figure
    from crankdyn_builtin.indicator.section import _POINTS

    offsets = {label: offset for label, _, _, offset in _POINTS}
    places = {"c″": (0.0786, 4.41), "c": (0.0786, 3.907), "f": (0.0790, 3.80)}
    points = [(label, v, p, offsets[label]) for label, (v, p) in places.items()]
    volume = np.linspace(0.0786, 1.26, 80)
    pressure = 0.1 + 7.0 * np.exp(-6 * (volume - 0.0786))
    fig = _pv_figure(volume, pressure, None, points, lambda key, **kw: key)
    to_svg(fig)
    ax = fig.axes[0]
    renderer = fig.canvas.get_renderer()
    where = {label: ax.transData.transform(place) for label, place in places.items()}
    centres = {}
    for text in ax.texts:
        box = text.get_window_extent(renderer)
        centres[text.get_text()] = np.array([(box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2])
    assert sorted(centres, key=lambda label: -centres[label][1]) == ["c″", "c", "f"]
    for label, centre in centres.items():
        assert min(where, key=lambda k: np.hypot(*(centre - where[k]))) == label


def test_labels_on_one_side_of_close_points_stand_apart():
    """c, f and c″ of a diesel lie within a few tenths of a megapascal at TDC: their labels are
    moved apart to the gap between centres, the others keep their places."""
    from crankdyn_builtin.indicator.figures import (
        LABEL_GAP_PT,
        LABEL_HALF_HEIGHT_PT,
        separated_labels,
    )

    points = [
        ("c", 0.23, 5.57, (-4, 2)),
        ("f", 0.23, 5.60, (-5, 3)),
        ("c″", 0.23, 5.40, (4, -2)),
        ("z", 0.25, 10.5, (4, 2)),
        ("a", 3.4, 0.14, (-4, -3)),
        ("r", 0.23, 0.14, (4, 3)),
        ("b″", 3.4, 0.3, (5, 0)),
    ]
    height_pt, pressures = 200.0, [0.14, 10.5]
    out = {
        label: (p, dy) for label, _, p, (_, dy) in separated_labels(points, pressures, height_pt)
    }
    scale = height_pt / (10.5 - 0.14)

    def centre(label):
        p, dy = out[label]
        return (p - 0.14) * scale + dy

    # on the left: c (5.57 MPa, 2 pt up) and f (5.60, 3 pt up) were 0.3·scale + 1 ≈ 6.8 pt apart
    assert centre("f") - centre("c") == pytest.approx(LABEL_GAP_PT)
    assert out["c"][1] == 2 + LABEL_HALF_HEIGHT_PT  # the lower one keeps its place
    assert out["a"][1] == -3 - LABEL_HALF_HEIGHT_PT
    assert out["c″"][1] == -2 - LABEL_HALF_HEIGHT_PT  # alone on its side near TDC
    assert out["z"][1] == 2 + LABEL_HALF_HEIGHT_PT
    # r and b″ are close in height but at opposite ends of the stroke: both keep their places
    assert out["r"][1] == 3 + LABEL_HALF_HEIGHT_PT and out["b″"][1] == 0


def test_a_trace_without_points_has_no_labels_to_separate():
    from crankdyn_builtin.indicator.figures import separated_labels

    assert separated_labels([], [0.1, 5.0], 200.0) == []


@pytest.mark.parametrize(
    ("example", "with_rho"),
    [("petrol-1cyl", False), ("two-stroke-1cyl", False), ("diesel-1cyl", True)],
)
def test_the_closed_form_shows_pre_expansion_only_for_a_diesel(example, with_rho):
    """A spark-ignition engine burns at constant volume (ρ = 1): its p_b and p_i′ are written
    without ρ (Otto's forms), a diesel's with it; both are the value computed."""
    import html as html_lib
    import re

    from conftest import shared_html

    page = shared_html(example).linked_html
    page = re.sub(r"<(script|style|svg)\b.*?</\1>", " ", page, flags=re.S)
    text = html_lib.unescape(re.sub(r"<[^>]+>", "", page)).replace("\u2060", "")
    text = text.replace("\xa0", " ")
    (p_b,) = re.findall(r"pb = (pz\S+) = ", text)
    closed = re.findall(r"pi′ = (\S.*?\]) = ", text)
    assert closed
    assert ("ρ" in p_b) is with_rho and all(("ρ" in c) is with_rho for c in closed), (p_b, closed)


@pytest.mark.parametrize(
    "fraction, said",
    [(None, "Рекомендований тиск pz′ = 0,85·pz"), (0.85, "Заданий тиск pz′ = 0,85·pz")],
)
def test_a_peak_lowered_inside_the_theoretical_diagram_is_said_so(fraction, said):
    """A petrol engine at ε = 12: p_z′ = 0.85·p_z 12° after TDC, the usual or the given, would
    stand above the theoretical diagram; the note says what it took instead and why, and a given
    fraction is also named on the console."""
    import re

    from conftest import shared_html, shared_run

    from crankdyn.report.plausibility import console_lines, warnings

    high = {"cycle": {"compression_ratio": 12.0, "rounding": {"peak_pressure_fraction": fraction}}}
    run = shared_run("petrol-1cyl-uk", high, stages=["indicator"])
    r = run.outputs["indicator"].results
    lowered = {"requested_fraction": 0.85, "given": fraction is not None}
    assert r["peak_lowered"] == {**lowered, "share_of_theoretical": 0.97}
    assert r["peak_pressure_fraction"] < 0.85
    html = shared_html("petrol-1cyl-uk", high, "uk", ("indicator",)).linked_html
    text = re.sub(r"[\u00a0\u202f]", " ", re.sub(r"<[^>]+>", "", html))
    # to the four digits the values taken list it with, one number in both places
    taken = f"{r['peak_pressure_fraction']:.4f}".replace(".", ",")
    assert f"{said} у точці z′ (12° після ВМТ) лежав би вище за теоретичну діаграму" in text
    assert f"тож узято pz′ = {taken}·pz, 97 % тиску теоретичної діаграми" in text
    # the values taken list the fraction the diagram takes, as the section says; the given
    # data list the task's own
    row, cells = "Відношеннядійсногонайбільшоготискудотеоретичногоpz′/pz", re.sub(r"\s", "", text)
    listed = "0,85" if fraction else f"{r['peak_pressure_fraction']:.4f}".replace(".", ",")
    assert f"{row}{listed}" in cells and len(re.findall(row, cells)) == 1
    lines = console_lines(warnings(run.scene, REGISTRY, run), REGISTRY)
    named = [line for line in lines if "cycle.rounding.peak_pressure_fraction" in line]
    assert len(named) == (fraction is not None), lines
    usual = shared_run("petrol-1cyl-uk", stages=["indicator"]).outputs["indicator"].results
    assert usual["peak_lowered"] is None and usual["peak_pressure_fraction"] == 0.85


def test_the_pressure_at_tdc_is_stated_and_its_rise_listed_among_the_values_taken():
    """Point c″ of the rounding: p_c″ = p_c + 0.5 MPa (the rise the method's construction takes by
    default), at most 1.25·p_c (Kolchin and Demidov): the example's p_c = p_a ε^n₁ = 1.857 MPa
    keeps it to 0.25·p_c, which the indicator section says with its reason; the rise is in the
    table of values taken; a diesel's p_c of 4.1 MPa takes the whole 0.5 MPa."""
    import re

    from conftest import shared_html, shared_run

    r = shared_run("petrol-1cyl-uk", stages=["indicator"]).outputs["indicator"].results
    c = shared_run("petrol-1cyl-uk", stages=["indicator"]).scene.cycle
    p_c = c.intake_pressure * c.compression_ratio**c.compression_index  # independently
    assert r["compression_end_pressure_Pa"] == pytest.approx(p_c, rel=1e-12)
    assert 0.25 * p_c < 0.5e6
    assert r["pressure_rise_to_tdc_Pa"] == pytest.approx(0.25 * p_c, rel=1e-12)
    assert r["tdc_pressure_rounded_Pa"] == pytest.approx(1.25 * p_c, rel=1e-12)
    html = shared_html("petrol-1cyl-uk", None, "uk").linked_html
    text = re.sub(r"[\u00a0\u202f]", " ", re.sub(r"<[^>]+>", "", html))
    p_tdc = f"{r['tdc_pressure_rounded_Pa'] / 1e6:.3f}".replace(".", ",")
    rise = f"{r['pressure_rise_to_tdc_Pa'] / 1e6:.3f}".replace(".", ",")
    assert f"тиск у ВМТ pc″ = {p_tdc} МПа, на {rise} МПа вищий, ніж у кінці стиснення" in text
    ratio = f"{1 + 0.5e6 / p_c:.4g}".replace(".", ",")
    assert f"Звичайне підвищення на 0,5 МПа [1, підрозд. 3.1] дало б тут pc″ = {ratio}·pc" in text
    taken = text[text.index("Таблиця 1.2 – Прийняті величини") :][:600]
    assert "Перевищення тиску у ВМТ над тиском кінця стиснення" in taken
    diesel = shared_run("diesel-1cyl", stages=["indicator"]).outputs["indicator"].results
    assert diesel["pressure_rise_to_tdc_Pa"] == 0.5e6 and diesel["pressure_rise_limited"] is None


def test_the_theoretical_diagram_integrated_on_the_grid_is_checked_against_its_closed_form():
    """The closed form p_i′, with a four-stroke's pumping strokes p_a − p_r, against the grid's
    integral of the sharp-cornered diagram: within 0.1 % at 1°, and said in the section; a
    port-scavenged two-stroke, whose closed form takes its lost stroke as 1 − ψ, has no such line."""
    import re

    from conftest import shared_html, shared_run

    scene = shared_run("petrol-1cyl-uk", stages=["indicator"]).scene
    r = shared_run("petrol-1cyl-uk", stages=["indicator"]).outputs["indicator"].results
    check = r["closed_form_check"]
    pumping = scene.cycle.intake_pressure - scene.cycle.exhaust_pressure
    assert check["pumping_Pa"] == pytest.approx(pumping)
    assert check["closed_Pa"] == pytest.approx(
        r["theoretical_mean_indicated_pressure_Pa"] + pumping
    )
    assert abs(check["deviation_relative"]) < 1e-3
    html = shared_html("petrol-1cyl-uk", None, "uk").linked_html
    text = re.sub(r"[\u00a0\u202f]", " ", re.sub(r"<[^>]+>", "", html))
    numeric = f"{check['numeric_Pa'] / 1e6:.4f}".replace(".", ",")
    assert f"обчислена чисельним інтегруванням, дає pi′ + (pa − pr) = {numeric} МПа" in text
    two = shared_run("two-stroke-1cyl", stages=["indicator"]).outputs["indicator"].results
    assert two["closed_form_check"] is None


def test_a_diesels_peak_without_a_given_angle_is_put_on_its_isobar():
    """The diesel example without its peak angle: z′ 2/3 along the isobar at p_z (nothing
    lowered), the same angle in the results, the section, the method note and the values taken."""
    import re
    from html import unescape

    from conftest import shared_html, shared_run

    free = {"cycle": {"rounding": {"peak_angle_after_tdc_deg": None}}}
    run = shared_run("diesel-1cyl", free, stages=["indicator"])
    r = run.outputs["indicator"].results
    rho = run.scene.cycle.pre_expansion_ratio
    volume = r["clearance_volume_m3"] * (1 + 2 / 3 * (rho - 1))
    assert r["peak_on_isobar"] == {"share": 2 / 3, "volume_m3": pytest.approx(volume, rel=1e-12)}
    assert r["peak_lowered"] is None and r["peak_pressure_fraction"] == 1.0
    assert 0 < r["peak_angle_after_tdc_deg"] != 12.0
    gas = run.outputs["indicator"].data["gas_pressure"]
    assert gas.rounding.peak_angle_after_tdc_deg == r["peak_angle_after_tdc_deg"]
    assert max(gas.pressure_Pa) == pytest.approx(run.scene.cycle.max_pressure, rel=1e-3)
    html = shared_html("diesel-1cyl", free, "en", ("indicator",)).linked_html
    text = unescape(re.sub(r"[\u00a0\u202f\u2060]", " ", re.sub(r"<[^>]+>", "", html)))
    assert "a diesel's peak z′ lies about 2/ 3 along the isobar of heat addition" in text
    angle = f"{r['peak_angle_after_tdc_deg']:.1f}"
    assert f"{angle}° after TDC, where the theoretical diagram" in text
    assert f"peak pz′ = pz at {angle}° after TDC" in text  # the method note
    cells = re.sub(r"\s", "", text)
    assert f"Crankangleofthepeakpressure(afterTDC){angle}°" in cells
    given = shared_run("diesel-1cyl", stages=["indicator"]).outputs["indicator"].results
    assert given["peak_on_isobar"] is None and given["peak_angle_after_tdc_deg"] == 12.0


def test_given_data_table_names_the_peak_fraction_taken_instead_of_the_given():
    """A given p_z′/p_z that would stand above the theoretical diagram is lowered by the stage;
    the given-data table prints the task's value and the one taken, with the section that says
    why; a fraction taken as given is printed alone."""
    from conftest import shared_html, shared_run

    lowered = {"cycle": {"rounding": {"peak_pressure_fraction": 0.99}}}
    run = shared_run("petrol-1cyl", lowered)
    taken = run.outputs["indicator"].data[GAS_PRESSURE].rounding.peak_pressure_fraction
    assert taken < 0.99 - 1e-3
    html = shared_html("petrol-1cyl", lowered, "en").linked_html
    section = re.search(r"<h2[^>]*>(\d+) Indicator diagram", html)
    cell = re.search(r"<i>p</i><sub>z′</sub>/<i>p</i><sub>z</sub></td><td>([^<]*)<", html)
    assert section and cell
    assert cell.group(1) == f"0.99 (taken: {taken:.3f}, see section {section.group(1)})"
    plain = shared_html("petrol-1cyl", None, "en").linked_html
    assert "(taken:" not in plain


@pytest.mark.parametrize("rho", [None, 1.45])
def test_a_diesel_without_its_pre_expansion_ratio_is_warned_of_the_lowered_peak(rho):
    """A diesel taken at ρ = 1 (none given): the expansion line falls below p_z a few degrees after
    TDC, so p_z′ is lowered well below the given p_z; the console says how far and asks for ρ.
    With the example's own ρ = 1.45 nothing is said."""
    from conftest import shared_run

    from crankdyn.report.plausibility import console_lines, warnings

    changes = {"cycle": {"pre_expansion_ratio": rho}}
    run = shared_run("diesel-1cyl", changes, stages=["indicator"])
    r = run.outputs["indicator"].results
    lines = console_lines(warnings(run.scene, REGISTRY, run), REGISTRY)
    named = [line for line in lines if "cycle.pre_expansion_ratio" in line]
    if rho is not None:
        assert not named, lines
        return
    assert r["peak_lowered"] is not None and not r["peak_lowered"]["given"]
    (line,) = named
    share = round(100 * (1 - r["peak_pressure_fraction"]))
    assert share > 3  # the given p_z is far from reached
    peak = r["peak_pressure_rounded_Pa"] / 1e6
    assert f"p_z' = {peak:.2f} MPa is {share} % below the given p_z" in line
