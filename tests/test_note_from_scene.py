"""Every sentence of the note follows from its own scene: no number of another engine in the
catalogs' fixed sentences, the values the calculation takes in the table of values taken (not
among the task's data), the power take-off end and the journal proportions named after what the
engine is for, the extremes of a periodic speed at the first angle of the cycle everywhere."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest
from conftest import FLAT_FOUR_ENGINE, as_read, shared_html, shared_run

ROOT = Path(__file__).resolve().parents[1]


def _text(html: str) -> str:
    return as_read(re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html)))


def _tables_1(text: str, language: str) -> tuple[str, str]:
    """The text of table 1.1 (the task's data) and of table 1.2 (the values taken; "" where the
    task gives every value and the note has no such table)."""
    word = {"ru": "Таблица", "uk": "Таблиця", "en": "Table"}[language]
    given = text.index(f"{word} 1.1")
    if f"{word} 1.2" not in text:
        return text[given : text.index(f"{word} 2.1")], ""
    taken = text.index(f"{word} 1.2")
    end = text.index(f"{word} 2.1") if f"{word} 2.1" in text else taken + 3000
    return text[given:taken], text[taken:end]


@pytest.mark.parametrize("language", ["en", "uk", "ru"])
def test_the_symbol_lists_intro_holds_no_number_of_another_engine(language):
    """The intro is the same sentence for every engine: a value in it ("R = S/2 = 39 мм") is
    some other engine's."""
    with open(ROOT / "templates" / "i18n" / f"{language}.toml", "rb") as fh:
        catalog = tomllib.load(fh)
    tables = [catalog]
    intros = []
    while tables:  # the key wherever its table puts it
        table = tables.pop()
        intros += [v for k, v in table.items() if k == "symbols_intro"]
        tables += [v for v in table.values() if isinstance(v, dict)]
    (intro,) = intros
    assert not re.search(r"\d", intro), intro


_NO_SHAFT_NOR_DENSITY = {"flywheel": {"engine_inertia": None, "rim_density": None}}


def _flywheel_note(changes: dict, language: str = "ru") -> str:
    return _text(shared_html("inline4-petrol", changes, language, ("flywheel",)).linked_html)


def test_a_defaulted_shaft_inertia_and_rim_density_stand_among_the_values_taken():
    text = _flywheel_note(_NO_SHAFT_NOR_DENSITY)
    given, taken = _tables_1(text, "ru")
    for quantity in ("Момент инерции коленчатого вала без масс колен", "Плотность материала"):
        assert quantity not in given and quantity in taken, quantity
    assert "J в 0 кг·м²" in taken and "ρ м 7200 кг/м³" in taken
    assert "J в в задании не указан, поэтому он принят равным нулю" in text
    assert "принят серый чугун, ρ м = 7200 кг/" in text


def test_a_given_shaft_inertia_and_rim_density_stay_the_task_data_and_name_the_material():
    text = _flywheel_note({})  # the example gives J_e = 0.006 kg*m^2 and a steel rim, 7850 kg/m^3
    given, taken = _tables_1(text, "ru")
    for quantity in ("Момент инерции коленчатого вала без масс колен", "Плотность материала"):
        assert quantity in given and quantity not in taken, quantity
    assert "J в в задании не указан" not in text and "Материал обода в задании" not in text
    assert "Материал обода – сталь, ρ м = 7850 кг/" in text


def test_a_shaft_inertia_given_as_zero_is_no_assumption():
    text = _flywheel_note({"flywheel": {"engine_inertia": "0 kg*m^2"}})
    given, taken = _tables_1(text, "ru")
    assert "без масс колен" in given and "без масс колен" not in taken
    assert "принят равным нулю" not in text


def test_the_speed_extremes_are_the_first_in_the_cycle_in_both_sections():
    """The in-line four's torque repeats every 720°/4 = 180°: W and the speed have a least value
    in every period; both sections give the first one, and say why."""
    run = shared_run("inline4-petrol")
    flywheel = run.outputs["flywheel"].results
    speed = run.outputs["speed_fluctuation"].results
    period = 720 / 4
    assert flywheel["torque_period_deg"] == pytest.approx(period)
    assert speed["speed_period_deg"] == pytest.approx(period)
    for key in ("excess_work_min_crank_angle_deg", "excess_work_max_crank_angle_deg"):
        assert 0 <= flywheel[key] < period, key
    for key in ("omega_min_crank_angle_deg", "omega_max_crank_angle_deg"):
        assert 0 <= speed[key] < period, key
    # the speed is least where W is least: the same angle, to the flywheel table's 1° grid
    step = run.scene.analysis.angle_step_deg
    assert abs(
        speed["omega_min_crank_angle_deg"] - flywheel["excess_work_min_crank_angle_deg"]
    ) <= (2 * step)
    text = _text(shared_html("inline4-petrol", None, "ru").linked_html)
    assert text.count("повторяется через каждые 180°") == 2


def _torque_and_bearings(application: str | None) -> str:
    changes = {"engine": {"application": application}} if application else None
    html = shared_html("inline4-petrol", changes, "uk", ("torque", "bearings")).linked_html
    return _text(html)


def test_an_aircraft_engine_has_a_propeller_end_and_its_journal_proportions_are_borrowed():
    air = _torque_and_bearings("aircraft")
    plain = _torque_and_bearings(None)
    assert "в напрямку до повітряного гвинта" in air and "з боку маховика" not in air
    assert "кінець з боку повітряного гвинта" in air
    assert "в напрямку до маховика" in plain and "кінець з боку маховика" in plain
    sizes = "за типовими співвідношеннями для автомобільних і тракторних двигунів ["
    assert sizes in air and sizes in plain
    borrowed = "Двигун у завданні – авіаційний, а не автомобільний чи тракторний"
    assert borrowed in air and "а не автомобільний" not in plain


def test_an_aircraft_note_speaks_of_its_propeller_not_of_a_flywheel():
    """An aircraft engine has no flywheel: the introduction names the shaft and propeller's
    torsional calculation instead, and the calculations left out say why there is no flywheel."""
    changes = {"engine": {"application": "aircraft"}, "flywheel": None}
    air = _text(shared_html("inline4-petrol", changes, "uk").linked_html)
    plain = _text(shared_html("inline4-petrol", {"flywheel": None}, "uk").linked_html)
    assert "розрахунку вала з повітряним гвинтом на крутильні коливання" in air
    assert "вибору маховика" not in air and "вибору маховика" in plain
    # the reason follows the sentence's colon: its own explanation in parentheses, not a second colon
    assert "авіаційний двигун не має маховика (його роль виконує повітряний гвинт)" in air
    assert "у завданні немає даних про маховик" in plain


@pytest.mark.parametrize("application", ["automotive", "tractor"])
def test_a_car_or_tractor_engine_takes_the_proportions_as_its_own_kind(application):
    text = _torque_and_bearings(application)
    assert "а не автомобільний" not in text and "в напрямку до маховика" in text


def _v8_uk() -> str:
    return _text(shared_html("v8-petrol", None, "uk").linked_html)


def test_a_conclusion_names_the_section_and_table_of_the_cranks_summed_loads():
    text = _v8_uk()
    found = re.search(
        r"сили t ?і z ?, що діють на коліно, сумарні від усіх його циліндрів, – у розділі (\d+),"
        r" табл\. (\d+)\.1\.",
        text,
    )
    assert found and found.group(1) == found.group(2), found
    assert f"Таблиця {found.group(1)}.1 – Сили і набіжні моменти на колінах" in text


def test_the_conclusion_counts_the_counterweights_the_means_table_lists():
    """Each row of the means table is a crank's pair, m (m_web × 2): four counterweights for
    two rows, not two."""
    text = _v8_uk()
    pairs = len(re.findall(r"противага, коліно \d+ [\d ,]+ [\d,]+ \([\d,]+ × 2\)", text))
    assert pairs == 2
    numerals = "одна|дві|три|чотири|п’ять|шість|сім|вісім|дев’ять".split("|")
    assert f"Засоби зрівноваження: {numerals[2 * pairs - 1]} противаги" in text


def test_a_figure_over_several_pages_is_continued_in_the_middle_and_concluded_at_the_end(
    monkeypatch,
):
    from crankdyn_builtin.drawing import section

    monkeypatch.setattr(section.md, "positions_sheets", lambda positions, frames: [[0], [1], [2]])
    monkeypatch.setattr(section.md, "positions_scale", lambda positions: 0.1)
    monkeypatch.setattr(section, "scale_text", lambda scale, t: "1:10")
    shown = []

    class Context:
        @staticmethod
        def t(key, **params):
            return key

        @staticmethod
        def figure(draw, caption, name, see, see_params=None):
            shown.append((caption, see))
            return name

    from types import SimpleNamespace

    one_cylinder = SimpleNamespace(guides=[SimpleNamespace(bore_m=0.08)])
    section._positions_figures(Context(), one_cylinder, None)
    assert shown == [
        ("drawing.positions_caption", "drawing.see_positions"),
        ("drawing.positions_caption_middle", "drawing.see_positions_middle"),
        ("drawing.positions_caption_continued", "drawing.see_positions_continued"),
    ]
    catalogs = {}
    for language in ("en", "uk", "ru"):
        path = ROOT / "plugins/crankdyn_builtin/drawing/i18n" / f"drawing.{language}.toml"
        with open(path, "rb") as fh:
            catalogs[language] = tomllib.load(fh)["drawing"]
    assert catalogs["uk"]["positions_caption_middle"].endswith("(продовження, М {scale})")
    assert catalogs["uk"]["positions_caption_continued"].endswith("(закінчення, М {scale})")
    assert catalogs["ru"]["positions_caption_middle"].endswith("(продолжение, М {scale})")
    assert catalogs["ru"]["positions_caption_continued"].endswith("(окончание, М {scale})")


def test_a_main_journal_loaded_by_in_phase_cranks_is_said_to_be_and_the_remedy_named():
    """The in-line four's cranks 2 and 3 are in phase and the shaft has no counterweights: the
    journal between them carries their whole centrifugal force C = m_R R ω² at every angle."""
    import math

    m_r = 0.60 * (1 - 0.275) + 0.35 + 2 * 0.25  # rod's big-end share, crank pin, two webs
    c = m_r * 0.078 / 2 * (math.pi * 5600 / 30) ** 2
    r = shared_run("inline4-petrol").outputs["bearings"].results
    assert not r["with_counterweights"]
    middle = next(j for j in r["main_journals"] if j["journal"] == "2-3")
    assert r["crank_centrifugal_N"] == pytest.approx(c, rel=1e-9)
    assert middle["centrifugal_N"] == pytest.approx(c, rel=1e-6)
    text = _text(shared_html("inline4-petrol", None, "ru").linked_html)
    kn = f"{c / 1e3:.2f}".replace(".", ",")
    assert (
        f"Наибольшую среднюю нагрузку несёт коренная шейка 2–3; она воспринимает главным образом центробежные силы "
        f"соседних колен: их равнодействующая {kn} кН"
    ) in text
    # the remedy: every crank balanced by itself; counterweights on cranks 2 and 3 alone, in
    # phase, would leave a free centrifugal force of 2·C (the shaft's own ΣC = 0)
    directions = shared_run("inline4-petrol").outputs["balancing"].results["crank_directions_deg"]
    assert directions[1] == directions[2]
    assert (
        "Противовесы на щеках каждого колена, каждый из которых уравновешивает своё колено, "
        "сняли бы с неё эту нагрузку; противовесы только на коленах у этой шейки оставили бы "
        "центробежные силы вала неуравновешенными."
    ) in text
    assert "Коренную шейку 2–3 нагружают главным образом центробежные силы соседних колен" in text
    assert f"для одного колена C = {kn} кН" in text


def test_a_shaft_with_counterweights_is_not_said_to_lack_them():
    text = _text(shared_html("inline3-petrol", None, "ru").linked_html)
    assert shared_run("inline3-petrol").outputs["bearings"].results["with_counterweights"]
    assert "воспринимает главным образом центробежные силы" not in text


def _foreign_registry(taken_rows):
    """The built-in plugins and a third-party one whose stage takes a value the scene does not
    give (``StagePresentation.taken_rows``)."""
    import types

    from crankdyn.plugin.contracts import KINEMATICS
    from crankdyn.plugin.hooks import hookimpl
    from crankdyn.plugin.registry import collect, plugin_manager
    from crankdyn.plugin.types import Stage, StageOutput, StagePresentation

    stage = Stage(
        name="extra",
        requires=(KINEMATICS,),
        provides=(),
        applies=lambda scene: None,
        run=lambda scene, inputs: StageOutput(results={}),
        presentation=StagePresentation(
            title_key="extra.title",
            render=lambda output, ctx: "<p>extra</p>",
            taken_rows=taken_rows,
        ),
    )
    module = types.ModuleType("taking_plugin")
    module.crankdyn_stages = hookimpl(lambda: [stage])
    module.crankdyn_mechanisms = hookimpl(lambda: [])
    return collect(plugin_manager(extra_plugins=[module]))


def test_a_plugins_taken_values_stand_in_the_table_of_values_taken_and_garbage_is_named():
    from conftest import modified

    from crankdyn.errors import PluginFailure
    from crankdyn.output.pipeline import run_and_render
    from crankdyn.report.document import render_html
    from crankdyn.scene.model import scene_from_dict

    scene = scene_from_dict(modified("kinematics-only", {"report": {"language": "en"}}))
    row = ("Friction coefficient", "<i>f</i>", "0.02", "")
    registry = _foreign_registry(lambda scene, ctx: [row])
    result, _ = run_and_render(scene, registry, ["json"], ["extra"])
    text = _text(render_html(result, registry, "en").linked_html)
    given, taken = _tables_1(text, "en")
    assert "Friction coefficient f 0.02" in taken and "Friction coefficient" not in given
    with pytest.raises(PluginFailure) as caught:
        run_and_render(scene, _foreign_registry(lambda scene, ctx: 42), ["html"], ["extra"])
    assert "taken_rows returned 42" in str(caught.value)


@pytest.mark.parametrize(
    "changes, grade, strength_MPa",
    [(_NO_SHAFT_NOR_DENSITY, "серого чугуна СЧ 20", 200.0), ({}, "стали 45", 600.0)],
)
def test_the_rims_stress_is_judged_against_its_materials_tensile_strength(
    changes, grade, strength_MPa
):
    """σ = ρ v² of a thin rotating ring against the tensile strength of the material its density
    names (ГОСТ 1412-85: СЧ 20 at least 200 MPa; ГОСТ 1050: steel 45, 600 MPa), as a factor of
    safety σ_u/σ; the standard is cited and listed."""
    run = shared_run("inline4-petrol", changes or None)
    rim = run.outputs["flywheel"].results["rim"]
    speed = run.scene.engine.angular_velocity_rad_s * rim["outer_diameter_m"] / 2
    margin = strength_MPa * 1e6 / (rim["density_kg_m3"] * speed**2)
    assert rim["strength_margin"] == pytest.approx(margin, rel=1e-12)
    text = _flywheel_note(changes)
    found = re.search(
        rf"Для {grade} с пределом прочности при растяжении σ в = (\d+) МПа \[(\d+)\] "
        r"запас прочности обода σ в / ?σ = ([\d,]+)",
        text,
    )
    assert found, text[text.index("Обод") : text.index("Обод") + 800]
    assert float(found.group(1)) == strength_MPa
    assert float(found.group(3).replace(",", ".")) == pytest.approx(margin, rel=0.05)
    standard = "ГОСТ 1412-85" if strength_MPa == 200.0 else "ГОСТ 1050-2013"
    html = shared_html("inline4-petrol", changes or None, "ru", ("flywheel",)).linked_html
    listed = re.search(r'<ol class="references">(.*?)</ol>', html, flags=re.S).group(1)
    items = [_text(item) for item in re.findall(r"<li[^>]*>(.*?)</li>", listed, flags=re.S)]
    assert items[int(found.group(2)) - 1].strip().startswith(standard)


def _two_stroke_diesel(cycle: dict | None = None, language: str = "uk") -> str:
    """The indicator section of the one-cylinder diesel made a two-stroke (``cycle`` laid over its
    cycle data), with the given data."""
    changes = {"engine": {"strokes": 2}, "cycle": {"exhaust_pressure": None, **(cycle or {})}}
    return _text(shared_html("diesel-1cyl", changes, language, ("indicator",)).linked_html)


def test_a_two_stroke_note_has_no_pumping_strokes():
    """A two-stroke cycle has no exhaust and intake strokes: no pumping work L_нас in its
    diagram fullness, which is p_i/p_i′; the four-stroke's keeps them."""
    two = _two_stroke_diesel()
    four = _text(shared_html("diesel-1cyl", None, "uk", ("indicator",)).linked_html)
    assert "L нас" in four and "без насосних ходів" in four
    assert "L нас" not in two and "без насосних ходів" not in two
    assert "робота насосних ходів" not in two  # nor in the list of symbols
    assert re.search(r"φ п = p i / p i ′ = \d,\d+ \(у двотактному циклі насосних ходів немає", two)


def test_a_pre_expansion_ratio_the_scene_leaves_out_is_taken_and_said_to_be():
    """ρ = 1 that the scene does not give stands in table 1.2 with the sentence saying so; a
    diesel with ρ = 1 adds no heat at constant pressure, one with ρ > 1 does."""
    taken = _two_stroke_diesel({"pre_expansion_ratio": None})
    given_one = _two_stroke_diesel({"pre_expansion_ratio": 1.0})
    given = _two_stroke_diesel()  # the example's ρ = 1.45
    quantity = "Ступінь попереднього розширення ρ 1"
    table_given, table_taken = _tables_1(taken, "uk")
    assert quantity not in table_given and quantity in table_taken
    assert (
        "завдання не задає, тому прийнято ρ = 1: усю теплоту підведено за сталого об’єму" in taken
    )
    table_given, table_taken = _tables_1(given_one, "uk")
    assert quantity in table_given and quantity not in table_taken
    assert "лише за сталого об’єму (задано ступінь попереднього розширення ρ = 1)" in given_one
    for text in (taken, given_one):
        assert "за сталого тиску" not in text
    assert "за сталого тиску до об’єму ρ V c" in given
    assert "прийнято ρ = 1" not in given


def test_an_exact_irregularity_above_the_required_one_is_said_with_the_flywheel_it_needs():
    """A chosen flywheel of the energy method's size for [δ] = 0,05 on the one-cylinder diesel:
    the exact periodic solution gives a larger δ; the note does not say it confirms the energy
    method, it says by how much δ is exceeded and the flywheel the exact solution needs (a chosen
    flywheel is the task's, not raised)."""
    design_changes = {"flywheel": {"required_irregularity": 0.05}}
    designed = shared_run("diesel-1cyl", design_changes, ("speed_fluctuation",))
    designed = designed.outputs["flywheel"].results
    chosen = f"{designed['required_flywheel_inertia_kg_m2']:.6g} kg*m^2"
    changes = {"flywheel": {"required_irregularity": 0.05, "inertia": chosen}}
    r = shared_run("diesel-1cyl", changes, ("speed_fluctuation",))
    assert not r.outputs["flywheel"].results["flywheel_raised"]
    speed = r.outputs["speed_fluctuation"].results
    assert speed["irregularity"] > 0.0505  # above [δ] by more than the printed digits hide
    needed, used = speed["flywheel_inertia_ode_kg_m2"], speed["flywheel_inertia_kg_m2"]
    assert used == r.outputs["flywheel"].results["flywheel_inertia_kg_m2"] and needed > used
    text = _text(shared_html("diesel-1cyl", changes, "uk", ("speed_fluctuation",)).linked_html)
    assert "підтверджує" not in text
    excess = f"{100 * (speed['irregularity'] / 0.05 - 1):.2g}".replace(".", ",")
    growth = f"{100 * (needed / used - 1):.2g}".replace(".", ",")
    sentence = (
        (
            f"на {excess} % більший за допустимий [δ] = 0,05 (енергетичний метод дає 0,0500): "
            f"маховик {used:.4g} кг·м² вимоги не виконує; щоб дотриматися [δ], його момент інерції "
            f"слід збільшити на {growth} %, приблизно до {needed:.4g} кг·м²."
        )
        .replace(".", ",")
        .replace("кг·м²,", "кг·м².")
    )
    conclusions = text[text.rindex("Висновки") :]
    assert sentence in conclusions, sentence
    assert sentence in text[: text.rindex("Висновки")]  # said in the section too


def _boxer_changes() -> dict:
    """A flat four on the V8 example's masses and cycle: its crank layout balances every force
    and the first-order and centrifugal couples, Lanchester's shafts (asked for) take the
    second-order one."""
    return {"engine": dict(FLAT_FOUR_ENGINE), "balancing": {"balance_orders": [1, 2]}}


def test_a_boxers_balance_shafts_are_said_to_take_the_second_order_couple_only():
    results = shared_run("v8-petrol", _boxer_changes(), ("balancing",)).outputs["balancing"]
    r = results.results
    assert r["counterweights"] == [] and {s["order"] for s in r["balance_shafts"]} == {2}
    text = _text(shared_html("v8-petrol", _boxer_changes(), "uk", ("balancing",)).linked_html)
    means = "вони зрівноважують момент сил інерції другого порядку (Σ M II )"
    assert means in text[text.rindex("Висновки") :]
    assert "Σ M II 2,0000 незрівноважено два зрівноважувальні вали з противагами на кінцях" in text
    scheme = "Схема двигуна сама зрівноважує відцентрові сили та їхній момент"
    assert scheme in text
    # no counterweights fitted: none described, none of their radius taken
    for words in (
        "противаги на колінчастому валу",
        "центр мас противаг прийнято",
        "сили першого і",
    ):
        assert words not in text, words


def test_given_values_stand_in_the_task_data_and_values_taken_among_those_taken():
    """An angle step and a journal size the scene gives are the task's data (table 1.1); a step
    and a size the calculation takes (the typical proportions') stand with the values taken
    (table 1.2), with the value taken."""
    given, taken = _tables_1(_flywheel_note({}), "ru")  # the example gives Δα = 1°
    assert "Шаг по углу" in given and "Шаг по углу" not in taken
    changes = {
        "analysis": {"angle_step_deg": None},
        "bearings": {"crank_pin_diameter": "48 mm", "crank_pin_width": None},
    }
    run = shared_run("inline4-petrol", changes)
    sizes = run.outputs["bearings"].results["dimensions"]
    given, taken = _tables_1(_text(shared_html("inline4-petrol", changes, "ru").linked_html), "ru")
    assert "Шаг по углу" not in given and "Шаг по углу" in taken
    assert "Диаметр шатунной шейки 48 мм" in given and "Диаметр шатунной шейки" not in taken
    width = f"{sizes['crank_pin_width_m'] * 1e3:.4g}".replace(".", ",")
    assert f"Длина шатунной шейки {width} мм" in taken and "Длина шатунной шейки" not in given


def test_a_centrifugally_loaded_journal_over_its_pressure_gets_counterweights_first():
    """The in-line four's journal 2–3, loaded chiefly by its cranks' centrifugal forces, exceeds
    the allowable mean pressure: the conclusion asked only for a larger journal (a V12's needed a
    width that left no room for its webs); counterweights come first, the d·B without them."""
    text = _text(shared_html("inline4-petrol", None, "ru").linked_html)
    assert (
        "нагрузка главным образом центробежная, поэтому прежде всего следует установить "
        "противовесы на щеки каждого колена; без них ей нужна площадь проекции d · B ≥"
    ) in text
    assert (
        "коренную шейку нагружают главным образом центробежные силы соседних колен, которые "
        "сняли бы противовесы на щеках каждого колена; без противовесов площадь проекции коренной "
        "шейки следовало бы увеличить"
    ) in text
    counterweights = shared_html("inline3-petrol", None, "ru").linked_html
    assert "прежде всего следует установить противовесы" not in _text(counterweights)


def test_a_given_ignition_delay_is_not_said_to_be_taken_from_the_textbook():
    """τ_i given in the task's data (the example's 1.2 ms): the rounding says 6·n·τ_i with the
    given τ_i; left out, it is the textbook's 1.5 ms, taken."""
    given = _text(shared_html("diesel-1cyl", None, "en", ("indicator",)).linked_html)
    assert "[1, §3.1] with the given τ i = 1.2 ms (in seconds in the product)." in given
    assert "The ignition delay follows the textbook" not in given
    left_out = {"cycle": {"rounding": {"combustion_delay_time": None}}}
    taken = _text(shared_html("diesel-1cyl", left_out, "en", ("indicator",)).linked_html)
    assert "The ignition delay follows the textbook [1, §3.1]" in taken
    assert "with τ i = 1.5 ms (in seconds in the product)." in taken
    assert "the given τ" not in taken


def test_a_boxer_twins_cylinders_lie_left_and_right_not_in_banks():
    """A flat twin has one cylinder on each side: not "the odd-numbered cylinders lie in the left
    bank", which a boxer of four or more says; a balance shaft's table row sets its participle
    off with commas (uk)."""
    twin = {"engine": {"layout": "boxer", "cylinders": 2, "firing_order": [1, 2]}}
    text = _text(shared_html("inline4-petrol", twin, "en", ("bays",)).linked_html)
    assert "cylinder 1 lies on the left, cylinder 2 opposite it on the right" in text
    assert "odd-numbered" not in text and "bank" not in text
    four = _text(shared_html("v8-petrol", _boxer_changes(), "en", ("bays",)).linked_html)
    assert "the odd-numbered cylinders lie in the left bank" in four
    uk = _text(shared_html("inline4-petrol", twin, "uk", ("balancing",)).linked_html)
    assert "вала 1-го порядку, що обертається назустріч колінчастому валу," in uk


def test_a_shared_pins_rod_centrifugal_term_is_said_of_all_its_rods():
    """c_r = −Σ m_rR·R·ω²/F_p sums the rods on one pin (two on a V8's): its meaning says so, in
    the list of symbols and under the equation, not "of the rod"."""
    text = _v8_uk()
    assert "питома відцентрова сила обертових частин усіх шатунів шийки" in text
    assert "питома відцентрова сила обертової частини шатуна," not in text


def test_a_shared_pins_forces_t_i_and_z_i_are_said_of_the_crank():
    """On a V8's shared pins t_i and z_i of the torque and bearings sections are each crank's sums
    over its two cylinders: the list of symbols says so, not "of cylinder i"."""
    text = _v8_uk()
    assert "(сума сил його циліндрів, кожного за його кута циклу)" in text
    assert "сила i -го циліндра за його кута циклу" not in text.replace("i-го", "i -го")
