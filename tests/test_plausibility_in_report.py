"""Values no real engine has, said in the note: a sentence in the section of the quantity and one
in the conclusions, in the note's language, with the source of an allowable value cited [n]."""

from __future__ import annotations

import html as html_lib
import re

import pytest
from conftest import modified

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.report.i18n import translator
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()


def _plain(markup: str) -> str:
    text = html_lib.unescape(re.sub(r"<[^>]+>", " ", markup))
    for space in ("\u00a0", "\u202f"):  # the report keeps numbers on the line of their unit
        text = text.replace(space, " ")
    return " ".join(text.replace("\u2060", "").split())


class Note:
    """The note of an example with ``changes``, only the stages up to ``stages`` run."""

    def __init__(self, example: str, changes: dict, stages: tuple[str, ...], language: str):
        scene = scene_from_dict(modified(example, changes), base_dir=examples_dir())
        self.result = run_scene(scene, REGISTRY, requested=stages)
        self.html = render_html(self.result, REGISTRY, language).linked_html
        self.t = translator(language, REGISTRY.catalogs)

    def section(self, stage: str) -> str:
        start = self.html.index(f'data-stage="{stage}"')
        return _plain(self.html[start : self.html.index("</section>", start)])

    @property
    def conclusions(self) -> str:
        start = self.html.index('<ol class="conclusions">')
        return _plain(self.html[start : self.html.index("</ol>", start)])

    @property
    def references(self) -> list[str]:
        block = re.search(r'<ol class="references">(.*?)</ol>', self.html, flags=re.S).group(1)
        return [_plain(item) for item in re.findall(r"<li>(.*?)</li>", block, flags=re.S)]

    def cited(self, text: str) -> str:
        """The reference a "[n]" at the end of a range in ``text`` names."""
        number = int(re.search(r"\[(\d+)\]", text).group(1))
        return self.references[number - 1]


def test_a_mechanical_efficiency_above_0_95_is_said_in_the_torque_section_and_the_conclusions():
    # 55 kW of the example give eta_m = 0.833; 64 kW of the same indicated power give 0.969
    high = Note("inline4-petrol", {"engine": {"effective_power": "64 kW"}}, ("torque",), "uk")
    eta = high.result.outputs["torque"].results["mechanical_efficiency"]
    assert eta == pytest.approx(0.833 * 64 / 55, rel=2e-3) and eta > 0.95
    section = high.section("torque")
    assert f"Механічний ККД η м = {eta:.3f}".replace(".", ",") in section
    assert "перевищує 0,95" in section and "η м = 0,7–0,9 [" in section
    cited = high.cited(section[section.index("перевищує 0,95") :])
    assert cited.startswith("Колчин А. И., Демидов В. П.")
    assert high.t("plausibility.mechanical_efficiency_conclusion") in high.conclusions
    usual = Note("inline4-petrol", {}, ("torque",), "uk")
    assert "перевищує 0,95" not in usual.section("torque")
    assert usual.t("plausibility.mechanical_efficiency_conclusion") not in usual.conclusions


def test_a_mechanical_efficiency_below_0_60_is_said_in_the_torque_section_and_the_conclusions():
    # 55 kW of the example give eta_m = 0.833; 35 kW of the same indicated power give 0.530
    low = Note("inline4-petrol", {"engine": {"effective_power": "35 kW"}}, ("torque",), "ru")
    eta = low.result.outputs["torque"].results["mechanical_efficiency"]
    assert eta == pytest.approx(0.833 * 35 / 55, rel=2e-3) and eta < 0.60
    section = low.section("torque")
    assert "ниже 0,6" in section and "η м = 0,7–0,9 [" in section
    assert low.t("plausibility.mechanical_efficiency_low_conclusion") in low.conclusions
    usual = Note("inline4-petrol", {}, ("torque",), "ru")
    assert "ниже 0,6" not in usual.section("torque")


def test_a_crank_pin_pressure_above_the_allowable_one_is_compared_with_the_textbooks_values():
    # the example's pin: mean about 6.2 MPa, largest 10.2 MPa against 12 and 20 MPa of petrol
    # engines; a pin 12 mm wide instead of 31 mm carries 31/12 times the pressure
    narrow = Note("inline4-petrol", {"bearings": {"crank_pin_width": "12 mm"}}, ("bearings",), "ru")
    pins = narrow.result.outputs["bearings"].results["crank_pins"]
    p_mean = max(pin["mean_MPa"] for pin in pins)
    wide = Note("inline4-petrol", {}, ("bearings",), "ru").result.outputs["bearings"].results
    assert p_mean == pytest.approx(
        max(pin["mean_MPa"] for pin in wide["crank_pins"]) * 30.996 / 12, rel=1e-3
    )
    section = narrow.section("bearings")
    sentence = section[section.index("Среднее давление на шатунный подшипник достигает") :]
    assert f"достигает {p_mean:.3g}".replace(".", ",") in sentence
    assert (
        "для бензиновых двигателей допустимы среднее давление до 12 МПа и наибольшее до 20 МПа ["
    ) in sentence
    assert narrow.cited(sentence).startswith("Колчин А. И., Демидов В. П.")
    # the pin's diameter is not given: the verdict rests on an assumed size
    key = "bearings.plausibility_pin_pressure_spark_assumed_conclusion"
    assert narrow.t(key).split("d·B", 1)[0] in narrow.conclusions
    usual = Note("inline4-petrol", {}, ("bearings",), "ru")
    # a usual engine's pressures are said to be within the allowable ones, not above them
    pin_sentence = re.search(r"шатунный подшипник достигает [^.]*\.", usual.section("bearings"))
    assert "тогда как для бензиновых двигателей" not in pin_sentence.group(0)
    assert "в пределах значений, допустимых для бензиновых двигателей:" in usual.section("bearings")
    assert narrow.t(key).split("d·B", 1)[0] not in usual.conclusions


@pytest.mark.parametrize(
    ("changes", "widths"),
    [
        ({"engine": {"layout": "boxer", "cylinder_spacing": "56 mm"}}, "assumed"),
        (
            {"engine": {"cylinder_spacing": "60 mm"}, "bearings": {"crank_pin_width": "40 mm"}},
            "given",
        ),
        ({}, "fit"),
    ],
)
def test_journals_wider_than_the_crank_pitch_are_said_not_to_fit(changes, widths):
    """A main journal between every two cranks needs B_pin + B_main < a (the webs besides): the
    in-line 4's 31.0 + 25.8 mm fit its 92 mm; as a flat four 56 mm apart (the widths assumed
    from the bore) or with a 40 mm pin 60 mm apart (a width given) they do not, and the section
    and the conclusions say so with the sizes; the rule stays silent where they fit."""
    note = Note("inline4-petrol", changes, ("bearings",), "uk")
    sizes = note.result.outputs["bearings"].results["dimensions"]
    spacing = note.result.scene.engine.cylinder_spacing
    total = sizes["crank_pin_width_m"] + sizes["main_journal_width_m"]
    section = note.section("bearings")
    if widths == "fit":
        assert total < spacing
        assert "навіть без урахування двох щік" not in section
        return
    assert total > spacing
    said = f"{total * 1e3:.1f} мм – більше за крок колін".replace(".", ",")
    assert said in section
    assert ("Ширину шийок у завданні не вказано" in section) is (widths == "assumed")
    assert f"крок колін a = {spacing * 1e3:g} мм" in note.conclusions


def test_a_diesels_crank_pin_is_judged_by_the_diesels_allowable_pressures():
    # the diesel example's pin within 16 and 42 MPa; 10 mm wide it carries several times more
    narrow = Note("diesel-1cyl", {"bearings": {"crank_pin_width": "10 mm"}}, ("bearings",), "uk")
    section = narrow.section("bearings")
    assert "для дизелів допустимі середній тиск до 16 МПа і найбільший до 42 МПа [" in section
    conclusion = narrow.t("bearings.plausibility_pin_pressure_diesel_assumed_conclusion")
    assert conclusion.split("d·B", 1)[0] in narrow.conclusions
    # what the sizes must give, said as a condition on the pressure
    assert "щоб тиск не перевищував допустимого, потрібно d · B ≥" in narrow.conclusions
    usual = Note("diesel-1cyl", {}, ("bearings",), "uk")
    assert "для дизелів допустимі" not in usual.section("bearings")


def test_a_diesels_peak_pressure_outside_its_usual_range_is_said_in_the_indicator_section():
    # a diesel's p_z' = p_z: 22 MPa, above the 20 MPa of the most boosted diesels but below the
    # 25 MPa where the peak-pressure rule of every engine speaks
    high = Note("diesel-1cyl", {"cycle": {"max_pressure": "22 MPa"}}, ("indicator",), "en")
    peak = high.result.outputs["indicator"].results["peak_pressure_rounded_Pa"] / 1e6
    assert peak == pytest.approx(22.0, rel=1e-9)
    assert f"p z ′ = {peak:.3g} MPa lies outside 5–20 MPa" in high.section("indicator")
    assert high.t("indicator.plausibility_diesel_peak_conclusion") in high.conclusions
    usual = Note("diesel-1cyl", {}, ("indicator",), "en")  # p_z' = p_z = 8.5 MPa
    assert "usual range of diesels" not in usual.section("indicator") + usual.conclusions


@pytest.mark.parametrize(
    "changes, phrase, conclusion",
    [
        (
            {"engine": {"rpm": 20000}},
            "Середня швидкість поршня 52 м/с перевищує 25 м/с",
            "plausibility.piston_speed_conclusion",
        ),  # c_m = S n / 30 = 0.078 * 20000 / 30
        (
            {"engine": {"rod_ratio": 0.6}},
            "λ = 0,6 лежить поза межами 0,15–0,45",
            "plausibility.rod_ratio_conclusion",
        ),
    ],
)
def test_a_piston_speed_or_rod_ratio_outside_the_usual_range_is_said_with_the_given_data(
    changes, phrase, conclusion
):
    odd = Note("petrol-1cyl", changes, ("kinematics",), "uk")
    given = odd.section("input")
    assert phrase in given and odd.t(conclusion) in odd.conclusions
    assert "engine." not in given  # in the engineer's words, no input key
    usual = Note("petrol-1cyl", {}, ("kinematics",), "uk")
    given = usual.section("input")
    assert "лежить поза межами" not in given and "перевищує" not in given
    assert usual.t(conclusion) not in usual.conclusions


def test_a_fuller_diagram_than_the_usual_is_said_with_its_excess():
    """A diesel's rounded diagram with p_z' = p_z keeps more of the theoretical area than the
    actual cycle: φ_п above 0.95 is said, with the mean pressure's excess over φ_п = 0.95."""
    note = Note("diesel-1cyl", {}, ("indicator",), "ru")
    results = note.result.outputs["indicator"].results
    phi = results["diagram_fullness"]
    assert results["diagram_fullness_usual"] == [0.92, 0.95] and phi > 0.95
    excess = f"{100 * (phi / 0.95 - 1):.2g}".replace(".", ",")
    assert "Обычные значения для дизелей – 0,92…0,95" in note.section("indicator")
    assert f"получены до {excess} % больше, чем при φ" in note.section("indicator")


def test_a_given_mean_indicated_pressure_off_the_diagrams_is_warned_of_on_the_console():
    """The thermal calculation's p_i further than 3 % from the diagram's: the console warns (the
    student can still correct the data), and the note says it once, in its own check, with no
    plausibility sentence of its own."""
    from crankdyn.report.plausibility import console_lines, warnings

    # the example's diagram gives p_i = 1,230 MPa without the pumping strokes: 1,0 MPa is 19 %
    # off, 1,22 MPa within 1 %
    off = Note(
        "diesel-1cyl", {"cycle": {"mean_indicated_pressure": "1.0 MPa"}}, ("indicator",), "ru"
    )
    deviation = off.result.outputs["indicator"].results["mean_indicated_pressure_deviation_percent"]
    assert abs(deviation) > 3.0
    found = warnings(off.result.scene, REGISTRY, off.result)
    lines = console_lines(found, REGISTRY)
    assert any("cycle.mean_indicated_pressure" in line and "%" in line for line in lines), lines
    assert 'class="plausibility"' not in off.html
    check = off.t("indicator.check_bad", deviation="").split("{")[0][:40]
    assert off.conclusions.count(check) == 1
    within = Note(
        "diesel-1cyl", {"cycle": {"mean_indicated_pressure": "1.22 MPa"}}, ("indicator",), "ru"
    )
    assert within.result.outputs["indicator"].results["mean_indicated_pressure_deviation_percent"]
    assert not any(
        key == "indicator.plausibility_mean_pressure"
        for key, _ in warnings(within.result.scene, REGISTRY, within.result)
    )


@pytest.mark.parametrize(
    ("changes", "stages"),
    [
        ({"engine": {"stroke": "140 mm", "rpm": 3000}}, ("kinematics",)),  # S/D = 1.71: given data
        ({"engine": {"effective_power": "64 kW"}}, ("torque",)),  # η_m = 0.969: its own section
    ],
)
def test_a_plausibility_sentence_is_a_paragraph_not_its_markup_as_text(changes, stages):
    """The given data's sentences are joined to its markup as markup: a paragraph of class
    "plausibility", never "<p class=…>" printed in the note as text."""
    note = Note("inline4-petrol", changes, stages, "uk")
    assert note.html.count('<p class="plausibility">') == 1
    assert "&lt;p" not in note.html and "&lt;/" not in note.html
