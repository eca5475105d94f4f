"""Texts that must follow the engine in front of them: a boosted intake named by its own
pressures, the radii of means the calculation did not fit, the rods' offset couples against the
means actually fitted, the kinematics of several cylinders, the mechanical efficiency of data
that do not belong together, the title page and the list of symbols."""

from __future__ import annotations

import html as html_text
import re

import pytest
from conftest import shared_html, shared_run

from crankdyn.report.document import _vector_magnitudes
from crankdyn.report.plausibility import mechanical_efficiency


def _text(name, changes=None, language="en", stages=None) -> str:
    html = shared_html(name, changes, language, stages).linked_html
    plain = html_text.unescape(re.sub(r"<[^>]+>", " ", html))
    return " ".join(plain.replace("\xa0", " ").split())


#: The bundled in-line four's data as an in-line five, cranks 72° apart (firing 1-2-4-5-3).
INLINE_FIVE = {"engine": {"cylinders": 5, "firing_order": [1, 2, 4, 5, 3]}}

#: The petrol single with an intake above its exhaust pressure (a supercharged engine).
BOOSTED = {"cycle": {"intake_pressure": "0.15 MPa", "exhaust_pressure": "0.12 MPa"}}


def test_a_boosted_engines_pumping_gain_is_said_with_its_own_pressures():
    run = shared_run("petrol-1cyl", BOOSTED, ("indicator",))
    assert run.outputs["indicator"].results["pumping_work_J"] > 0
    text = _text("petrol-1cyl", BOOSTED, "en", ("indicator",))
    assert (
        "Here the intake pressure p a = 0.1500 MPa is above the exhaust pressure p r = 0.1200 MPa"
        in text
    )
    assert "With the intake above the exhaust pressure (boost)" not in text
    # the valve timing the rounding applies: the exhaust opening and the overlap, not the intake closing
    assert "the valve overlap about TDC, where the pressure passes from p r to p a" in text
    assert "the intake valve closing after it" not in text


def test_a_radius_of_means_not_fitted_is_marked_in_the_given_data():
    # an in-line four's crank arrangement balances C and its moment: no counterweights fitted
    given = {"balancing": {"counterweight_radius": "60 mm", "balance_orders": []}}
    r = shared_run("inline4-petrol", given, ("balancing",)).outputs["balancing"].results
    assert not r["counterweights"] and not r["balance_shafts"]
    text = _text("inline4-petrol", given, "en", ("balancing",))
    assert "Radius of the counterweights' centre of mass (no counterweights fitted) 60 mm" in text
    # fitted ones are not marked
    every = {"balancing": {"counterweight_radius": "60 mm", "counterweights": "every_crank"}}
    assert "(no counterweights fitted)" not in _text("inline4-petrol", every, "en", ("balancing",))


def test_the_rod_offset_couples_are_set_against_the_means_the_engine_has():
    """A V8's rods side by side on the pins: without balance shafts the sentence names the
    counterweights only (not shafts the engine lacks)."""
    r = shared_run("v8-petrol", None, ("balancing",)).outputs["balancing"].results
    assert r["counterweights"] and not r["balance_shafts"]
    text = _text("v8-petrol", None, "en", ("balancing",))
    assert "the counterweights, which lie in the cranks' planes, do not remove them" in text
    assert "balance shafts, which lie" not in text


def test_several_cylinders_kinematics_count_each_alpha_from_its_own_tdc():
    sentence = "for each, α is measured from its own TDC"
    assert sentence in _text("inline4-petrol", None, "en", ("kinematics",))
    assert sentence not in _text("petrol-1cyl", None, "en", ("kinematics",))
    # a radial engine's articulated rods move their pistons otherwise than the master's
    assert sentence not in _text("radial9-aircraft", None, "en", ("kinematics",))


def test_a_mechanical_efficiency_of_one_or_more_is_said_to_be_impossible():
    rule = mechanical_efficiency("eta")
    assert rule.check(None, {"eta": 0.85}) == []
    assert rule.check(None, {"eta": 0.97})[0][0] == "plausibility.mechanical_efficiency"
    assert rule.check(None, {"eta": 1.0})[0][0] == "plausibility.mechanical_efficiency_impossible"
    assert rule.check(None, {"eta": 1.98})[0][0] == "plausibility.mechanical_efficiency_impossible"
    assert rule.check(None, {"eta": 0.5})[0][0] == "plausibility.mechanical_efficiency_low"


def test_a_subtitle_naming_the_discipline_is_not_printed_under_it_again():
    named = {
        "report": {
            "discipline": "Marine engines",
            "subtitle": "Course project in Marine engines",
        }
    }
    text = _text("kinematics-only", named, "en", ())
    assert text.count("Marine engines") == 1
    other = {"report": {"discipline": "Marine engines", "subtitle": "Variant of the spring term"}}
    assert "Variant of the spring term" in _text("kinematics-only", other, "en", ())


def test_a_light_letter_is_the_bold_ones_magnitude_only_in_the_same_unit():
    vector, magnitude = "<b><i>q</i></b><sub>p</sub>", "<i>q</i><sub>p</sub>"
    assert _vector_magnitudes([vector, magnitude], ["unit.MPa", "unit.MPa"]) == {vector: magnitude}
    # the torsion's vector of disc angles (rad) and the balancing's shaft angle (°)
    assert _vector_magnitudes(["<b><i>θ</i></b>", "<i>θ</i>"], ["unit.rad", "°"]) == {}
    # a matrix (no unit) has no magnitude: Φ of the mode shapes beside the cycle's angle Φ
    assert _vector_magnitudes(["<b>Φ</b>", "Φ"], ["", ""]) == {}


#: A 60° V6 on three shared pins (cranks 0°, 240°, 120°): its free second-order moment turns.
V6_SHARED_PINS = {
    "engine": {
        "cylinders": 6,
        "bank_angle_deg": 60,
        "firing_order": ["1L", "1R", "2L", "2R", "3L", "3R"],
        "crank_angles_deg": [0, 240, 120],
        "uneven_firing": True,
    },
    "balancing": {"balance_orders": []},
}


def test_a_rotating_free_moment_of_a_higher_order_is_said_to_turn_at_that_speed():
    r = shared_run("v8-petrol", V6_SHARED_PINS, ("balancing",)).outputs["balancing"].results
    second = next(o for o in r["orders"] if o["order"] == 2)
    assert second["moment_hodograph"]["sense"] == "forward"
    text = _text("v8-petrol", V6_SHARED_PINS, "en", ("balancing",))
    assert "Σ M II turns with the shaft at 2ω, at a constant size" in text
    # the centrifugal forces' moment turns at ω, said without a speed
    assert "Σ M C turns with the shaft at a constant size" in text


def test_a_rod_model_other_than_the_forces_one_is_said_to_be_its_sections_own():
    """The forces and the torque keep the textbook's two-mass split whatever rod model the
    rod-dynamics section takes: its conclusion must not say that the calculation used another,
    and says the forces keep the split only where they were computed."""
    inertia = {"masses": {"rod_moment_of_inertia": "0.02 kg m^2"}}
    three = {**inertia, "rod_dynamics": {"model": "three_mass"}}
    text = _text("diesel-1cyl", three, "en", ("rod_dynamics", "forces"))
    assert "gives that torque by the three-mass model" in text
    assert "The forces and the torque keep the textbook's two-mass split" in text
    assert "the calculation uses" not in text
    alone = _text("diesel-1cyl", three, "en", ("rod_dynamics",))
    assert "gives that torque by the three-mass model" in alone
    assert "keep the textbook's two-mass split" not in alone
    two = _text("diesel-1cyl", inertia, "en", ("rod_dynamics",))
    assert "the calculation uses the textbook's two-mass split" in two


def test_the_split_pin_offset_that_would_even_a_v_engines_firing():
    from crankdyn_builtin.bays.section import split_pin_offset_deg

    assert split_pin_offset_deg(6, 3, 60.0, 120.0) == 60.0  # a 60° V6
    assert split_pin_offset_deg(6, 3, 90.0, 120.0) == 30.0  # a 90° V6 (the even-fire 30° split)
    assert split_pin_offset_deg(10, 5, 90.0, 72.0) == 18.0  # a 90° V10
    assert split_pin_offset_deg(8, 4, 90.0, 90.0) is None  # a 90° V8 fires evenly already
    assert split_pin_offset_deg(2, 1, 90.0, 360.0) is None  # a V-twin: not said
    assert split_pin_offset_deg(6, 6, 60.0, 120.0) is None  # a pin of its own for each cylinder


def test_a_v6_on_shared_pins_is_told_how_even_firing_is_had():
    text = _text("v8-petrol", V6_SHARED_PINS, "en", ("bays",))
    assert "intervals" in text
    assert (
        "Even firing every 120° is obtained by offsetting the left and right banks' crank pins "
        "from each other by 60° (split pins)"
    ) in text
    assert "split pins" not in _text("v8-petrol", None, "en", ("bays",))


def test_a_crosshead_engines_side_force_acts_on_the_guides():
    """A crosshead engine's side force presses the crosshead's slide on its guides, and its
    reciprocating mass is the piston's with the piston rod and the crosshead: no text of the
    note puts the piston against the cylinder wall."""
    crosshead = {"engine": {"crosshead": True}}
    text = _text("diesel-1cyl", crosshead, "en")
    assert "specific side force pressing the crosshead's slide against its guides" in text
    assert "the specific side force on the crosshead's guides largest in magnitude is N" in text
    assert "Mass of the reciprocating parts (piston, piston rod and crosshead)" in text
    assert "A the crosshead pin axis" in text
    assert "cylinder wall" not in text and "piston pin" not in text
    # the same engine without a crosshead keeps the trunk piston's texts
    assert "cylinder wall" in _text("diesel-1cyl", None, "en")
    # the rod's upper end is the crosshead's
    with_rod = {"engine": {"crosshead": True}, "masses": {"rod_moment_of_inertia": "0.02 kg m^2"}}
    rod_text = _text("diesel-1cyl", with_rod, "en")
    assert "small (crosshead) end" in rod_text and "small end" not in rod_text


def test_a_big_end_bearing_loaded_above_its_pin_is_explained():
    """At a low speed a V8's firing rod carries more than its pin does from both rods (the other
    rod's inertia and the rods' centrifugal force pull the other way): the note says why; at the
    example's speed the pin carries more and nothing is said."""
    slow = {"engine": {"rpm": 2000}}
    r = shared_run("v8-petrol", slow, ("bearings",)).outputs["bearings"].results
    rod = max(b["max_N"] for b in r["rod_bearings"])
    pin = max(p["max_N"] for p in r["crank_pins"])
    assert rod > pin
    text = _text("v8-petrol", slow, "en", ("bearings",))
    assert (
        f"The largest force on a big-end bearing ({rod / 1e3:.2f} kN) exceeds the largest load on "
        f"the crank pin from all its rods ({pin / 1e3:.2f} kN)"
    ) in text
    assert "exceeds the largest load on the crank pin" not in _text(
        "v8-petrol", None, "en", ("bearings",)
    )


def test_a_slow_engines_small_table_values_keep_four_digits():
    """A low-speed marine engine's piston acceleration (about 160 m/s²) printed without decimals
    would leave the worked line's p_j off its own result in the third digit."""
    from crankdyn.report.worked import column_decimals

    assert column_decimals([17168.0, -9683.0], 0) == 0  # a car engine's j: as before
    assert column_decimals([157.93, -100.2], 0) == 1
    assert column_decimals([-22.137, 5.0], 0) == 2
    assert column_decimals([164.2], 1) == 1  # ω_r of a car engine: unchanged
    assert column_decimals([0.004], 0) == 3  # at most three more
    assert column_decimals([0.0, float("nan")], 2) == 2
    slow = {"engine": {"rpm": 120}}
    r = shared_run("diesel-1cyl", slow, ("forces",)).outputs["forces"].results
    assert r is not None
    text = _text("diesel-1cyl", slow, "en", ("forces",)).replace("\u2060", "").replace(" ", "")
    worked = re.search(
        r"pj=−msjp/Fp=\(−([\d.]+)·\((−?[\d.]+)\)/([\d.]+)\)·10−6=(−?[\d.]+)MPa", text
    )
    assert worked
    m, j, area, result = (float(x.replace("−", "-")) for x in worked.groups())
    assert "." in worked.group(2)  # j printed with decimals: 9,94 m/s², not 10
    assert -m * j / area * 1e-6 == pytest.approx(result, abs=1.5e-3)


def test_a_large_marine_engines_masses_are_accepted_and_bounded():
    """A low-speed marine engine's piston with rod and crosshead (8,5 t) and rod (I_G 4000 kg·m²)
    are scene values; 60 t is refused with the field, the value and the bound."""
    from conftest import modified

    from crankdyn.errors import SceneError
    from crankdyn.scene.model import scene_from_dict

    big = modified(
        "diesel-1cyl",
        {"masses": {"piston_group": "8.5 t", "rod": "6 t", "rod_moment_of_inertia": "4000 kg m^2"}},
    )
    assert scene_from_dict(big).masses.piston_group == pytest.approx(8500.0)
    too_big = modified("diesel-1cyl", {"masses": {"piston_group": "60 t"}})
    with pytest.raises(
        SceneError, match=r"masses.piston_group = '60 t': must be > 0 kg and <= 50000 kg"
    ):
        scene_from_dict(too_big)


def _own_inertia_enough(application: str) -> dict:
    """The in-line four with a heavy shaft: its own inertia meets [δ] at the rated speed."""
    return {
        "engine": {"application": application},
        "flywheel": {"required_irregularity": 0.2, "engine_inertia": "1 kg*m^2"},
    }


def test_an_outboard_motor_keeps_its_flywheel_magneto_where_delta_needs_none():
    changes = _own_inertia_enough("outboard")
    r = shared_run("inline4-petrol", changes, ("flywheel",)).outputs["flywheel"].results
    assert r["own_inertia_sufficient"]
    text = _text("inline4-petrol", changes, "en", ("flywheel",))
    assert "An outboard motor carries a flywheel all the same: the magneto's rotor" in text
    assert "chosen for starting and idling" in text
    assert "A vehicle's engine carries a flywheel" not in text


def test_an_aircraft_engine_meeting_delta_alone_is_not_told_its_propeller_is_not_needed():
    changes = _own_inertia_enough("aircraft")
    text = _text("inline4-petrol", changes, "en", ("flywheel",))
    assert "even without the propeller; the propeller, whose moment of inertia" in text
    assert "with the propeller, whose moment of inertia the assignment does not give, δ is" in text
    assert "none ([δ] is met without the propeller)" in text
    assert "propeller's moment of inertia is not needed" not in text


def test_the_coefficients_table_leaves_out_columns_with_a_dash_in_every_row():
    """An in-line five cancels the forces of every order: no force has a hodograph, so the
    hodograph's columns would hold a dash in every row; the moments keep their plane."""
    five = INLINE_FIVE
    r = shared_run("inline4-petrol", five, ("balancing",)).outputs["balancing"].results
    assert all(o["force_coefficient"] < 1e-9 for o in r["orders"])
    text = _text("inline4-petrol", five, "en", ("balancing",))
    assert "Plane of the moment from the vertical" in text
    assert "Major axis from the vertical" not in text
    # the in-line four's second-order force has its hodograph
    assert "Major axis from the vertical" in _text("inline4-petrol", None, "en", ("balancing",))


def test_the_forces_summed_on_a_single_crank_are_each_cylinders_own():
    """A radial's cylinders all act on its one crank: z_i and t_i of the sum are the cylinders'
    own forces, not the i-th crank's sum of its cylinders (a V8's bank of two on each pin)."""
    radial = _text("radial9-aircraft", None, "en", ("torque",))
    assert "specific radial force of cylinder i at its own cycle angle" in radial
    assert "on crank i (the sum over its cylinders" not in radial
    v8 = _text("v8-petrol", None, "en", ("torque",))
    assert "on crank i (the sum over its cylinders" in v8


def test_moments_that_repeat_the_first_orders_star_are_explained():
    """An in-line five's cranks 72° apart: 4·72° ≡ −72° and 6·72° ≡ 72° (mod 360°), so ΣM_IV and
    ΣM_VI have ΣM_I's coefficient; an in-line three's 2·120° ≡ −120°, 4·120° ≡ 120°. The
    coefficients agree in the table, and the note says why."""
    five = INLINE_FIVE
    r = shared_run("inline4-petrol", five, ("balancing",)).outputs["balancing"].results
    assert r["first_star_repeats"] == [{"order": 4, "sign": -1}, {"order": 6, "sign": 1}]
    by_order = {o["order"]: o["moment_coefficient"] for o in r["orders"]}
    assert by_order[4] == pytest.approx(by_order[1], rel=1e-9)
    assert by_order[6] == pytest.approx(by_order[1], rel=1e-9)
    assert by_order[1] == pytest.approx(0.4490, abs=5e-5)  # the textbook's in-line five
    text = _text("inline4-petrol", five, "en", ("balancing",))
    assert "The moments Σ M IV and Σ M VI have the first order's coefficient" in text
    assert "4 ξ i ≡ − ξ i and 6 ξ i ≡ ξ i (mod 360°)" in text
    three = shared_run("inline3-petrol", None, ("balancing",)).outputs["balancing"].results
    assert three["first_star_repeats"] == [{"order": 2, "sign": -1}, {"order": 4, "sign": 1}]
    # an in-line four has no first-order moment: nothing to repeat
    four = shared_run("inline4-petrol", None, ("balancing",)).outputs["balancing"].results
    assert four["first_star_repeats"] == []


def test_the_radii_of_means_the_calculation_takes_are_in_the_table_of_values_taken():
    """The single cylinder's counterweights at R and its balance shaft at R/2, neither radius
    given: both in the table of the values taken (R = 39 mm); a given radius is not."""
    text = _text("petrol-1cyl", None, "en", ("balancing",))
    taken = text[text.index("Values taken in the calculation") :]
    assert "Radius of the counterweights' centre of mass 39 mm" in taken
    assert "Radius of the balance-shaft masses' centre of mass 19.5 mm" in taken
    given = {"balancing": {"counterweight_radius": "45 mm"}}
    taken = _text("petrol-1cyl", given, "en", ("balancing",))
    assert "Radius of the counterweights' centre of mass 39 mm" not in taken


def test_the_full_support_shaft_the_calculation_takes_is_in_the_table_of_values_taken():
    """The section on the cranks takes a main support between neighbouring cranks and at both
    ends (five for an in-line four), which no assignment gives: a row of the values taken; a
    single cylinder's crank has no such choice."""
    text = _text("inline4-petrol", None, "en", ("bays",))
    taken = text[text.index("Values taken in the calculation") :]
    assert (
        "Main supports of the crankshaft (one between neighbouring cranks and one at each end) 5"
        in taken
    )
    assert "Main supports of the crankshaft" not in _text("petrol-1cyl", None, "en", ("bays",))


def test_a_part_of_table_b3_without_the_torque_names_the_table_that_has_it():
    """An in-line five's table B.3 is set in two parts (cranks 1–4 and 5 with the torque M_d):
    both have the rows at M_d's extremes, and the first, which has no column of M_d, says in
    which table M_d is."""
    text = _text("inline4-petrol", INLINE_FIVE, "en", ("torque",))
    notes = [
        re.split(r"\. (?:For|The) ", text[m.start() :], maxsplit=1)[0]
        for m in re.finditer(r"Note\. Besides the rows every 30°", text)
    ]
    notes = [n for n in notes if "M d" in n]
    assert len(notes) == 2, notes
    first, second = notes
    part = re.search(r"Table (\d+\.\d+) — Forces and running torques on crank 5\b", text)
    assert part, "the second part holds crank 5 and the torque"
    assert first.count(f"(table {part.group(1)})") == 2  # both extremes: largest and least
    assert "(table" not in second


def test_the_dangerous_loads_table_says_its_q_leaves_the_counterweights_out():
    """Table B.4's q is the textbook's, without the counterweights the bearings' loads take: its
    caption says so where the shaft carries counterweights, and only there."""
    every = {"balancing": {"counterweights": "every_crank"}}
    caption = "(q without the counterweights' centrifugal forces) [1, table B.4]"
    assert caption in _text("inline4-petrol", every, "en", ("torque", "balancing"))
    assert "counterweights' centrifugal forces)" not in _text(
        "inline4-petrol", None, "en", ("torque", "balancing")
    )
