"""A V12 diesel with master and slave (articulated) rods: what its note says of the crank-pin
load, the crank's centrifugal force, the slave pin, the mean torque, the torque period and the
balance, each number against a value worked out here from the scene's data.

Independent reference, written here: the master rod's rotating part m_rod (1 − l_R/L); a slave
rod's rotating part m_sr (1 − κ) lumped at its pin and split statically between the big end and
the piston pin, the big end's share (1 − r cos γ₁/L) (Poda 2007, fig. 9); the crank pin's load
|(t_Σ, z_Σ + c_r)| with c_r = −m_rR R ω²/F_p of those rod masses alone.
"""

from __future__ import annotations

import functools
import math
import re

import numpy as np
import pytest

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.scene.model import scene_from_dict

V12 = {
    "engine": {
        "name": "V12 diesel, articulated rods",
        "strokes": 4,
        "cylinders": 12,
        "layout": "V",
        "bank_angle_deg": 60,
        "rod_type": "articulated",
        "rpm": 2000,
        "bore": "150 mm",
        "stroke": "180 mm",
        "rod_length": "320 mm",
        "cylinder_spacing": "190 mm",
    },
    "masses": {
        "piston_group": "4.1 kg",
        "rod": "6.2 kg",
        "rod_cm_fraction": 0.30,
        "crank_pin": "3.9 kg",
        "crank_web": "3.1 kg",
    },
    "cycle": {
        "ignition": "diesel",
        "compression_ratio": 15.0,
        "intake_pressure": "0.14 MPa",
        "compression_index": 1.36,
        "max_pressure": "10.5 MPa",
        "pre_expansion_ratio": 1.35,
        "expansion_index": 1.24,
        "exhaust_pressure": "0.16 MPa",
    },
    "articulated": {"pin_radius": "62 mm", "slave_rod": "4.8 kg", "slave_rod_cm_fraction": 0.45},
    "analysis": {"stages": ["bearings", "balancing"]},
}

OMEGA = 2000 * math.pi / 30
R, L, AREA = 0.09, 0.32, math.pi * 0.15**2 / 4
#: master rod's rotating part + the slave rod's share at the big end (γ₁ = γ = 60°)
RODS_KG = 6.2 * (1 - 0.30) + 4.8 * (1 - 0.45) * (1 - 0.062 * math.cos(math.radians(60)) / L)
THROW_KG = RODS_KG + 3.9 + 2 * 3.1


@functools.cache
def v12_run(language: str = "ru"):
    data = {**V12, "report": {"language": language}}
    return run_scene(scene_from_dict(data, base_dir=examples_dir()), default_registry())


@functools.cache
def v12_html(language: str = "ru") -> str:
    return render_html(v12_run(language), default_registry(), language).linked_html


def v12_text(language: str = "ru") -> str:
    text = re.sub(r"<[^>]+>", "", v12_html(language))
    return text.replace("\xa0", " ").replace("\u202f", " ").replace("\u2060", "")


def number(text: str) -> float:
    return float(text.replace(" ", "").replace(",", ".").replace("−", "-"))


def conclusions(language: str = "ru") -> str:
    html = v12_html(language)
    part = html[html.index('<ol class="conclusions">') :]
    return re.sub(r"<[^>]+>", "", part).replace("\xa0", " ").replace("\u202f", " ")


def test_the_crank_pin_load_is_the_master_rods_with_the_rods_centrifugal_force_only():
    run = v12_run()
    bay = run.outputs["bays"].tables.arrays("bay")
    c_rod = -RODS_KG * R * OMEGA**2 / AREA
    expected = np.hypot(bay["bay_tangential_Pa"], bay["bay_radial_Pa"] + c_rod)
    assert bay["pin_load_Pa"] == pytest.approx(expected, rel=1e-9)
    # the same load the bearings section draws and tabulates for crank pin 1
    pin = run.outputs["bearings"].results["crank_pins"][0]
    assert pin["max_N"] == pytest.approx(expected.max() * AREA, rel=1e-9)
    c_throw = -THROW_KG * R * OMEGA**2 / AREA
    assert run.outputs["bays"].results["centrifugal_Pa"] == pytest.approx(c_throw, rel=1e-9)


def test_the_conclusions_cite_one_crank_pin_load_in_both_places():
    """The bays' conclusion (MPa and kN, angle) and the bearings' one (kN) give the same load."""
    run = v12_run()
    bay = run.outputs["bays"].tables.arrays("bay")
    peak = int(np.argmax(bay["pin_load_Pa"]))
    said = conclusions()
    found = re.search(
        r"шатунную шейку qш\.ш = ([\d,]+) МПа \(([\d,]+) кН\) при α = ([\d,]+)°", said
    )
    assert found, said
    assert number(found.group(1)) == pytest.approx(bay["pin_load_Pa"][peak] / 1e6, abs=6e-4)
    kn = number(found.group(2))
    assert kn == pytest.approx(bay["pin_load_Pa"][peak] * AREA / 1e3, abs=6e-3)
    assert number(found.group(3)) == pytest.approx(bay["crank_angle_deg"][peak], abs=0.05)
    bearings = re.search(r"одинакова \(лишь сдвинута по фазе\): до ([\d,]+) кН", said)
    assert bearings and number(bearings.group(1)) == kn
    assert "нагружают все цилиндры колена" not in said
    assert "только главный шатун" in said


def test_the_throws_centrifugal_force_has_its_own_symbol_and_value():
    text = v12_text()
    c_throw = -THROW_KG * R * OMEGA**2 / AREA / 1e6
    found = re.search(r"cΣ = −mR Rω²/Fп = (−[\d,]+) МПа", text)
    assert found and number(found.group(1)) == pytest.approx(c_throw, abs=6e-4)
    forces_kg = re.search(r"а не масса ([\d,]+) кг одного цилиндра", text)
    assert forces_kg and number(forces_kg.group(1)) == pytest.approx(
        THROW_KG - 2.64 * 0.903125, abs=6e-3
    )


def test_only_the_master_rod_is_said_to_bear_on_the_crank_pin():
    text = v12_text()
    assert "несколько шатунов" not in text
    assert "На шатунную шейку действует только главный шатун" in text
    assert "главный и прицепные шатуны" not in text.replace("с главным и прицепными", "")
    assert "шатуны: главный и прицепные." in text


def test_the_slave_pin_taken_as_zero_is_said_and_listed_with_the_values_taken():
    text = v12_text()
    taken = text[text.index("Принятые величины") :]
    assert "Масса пальца прицепного шатуна" in taken[: taken.index("Кинематика")]
    given_table = text[: text.index("Принятые величины")]
    assert "Масса пальца прицепного шатуна" not in given_table.split("Исходные данные")[-1]
    assert "Масса пальца прицепного шатуна в задании не указана и принята равной нулю" in text
    given = {**V12, "articulated": {**V12["articulated"], "slave_pin": "0.7 kg"}}
    run = run_scene(scene_from_dict(given, base_dir=examples_dir()), default_registry(), ["bays"])
    html = render_html(run, default_registry(), "ru").linked_html
    assert "не указана и принята равной нулю" not in html
    assert "Масса пальца прицепного шатуна</td>" in html and "(не задана, принята" not in html
    terms = run.outputs["bays"].results["rotating_mass_terms"]
    assert terms["rods_kg"] == pytest.approx(RODS_KG + 0.7 * 0.903125, rel=1e-12)


def test_bank_letters_are_the_reports_in_the_slave_table_caption():
    text = v12_text()
    assert "прицепного цилиндра 1П)" in text and "прицепного цилиндра 1R" not in text
    data = {**V12, "report": {"language": "uk"}}
    run = run_scene(scene_from_dict(data, base_dir=examples_dir()), default_registry(), ["bays"])
    assert "причіпного циліндра 1П)" in render_html(run, default_registry(), "uk").linked_html


def test_the_slave_rod_table_prints_no_padding_zeros():
    html = v12_html()
    table = html[html.index("Прицепные шатуны</caption>") :]
    cells = re.findall(r"<td[^>]*>([^<]*)</td>", table[: table.index("</table>")])
    length = v12_run().outputs["bays"].results["slaves"][0]["slave_rod_length_m"]
    assert cells[:4] == ["1П", "60", "60", f"{length * 1e3:.2f}".replace(".", ",")]


def test_the_second_order_check_multiplies_out_as_printed():
    text = v12_text()
    found = re.search(r"CII = λCI = ([\d,]+)·([\d ]+) = ([\d ]+) Н", text)
    assert found, text
    lam, c1, c2 = (number(found.group(k)) for k in (1, 2, 3))
    assert lam == 0.28125  # R/L = 90/320 exactly
    assert round(lam * c1) == c2


def test_the_mean_torque_gap_of_the_slave_cylinders_is_explained_with_its_numbers():
    run = v12_run()
    torque = run.outputs["torque"].results
    master = run.outputs["indicator"].results["indicated_work_J"]
    slave = (run.outputs["bays"].results["indicated_work_J"] - 6 * master) / 6
    text = v12_text()
    found = re.search(
        r"Средний момент двигателя ([\d ]+) Н·м не равен 12·([\d,]+) = ([\d ]+) Н·м.*?"
        r"работу ([\d ]+) Дж вместо ([\d ]+) Дж главного \(больше на ([\d,]+) %\)",
        text,
    )
    assert found, text
    assert number(found.group(1)) == round(torque["mean_Nm"])
    assert number(found.group(2)) == pytest.approx(master / (4 * math.pi), abs=0.06)
    # the product printed is the product of the printed factors
    assert number(found.group(3)) == round(12 * number(found.group(2)))
    assert number(found.group(4)) == round(slave) and number(found.group(5)) == round(master)
    assert number(found.group(6)) == pytest.approx(100 * (slave / master - 1), abs=6e-3)
    # the engine's mean is the masters' and the slaves' together
    assert torque["mean_Nm"] == pytest.approx(6 * (master + slave) / (4 * math.pi), rel=1e-3)


def test_central_rods_have_no_slave_work_sentence():
    from conftest import shared_html, shared_run

    assert "slave_work" not in shared_run("v8-petrol").outputs["torque"].results
    html = shared_html("v8-petrol", language="ru").linked_html
    assert "прицепн" not in html


def test_the_torque_period_note_follows_the_engine():
    """The bays of a V12 repeat every 120° though the slaves' dead centres are shifted."""
    run = v12_run()
    assert run.outputs["torque"].results["period_deg"] == 120
    text = v12_text()
    assert "повторяется лишь через весь цикл" not in text
    assert "Крутящий момент тем не менее повторяется через 120°" in text


def test_a_v_engine_needing_no_means_prints_no_means_text():
    text = v12_text()
    section = text[text.index("Уравновешенность сил и моментов и средства") :]
    section = section[: section.index("Полярные диаграммы нагрузок")]
    # several cranks: only the free forces need no means; counterweights may still unload journals
    assert "Свободные силы и моменты двигателя средств уравновешивания не требуют" in section
    assert "Средства уравновешивания не требуются" not in section
    for generic in (
        "Уравновешивающий вал несёт",
        "Массы определены для выбранных",
        "При добавлении этих",
    ):
        assert generic not in section
    assert "однорядного двигателя" not in text


def test_the_negligible_remainder_gives_its_share_and_the_approximation():
    run = v12_run()
    b = run.outputs["balancing"].results
    share = 100 * b["absolute"]["sum_PVI_N"] / b["first_order_N"]
    said = conclusions()
    found = re.search(r"не более ([\d,]+) % амплитуды силы инерции первого порядка", said)
    assert found and number(found.group(1)) == pytest.approx(share, rel=0.05)
    assert "менее 1 %" not in said
    # the balance rests on each cylinder's own reciprocating mass, the slaves' 6,260 kg
    assert "с собственной массой каждого цилиндра" in said and "6,260 кг" in said


def test_a_chosen_firing_order_is_noted_in_the_reports_bank_letters():
    text = v12_text()
    order = v12_run().outputs["bays"].results["firing_order"]
    assert "–".join(order) not in text  # Latin "1L–6R–…"
    printed = "–".join(label.replace("L", "Л").replace("R", "П") for label in order)
    assert f"Порядок работы цилиндров {printed} и схема колен" in text


def test_a_v_engines_slave_piston_has_the_smaller_second_harmonic_and_the_note_says_so():
    """The note printed the master's A_2 as the slave's (a maximum taken over every cylinder,
    the masters included) and called it larger. With the pin at the bank angle (γ₁ = γ = 60°),
    R = 90 mm, L = 320 mm and r_p = 68 mm a V engine's slave piston has |A_2| = 0.2562, by an
    independent linkage calculation, against the master's 0.2870; a radial's slaves exceed it."""
    data = {
        **V12,
        "articulated": {**V12["articulated"], "pin_radius": "68 mm"},
        "analysis": {"stages": ["balancing"]},
        "report": {"language": "ru"},
    }
    run = run_scene(scene_from_dict(data, base_dir=examples_dir()), default_registry())
    r = run.outputs["balancing"].results
    assert r["slave_second_harmonic_max"] == pytest.approx(0.2562, abs=5e-4)
    assert r["acceleration_harmonics"]["II"] == pytest.approx(0.2870, abs=5e-4)
    text = re.sub(r"<[^>]+>", "", render_html(run, default_registry(), "ru").linked_html)
    text = text.replace("\u2060", "").replace("\xa0", " ")
    assert "вторая меньше: |A2| = 0,2562 против A2 = 0,2870 у главного" in text
    assert "имеет меньшую вторую гармонику" in text
    from conftest import shared_run

    radial = shared_run("radial9-aircraft", None, ("balancing",)).outputs["balancing"].results
    assert radial["slave_second_harmonic_max"] > radial["acceleration_harmonics"]["II"]


def test_a_v_engines_scheme_describes_its_one_slave_rod_per_master():
    """A V engine's master rod carries one slave rod, all alike: the scheme's text named "one of
    the slave rods" and their slightly different lengths, as a radial's."""
    data = {**V12, "analysis": {"stages": ["drawing"]}, "report": {"language": "ru"}}
    run = run_scene(scene_from_dict(data, base_dir=examples_dir()), default_registry())
    text = re.sub(r"<[^>]+>", "", render_html(run, default_registry(), "ru").linked_html)
    assert "Главный шатун вместе с пальцем прицепного шатуна является одним звеном" in text
    assert "одного из прицепных шатунов" not in text and "различаются по длине" not in text


def test_a_knuckle_pin_off_the_bank_angle_fails_the_check_and_the_note_says_so():
    """With γ₁ ≠ γ the slave pistons move unsymmetrically and have odd harmonics, which the
    orders of the central crank-slider leave out: the direct sum of the real forces then leaves
    more than the vector method, and the note concluded "balanced" with no word of the failed
    check. The console warns, naming the pin angle, and the conclusions qualify the balance; at
    the bank angle itself the check passes and nothing is said."""
    from crankdyn.report.plausibility import console_lines, warnings

    registry = default_registry()
    for pin_angle, fails in ((69, True), (60, False)):
        data = {
            **V12,
            "articulated": {**V12["articulated"], "pin_angle_deg": pin_angle},
            "analysis": {"stages": ["balancing"]},
            "report": {"language": "en"},
        }
        run = run_scene(scene_from_dict(data, base_dir=examples_dir()), registry)
        assert run.outputs["balancing"].results["residual"]["vanishes"] is not fails
        lines = console_lines(warnings(run.scene, registry, run), registry)
        assert any("Check articulated.pin_angle_deg" in line for line in lines) is fails
        text = re.sub(r"<[^>]+>", "", render_html(run, registry, "en").linked_html)
        said = "so the balance stated above holds for the analysed orders only" in text
        assert said is fails


def test_the_slave_work_sentence_is_left_out_where_the_printed_torques_agree():
    """ "The mean torque 2906 N·m is not 12·242.2 = 2906 N·m" would contradict itself: where the
    printed product equals the printed mean (a slave's work within the print's resolution of
    the master's), the sentence is left out."""
    import copy
    from html import unescape

    run = copy.deepcopy(v12_run("en"))
    torque = run.outputs["torque"].results
    torque["slave_work"]["master_torque_Nm"] = torque["mean_Nm"] / 12 * (1 + 1e-6)
    text = unescape(re.sub(r"<[^>]+>", "", render_html(run, default_registry(), "en").linked_html))
    assert "the number of cylinders times one master cylinder's mean torque" not in text
    assert "the number of cylinders times one master cylinder's mean torque" in unescape(
        v12_text("en")
    )


def test_the_given_data_name_the_master_rods_mass():
    """With articulated rods the "connecting rod" of the given data is the master rod (the slave
    rod has rows of its own)."""
    text = v12_text()
    assert "Масса главного шатуна" in text and "Масса шатуна" not in text
    assert "до центра масс главного шатуна" in text


def test_one_slave_rod_on_a_pin_is_named_in_the_singular_and_its_master_bearing_carries_both():
    """A V12's pin carries one master and one slave rod: the master rod's rotating part takes the
    share of the slave rod and its pin (singular), and Q of a big-end bearing is the pin's whole
    load (the master rod's bearing carries the slave rod's force), not one rod's own."""
    text = v12_text()
    assert "вместе с долей прицепного шатуна и его пальца" in text
    assert "долями прицепных шатунов и их пальцев" not in text
    assert "для шатунного подшипника – сила только его шатуна" not in text
    assert "наибольшая за цикл сила, нагружающая шатунную шейку" in text


def test_a_torque_period_longer_than_the_firing_interval_is_explained():
    """Twelve cylinders fire every 60°, but the torque repeats every 120°: the slave cylinders
    differ from the master ones, and the note says so."""
    r = v12_run().outputs["torque"].results
    assert r["period_deg"] == pytest.approx(2 * r["period_even_firing_deg"])
    text = v12_text()
    assert "Период крутящего момента – 120°, а не 60°" in text
    assert "прицепные цилиндры отличаются от главных" in text


def test_a_radials_torque_period_names_its_one_master_cylinder():
    """A single-row radial has one master cylinder: its slaves differ "from the master one"."""
    import re

    from conftest import shared_html, shared_run

    r = shared_run("radial9-aircraft").outputs["torque"].results
    html = shared_html("radial9-aircraft", None, "ru").linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", html).split())
    assert r["period_deg"] > r["period_even_firing_deg"]  # 720° against 80°
    assert "прицепные цилиндры отличаются от главного (" in text
    assert "отличаются от главных" not in text


def test_a_v_engines_shaft_angle_is_counted_from_the_first_cylinders_tdc():
    """The vector method's θ: the i-th cylinder reaches TDC at θ = ξ_i, ξ_1 = 0, so θ counts from
    the first cylinder's TDC in a V as in an in-line engine (it was said to count "from the
    vertical", which is 45° off in a 90° V). The method's own geometry of a 90° V-twin: ξ_1 = 0,
    ξ_2 = 90°."""
    import numpy as np
    from conftest import V_TWIN_ENGINE, shared_html

    from crankdyn.physics import balancing as bal

    g = bal.geometry([0.0, 90.0], [0, 0], [0.0], bal.vertical_axis_deg("V", 90.0))
    assert np.degrees(g.cylinder_phase_rad) == pytest.approx([0.0, 90.0])  # ξ_1 = 0, ξ_2 = 90°
    text = shared_html("v8-petrol", {"engine": V_TWIN_ENGINE}, "en").linked_html
    assert "crankshaft angle from the TDC of the first cylinder" in text
    assert "measured from the vertical (that of the first crank)" not in text


def test_the_pins_centrifugal_force_is_the_master_rods_with_its_slaves_shares():
    """Only the master rod acts on the crank pin of articulated rods: c_r is the centrifugal force
    of its rotating part with the slave rods' shares, not "of all the rods on the pin"."""

    from conftest import shared_html

    html = shared_html("radial9-aircraft", None, "ru").linked_html
    from conftest import symbol_rows

    rows = symbol_rows(html)
    said = [row for row in rows if row.startswith("cr – ")]
    assert said and said[0].startswith(
        "cr – удельная центробежная сила вращающейся части главного шатуна с долями прицепных"
    )
    assert "всех шатунов шейки" not in html
