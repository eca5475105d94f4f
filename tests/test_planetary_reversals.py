"""Planetary crank mechanism with a fixed ring gear of ratio 3 (72/24 teeth, module 1.25 mm, pin
radius 8 mm, psi0 = 0): every reversal of the piston, the secondary stroke, the mean speeds, the
acceleration at TDC, the tooth flank changes and what the note says about them, each against a
closed form written here: a = 30 mm, k = -2, so x_B = a sin(phi) - e sin(2 phi),
z_B = a cos(phi) + e cos(2 phi) and z_A = z_B + sqrt(L^2 - x_B^2)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from crankdyn.engine.orchestrator import run_scene
from crankdyn.physics import planetary as pl
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.scene.model import scene_from_dict
from crankdyn_builtin.planetary.compute import curve_name, secondary_strokes

REGISTRY = default_registry()
A, E, L = 0.030, 0.008, 0.140  # carrier radius, pin radius, rod [m]
RPM = 2400.0


def _closed_form_pin_height(phi):
    x = A * np.sin(phi) - E * np.sin(2 * phi)
    z = A * np.cos(phi) + E * np.cos(2 * phi)
    return z + np.sqrt(L * L - x * x)


def _ring_geometry(pin=E):
    return pl.PlanetaryGeometry("internal", 0.045, 0.015, pin, 0.0, L)


def _ring_scene(language="uk"):
    return scene_from_dict(
        {
            "report": {"title": "Planetary", "language": language, "year": 2026},
            "engine": {
                "name": "ring 72 / planet 24",
                "mechanism": "planetary",
                "strokes": 4,
                "rpm": RPM,
                "bore": "76 mm",
                "stroke": "62.3033 mm",
                "rod_length": "140 mm",
            },
            "mechanism": {
                "gear": "internal",
                "fixed_gear_teeth": 72,
                "planet_teeth": 24,
                "module": "1.25 mm",
                "pin_radius": "8 mm",
                "pin_phase_deg": 0,
                "pressure_angle_deg": 20,
            },
            "masses": {"piston_group": "0.38 kg", "rod": "0.50 kg", "rod_cm_fraction": 0.28},
        }
    )


@pytest.fixture(scope="module")
def ring_run():
    return run_scene(_ring_scene(), REGISTRY)


def _grid_extrema():
    """Local extremes of the closed form on a 0.0001 deg grid: (angle deg, height m, kind)."""
    phi = np.radians(np.arange(0.0, 360.0, 1e-4))
    z = _closed_form_pin_height(phi)
    before, after = np.roll(z, 1), np.roll(z, -1)
    found = []
    for i in np.flatnonzero((z > before) & (z >= after)):
        found.append((math.degrees(phi[i]), z[i], "tdc"))
    for i in np.flatnonzero((z < before) & (z <= after)):
        found.append((math.degrees(phi[i]), z[i], "bdc"))
    return sorted(found)


def test_every_reversal_of_the_piston_matches_the_closed_form():
    reversals = pl.piston_reversals(_ring_geometry())
    expected = _grid_extrema()
    assert [r.kind for r in reversals] == [kind for _, _, kind in expected]
    assert len(reversals) == 4
    for reversal, (angle, height, _) in zip(reversals, expected, strict=True):
        assert math.degrees(reversal.carrier_angle_rad) == pytest.approx(angle, abs=2e-4)
        assert reversal.height_m == pytest.approx(height, abs=1e-12)
    # the closed form's own values: TDC 178 mm at 0, the secondary TDC a - ... at 180 deg
    assert reversals[0].height_m == pytest.approx(A + E + L, abs=1e-15)
    assert math.degrees(reversals[2].carrier_angle_rad) == pytest.approx(180.0, abs=1e-9)
    assert reversals[2].height_m == pytest.approx(-A + E + L, abs=1e-15)
    # the two BDCs are mirror images about 180 deg
    first, second = (math.degrees(reversals[i].carrier_angle_rad) for i in (1, 3))
    assert first + second == pytest.approx(360.0, abs=1e-9)
    assert first == pytest.approx(136.4, abs=0.05)


def test_a_conventional_reversal_count_for_the_cardan_straight_line():
    """Ring gear 2:1 with the pin on the pitch circle: harmonic motion, two reversals."""
    g = pl.PlanetaryGeometry("internal", 0.04, 0.02, 0.02, 0.0, L)
    reversals = pl.piston_reversals(g)
    assert [(round(math.degrees(r.carrier_angle_rad), 9), r.kind) for r in reversals] == [
        (0.0, "tdc"),
        (180.0, "bdc"),
    ]


def test_sign_changes_skip_a_touching_zero():
    """cos(phi) + 1 only touches zero at pi; sin(2 phi) changes sign four times."""
    assert pl.sign_changes(lambda p: np.cos(p) + 1.0, 2 * np.pi) == []
    roots = pl.sign_changes(lambda p: np.sin(2 * p), 2 * np.pi)
    assert roots == pytest.approx([0.0, np.pi / 2, np.pi, 3 * np.pi / 2], abs=1e-12)


@pytest.mark.parametrize(
    "gear, pin, name",
    [
        ("internal", 0.015, "hypocycloid"),
        ("internal", 0.008, "hypotrochoid_curtate"),
        ("internal", 0.020, "hypotrochoid_prolate"),
        ("external", 0.015, "epicycloid"),
        ("external", 0.008, "epitrochoid_curtate"),
        ("external", 0.020, "epitrochoid_prolate"),
    ],
)
def test_curve_is_named_by_where_the_pin_lies(gear, pin, name):
    g = pl.PlanetaryGeometry(gear, 0.045, 0.015, pin, 0.0, L)
    assert curve_name(g) == name


def test_stage_results_secondary_stroke_speeds_and_tdc_acceleration(ring_run):
    r = ring_run.outputs["planetary"].results
    expected = _grid_extrema()
    z_tdc = A + E + L
    stroke = z_tdc - min(height for _, height, _ in expected)
    assert r["stroke_m"] == pytest.approx(stroke, abs=1e-11)
    assert [item["kind"] for item in r["reversals"]] == ["tdc", "bdc", "tdc", "bdc"]
    assert [item["main"] for item in r["reversals"]] == [True, True, False, True]
    assert r["bdc_crank_angles_deg"] == pytest.approx([expected[1][0], expected[3][0]], abs=2e-4)
    # the secondary stroke: from BDC up to the secondary TDC at 180 deg, z_A = L + e - a
    secondary = (L + E - A) - (z_tdc - stroke)
    (only,) = secondary_strokes(r["reversals"])
    assert only["depth_m"] == pytest.approx(secondary, abs=1e-11)
    assert only["from_deg"] == pytest.approx(expected[1][0], abs=2e-4)
    assert only["to_deg"] == pytest.approx(180.0, abs=1e-9) and only["direction"] == "rise"
    assert only["depth_m"] * 1e3 == pytest.approx(2.303, abs=5e-4)
    assert r["piston_path_m"] == pytest.approx(2 * stroke + 2 * secondary, abs=1e-10)
    assert r["mean_piston_speed_m_s"] == pytest.approx(stroke * RPM / 30.0, rel=1e-12)
    assert r["mean_piston_speed_path_m_s"] == pytest.approx(
        (2 * stroke + 2 * secondary) * RPM / 60.0, rel=1e-9
    )
    # TDC: z_A'' = z_B'' - x_B'^2 / L with z_B'' = -(a + 4e), x_B' = a - 2e
    omega = math.pi * RPM / 30.0
    j_tdc = omega**2 * ((A + 4 * E) + (A - 2 * E) ** 2 / L)
    assert r["j_tdc_m_s2"] == pytest.approx(j_tdc, rel=1e-12)
    radius = stroke / 2
    conventional = radius * omega**2 * (1 + radius / L)
    assert r["conventional_j_tdc_m_s2"] == pytest.approx(conventional, rel=1e-12)
    assert r["j_tdc_m_s2"] / conventional - 1 == pytest.approx(0.665, abs=0.005)


def test_tooth_force_changes_sign_where_the_rod_line_passes_the_planet_centre(ring_run):
    """F_t is the moment of the rod force about the planet centre C over r_p: it vanishes where the
    rod's line passes through C, here found from the closed-form positions."""
    angles = ring_run.outputs["planetary"].results["tooth_force_sign_changes_deg"]
    assert len(angles) == 4
    assert angles[0] == pytest.approx(0.0, abs=1e-9) and angles[2] == pytest.approx(180.0, abs=1e-9)
    assert angles[1] + angles[3] == pytest.approx(360.0, abs=1e-7)
    for angle in angles:
        phi = math.radians(angle)
        centre = np.array([A * math.sin(phi), A * math.cos(phi)])
        pin = centre + E * np.array([math.sin(-2 * phi), math.cos(-2 * phi)])
        piston = np.array([0.0, float(_closed_form_pin_height(phi))])
        along, off = piston - pin, centre - pin
        distance = abs(along[0] * off[1] - along[1] * off[0]) / np.hypot(*along)
        assert distance < 1e-12


def _plain(html: str) -> str:
    """The text without tags, its no-break and narrow spaces as plain ones."""
    text = re.sub(r"<[^>]+>", "", html)
    return text.replace("\xa0", " ").replace("\u202f", " ").replace("\u2060", "")


def _section(html: str) -> str:
    return html.split('data-stage="planetary"', 1)[1].split("data-stage=", 1)[0]


def test_note_describes_both_bdcs_the_secondary_stroke_and_the_curve(ring_run):
    html = render_html(ring_run, REGISTRY, "uk").linked_html
    section = _section(html)
    text = _plain(section)
    assert "136,4 і 223,6°" in text and "вторинна ВМТ за α = 180° (sп = 60 мм)" in text
    assert "від α = 136,4° до 180° поршень повертається вгору на 2,303 мм" in text
    assert "гіпотрохоїді (укороченій гіпоциклоїді)" in text
    assert "епіциклоїд" not in text.lower()
    for absent in ("шийк", "колінчаст", "розпірн", "кочене", "3,0000", "−2,0000", "90,000"):
        assert absent not in text, absent
    assert "(Ft = 0 F)" not in text and "– нуль" not in text
    # MN = 0 at TDC here: no paragraph explaining a nonzero arm
    assert "MN = 0, як у звичайного" in text
    # 2.303 mm of 62.303 mm: the double generation sentence names 30 and 60 mm planets
    assert "90 − 30 = 60 мм" in text
    # the given data of the mechanism in table 1.1, as given
    given = _plain(html.split("Таблиця 1.1", 1)[1].split("</table>", 1)[0])
    for row in ("Число зубів нерухомого колеса", "Модуль зачеплення"):
        assert row in given
    cells = re.findall(r"<td[^>]*>(.*?)</td>", html.split("Таблиця 1.1", 1)[1].split("</table>")[0])
    for value in ("72", "24", "1,25", "8", "20"):
        assert value in cells, value


def test_conclusions_come_from_the_numbers(ring_run):
    html = render_html(ring_run, REGISTRY, "uk").linked_html
    conclusions = _plain(html.split('id="sec-conclusions"', 1)[1].split("</section>", 1)[0])
    r = ring_run.outputs["planetary"].results
    fastest = max(abs(r["v_max_m_s"]), abs(r["v_min_m_s"]))
    assert f"|vп|max = {fastest:.2f}".replace(".", ",") in conclusions
    excess = r["j_tdc_m_s2"] / r["conventional_j_tdc_m_s2"] - 1
    assert f"на {excess * 100:.1f} % більше".replace(".", ",") in conclusions
    assert "66,5 %" in conclusions  # 4004,7 against 2405,5 m/s²
    assert "4,98 м/с" in conclusions and "5,17 м/с" in conclusions
    assert "змінює знак чотири рази" in conclusions
    assert "але ефективне плече" not in conclusions
    assert "13,79°" in conclusions


def test_sources_are_textbooks_with_their_numbers(ring_run):
    html = render_html(ring_run, REGISTRY, "uk").linked_html
    listed = re.findall(r"<li[^>]*>(.*?)</li>", html.split('class="references"')[-1], re.S)
    text = " ".join(listed)
    assert "Артоболевский" in text and "Планетарные передачи" in text
    assert "за методикою" not in _section(html)


@pytest.mark.parametrize("gear, outward", [("internal", True), ("external", False)])
def test_fixed_gear_is_hatched_on_the_side_away_from_the_planet(gear, outward):
    """ГОСТ 2.770: the fixed ring is hatched outside its pitch circle, a fixed sun inside."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot as plt
    from matplotlib.collections import LineCollection

    from crankdyn.plugin.types import MechanismGeometry
    from crankdyn.report import mechanism_drawing as md
    from crankdyn_builtin.planetary.geometry import planetary_geometry

    if gear == "internal":
        geometry = planetary_geometry(_ring_scene(), np.radians([45.0]))
        fixed_mm = 45.0
    else:
        geometry = MechanismGeometry(
            joints={
                "crank_centre": np.zeros((1, 2)),
                "planet_centre": np.array([[0.04 * math.sin(0.5), 0.04 * math.cos(0.5)]]),
            },
            circles=[("crank_centre", 0.03, "fixed"), ("planet_centre", 0.01, "moving")],
        )
        fixed_mm = 30.0
    fig, ax = plt.subplots()
    md.draw_mechanism(ax, geometry, 0)
    strokes = []
    for collection in ax.collections:
        if isinstance(collection, LineCollection):
            for segment in collection.get_segments():
                start, end = np.hypot(*segment[0]), np.hypot(*segment[1])
                if abs(start - fixed_mm) < 1e-9:
                    strokes.append(end - start)
    plt.close(fig)
    assert len(strokes) >= 12
    assert all(bool(d > 0) == outward for d in strokes)


def test_sun_gear_example_path_and_secondary_strokes_from_the_closed_form():
    """The bundled example (sun 60, planet 20, module 1 mm, e = 10 mm, psi0 = 30 deg, L = 150 mm):
    a = 40 mm, k = 4; the extremes and the path per turn of z_A = a cos(phi) + e cos(psi0 + 4 phi)
    + sqrt(L^2 - x_B^2) on a 0.0001 deg grid."""
    from crankdyn.cli import examples_dir

    a, e, rod, psi0 = 0.040, 0.010, 0.150, math.radians(30.0)
    phi = np.radians(np.arange(0.0, 360.0, 1e-4))
    x = a * np.sin(phi) + e * np.sin(psi0 + 4 * phi)
    z = a * np.cos(phi) + e * np.cos(psi0 + 4 * phi) + np.sqrt(rod * rod - x * x)
    before, after = np.roll(z, 1), np.roll(z, -1)
    extremes = np.flatnonzero(((z > before) & (z >= after)) | ((z < before) & (z <= after)))
    heights = z[extremes]
    path = float(np.sum(np.abs(np.diff(np.append(heights, heights[0])))))
    import tomllib

    with open(examples_dir() / "planetary-kinematics.toml", "rb") as handle:
        scene = scene_from_dict(tomllib.load(handle), base_dir=examples_dir())
    r = run_scene(scene, REGISTRY).outputs["planetary"].results
    assert r["reversal_count"] == len(extremes) == 8
    assert r["piston_path_m"] == pytest.approx(path, abs=1e-9)
    strokes = secondary_strokes(r["reversals"])
    assert len(strokes) == (len(extremes) - 2) // 2 == 3
    # the main stroke twice and every secondary stroke there and back make up the path
    total = 2 * r["stroke_m"] + 2 * sum(s["depth_m"] for s in strokes)
    assert total == pytest.approx(path, abs=1e-9)
    assert [s["direction"] for s in strokes] == ["rise", "rise", "fall"]


def test_the_positions_figure_shows_every_dead_centre(ring_run):
    """Both BDCs and the secondary TDC at 180 deg are drawn among the characteristic positions."""
    drawn = ring_run.outputs["drawing"].results["crank_angles_deg"]
    expected = _grid_extrema()
    assert drawn["bdc"] == pytest.approx(expected[1][0], abs=1e-3)
    assert drawn["bdc_2"] == pytest.approx(expected[3][0], abs=2e-4)
    assert drawn["secondary_tdc_1"] == pytest.approx(180.0, abs=1e-9)
    figures = render_html(ring_run, REGISTRY, "uk").figures
    svg = "".join(f.svg.decode("utf-8") for f in figures if "positions" in f.name)
    assert "вторинна ВМТ" in svg and "α = 136,4°" in svg and "α = 223,6°" in svg


def test_shallow_secondary_strokes_are_described_but_not_drawn():
    from crankdyn_builtin.planetary.compute import extra_dead_centres

    reversals = [
        {"crank_angle_deg": 0.0, "displacement_m": 0.0, "kind": "tdc", "main": True},
        {"crank_angle_deg": 50.0, "displacement_m": 0.030, "kind": "bdc", "main": False},
        {"crank_angle_deg": 60.0, "displacement_m": 0.0299, "kind": "tdc", "main": False},
        {"crank_angle_deg": 140.0, "displacement_m": 0.080, "kind": "bdc", "main": False},
        {"crank_angle_deg": 170.0, "displacement_m": 0.070, "kind": "tdc", "main": False},
        {"crank_angle_deg": 220.0, "displacement_m": 0.100, "kind": "bdc", "main": True},
    ]
    # 0.1 mm back (0.1 % of S) is not drawn, 10 mm back (10 %) is
    assert extra_dead_centres(reversals, secondary_strokes(reversals), 0.100) == {
        "secondary_bdc_1": 140.0,
        "secondary_tdc_1": 170.0,
    }


def test_the_task_gives_no_rod_ratio_for_a_carrier(ring_run):
    """The assignment's data list λ = R/L only for a mechanism with a crank radius."""
    html = render_html(ring_run, REGISTRY, "uk").linked_html
    assignment = _plain(html.split('class="assignment"', 1)[1].split("</section>", 1)[0])
    assert "D = 76 мм, S = 62,303 мм, " in assignment and "λ" not in assignment
    # the mechanism's own data follow, angles with the degree sign at the number
    assert "zf = 72, zp = 24, m = 1,25 мм, e = 8 мм, ψ0 = 0°, αw = 20°, n = 2400" in assignment


def test_a_two_turn_period_is_compared_with_a_conventional_mechanism_over_two_turns():
    """A 75/30 ring (i = 2,5) repeats its motion every two carrier turns: a conventional
    crank-slider reverses four times and travels 4S over that angle. The note compared the
    planetary's four reversals and its path with one turn's two and 2S ("not twice, as in a
    conventional mechanism, but four times"), which was false."""
    scene = _two_turn_scene()
    result = run_scene(scene, REGISTRY)
    r = result.outputs["planetary"].results
    assert r["period_revolutions"] == 2 and r["conventional_reversals"] == 4
    assert r["conventional_path_m"] == pytest.approx(4 * r["stroke_m"], rel=1e-12)
    assert r["reversal_count"] == 4 and r["piston_path_m"] < r["conventional_path_m"]
    html = render_html(result, REGISTRY).linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", html).replace("\u202f", " ").split())
    assert "не двічі" not in text and "за оберт водила" not in text
    assert "у звичайного кривошипно-шатунного механізму за той самий кут – чотири рази" in text
    four_s = f"4S = {4 * r['stroke_m'] * 1e3:.2f} мм".replace(".", ",")
    assert four_s in text


def _two_turn_scene():
    """A 75/30 ring (i = 2,5): the motion repeats every two carrier turns."""
    return scene_from_dict(
        {
            "report": {"title": "Planetary", "language": "uk", "year": 2026},
            "engine": {
                "name": "ring 75 / planet 30",
                "mechanism": "planetary",
                "strokes": 4,
                "rpm": RPM,
                "bore": "70 mm",
                "stroke": "82.2682 mm",
                "rod_length": "130 mm",
            },
            "mechanism": {
                "gear": "internal",
                "fixed_gear_teeth": 75,
                "planet_teeth": 30,
                "module": "1.25 mm",
                "pin_radius": "15 mm",
                "pin_phase_deg": 20,
                "pressure_angle_deg": 20,
            },
            "masses": {"piston_group": "0.38 kg", "rod": "0.52 kg", "rod_cm_fraction": 0.3},
        }
    )


def test_the_positions_of_a_two_turn_period_keep_their_angles_beyond_360_degrees():
    """The fastest travel towards TDC of the 75/30 ring is at 647,5° (the kinematics' v_min): the
    positions figure labelled and drew it at 287,5°, the angle wrapped at one turn."""
    result = run_scene(_two_turn_scene(), REGISTRY)
    kinematics = result.outputs["planetary"].results
    drawing = result.outputs["drawing"].results
    assert drawing["motion_period_deg"] == 720.0
    angles = drawing["crank_angles_deg"]
    assert all(0.0 <= a < 720.0 for a in angles.values())
    assert angles["v_min"] == pytest.approx(kinematics["v_min_crank_angle_deg"], abs=0.05)
    assert angles["v_min"] > 360.0


def test_family_panel_titles_print_numbers_in_the_report_locale(ring_run):
    """A 75-tooth ring of module 1.25 (93.75 mm) has its planets' diameters 31.25, 46.875 and
    62.5 mm: "31,25" in a Ukrainian note, parted from the next diameter by a semicolon (a
    comma would read as part of the number)."""
    from functools import partial

    from crankdyn.report.context import FigureFile
    from crankdyn.report.i18n import translator
    from crankdyn_builtin.planetary.figures import _family_plot

    t = translator("uk")
    family = ring_run.outputs["planetary"].tables["family"]
    svg = FigureFile("f.svg", build=partial(_family_plot, family, 0.09375, t), t=t).draw()
    text = re.sub(r"<style.*?</style>", "", svg.decode("utf-8"), flags=re.S)
    text = re.sub(r"\s+", "", re.sub(r"<[^>]+>", "", text))
    assert "=31,25;" in text and "=62,5;" in text and "=93,75мм" in text
    assert "31.25" not in text
