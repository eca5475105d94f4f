"""The core knows no built-in plugin, and a plugin brings everything of its own.

* The core's source (``src/crankdyn``) names no registered built-in stage, mechanism, scene table
  or answer-key result: whatever is specific to a plugin is declared by it (``Stage.symbols``,
  ``Stage.section_symbols``, ``Stage.plausibility``, ``Stage.appendix``, ``Mechanism.plausibility``)
  and read by the core from the registry.
* A throw-away mechanism registered through ``plugin_manager(extra_plugins=...)`` is drawn from
  the run's registry, gets its symbols, its plausibility rules and its answer column, with
  nothing under ``src/`` or ``templates/`` touched.
"""

from __future__ import annotations

import ast
import hashlib
import importlib
import textwrap
import typing
from pathlib import Path

import pytest
from conftest import modified

from crankdyn.batch import answer_key
from crankdyn.cli import examples_dir
from crankdyn.output import writers as outputs
from crankdyn.output.pipeline import run_and_render
from crankdyn.plugin import contracts
from crankdyn.plugin.registry import Registry, collect, default_registry, plugin_manager
from crankdyn.report.plausibility import console_lines, warnings
from crankdyn.scene.model import Engine, scene_from_dict

ROOT = Path(__file__).resolve().parents[1]
CORE = ROOT / "src" / "crankdyn"

#: Names the core may spell although a built-in uses them too: the data keys of crankdyn.plugin.contracts
#: (the core's contract between plugins: "kinematics" is the key of a PistonMotion and the name of
#: the stage providing it) and the values the core scene model itself offers (engine.rod_type =
#: "articulated", also the name of the bay stage's table).
SHARED = {
    value for name, value in vars(contracts).items() if name.isupper() and isinstance(value, str)
} | {
    choice
    for info in Engine.model_fields.values()
    for choice in typing.get_args(info.annotation)
    if isinstance(choice, str)
}


def built_in_names(registry) -> set[str]:
    """The names a built-in plugin owns: its stages, mechanisms, error probes and scene tables."""
    stages = registry.stages.values()
    return (
        {s.name for s in stages}
        | set(registry.mechanisms)
        | set(registry.error_probes)
        | {s.options_table for s in stages if s.options_table}
    )


def result_keys(registry) -> set[str]:
    """The stages' results the answer key reads (``AnswerColumn.key``): the physics library names
    the same quantities (``max_pressure_Pa``), the rest of the core never."""
    return {c.key.split(".")[0] for s in registry.stages.values() for c in s.answer_columns}


def named_in(source: str, names: set[str]) -> set[str]:
    """The ``names`` that a string literal of the Python ``source`` is, or starts a dotted key of."""
    found = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            found |= {
                name for name in names if node.value == name or node.value.startswith(name + ".")
            }
    return found


def test_the_scan_finds_a_built_in_name():
    """The scan itself can fail: a core listing the crank-sliders by name is caught."""
    assert named_in(
        '_CRANK_SLIDERS = ("crank_slider", "offset_crank")\n', built_in_names(default_registry())
    ) == {"crank_slider", "offset_crank"}


def test_the_core_names_no_built_in_stage_mechanism_table_or_result():
    registry = default_registry()
    names = built_in_names(registry) - SHARED
    results = result_keys(registry) - SHARED
    assert {
        "indicator",
        "numerics",
        "offset_crank_slider",
    } <= names and "max_pressure_Pa" in results
    found = set()
    for path in sorted(CORE.rglob("*.py")):
        source = path.read_text(encoding="utf-8")
        physics = path.parent.name == "physics"
        found |= {
            (path.name, name) for name in named_in(source, names if physics else names | results)
        }
    assert found == set(), "the core names built-ins: " + repr(sorted(found))


PLUGIN = '''
"""A throw-away mechanism: a crank-slider under a name of its own, with a kinematics stage that
gives the stroke, a letter of its own, a plausibility rule of its own and the core's λ rule."""
from pathlib import Path

import numpy as np

from crankdyn.plugin.hooks import hookimpl
from crankdyn.physics import kinematics as kin
from crankdyn.physics.plane import along, polar
from crankdyn.report.plausibility import ROD_RATIO
from crankdyn.plugin.types import (AnswerColumn, Catalog, Guide, Mechanism, MechanismGeometry,
                                   PlausibilityRule, Stage, StageOutput, StagePresentation,
                                   Symbol)

HERE = Path(__file__).resolve().parent
NAME = "throwaway_slider"


def geometry(scene, crank_angle_rad):
    e = scene.engine
    R, L = e.crank_radius_m, e.rod_length_m
    alpha = np.asarray(crank_angle_rad, dtype=float)
    s = kin.piston_displacement_exact_m(alpha, R, R / L)
    return MechanismGeometry(
        joints={"crank_centre": np.zeros((len(alpha), 2)), "crank_pin": polar(R, alpha),
                "wrist_pin": along(0.0, R + L - s)},
        links=[("crank", "crank_centre", "crank_pin"), ("rod", "crank_pin", "wrist_pin")],
        guides=[Guide("wrist_pin", travel_m=(L - R, L + R), bore_m=e.bore)],
        dimensions={"R": R, "L": L, "D": e.bore, "S": 2 * R}, travel_m=s)


def slow(scene, results=None):
    rpm = scene.engine.rpm
    return [("plausibility.throwaway_slow", {"rpm": rpm})] if rpm < 1000 else []


MECHANISM = Mechanism(NAME, "a throw-away crank-slider", geometry=geometry,
                      plausibility=(ROD_RATIO, PlausibilityRule("slow", slow)))


def run(scene, inputs):
    return StageOutput(results={"stroke_m": float(2.0 * scene.engine.crank_radius_m)})


def render(output, ctx):
    return ctx.render_template("sections/throwaway_slider.html.j2", r=output.results)


STAGE = Stage(name="throwaway_slider", requires=(), provides=(),
              applies=lambda scene: None if scene.engine.mechanism == NAME else "another mechanism",
              run=run,
              answer_columns=(AnswerColumn("throwaway_stroke_mm", "stroke_m", "mm", factor=1e3),),
              presentation=StagePresentation(
                  title_key="throwaway_slider.title", render=render,
                  template_dir=HERE / "templates",
                  symbols={"travel": Symbol("h", {"en": "t"}, "unit.mm")}))


@hookimpl
def crankdyn_mechanisms():
    return [MECHANISM]


@hookimpl
def crankdyn_stages():
    return [STAGE]


@hookimpl
def crankdyn_catalogs():
    return [Catalog(language=p.stem.rsplit(".", 1)[-1], path=p) for p in sorted((HERE / "i18n").glob("*.toml"))]
'''

TEMPLATE = "<p class=\"throwaway\">{{ _('throwaway_slider.body') }}</p>\n{{ eq('<i>h</i><sub>t</sub> = 2<i>R</i>') }}\n"
CATALOG = """[throwaway_slider]
title = "Stroke of the throw-away slider"
body = "The stroke follows from the crank radius."

[symbol.throwaway_slider]
travel = "stroke of the throw-away slider"

[plausibility]
throwaway_slow = "The engine turns slowly ({rpm} rpm)."
"""


def _tree_digest(*folders: Path) -> str:
    digest = hashlib.sha256()
    for folder in folders:
        for path in sorted(
            p for p in folder.rglob("*") if p.is_file() and "__pycache__" not in p.parts
        ):
            digest.update(str(path.relative_to(ROOT)).encode() + path.read_bytes())
    return digest.hexdigest()


@pytest.fixture
def throwaway_registry(tmp_path, monkeypatch):
    package = tmp_path / "throwaway_mechanism_plugin"
    (package / "templates" / "sections").mkdir(parents=True)
    (package / "i18n").mkdir()
    (package / "__init__.py").write_text("", encoding="utf-8")
    (package / "plugin.py").write_text(textwrap.dedent(PLUGIN), encoding="utf-8")
    (package / "templates" / "sections" / "throwaway_slider.html.j2").write_text(
        TEMPLATE, encoding="utf-8"
    )
    for language in ("en", "uk", "ru"):  # English texts in every language: enough for this test
        (package / "i18n" / f"throwaway_slider.{language}.toml").write_text(
            CATALOG, encoding="utf-8"
        )
    monkeypatch.syspath_prepend(str(tmp_path))
    plugin = importlib.import_module("throwaway_mechanism_plugin.plugin")
    return collect(plugin_manager(extra_plugins=[plugin]))


def _scene(changes: dict):
    data = modified(
        "kinematics-only",
        {"engine": {"mechanism": "throwaway_slider", **changes}, "report": {"language": "en"}},
    )
    return scene_from_dict(data, base_dir=examples_dir())


def test_a_throw_away_mechanism_is_drawn_with_its_symbols_rules_and_answer_column(
    throwaway_registry,
):
    before = _tree_digest(ROOT / "src", ROOT / "templates")
    registry = throwaway_registry
    # λ = 0.6 (above the crank-slider's 0.45) at 800 rpm: the core's rule and the plugin's own
    scene = _scene({"rod_length": "83.3 mm", "rpm": 800})  # λ = 50/83.3 = 0.6
    keys = [key for key, _ in warnings(scene, registry)]
    assert keys == ["plausibility.rod_ratio", "plausibility.throwaway_slow"]
    assert warnings(scene, Registry()) == []  # without the plugin: none of its rules holds

    result, files = run_and_render(scene, registry, ["html", "json"])
    # drawn by the built-in drawing stage from the run's registry (it has no piston motion of its own)
    assert "drawing_linkage" in result.stages_run and "throwaway_slider" in result.stages_run
    assert any(name.startswith("figures/") and name.endswith("_scheme.svg") for name in files)
    html = files["report.html"].decode("utf-8")
    # its letter h_t in the list of symbols with its meaning from the plugin's catalog
    assert (
        '<span class="symbol"><i>h</i><sub>t</sub></span> – <span class="meaning">'
        "stroke of the throw-away slider"
    ) in html
    # its rule's warning in its own words, from its own catalog
    assert (
        console_lines(warnings(scene, registry, result), registry)[1]
        == "The engine turns slowly (800 rpm)."
    )

    # its answer column, read from results.json: the scene's stroke, 100 mm
    columns = answer_key.answer_columns(registry)
    assert [c.name for c in columns if c.stage == "throwaway_slider"] == ["throwaway_stroke_mm"]
    answers = answer_key.answers(outputs.results_document(result), columns)
    assert answers["throwaway_stroke_mm"] == pytest.approx(100.0, rel=1e-9)
    assert _tree_digest(ROOT / "src", ROOT / "templates") == before


def test_the_default_registry_does_not_know_the_throw_away_mechanism(throwaway_registry):
    """The drawing stage has no registry of its own: only the run's registry knows the mechanism."""
    assert "throwaway_slider" in throwaway_registry.mechanisms
    assert "throwaway_slider" not in default_registry().mechanisms
