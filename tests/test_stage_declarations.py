"""Stages declare the figures and tables they produce (``Stage.figures``, ``Stage.tables``):
the core refuses a figure or a table not declared, naming the stage; every bundled example draws and
writes only what its stages declare."""

from __future__ import annotations

import matplotlib.pyplot as plt
import pytest
from conftest import example_data, modified
from markupsafe import Markup

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import plan, run_plan, run_scene
from crankdyn.errors import PluginError
from crankdyn.plugin.registry import Registry, default_registry
from crankdyn.plugin.types import Stage, StageOutput, StagePresentation, declared
from crankdyn.report.context import RenderContext
from crankdyn.report.document import _environment, render_html
from crankdyn.report.figures import new_figure
from crankdyn.report.i18n import available_languages, translator
from crankdyn.report.typeset import symbol_table
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()
EXAMPLES = sorted(p.stem for p in examples_dir().glob("*.toml"))
# A 5° grid, one timed repeat over two angle steps in the numerics study, one tolerance in the torsional
# solver comparison: the same sections, figures and tables (which of them appear does not depend on
# the grid or the repeats), in a fraction of the time.
LIGHTER = {
    "analysis": {"angle_step_deg": 5.0},
    "numerics": {"repeats": 1, "steps_deg": [10.0, 5.0]},
    "torsion": {"compare_rtols": [1e-3], "reference_rtol": 1e-5, "compare_fraction": 0.1},
}


def test_declared_names_and_patterns():
    assert declared("speed", ("speed", "modes")) and not declared("speeds", ("speed",))
    assert declared("wear_pin4", ("wear_pin*",)) and not declared("pin4", ("wear_pin*",))
    assert not declared("anything", ())


def _throwaway(figures=(), tables=(), draw="plot", table="main"):
    def run(scene, inputs):
        return StageOutput(results={"x": 1.0}, tables={table: {"x": [1.0]}} if table else {})

    def render(output, ctx):
        fig, ax = new_figure(4, 3)
        ax.plot([0, 1], [0, 1])
        return ctx.figure(fig, "a figure", draw)

    return Stage(
        name="throwaway",
        requires=(),
        provides=(),
        applies=lambda s: None,
        run=run,
        tables=tables,
        presentation=StagePresentation(title_key="throwaway.title", render=render, figures=figures),
    )


def _registry(stage: Stage) -> Registry:
    registry = Registry(mechanisms=REGISTRY.mechanisms, catalogs=REGISTRY.catalogs)
    registry.stages[stage.name] = stage
    return registry


def test_a_table_not_declared_is_refused_naming_the_stage_and_the_table():
    scene = scene_from_dict(example_data("kinematics-only"))
    stage = _throwaway(tables=("other",))
    with pytest.raises(
        PluginError, match=r"stage 'throwaway' returned the tables \['main'\].*Stage.tables"
    ):
        run_plan(scene, plan(scene, _registry(stage)))
    assert (
        run_plan(scene, plan(scene, _registry(_throwaway(tables=("ma*",)))))
        .outputs["throwaway"]
        .tables
    )


def test_a_figure_not_declared_is_refused_naming_the_stage_and_the_figure():
    scene = scene_from_dict(example_data("kinematics-only"))
    result = run_scene(scene, _registry(_throwaway(figures=("scheme",), tables=("main",))))
    with pytest.raises(
        PluginError, match=r"stage 'throwaway' drew the figure 'plot'.*StagePresentation.figures"
    ):
        render_html(result, _registry(result.plan.order[0]))
    result = run_scene(scene, _registry(_throwaway(figures=("plot",), tables=("main",))))
    report = render_html(result, _registry(result.plan.order[0]))
    assert [f.name for f in report.figures] == ["fig_2_1_plot.svg"]


class _Recording(RenderContext):
    """Records (stage, figure name) and checks it as ``figure`` does, without writing the SVG."""

    drawn: list

    def figure(
        self, fig, caption: str, name: str, see: str | None = None, see_params: dict | None = None
    ) -> Markup:
        self.check_figure_declared(name)
        self.drawn.append((self.stage_name, name))
        plt.close(
            fig() if callable(fig) else fig
        )  # a builder is called: every example's figures are built
        return Markup("")


def _example(example: str):
    """Every stage of the example run, and each section rendered with the figures recorded."""
    data = example_data(example)
    lighter = {
        table: changes
        for table, changes in LIGHTER.items()
        if table in data or (table == "numerics" and "cycle" in data)
    }
    scene = scene_from_dict(modified(example, lighter), base_dir=examples_dir())
    result = run_scene(scene, REGISTRY, None, available_languages())
    ctx = _Recording(
        t=translator(scene.report.language, REGISTRY.catalogs),
        env=_environment(REGISTRY, result),
        table_step_deg=scene.analysis.table_step_deg,
        cycle_deg=scene.engine.cycle_deg,
        scene=scene,
        symbols=symbol_table(REGISTRY.stages.values()),  # the stages' own letters, as a report's
    )
    ctx.drawn = []
    for number, stage in enumerate(result.plan.order, start=2):
        ctx.start_section(number, stage.name, stage.presentation.figures)
        ctx.conclusions = []
        stage.presentation.render(result.outputs[stage.name], ctx)
    return result, ctx.drawn


@pytest.mark.parametrize("example", EXAMPLES)
def test_every_example_draws_and_writes_only_what_its_stages_declare(example):
    result, drawn = _example(example)
    stages = {s.name: s for s in result.plan.order}
    assert drawn, "no figure drawn"
    undeclared = [
        (stage, name)
        for stage, name in drawn
        if not declared(name, stages[stage].presentation.figures)
    ]
    assert not undeclared, undeclared
    tables = [
        (stage, name) for stage, output in result.outputs.items() for name in output.tables.keys()
    ]
    assert not [(stage, name) for stage, name in tables if not declared(name, stages[stage].tables)]


def test_every_built_in_stage_declares_its_figures_and_tables():
    """A section that draws declares its figures; the declarations are names (or patterns), not empty."""
    for stage in REGISTRY.stages.values():
        assert stage.presentation.figures, f"{stage.name} declares no figure"
        assert all(
            isinstance(n, str) and n for n in (*stage.presentation.figures, *stage.tables)
        ), stage.name
        assert stage.tables or stage.name.startswith("drawing"), f"{stage.name} declares no table"
