"""A driven machine's (a compressor's) and a given flywheel's flywheel section."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from crankdyn.physics import flywheel as fw
from crankdyn_builtin.flywheel.compute import _excess_results


def _torque(mean_Nm: float):
    angle_deg = np.arange(0.0, 720.0, 0.5)
    torque = mean_Nm + 40.0 * np.sin(np.radians(angle_deg))
    return SimpleNamespace(crank_angle_deg=angle_deg, torque_Nm=torque, strokes=4)


@pytest.mark.parametrize("mean_Nm", [11.31, -11.31])
def test_excess_work_share_is_of_the_work_done_or_taken_in(mean_Nm):
    """M = M_m + 40 sin α over 720°: W = 40 (1 − cos α) swings by ΔL = 80 J, and the work per
    cycle is |M_m|·4π, so ΔL is 80 / (11.31·4π) = 56.3 % of it, whether the shaft gives that work
    (an engine) or takes it in (a compressor, M_m < 0: printed as 0 % before)."""
    torque = _torque(mean_Nm)
    excess = fw.excess_work(np.radians(torque.crank_angle_deg), torque.torque_Nm)
    r = _excess_results(excess, torque)
    assert r["excess_work_J"] == pytest.approx(80.0, rel=1e-4)
    assert r["excess_work_relative"] == pytest.approx(80.0 / (11.31 * 4 * math.pi), rel=1e-4)


def test_a_driven_machines_flywheel_section_says_the_shaft_takes_work_in(tmp_path):
    """A compressor's mean torque is negative: the section said "the resisting torque is taken
    constant and equal to M_m" (−11,31 N·m: a resisting torque that drives), and "ΔL is 0 % of
    the work per cycle"; it says the shaft is driven and gives ΔL's share of the work taken in."""
    import re

    from crankdyn.engine.orchestrator import run_scene
    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.document import render_html
    from crankdyn.scene.model import scene_from_dict

    # a compressor's pressure over its one-turn cycle: compressed while the piston rises to its
    # top dead centre (180..360°), delivered, re-expanded just after it, drawn in at 1 bar
    angle = np.arange(0.0, 360.0, 0.5)
    rising = np.clip((angle - 180.0) / 180.0, 0.0, None) ** 3
    expanding = np.clip(1.0 - angle / 30.0, 0.0, None)
    bar = 1.0 + 7.2 * np.maximum(rising, expanding)
    trace = tmp_path / "compressor.csv"
    trace.write_text(
        "crank_angle_deg,pressure_bar\n"
        + "".join(f"{a:.1f},{p:.4f}\n" for a, p in zip(angle, bar, strict=True))
    )
    scene = scene_from_dict(
        {
            "report": {"title": "Компресор", "language": "uk", "year": 2026},
            "engine": {
                "name": "Компресор",
                "application": "stationary",
                "strokes": 2,
                "cylinders": 1,
                "rpm": 1450,
                "bore": "80 mm",
                "stroke": "70 mm",
                "rod_length": "150 mm",
            },
            "masses": {"piston_group": "0.55 kg", "rod": "0.48 kg", "rod_cm_fraction": 0.3},
            "cycle": {
                "source": "trace",
                "trace_file": str(trace),
                "trace_format": "csv",
                "trace_firing_tdc_deg": 0,
                "compression_ratio": 21.0,
            },
            "flywheel": {"required_irregularity": 0.02},
        },
        base_dir=tmp_path,
    )
    registry = default_registry()
    stages = ["indicator", "forces", "torque", "flywheel", "speed_fluctuation"]
    result = run_scene(scene, registry, stages)
    assert result.outputs["flywheel"].results["mean_torque_Nm"] < 0
    # the swing over the mean's magnitude: positive, as an engine's
    torque = result.outputs["torque"].results
    assert torque["non_uniformity"] > 0
    assert result.outputs["speed_fluctuation"].results["load_torque_Nm"] < 0
    html = render_html(result, registry, "uk").linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html)).replace("\u202f", " ")
    assert "вал не віддає роботу, а споживає її" in text
    assert "момент опору прийнято сталим" not in text
    assert re.search(r"ΔL становить [1-9]\d*(,\d+)? % індикаторної роботи двигуна за цикл", text)
    assert "Тут Mоп &lt; 0: машина споживає роботу" in text  # the constant torque drives it
    # its conclusions give the torque largest in magnitude, its least, where it loads most
    forces = result.outputs["forces"].results
    assert -forces["torque_min_Nm"] > forces["torque_max_Nm"] > 0
    least = f"{forces['torque_min_Nm']:.4g}".replace("-", "−").replace(".", ",")
    assert f"Найбільший за модулем момент {least} Н·м" in text


def test_a_given_flywheel_with_no_shaft_inertia_is_not_said_to_be_sized():
    """With the flywheel given (its inertia, no required δ), nothing is sized: J_e taken as zero
    makes the coefficient of speed fluctuation an estimate on the safe side, not "the flywheel
    is sized with a margin"."""
    import re

    from conftest import shared_html

    changes = {
        "flywheel": {
            "inertia": "0.2 kg*m^2",
            "required_irregularity": None,
            "engine_inertia": None,
            "rim_mean_diameter": None,
            "rim_density": None,
        }
    }
    page = shared_html("inline4-petrol", changes, "uk", ("forces", "torque", "flywheel"))
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", page.linked_html))
    assert "коефіцієнт нерівномірності обертання з заданим маховиком оцінено із запасом" in text
    assert "маховик розраховано із запасом" not in text


def test_a_one_crank_shafts_own_inertia_is_without_its_cranks_mass():
    """A radial's shaft has one crank: its flywheel section, table and list of symbols said
    "без масс колен" and "на щеках колен"; an in-line four keeps the plural."""
    import re

    from conftest import shared_html

    radial = shared_html("radial9-aircraft", {"flywheel": {"inertia": "3.2 kg*m^2"}}, "ru")
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", radial.linked_html))
    assert "без массы колена" in text and "без масс колен" not in text
    assert "на щеках колена" in text and "на щеках колен " not in text
    four = shared_html("inline4-petrol", None, "ru")
    assert "без масс колен" in re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", four.linked_html))


@pytest.mark.parametrize(
    "language, title, row, defined",
    [
        (
            "en",
            "Speed fluctuation with the propeller",
            "Moment of inertia of the propeller (taking the flywheel's part)",
            "so in this note the flywheel is the propeller",
        ),
        (
            "uk",
            "Нерівномірність обертання з повітряним гвинтом",
            "Момент інерції повітряного гвинта (виконує роль маховика)",
            "тож у цій записці маховик – це гвинт",
        ),
    ],
)
def test_an_aircraft_engines_flywheel_is_its_propeller(language, title, row, defined):
    """A radial aircraft engine given its propeller's inertia: the section is the speed
    fluctuation with the propeller, the given data and the list of symbols name the propeller,
    and the section says once that its "flywheel" is the propeller; a car engine's keeps its
    flywheel."""
    import html as html_lib
    import re

    from conftest import shared_html

    given = {"flywheel": {"inertia": "2.5 kg m^2"}}
    html = shared_html("radial9-aircraft", given, language).linked_html
    text = html_lib.unescape(re.sub(r"<[^>]+>", "", html))
    assert title in text and row in text and defined in text
    listed = text[text.index("J" + ("f" if language == "en" else "мах") + " –") :][:120]
    assert ("propeller" if language == "en" else "гвинта") in listed, listed
    keyword = {"en": "PROPELLER", "uk": "ПОВІТРЯНИЙ ГВИНТ"}[language]
    assert keyword in text and ("FLYWHEEL" if language == "en" else "МАХОВИК") not in text
    car = re.sub(r"<[^>]+>", "", shared_html("inline4-petrol", None, language).linked_html)
    assert title not in car and defined not in car and keyword not in car


def test_a_designed_flywheel_holds_at_its_speed_and_a_tiny_one_is_the_webs():
    """A flywheel designed for [δ] at the rated speed: the note says δ grows at lower speeds (so
    starting and idling choose it too); one of a few per cent of J_0 is said to be given by the
    parts turning with the shaft (the rotor, the clutch), not a part of its own."""
    import re

    from conftest import shared_html, shared_run

    loose = {"flywheel": {"required_irregularity": 0.076}}
    r = shared_run("inline4-petrol", loose, ("flywheel",)).outputs["flywheel"].results
    share = r["flywheel_inertia_kg_m2"] / r["required_total_inertia_kg_m2"]
    page = shared_html("inline4-petrol", loose, "en", ("flywheel",)).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", page)).replace("\u2060", "")
    assert (
        "These values are for the given speed n = 5600 rpm; at a lower speed ω² in the denominator of δ = ΔL/(Jω²) falls, which raises δ where ΔL does not fall faster"
        in text
    )
    said = "is in practice made up by the parts that turn with the shaft, the generator"
    assert 0 < share < 0.1 and said in text, share
    # the rim of the given diameter is still sized, for a flywheel made a part of its own
    separate = "for the case that the flywheel is made a separate part all the same"
    assert (separate in text) == (r["rim"] is not None)
    tight = shared_html("inline4-petrol", None, "en", ("flywheel",)).linked_html
    assert said not in tight and "These values are for the given speed" in tight
    assert "made a separate part all the same" not in tight


@pytest.mark.parametrize("rpm", [None, 1500])
def test_a_lower_speed_with_a_smaller_irregularity_is_explained(rpm):
    """The in-line 4 at its 5600 rpm: the reciprocating masses' torque cancels more of the gas
    torque's swings at 75 % and 50 % of the speed, whose δ are below the given one, so the note
    names those speeds and the least ΔL there instead of leaving "at a lower speed δ grows"
    contradicted by its own figures; at 1500 rpm δ only grows below, and nothing is said."""
    import re

    from conftest import shared_html, shared_run

    changes = {"engine": {"rpm": rpm}} if rpm else None
    r = shared_run("inline4-petrol", changes, ("flywheel",)).outputs["flywheel"].results
    html = shared_html("inline4-petrol", changes, "en", ("flywheel",)).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html))
    below = [row for row in r["lower_speeds"] if row["irregularity"] < r["irregularity"]]
    if rpm is None:
        assert [row["speed_fraction"] for row in below] == [0.75, 0.5]
        least = min(row["excess_work_J"] for row in below)
        assert (
            f"At {below[0]['rpm']:.0f} and {below[1]['rpm']:.0f} rpm δ is smaller than at the "
            "given speed" in text
        )
        assert f"(ΔL down to {least:.4g} J against {r['excess_work_J']:.4g} J)" in text
        assert "at still lower speeds δ grows" in text
    else:
        assert not below
        assert "is smaller than at the given speed" not in text


@pytest.mark.parametrize(
    ("language", "meaning", "summed"),
    [
        ("uk", "Mд – індикаторний крутний момент двигуна", r"сумарн\w* [\w ]*крутн"),
        ("ru", "Mд – индикаторный крутящий момент двигателя", r"суммарн\w* [\w ]*крутящ"),
    ],
)
def test_a_single_cylinders_torque_is_not_called_a_sum(language, meaning, summed):
    """One cylinder: nothing is summed, so neither the list of symbols nor the flywheel's section
    and conclusions call the engine's torque the total one."""
    import re

    from conftest import shared_html

    changes = {"flywheel": {"required_irregularity": 0.02}}
    html = shared_html("diesel-1cyl", changes, language).linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", html).split())
    assert meaning in text
    assert "ΔL" in text and not re.search(summed, text)


def test_a_rim_speed_over_the_limit_is_printed_with_the_digits_that_show_it():
    """50.04 m/s against an allowed 50 m/s: three digits would print "50,0 m/s exceeds the
    allowable 50 m/s"; the speed gets the digits that tell it from the limit, and no more where
    three already do."""
    from types import SimpleNamespace

    from crankdyn.report.i18n import translator
    from crankdyn_builtin.flywheel.section import rim_speed_text

    t = translator("uk")
    ctx = SimpleNamespace(num=lambda value, significant=4: t.number(value, significant))
    assert rim_speed_text(ctx, {"speed_m_s": 50.04, "max_speed_m_s": 50.0}) == "50,04"
    assert rim_speed_text(ctx, {"speed_m_s": 50.0004, "max_speed_m_s": 50.0}) == "50,0004"
    assert rim_speed_text(ctx, {"speed_m_s": 47.318, "max_speed_m_s": 50.0}) == "47,3"
    assert rim_speed_text(ctx, {"speed_m_s": 47.318, "max_speed_m_s": None}) == "47,3"


def test_a_cars_small_flywheel_is_not_said_to_be_hardly_needed():
    """A V8 car engine whose [δ] = 0.01 asks for a flywheel of 1 % of J_0: the note says that is
    all [δ] asks for, not that the shaft's parts make it up and "a separate flywheel is hardly
    needed", which the next paragraph (a vehicle's flywheel is larger) contradicts; a stationary
    engine's note says it as before."""
    import re

    from conftest import shared_html

    def text(application):
        changes = {
            "flywheel": {"required_irregularity": 0.01},
            "engine": {"application": application},
        }
        return " ".join(
            re.sub(r"<[^>]+>", "", shared_html("v8-petrol", changes, "en").linked_html).split()
        )

    car = text("automotive")
    assert re.search(r"So small a flywheel \([\d.]+ % of J0\) is all that \[δ\] at the given", car)
    assert "hardly needed" not in car and "made a separate part all the same" not in car
    assert "a separate flywheel is hardly needed" in text("stationary")


def test_the_excess_work_figure_calls_the_torque_indicated_not_total():
    """The legend of the excess work's figure: a single cylinder's torque is no sum, and any
    engine's is its indicated torque (as the English legend says)."""
    from conftest import shared_html

    changes = {"flywheel": {"required_irregularity": 0.02}}
    for language, words in (
        ("ru", "индикаторный крутящий момент"),
        ("uk", "індикаторний крутний момент"),
    ):
        figures = shared_html("diesel-1cyl", changes, language).figures
        svg = next(f for f in figures if "excess_work" in f.name).svg.decode()
        assert words in svg and "суммарный" not in svg and "сумарний" not in svg


def test_the_rims_stress_source_is_listed_only_where_a_rim_is_sized():
    """The thin ring's hoop stress comes from Timoshenko: cited at the rim's stress, so a note
    sizing no rim (an aircraft engine's propeller) does not list it among the section's sources."""
    import re

    from conftest import shared_html

    def text(name):
        return " ".join(re.sub(r"<[^>]+>", "", shared_html(name, None, "en").linked_html).split())

    with_rim = text("inline4-petrol")
    assert re.search(r"the hoop stress of a thin rotating ring \[\d+\] is σ", with_rim)
    assert "Timoshenko S. Strength of Materials" in with_rim
    assert "Timoshenko S. Strength of Materials" not in text("radial9-aircraft")


@pytest.mark.parametrize(
    ("application", "said"),
    [
        (None, "із заданим маховиком 0,2 кг·м² коефіцієнт нерівномірності обертання δ = "),
        (
            "aircraft",
            "із заданим моментом інерції повітряного гвинта 0,2 кг·м² коефіцієнт нерівномірності "
            "обертання δ = ",
        ),
    ],
)
def test_a_given_flywheel_is_not_a_result_of_the_abstract(application, said):
    """The abstract's results: δ with the flywheel (or the propeller) the assignment gives, not
    its moment of inertia as if the calculation had found it."""
    import re

    from conftest import shared_html

    changes = {"flywheel": {"inertia": "0.2 kg*m^2", "required_irregularity": 0.01}}
    if application:
        changes["engine"] = {"application": application}
    html = shared_html("inline4-petrol", changes, "uk").linked_html
    abstract = re.search(r'<section class="abstract".*?</section>', html, re.S).group(0)
    abstract = " ".join(re.sub(r"<[^>]+>", "", abstract).replace("\u202f", " ").split())
    assert said in abstract, abstract
    assert "момент інерції маховика 0,2" not in abstract
    # its table checks the given flywheel (or propeller): it is neither chosen nor found
    body = " ".join(re.sub(r"<[^>]+>", "", html).split())
    caption = (
        "Нерівномірність обертання з повітряним гвинтом за енергетичним методом"
        if application
        else "Перевірка заданого маховика за енергетичним методом"
    )
    assert caption in body and "вибраного маховика" not in body


def test_a_large_irregularity_at_a_lower_speed_is_said_to_be_beyond_the_energy_method():
    """δ = ΔL/(Jω²) takes the speed's swing small beside its mean: at a quarter of the speed an
    in-line four with [δ] = 0.05 would have δ = 0.31, which the note gives with the remark that it
    lies beyond the method; [δ] = 0.01 keeps every value small and gets no remark."""
    import re

    from conftest import shared_html, shared_run

    def text(required):
        changes = {"flywheel": {"required_irregularity": required}}
        html = shared_html("inline4-petrol", changes, "en", ("flywheel",)).linked_html
        rows = shared_run("inline4-petrol", changes, ("flywheel",)).outputs["flywheel"].results
        return " ".join(re.sub(r"<[^>]+>", "", html).split()), rows["lower_speeds"]

    large, rows = text(0.05)
    largest = max(row["irregularity"] for row in rows)
    assert largest > 0.25
    assert "Values of δ this large (up to 0.309) lie outside the energy method" in large
    # a car's conclusions do not state that δ as a result: they say it lies beyond the method
    car = {"flywheel": {"required_irregularity": 0.05}, "engine": {"application": "automotive"}}
    html = shared_html("inline4-petrol", car, "en", ("flywheel",)).linked_html
    said = " ".join(re.sub(r"<[^>]+>", "", html).split())
    conclusions = said[said.rindex("Conclusions") :]
    assert "would leave a δ above 0.25 with the full-load pressures" in conclusions
    assert "0.309" not in conclusions
    small, rows = text(0.01)
    assert max(row["irregularity"] for row in rows) < 0.25
    assert "lie outside the energy method" not in small
    assert "δ above 0.25" not in small
