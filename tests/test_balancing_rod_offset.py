"""A V-twin's rods side by side on its one crank pin: the couples of the rods' offset.

Independent reference, written here: each cylinder's reciprocating inertia force m_s j(alpha)
along its own axis, j by a central second difference of the exact piston position, the two
cylinders' planes one rod's width apart along the shaft; the moment Σ z_i F_i over a turn,
resolved by an FFT into the parts of each order turning with the shaft and against it.
"""

from __future__ import annotations

import html as html_lib
import math
import re

import numpy as np
import pytest
from conftest import V_TWIN_ENGINE, shared_html, shared_run

V_TWIN = {"engine": V_TWIN_ENGINE}


def _acceleration_over_omega2(alpha, R, L, h=1e-4):
    def x(a):
        return R * np.cos(a) + np.sqrt(L**2 - (R * np.sin(a)) ** 2)

    return -(x(alpha + h) - 2 * x(alpha) + x(alpha - h)) / h**2


def test_the_rods_offset_couples_against_a_direct_sum():
    run = shared_run("v8-petrol", V_TWIN, stages=["balancing"])
    e = run.scene.engine
    R, L, w = e.crank_radius_m, e.rod_length_m, e.angular_velocity_rad_s
    b = run.outputs["balancing"].results
    couples = b["rod_offset_couples"]
    # one big-end bearing of typical proportions: a pin 0.63 of the bore and 2 × 0.45 of its
    # diameter long, each to 0.1 mm as the bearing section takes them, shared by the two rods
    diameter = round(0.63 * e.bore * 1e4) / 1e4
    offset = round(2 * 0.45 * diameter * 1e4) / 1e4 / 2
    assert couples["offset_m"] == pytest.approx(offset, rel=1e-12)
    assert not couples["offset_given"] and couples["offset_source"] == "typical"
    m_s = b["reciprocating_mass_kg"]
    gamma = math.radians(45.0)
    theta = 2 * np.pi * np.arange(720) / 720
    # bank 0 (axis 0) at -b/2, bank 1 (axis gamma, its TDC gamma later) at +b/2
    moment = np.zeros(theta.size, dtype=complex)
    for axis, z in ((0.0, -0.5 * offset), (gamma, 0.5 * offset)):
        force = m_s * w**2 * _acceleration_over_omega2(theta - axis, R, L)
        moment += z * force * np.exp(1j * axis)
    spectrum = np.fft.fft(moment) / theta.size
    by_order = {x["order"]: x for x in couples["moments"]}
    for n in (1, 2, 4):
        assert by_order[n]["forward_Nm"] == pytest.approx(abs(spectrum[n]), rel=1e-5, abs=1e-5)
        assert by_order[n]["backward_Nm"] == pytest.approx(abs(spectrum[-n]), rel=1e-5, abs=1e-5)
    # the first order's couple turns against the shaft only: a crank counterweight cannot take it
    assert by_order[1]["forward_Nm"] == pytest.approx(0.0, abs=1e-9)
    # C_I b/2 · |1 - e^{2iγ}|/2·... : its closed form for two cylinders γ apart
    closed = 0.5 * m_s * R * w**2 * offset * 0.5 * abs(1 - np.exp(2j * gamma))
    assert by_order[1]["backward_Nm"] == pytest.approx(closed, rel=1e-9)


def test_a_given_rod_offset_is_taken():
    given = shared_run(
        "v8-petrol", {**V_TWIN, "balancing": {"rod_offset": "30 mm"}}, stages=["balancing"]
    )
    couples = given.outputs["balancing"].results["rod_offset_couples"]
    assert couples["offset_given"] and couples["offset_m"] == pytest.approx(0.030)


#: A 90° V4 on two cranks 180° apart, rods side by side: the cranks' second-order couples of
#: the offset add up instead of cancelling (as they do in the cross-plane V8).
V4 = {
    "engine": {
        "cylinders": 4,
        "bank_angle_deg": 90,
        "crank_angles_deg": [0, 180],
        "uneven_firing": True,
        "firing_order": ["1L", "2L", "1R", "2R"],
    },
    "balancing": {"rod_offset": "18 mm"},
}


def _offset_spectrum(run, offset, lags_rad, gamma):
    """The rods' offset couple Σ z_i F_i e^{iψ_i} over a turn, by an FFT: each crank (lag) with
    bank 0 (axis 0) at −b/2 and bank 1 (axis ``gamma``) at +b/2."""
    e = run.scene.engine
    R, L, w = e.crank_radius_m, e.rod_length_m, e.angular_velocity_rad_s
    m_s = run.outputs["balancing"].results["reciprocating_mass_kg"]
    theta = 2 * np.pi * np.arange(720) / 720
    moment = np.zeros(theta.size, dtype=complex)
    for lag in lags_rad:
        for axis, z in ((0.0, -0.5 * offset), (gamma, 0.5 * offset)):
            force = m_s * w**2 * _acceleration_over_omega2(theta - lag - axis, R, L)
            moment += z * force * np.exp(1j * axis)
    return np.fft.fft(moment) / theta.size


def _matches(couples, spectrum, orders=(1, 2, 4, 6)):
    by_order = {x["order"]: x for x in couples["moments"]}
    for n in orders:
        assert by_order[n]["forward_Nm"] == pytest.approx(abs(spectrum[n]), rel=1e-5, abs=1e-5)
        assert by_order[n]["backward_Nm"] == pytest.approx(abs(spectrum[-n]), rel=1e-5, abs=1e-5)
    return by_order


def test_the_rods_offset_couples_of_several_cranks_against_a_direct_sum():
    run = shared_run("v8-petrol", V4, stages=["balancing"])
    couples = run.outputs["balancing"].results["rod_offset_couples"]
    assert couples["cranks"] == 2
    spectrum = _offset_spectrum(run, 0.018, (0.0, np.pi), math.radians(90.0))
    by_order = _matches(couples, spectrum)
    # the two cranks' second-order couples add up: 2·(b/2)·√2·|A_2|C_I, about 76 N·m here
    assert by_order[2]["moment_Nm"] > 70
    # the tables' one-plane ΣM_II is zero; the section and the conclusions give the offset's
    html = shared_html("v8-petrol", V4, "en").linked_html
    text = re.sub(r"[\u00a0\u202f]", " ", re.sub(r"<[^>]+>", "", html))
    said = f"ΣMII = {by_order[2]['moment_Nm']:.0f} N·m"
    assert (
        "This offset adds longitudinal couples of the inertia forces to those of the tables" in text
    )
    assert text.count(said) >= 2, said
    # the balance table does not call ΣM_II balanced without saying in what model
    cells = re.sub(r"\s", "", text).replace("&#39;", "'")
    qualified = (
        "bythearrangementofthecylindersandcranks"
        "(eachcrank'scylindersinitsplane;therods'offsetleavesacouple"
    )
    assert "ΣMII0.0000balanced" + qualified in cells


def test_a_flat_plane_v8s_conclusion_leaves_the_rods_couples_out_of_what_balances_itself():
    """Cranks 0-180-180-0: the tables' one-plane moments all vanish, but the rods' offset leaves
    ΣM_II; the conclusion lists the moments the cranks balance without it."""
    flat = {
        "engine": {
            "crank_angles_deg": [0, 180, 180, 0],
            "firing_order": ["1L", "1R", "3L", "3R", "4L", "4R", "2L", "2R"],
        },
        "balancing": {"balance_orders": [1, 2]},  # shafts for ΣP_II: the conclusion says both
    }
    couples = shared_run("v8-petrol", flat, stages=["balancing"]).outputs["balancing"].results
    assert couples["rod_offset_couples"]["moments"][1]["moment_Nm"] > 100
    html = shared_html("v8-petrol", flat, "en").linked_html
    text = re.sub(r"[\u00a0\u202f]", " ", re.sub(r"<[^>]+>", "", html))
    (itself,) = re.findall(
        r"The arrangement of the cylinders and cranks itself balances [^.]*\.", text
    )
    assert re.search(r"ΣMI[,) ]", itself) and "ΣMII" not in itself and "ΣMIV" not in itself, itself
    # each bank a flat four, the banks' second-order forces in opposite phase 90° apart: their
    # sum pulsates across the V, along the horizontal
    assert (
        "The free forces act as follows: ΣPII pulsates along the horizontal across the shaft"
        in text
    )


def test_a_cross_plane_v8s_offset_couples_cancel_but_for_the_fourth_order():
    """Cranks at 0°, 90°, 270°, 180°: the offset's first- and second-order couples cancel over
    the shaft; the fourth-order ones, all in phase, add up."""
    run = shared_run("v8-petrol", stages=["balancing"])
    couples = run.outputs["balancing"].results["rod_offset_couples"]
    lags = np.radians([0.0, 90.0, 270.0, 180.0])
    by_order = _matches(couples, _offset_spectrum(run, couples["offset_m"], lags, np.pi / 2))
    assert by_order[1]["moment_Nm"] < 1e-9 and by_order[2]["moment_Nm"] < 1e-9
    assert by_order[4]["moment_Nm"] > 1


@pytest.mark.parametrize(
    ("language", "only", "left"),
    [
        ("ru", "остаётся лишь", "неуравновешенной остаётся"),
        ("uk", "залишається лише", "незрівноваженою залишається"),
        ("en", "only", "remains unbalanced"),
    ],
    ids=["ru", "uk", "en"],
)
def test_the_abstract_does_not_call_the_residuals_the_only_ones_before_the_rods_couples(
    language, only, left
):
    """The abstract says what the fitted means leave of the forces and then the couples the rods'
    offset leaves as well: the first list is not "the only" residuals then, and the couples
    follow as more ("besides"), not announced as "the parts named next"."""
    import re

    # the full note in Russian (shared with the next tests), the balancing alone in the others
    stages = None if language == "ru" else ("balancing",)
    html = shared_html("v8-petrol", V_TWIN, language=language, stages=stages).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html))
    couples = {"ru": "продольные моменты", "uk": "поздовжні моменти", "en": "longitudinal couples"}
    # the abstract's sentence up to the couples (their first mention)
    before = text[: text.index(couples[language])]
    sentence = before[before.rindex(". ") :]
    assert left in sentence and only not in sentence, sentence
    besides = {
        "ru": "; кроме того, смещение",
        "uk": "; крім того, зміщення",
        "en": "; besides, the",
    }
    assert besides[language] in sentence, sentence
    assert "далее" not in sentence and "далі" not in sentence and "named next" not in sentence


def test_a_one_crank_engines_table_gives_no_crank_angles():
    """A V-twin's one crank lags none: table 1.1 gives no row of the cranks' angles (a V8's,
    whose scene gives four, does)."""
    t = shared_html("v8-petrol", V_TWIN, language="en", stages=("bays",)).linked_html
    assert "Angles of the cranks (lag behind crank 1)" not in t
    eight = shared_html("v8-petrol", None, "en", ("bays",))  # the example gives its four
    assert "Angles of the cranks (lag behind crank 1)" in eight.linked_html


def test_a_v_twins_note_says_both_and_two_not_all_and_several():
    """A V-twin's two cylinders are "both" or "two", not "all" nor "several", and its one
    cylinder in each bank is no bank's "first"."""
    import re

    text = re.sub(r"<[^>]+>", "", shared_html("v8-petrol", V_TWIN, language="ru").linked_html)
    for said in (
        "Оба цилиндра действуют на общую шатунную шейку",
        "Колено нагружают два цилиндра",
        "На одну шатунную шейку действуют два шатуна",
        "Шатунные подшипники обоих цилиндров",
        "Оба цилиндра работают на одно колено",
        "ось поршневого пальца цилиндра каждого ряда",
        "два цилиндра на одном колене",
        "(1Л, 1П; оба нагружены одинаково)",
    ):
        assert said in text, said
    for unsaid in (
        "Все цилиндры",
        "несколько цилиндров",
        "несколько шатунов",
        "первого цилиндра каждого ряда",
        "1Л…1П",
    ):
        assert unsaid not in text, unsaid


def test_an_in_line_sixs_balance_names_the_negligible_forces_it_leaves():
    """The crank arrangement of an in-line six balances the free forces and moments but the
    sixth order's negligible force, which table 8.3 marks unbalanced: the sentence names it."""
    import re

    html = shared_html("inline6-diesel-trace", None, "ru", ("balancing",)).linked_html
    text = re.sub(r"<[^>]+>", "", html)
    assert "уравновешивает схема колен, кроме пренебрежимо малых ΣPVI" in text


def test_the_rods_offset_follows_a_given_crank_pin_width_in_both_sections():
    """A V-twin whose crank pin is given as 40 mm long and no rod offset: each rod's bearing is
    20 mm wide, so the rods' planes lie 20 mm apart for the balancing's couples and each 10 mm
    off the pin's middle for the bearings; the balancing says where the 20 mm come from."""
    pin = {**V_TWIN, "bearings": {"crank_pin_width": "40 mm"}}
    run = shared_run("v8-petrol", pin, stages=["balancing", "bearings"])
    couples = run.outputs["balancing"].results["rod_offset_couples"]
    assert couples["offset_m"] == pytest.approx(0.020) and couples["offset_source"] == "pin_width"
    bearings = run.outputs["bearings"].results
    assert bearings["rod_bearings"][0]["width_m"] == pytest.approx(0.020)
    html = shared_html("v8-petrol", pin, "en", ("balancing", "bearings")).linked_html
    text = html_lib.unescape(re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html)))
    assert (
        "lie 20 mm apart along the shaft (one big-end bearing's width: the given crank-pin width"
        in text
    )


def test_a_given_rod_offset_a_given_pin_width_contradicts_is_warned_of():
    """18 mm between the rods' planes on a 17 mm pin of two rods (each 8.5 mm wide): a warning
    naming both fields; the same offset on a 36 mm pin is what the pin gives, and is not."""
    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.plausibility import console_lines, warnings

    registry = default_registry()

    def named(pin: str) -> list[str]:
        changes = {
            **V_TWIN,
            "balancing": {"rod_offset": "18 mm"},
            "bearings": {"crank_pin_width": pin},
        }
        run = shared_run("v8-petrol", changes, stages=["balancing"])
        lines = console_lines(warnings(run.scene, registry, run), registry)
        return [line for line in lines if "balancing.rod_offset" in line]

    short = named("17 mm")
    assert len(short) == 1 and "8.5 mm" in short[0] and "bearings.crank_pin_width" in short[0]
    assert named("36 mm") == []


def test_the_plan_says_where_the_banks_offset_comes_from():
    """A V4 whose crank pin is given as 40 mm long: the engine's plan offsets the right bank from
    the left by one rod's bearing, 20 mm, and says it is the given pin shared by its two rods
    (the V8 without a pin length: the typical proportions)."""
    pin = {"engine": V4["engine"], "bearings": {"crank_pin_width": "40 mm"}}
    plan = shared_run("v8-petrol", pin, stages=["bays"]).outputs["bays"].results["plan"]
    assert plan["rod_offset_m"] == pytest.approx(0.020) and plan["rod_offset_source"] == "pin_width"
    html = shared_html("v8-petrol", pin, "en", ("bays",)).linked_html
    text = html_lib.unescape(re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html)))
    assert (
        "so the right bank's cylinders are offset from the left bank's along the shaft towards "
        "the flywheel by one big-end bearing's width, 20 mm (the given crank-pin width shared by "
        "the rods on it)." in text
    )
    typical = shared_run("v8-petrol", stages=["bays"]).outputs["bays"].results["plan"]
    assert typical["rod_offset_source"] == "typical"


def test_fork_and_blade_rods_are_said_to_make_no_couple():
    """Fork-and-blade rods of a V work in one plane: the section says so (no offset, no couple),
    where side-by-side rods get their couples; an in-line engine's rods say nothing of it."""
    fork = {"engine": {"rod_type": "fork"}}
    r = shared_run("v8-petrol", fork, stages=["balancing"]).outputs["balancing"].results
    assert r["rod_offset_couples"] is None
    html = shared_html("v8-petrol", fork, "en", ("balancing",)).linked_html
    said = "The fork-and-blade rods of a crank pin work in one plane"
    assert said in html
    assert said not in shared_html("v8-petrol", None, "en", ("balancing",)).linked_html
    # in Russian and Ukrainian a fork's partner is the inner (blade) rod: both rods are central
    for language, words in (
        ("ru", "Вильчатый и внутренний шатуны"),
        ("uk", "Вилчастий і внутрішній"),
    ):
        page = shared_html("v8-petrol", fork, language, ("balancing", "bays")).linked_html
        assert (
            words in page
            and "центральн" + ("ый шатун" if language == "ru" else "ий шатун") not in page
        )
    # one rod mass is given: the fork rod and the blade rod are said to be taken alike
    bays = shared_html("v8-petrol", fork, "en", ("bays",)).linked_html
    assert "The fork rod and the blade rod are taken alike" in bays
    assert "taken alike" not in shared_html("v8-petrol", None, "en", ("bays",)).linked_html


def test_an_offset_engines_second_order_vectors_stand_at_twice_its_cranks_angle():
    """A fictitious vector of the second order stands at twice its crank's angle from the
    cylinder axis: an offset crank-slider's crank is φ₀ off the axis at TDC, so its
    C_II vector stands at 2φ₀ (not on the axis), as its first-order one at φ₀."""
    import math

    from crankdyn_builtin.balancing.figures import _star_drawing

    r = shared_run("offset-crank-engine", stages=["balancing"]).outputs["balancing"].results
    tdc = r["crank_directions_deg"][0]
    assert 1.0 < abs(tdc) < 20.0
    fig = _star_drawing(
        ("I", "II"),
        [str(k + 1) for k in range(len(r["cylinder_labels"]))],
        r["crank_directions_deg"],
        r["cylinder_phases_deg"],
        r["cylinder_axes_deg"],
    )
    # the vectors' labels stand on them, 1.17 from the centre
    labelled = [
        math.degrees(math.atan2(*t.get_position()))
        for t in fig.axes[1].texts
        if abs(math.hypot(*t.get_position()) - 1.17) < 1e-9
    ]
    assert labelled == [pytest.approx(2 * tdc, abs=0.006)], labelled  # grouped to 0.01°


def test_the_residual_check_does_not_say_the_moments_vanish_beside_the_rods_couples():
    """A cross-plane V8's residual (the cylinders' forces in their cranks' planes) has no moment,
    but its side-by-side rods leave a fourth-order couple, given above the check: the check says
    its moments vanish in the cranks' planes and points to those couples."""
    r = shared_run("v8-petrol", None, stages=["balancing"]).outputs["balancing"].results
    scale = r["time_domain_check"]["moment_scale_Nm"]
    assert r["residual"]["moment_max_Nm"] <= 1e-9 * scale
    assert any(m["moment_Nm"] > 1e-6 * scale for m in r["rod_offset_couples"]["moments"])
    text = " ".join(
        re.sub(r"<[^>]+>", "", shared_html("v8-petrol", None, "en", ("balancing",)).linked_html)
        .replace("&#39;", "'")
        .split()
    )
    assert (
        "Their moments vanish as well, the cylinders' forces taken in their cranks' planes" in text
    )
    assert "Their moments vanish as well." not in text
