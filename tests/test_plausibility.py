"""Plausibility warnings: values no real engine has are named (never refused); defaults are listed."""

from __future__ import annotations

import re
import string
import tomllib
from pathlib import Path

import pytest
from conftest import as_read, example_data, modified, write_scene

from crankdyn.cli import examples_dir, main
from crankdyn.plugin.registry import default_registry
from crankdyn.report.plausibility import defaults_applied, warnings
from crankdyn.scene.model import load_scene, scene_from_dict

CATALOGS = Path(__file__).parents[1] / "templates" / "i18n"


REGISTRY = default_registry()


#: The example's bore (82 mm) with a stroke of 3.9 of it, slow enough for its piston speed.
LONG_STROKE = {"stroke": "320 mm", "rpm": 1000, "rod_ratio": 0.25}


def _keys(changes: dict, example: str = "petrol-1cyl") -> list[str]:
    scene = scene_from_dict(modified(example, changes), base_dir=examples_dir())
    return [key for key, _ in warnings(scene, REGISTRY)]


@pytest.mark.parametrize("path", sorted(examples_dir().glob("*.toml")), ids=lambda p: p.stem)
def test_no_bundled_example_is_implausible(path):
    assert warnings(load_scene(path), REGISTRY) == []


def test_mean_piston_speed_against_s_n_over_30():
    scene = scene_from_dict(
        modified("petrol-1cyl", {"engine": {"rpm": 20000}}), base_dir=examples_dir()
    )
    ((key, params),) = warnings(scene, REGISTRY)
    assert key == "plausibility.piston_speed"
    assert params["speed"] == pytest.approx(0.078 * 20000 / 30)  # c_m = S n / 30 = 52 m/s
    assert params["rpm_limit"] == pytest.approx(25 * 30 / 0.078)  # n at c_m = 25 m/s
    assert _keys({"engine": {"rpm": 9600}}) == []  # 24.96 m/s: just below the limit


@pytest.mark.parametrize(
    "changes, expected",
    [
        ({"engine": {"rod_ratio": 0.9999999}}, ["plausibility.rod_ratio"]),
        ({"engine": {"rod_ratio": 0.1}}, ["plausibility.rod_ratio"]),
        ({"engine": {"rod_ratio": 0.45}}, []),
        ({"engine": {"stroke": "140 mm", "rpm": 3000}}, ["plausibility.stroke_bore"]),  # S/D = 1.71
        ({"engine": {"stroke": "40 mm"}}, ["plausibility.stroke_bore"]),  # S/D = 0.49
        ({"engine": {"stroke": "130 mm"}}, []),  # 1.59
        # a low-speed marine crosshead diesel's S/D = 3…4.7, not a car engine's
        ({"engine": {**LONG_STROKE, "application": "marine"}}, []),  # 3.9
        ({"engine": LONG_STROKE}, ["plausibility.stroke_bore"]),
        (
            {"engine": {**LONG_STROKE, "stroke": "400 mm", "application": "marine"}},
            ["plausibility.stroke_bore"],  # 4.88
        ),
        ({"cycle": {"max_pressure": "26 MPa"}}, ["plausibility.peak_pressure"]),
        ({"masses": {"rod_cm_fraction": 0.7}}, ["plausibility.rod_cm"]),
        ({"masses": {"rod_cm_fraction": 0.05}}, ["plausibility.rod_cm"]),
    ],
)
def test_each_warning_fires_on_its_own(changes, expected):
    assert _keys(changes) == expected


@pytest.mark.parametrize(
    "changes, expected",
    [
        ({"engine": {"rod_length": "65 mm"}}, ["plausibility.rod_ratio"]),  # λ = 39/65 = 0.6 > 0.45
        ({"engine": {"rod_length": "130 mm"}}, []),  # λ = 39/130 = 0.3
        ({"masses": {"rod_cm_fraction": 0.7}}, ["plausibility.rod_cm"]),
    ],
)
def test_the_offset_crank_slider_is_checked_as_a_crank_slider(changes, expected):
    """The offset mechanism declares the crank-slider's λ and rod-centre rules as its own."""
    assert _keys(changes, "offset-crank-engine") == expected


def test_a_mechanism_without_the_rod_rules_gets_no_rod_warning():
    """λ = 0.6 is implausible only where a mechanism declares the rule: the planetary mechanism
    does not (its rod_ratio is no connecting rod's λ)."""
    registry = default_registry()
    planetary = registry.mechanisms["planetary"]
    assert all(rule.name != "rod_ratio" for rule in planetary.plausibility)
    assert "rod_ratio" in {
        rule.name for rule in registry.mechanisms["offset_crank_slider"].plausibility
    }


def test_catalogs_carry_every_warning_in_every_language_with_the_same_placeholders():
    english = tomllib.loads((CATALOGS / "en.toml").read_text(encoding="utf-8"))["plausibility"]
    for language in ("uk", "ru"):
        texts = tomllib.loads((CATALOGS / f"{language}.toml").read_text(encoding="utf-8"))[
            "plausibility"
        ]
        assert set(texts) == set(english)
        for key, text in texts.items():
            fields = {f for _, f, _, _ in string.Formatter().parse(text) if f}
            assert fields == {f for _, f, _, _ in string.Formatter().parse(english[key]) if f}
            assert not re.search(r"\b(the|and|above|outside)\b", text)  # no English sentence left


def test_defaults_applied_lists_what_the_scene_left_out():
    data = example_data("kinematics-only")
    scene = scene_from_dict(data, base_dir=examples_dir(), registry=REGISTRY)
    applied = dict(defaults_applied(scene))
    assert applied["engine.cylinders"] == 1 and applied["engine.mechanism"] == "crank_slider"
    assert applied["analysis.kinematics"] == "exact"
    assert "engine.strokes" not in applied and "engine.rpm" not in applied  # given in the scene
    data["engine"].pop("strokes")
    assert (
        dict(defaults_applied(scene_from_dict(data, base_dir=examples_dir())))["engine.strokes"]
        == 4
    )


@pytest.mark.parametrize(
    ("example", "unused", "used"),
    [
        (
            "two-stroke-1cyl",
            [
                "cycle.rounding.exhaust_closes_after_tdc_deg",
                "cycle.rounding.intake_opens_before_tdc_deg",
                "cycle.rounding.intake_closes_after_bdc_deg",
                "cycle.trace_firing_tdc_deg",
                "cycle.pre_expansion_ratio",
                "cycle.rounding.combustion_delay_time",
            ],
            ["cycle.rounding.pressure_rise_to_tdc"],
        ),
        (
            "diesel-rk-trace",
            ["cycle.rounding.exhaust_opens_before_bdc_deg", "cycle.pre_expansion_ratio"],
            ["engine.crankcase_pressure"],
        ),
        (
            "diesel-1cyl",
            ["cycle.trace_firing_tdc_deg"],
            [
                "cycle.rounding.exhaust_closes_after_tdc_deg",
                "cycle.rounding.intake_closes_after_bdc_deg",
            ],
        ),
    ],
)
def test_defaults_applied_leave_out_what_the_engine_and_cycle_do_not_use(example, unused, used):
    applied = dict(defaults_applied(load_scene(examples_dir() / f"{example}.toml")))
    assert [name for name in unused if name in applied] == []
    assert [name for name in used if name not in applied] == []


def test_check_and_report_print_the_warning_and_the_report_lists_it(tmp_path, capsys):
    scene = write_scene(
        tmp_path / "s.toml",
        modified("kinematics-only", {"engine": {"rpm": 30000}, "report": {"language": "uk"}}),
    )
    assert main(["check", str(scene)]) == 0
    checked = capsys.readouterr()
    assert "mean piston speed is 100 m/s" in checked.err and "engine.rpm" in checked.err
    assert "defaults applied" in checked.out and "engine.cylinders = 1" in checked.out
    assert "engine.mechanism = 'crank_slider'" in checked.out  # the registry's default
    assert main(["report", str(scene), "-o", str(tmp_path / "out"), "--format", "html", "-q"]) == 0
    assert "mean piston speed is 100 m/s" in capsys.readouterr().err
    html = (tmp_path / "out" / "report.html").read_text(encoding="utf-8")
    seen = (
        as_read(html).replace("\u202f", " ").replace("\u00a0", " ")
    )  # numbers kept on the line of their unit
    given = seen.split('id="sec-1"', 1)[1].split('id="sec-2"', 1)[0]  # the given data's section
    assert "Середня швидкість поршня 100 м/с перевищує 25 м/с" in given
    conclusions = seen.split('class="conclusions"', 1)[1].split("</ol>", 1)[0]
    assert "Середня швидкість поршня перевищує звичайну для поршневих двигунів" in conclusions
    assert "engine.rpm" not in seen  # the note speaks of the engine, not of its input file


def test_a_ukrainian_report_of_latin_title_texts_is_warned_about_on_the_terminal(tmp_path, capsys):
    from crankdyn.report.plausibility import language_warnings

    english = scene_from_dict(
        modified("inline4-petrol", {"report": {"language": "uk"}}), base_dir=examples_dir()
    )
    ((key, params),) = language_warnings(english)
    assert key == "plausibility.latin_texts" and params["language"] == "uk"
    assert params["fields"].split(", ")[:2] == ["report.title", "report.subtitle"]
    assert "engine.name" in params["fields"]
    assert (
        language_warnings(load_scene(examples_dir() / "petrol-1cyl-uk.toml")) == []
    )  # Cyrillic texts
    assert (
        language_warnings(load_scene(examples_dir() / "inline4-petrol.toml")) == []
    )  # an English report
    assert (
        main(
            [
                "report",
                str(examples_dir() / "inline4-petrol.toml"),
                "-o",
                str(tmp_path / "out"),
                "--format",
                "json",
                "-q",
                "--lang",
                "uk",
            ]
        )
        == 0
    )
    assert "report.title, report.subtitle" in capsys.readouterr().err


def test_a_scene_without_a_title_gets_the_report_languages_default_title():
    from crankdyn.engine.orchestrator import run_scene
    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.document import render_html

    data = modified("petrol-1cyl-uk", {})
    data["report"].pop("title", None)
    scene = scene_from_dict(data, base_dir=examples_dir())
    registry = default_registry()
    html = render_html(run_scene(scene, registry, requested=["kinematics"]), registry).linked_html
    assert "Динамічний розрахунок поршневого двигуна" in html
    assert "Dynamic calculation of a piston engine" not in html
