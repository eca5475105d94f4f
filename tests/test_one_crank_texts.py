"""Engines of one crank: a five-cylinder single-row radial with master and slave rods (ru) and a
45° V-twin with its rods side by side on the pin (uk). Their notes speak of the one crank and
its cylinders (no crank arrangement, no bays), the list of symbols gives each symbol one
meaning, the conclusions give the crank's load of all its cylinders and the abstract names what
the balancing means leave with the values.

Independent reference, written here from the scene's data: the radial's rotating mass of the
crank m_R = m_cp + 2 m_w + m_rod (1 − κ) + m_sr (1 − κ_s) Σ(1 − r cos γ₁/L) over the four slave
pins at γ₁ = 72°, 144°, 216°, 288° (Poda 2007, fig. 9); C_I = m_s R ω²; the fourth harmonic of
the piston acceleration A_4 = −(λ³/4 + 3λ⁵/16) (its series) and ΣP_IV = (i/2)|A_4| C_I of a
five-cylinder star (1 + 4 ≡ 0 mod 5).
"""

from __future__ import annotations

import functools
import math
import re
from collections import Counter

import numpy as np
import pytest

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.scene.model import scene_from_dict

RADIAL = {
    "report": {"language": "ru"},
    "engine": {
        "name": "Звездообразный двигатель 5Ч 12,5/14",
        "application": "aircraft",
        "strokes": 4,
        "cylinders": 5,
        "layout": "radial",
        "rod_type": "articulated",
        "rpm": 1700,
        "bore": "125 mm",
        "stroke": "140 mm",
        "rod_length": "255 mm",
    },
    "masses": {
        "piston_group": "1.8 kg",
        "rod": "3.6 kg",
        "rod_cm_fraction": 0.24,
        "crank_pin": "2.2 kg",
        "crank_web": "1.6 kg",
    },
    "articulated": {"pin_radius": "55 mm", "slave_rod": "0.9 kg", "slave_rod_cm_fraction": 0.45},
    "cycle": {
        "ignition": "spark",
        "compression_ratio": 5.0,
        "intake_pressure": "0.093 MPa",
        "compression_index": 1.34,
        "max_pressure": "3.6 MPa",
        "expansion_index": 1.24,
        "exhaust_pressure": "0.11 MPa",
    },
}

V_TWIN = {
    "report": {"language": "uk"},
    "engine": {
        "name": "Мотоциклетний двигун 2Ч 8,8/9,6",
        "application": "motorcycle",
        "strokes": 4,
        "cylinders": 2,
        "layout": "V",
        "bank_angle_deg": 45,
        "crank_angles_deg": [0],
        "firing_order": ["1L", "1R"],
        "uneven_firing": True,
        "rpm": 5500,
        "bore": "88 mm",
        "stroke": "96 mm",
        "rod_length": "170 mm",
    },
    "masses": {
        "piston_group": "0.55 kg",
        "rod": "0.62 kg",
        "rod_cm_fraction": 0.27,
        "crank_pin": "0.40 kg",
        "crank_web": "0.55 kg",
    },
    "cycle": {
        "ignition": "spark",
        "compression_ratio": 9.5,
        "intake_pressure": "0.092 MPa",
        "compression_index": 1.36,
        "max_pressure": "6.6 MPa",
        "expansion_index": 1.25,
        "exhaust_pressure": "0.115 MPa",
    },
    # the second order too: a V-twin's two second-order shafts carry unequal counterweights
    "balancing": {"balance_orders": [1, 2]},
}

OMEGA = 1700 * math.pi / 30
R, L, AREA = 0.070, 0.255, math.pi * 0.125**2 / 4
LAMBDA = R / L
SLAVE_LEVERS = sum(1 - 0.055 * math.cos(math.radians(72 * k)) / L for k in range(1, 5))
ROTATING_KG = 2.2 + 2 * 1.6 + 3.6 * (1 - 0.24) + 0.9 * (1 - 0.45) * SLAVE_LEVERS
FIRST_ORDER_N = (1.8 + 3.6 * 0.24) * R * OMEGA**2


@functools.cache
def _run(name: str):
    data = {"radial": RADIAL, "vtwin": V_TWIN}[name]
    return run_scene(scene_from_dict(data, base_dir=examples_dir()), default_registry())


@functools.cache
def _html(name: str) -> str:
    run = _run(name)
    return render_html(run, default_registry(), run.scene.report.language).linked_html


def _plain(html: str) -> str:
    text = re.sub(r"<[^>]+>", "", html)
    return " ".join(text.replace("\xa0", " ").replace("\u202f", " ").replace("\u2060", "").split())


def _part(name: str, start: str, end: str | None = None) -> str:
    html = _html(name)
    head = html.index(start)
    return html[head : html.index(end, head) if end else len(html)]


def _number(text: str) -> float:
    return float(text.replace(" ", "").replace(",", ".").replace("−", "-"))


@pytest.mark.parametrize(
    ("name", "words"),
    [
        (
            "radial",
            (
                "схема колен",
                "схемой колен",
                "схеме колен",
                "Для каждого колена",
                "на колена вала",
                "коленам вала",
                "Колена цилиндров",
                "отсек",
                "Угол колена (отставание",
            ),
        ),
        (
            "vtwin",
            (
                "схема колін",
                "схеми колін",
                "Для кожного коліна",
                "на коліна вала",
                "колінам вала",
                "Коліна циліндрів",
                "відсі",
                "Кут коліна (відставання",
                "поздовжніх моментів цих сил немає",
            ),
        ),
    ],
)
def test_a_one_crank_note_has_no_crank_arrangement_and_no_bays(name, words):
    text = _plain(_html(name))
    assert [w for w in words if w in text] == []


def test_the_one_crank_texts_speak_of_the_crank_and_its_cylinders():
    radial = _plain(_html("radial"))
    assert "6 Схема двигателя и силы, действующие на шатунную шейку" in radial
    assert "силы, действующие на шатунные шейки" not in radial
    assert "Таблица 7.2 – Наиболее опасные сочетания сил, действующих на колено вала" in radial
    assert "Силы всех цилиндров, действующие на шатунную шейку" in radial
    assert "Сдвиги рабочих циклов цилиндров (в порядке работы)" in radial
    twin = _plain(_html("vtwin"))
    assert "в циліндрів на одному коліні за кута розвалу 45°" in twin
    # the rods side by side on the pin: a small couple, neglected, not "no moments"
    assert "шатуни, що працюють поруч на одній шийці, зсувають їх уздовж вала" in twin
    assert "а моменти від цього зсуву наведено після таблиці сил" in twin


@pytest.mark.parametrize("name", ["radial", "vtwin"])
def test_each_symbol_of_the_list_has_one_meaning(name):
    rows = re.findall(r'<p class="symbol-row"><span class="symbol">(.*?)</span>', _html(name))
    assert [markup for markup, n in Counter(rows).items() if n > 1] == []
    listed = [_plain(row) for row in re.findall(r'<p class="symbol-row">(.*?)</p>', _html(name))]
    # c is one cylinder's centrifugal force: the crank's with all the rods is c_Σ
    meaning = {"radial": "шатуна одного цилиндра", "vtwin": "шатуна одного циліндра"}[name]
    c = [row for row in listed if row.startswith("c – ")]
    assert len(c) == 1 and meaning in c[0], c


def test_the_slave_rod_length_has_its_own_letter():
    rows = re.findall(r'<p class="symbol-row">(.*?)</p>', _html("radial"))
    rows = [_plain(row) for row in rows]
    assert "lп.ш – длина прицепного шатуна, мм (в формулах – м)" in rows
    assert not [row for row in rows if row.startswith("l – ")]
    assert "(R/lп.ш) sin αl − (r/lп.ш) sin(β − φ)" in _plain(_html("radial"))


def test_the_running_torque_of_a_crank_is_in_the_list_of_an_engine_of_several_cranks():
    """Table B.4's |t_k| has its entry; one crank's journal carries t_Σ = t, the crank's own, so
    its table B.4 has neither a row of the largest |t_Σ| nor a column t_Σ (they repeat t's)."""
    from conftest import shared_html

    v8 = shared_html("v8-petrol", None, "ru").linked_html
    listed = _plain(v8[v8.index('<div class="symbol-list">') :])
    assert "tk – удельный набегающий момент на коренной шейке за коленом" in listed
    assert "|tk|" in _plain(v8)
    radial = _html("radial")
    start = radial.index("Наиболее опасные сочетания сил, действующих на колено вала")
    table = radial[start : radial.index("</table>", start)]
    assert "<th>Экстремальное значение</th>" in table
    assert "t</i><sub>Σ</sub>" not in table and "|t_Σ|" not in table
    # the header, z and t at their largest and least, q at its largest
    assert len(re.findall(r"<tr[ >]", table)) == 6


def test_the_conclusions_give_the_crank_load_of_all_its_cylinders():
    torque = _run("radial").outputs["torque"].tables.arrays("torque")
    c_sum = -ROTATING_KG * R * OMEGA**2 / AREA
    q = np.hypot(torque["crank1_tangential_Pa"], torque["crank1_radial_Pa"] + c_sum)
    peak = int(np.argmax(q))
    said = _plain(_part("radial", '<ol class="conclusions">'))
    found = re.search(
        r"Наибольшая удельная результирующая нагрузка на колено от всех его цилиндров \([^)]*\) "
        r"q = ([\d,]+) МПа при α = (\d+)° \(табл\. 7\.2\)",
        said,
    )
    assert found, said
    assert _number(found.group(1)) == pytest.approx(q[peak] / 1e6, abs=6e-4)
    assert int(found.group(2)) == round(torque["crank_angle_deg"][peak])
    # one cylinder's load on the crank with one rod's centrifugal force is no result of the engine
    assert "только этого цилиндра" not in said and "От сил одного цилиндра" not in said


def test_the_abstract_names_what_the_means_leave_in_one_sentence():
    abstract = _plain(_part("radial", '<section class="abstract"', "</section>"))
    found = re.search(
        r"после установки средств уравновешивания неуравновешенной остаётся "
        r"ΣPIV = ([\d,]+) Н \(([\d,]+) % от CI\), а также ΣPVI = ([\d,]+) Н – пренебрежимо "
        r"малая величина \(([\d,]+) % от CI\)",
        abstract,
    )
    assert found, abstract
    fourth_text, fourth_share, sixth_text, sixth_share = (_number(g) for g in found.groups())
    # the amplitudes are the balancing's (each cylinder's own mass and motion, checked against
    # a direct sum in tests/test_articulated_slave_cycle.py); the shares are of the master's C_I
    b = _run("radial").outputs["balancing"].results
    first_order = b["first_order_N"]
    assert first_order < FIRST_ORDER_N  # the slave rods' shares lighten the master's piston pin
    fourth, sixth = b["absolute"]["sum_PIV_N"], b["absolute"]["sum_PVI_N"]
    assert fourth_text == pytest.approx(fourth, abs=0.5)
    assert fourth_share == pytest.approx(100 * fourth / first_order, rel=0.04)
    assert sixth_text == pytest.approx(sixth, rel=0.05)
    assert sixth_share == pytest.approx(100 * sixth / first_order, rel=0.1)
    assert "остаются лишь малые" not in abstract and "остаётся величина" not in abstract
    # not "only": the slave cylinders leave the parts of the first and second orders too
    assert "остаются лишь" not in abstract
    assert "прицепные цилиндры оставляют также составляющую сил первого порядка" in abstract


def test_the_v_twins_side_force_step_and_shafts_are_worded_as_an_engineer_writes():
    text = _plain(_html("vtwin"))
    # the side force is N (n is the crank speed)
    assert "найбільша за модулем бокова сила N" in text and "бокова сила n" not in text
    # a default step at its limit is not "the largest step not above 1°"
    assert "Крок за кутом Δα = 1° вибрано в цьому розрахунку: він ціле число разів" in text
    assert "найбільший крок, не більший за 1°" not in text
    # the second-order shafts of a V-twin carry unequal counterweights: no Lanchester pair
    shafts = _run("vtwin").outputs["balancing"].results["balance_shafts"]
    second = [s["masses"][0]["mass_radius_kg_m"] for s in shafts if s["order"] == 2]
    assert len(second) == 2 and not math.isclose(*second, rel_tol=1e-3)
    assert "два зрівноважувальні вали з різними противагами" in text
    assert "Ланчестера" not in _plain(_part("vtwin", "Таблиця 8.4", "</table>"))


def test_an_equal_pair_of_shafts_is_still_lanchesters():
    """An in-line four's second-order pair is Lanchester's balancer; a single cylinder's
    first-order pair (a shaft each way at the crank's speed) is not."""
    from conftest import shared_html

    text = _plain(shared_html("inline4-petrol", None, "uk").linked_html)
    assert "(механізм Ланчестера)" in text
    first = {"balancing": {"first_order_forward": "shaft"}}
    single = _plain(shared_html("petrol-1cyl-uk", first, "uk", ("balancing",)).linked_html)
    assert "два зрівноважувальні вали, що обертаються в протилежних напрямках" in single
    assert "Ланчестера" not in single


def test_a_radials_conclusions_give_the_master_cylinders_side_force_with_the_slave_rods():
    """The side force a conclusion names is the master cylinder's N_Σ with the slave rods'
    thrust (the bay table's extreme, a row of it), not one cylinder's N without them."""
    bay = _run("radial").outputs["bays"].tables.arrays("bay")
    side = bay["master_side_Pa"]
    peak = side[np.argmax(np.abs(side))] / 1e6
    text = _plain(_html("radial"))
    assert f"с учётом прицепных шатунов NΣ = {peak:.3f}".replace(".", ",").replace("-", "−") in text
    assert "боковая сила на стенку цилиндра N =" not in text
