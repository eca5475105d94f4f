"""Figures of their inputs alone (and the animation's fixed parts) drawn once per process (a
batch worker's next variant), the error study's kinematics forms and step timings measured once
per mechanism, the answer key's workbook cells."""

from __future__ import annotations

import io

import pytest
from openpyxl import load_workbook

from crankdyn.batch.variants import _Sheet
from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.output.writers import xlsx_bytes
from crankdyn.plugin.registry import default_registry
from crankdyn.report import figure_memo, figures
from crankdyn.report.context import draw_figures
from crankdyn.report.document import render_html
from crankdyn.scene.model import load_scene

REGISTRY = default_registry()
# the figures of the mechanism's geometry alone: the scheme, the positions, the rod's centre of
# mass path, the crank diagrams, the vector models (drawn to the scale of each order's amplitude)
SHARED = ("scheme", "positions", "rod_cm", "crank_diagrams", "vector_models")


def _figures(monkeypatch, language: str = "en", **overrides) -> tuple[dict, list[str]]:
    """(figure key -> SVG of the :data:`SHARED` figures, the keys drawn by matplotlib) of the
    drawing and balancing sections of petrol-1cyl (and kinematics, which they need)."""
    scene = load_scene(examples_dir() / "petrol-1cyl.toml", overrides or None)
    scene = scene.model_copy(
        update={"report": scene.report.model_copy(update={"language": language})}
    )
    rendered = render_html(run_scene(scene, REGISTRY, ["drawing", "balancing"]), REGISTRY)
    drawn: list[str] = []
    to_svg = figures.to_svg

    def counted(fig):
        drawn.append(next(f.key for f in rendered.figures if f._figure is fig))
        return to_svg(fig)

    monkeypatch.setattr(figures, "to_svg", counted)
    draw_figures(rendered.figures, workers=1)
    monkeypatch.setattr(figures, "to_svg", to_svg)
    return {f.key: f.svg for f in rendered.figures if f.key.startswith(SHARED)}, drawn


@pytest.fixture
def empty_memo(monkeypatch):
    monkeypatch.setattr(figure_memo, "_svgs", {})
    monkeypatch.setattr(figure_memo, "_values", {})
    monkeypatch.setattr(figure_memo, "_translators", {})


def test_a_variant_of_the_same_geometry_takes_the_drawn_svgs(monkeypatch, empty_memo):
    first, drawn_first = _figures(monkeypatch)
    assert set(SHARED) <= set(drawn_first)
    # another speed and piston mass: the scheme and positions are of the geometry alone
    second, drawn_second = _figures(
        monkeypatch, engine={"rpm": 3000}, masses={"piston_group": "0.61 kg"}
    )
    assert not [k for k in drawn_second if k.startswith(SHARED)]
    assert "piston" in drawn_second  # its velocity and acceleration change with the speed
    assert second == first
    figure_memo._svgs.clear()  # drawn afresh: the same bytes
    fresh, drawn_fresh = _figures(monkeypatch, engine={"rpm": 3000})
    assert set(drawn_fresh) >= set(first) and fresh == first


def test_another_bore_or_language_is_drawn_again(monkeypatch, empty_memo):
    first, _ = _figures(monkeypatch)
    wider, drawn = _figures(monkeypatch, engine={"bore": "90 mm"})
    assert {"scheme", "positions"} <= set(drawn) and wider["scheme"] != first["scheme"]
    ukrainian, drawn = _figures(monkeypatch, language="uk")
    assert {"scheme", "positions"} <= set(drawn) and ukrainian["scheme"] != first["scheme"]


def test_the_animations_fixed_parts_are_drawn_once_per_geometry(monkeypatch, empty_memo):
    from crankdyn.report import mechanism_drawing as md

    drawn = []
    static_svg = md._static_svg

    def counted(*args):
        drawn.append(args)
        return static_svg(*args)

    monkeypatch.setattr(md, "_static_svg", counted)

    def animation(**overrides):
        scene = load_scene(examples_dir() / "petrol-1cyl.toml", overrides or None)
        output = run_scene(scene, REGISTRY, ["drawing"]).outputs["drawing"]
        return md.animation_svg(output.artifacts["animation"])

    first = animation()
    assert animation(engine={"rpm": 3000}) == first and len(drawn) == 1  # the same mechanism
    wider = animation(engine={"bore": "90 mm"})
    assert len(drawn) == 2 and wider[0] != first[0]
    figure_memo._values.clear()  # drawn afresh: the same bytes
    assert animation() == first and len(drawn) == 3


def test_a_figure_of_unpicklable_inputs_is_not_kept():
    builder = figure_memo.MemoFigure(lambda x: x, lambda: None)
    assert builder.digest is None
    figure_memo.keep(None, None, None, b"<svg/>")
    assert figure_memo.svg(None, None, None) is None


def test_the_kinematics_forms_are_measured_once_per_mechanism():
    from crankdyn_builtin.numerics import compute

    first = compute._kinematics_forms(0.04, 0.27, 3)
    first[0]["form"] = "changed by its caller"
    second = compute._kinematics_forms(0.04, 0.27, 3)
    assert second[0]["form"] == "two_term"
    assert [r["time_per_evaluation_s"] for r in second[1:]] == [
        r["time_per_evaluation_s"] for r in first[1:]
    ]
    other = compute._kinematics_forms(0.045, 0.27, 3)
    assert other[-1]["displacement_error_max_m"] != second[-1]["displacement_error_max_m"] or (
        other[0]["displacement_error_max_m"] != second[0]["displacement_error_max_m"]
    )


def test_the_steps_are_timed_once_per_mechanism(monkeypatch):
    """Another speed or piston mass takes the timings of the first run of that mechanism (its
    errors and per-call overhead are its own); another bore is timed again."""
    from crankdyn_builtin.numerics import compute

    compute._kept_timings.cache_clear()
    timed = []
    time_steps = compute.time_steps

    def counted(scene, *args, **kwargs):
        timed.append(scene.engine.rpm)
        return time_steps(scene, *args, **kwargs)

    monkeypatch.setattr(compute, "time_steps", counted)

    def numerics(**overrides):
        scene = load_scene(examples_dir() / "petrol-1cyl.toml", overrides or None)
        return run_scene(scene, REGISTRY, ["numerics"]).outputs["numerics"].results

    first = numerics()
    slower = numerics(engine={"rpm": 3000}, masses={"piston_group": "0.61 kg"})
    assert timed == [5600.0]
    assert [s["time_s"] for s in slower["steps"]] == [s["time_s"] for s in first["steps"]]
    assert [s["mean_torque_Nm"] for s in slower["steps"]] != [
        s["mean_torque_Nm"] for s in first["steps"]
    ]
    assert slower["per_call_overhead_s"] is not None
    numerics(engine={"bore": "90 mm"})
    assert len(timed) == 2


def test_the_answer_key_sheet_holds_each_column_as_one_kind_of_number():
    rows = [["v01", 1, 4000, None, True, "0.41 kg"], ["v02", 2, 4100, 2.5, False, 3]]
    header = ["variant", "row", "engine.rpm", "result", "flag", "mixed"]
    sheet = load_workbook(io.BytesIO(xlsx_bytes([("key", _Sheet(rows, header))]))).active
    values = [[c.value for c in r] for r in sheet.iter_rows(min_row=2)]
    assert values == [["v01", 1, 4000, None, True, "0.41 kg"], ["v02", 2, 4100, 2.5, False, 3]]
    # a whole-number column with an empty cell holds floats, as a data frame does
    assert list(_Sheet([[1], [None], [3]], ["x"]).itertuples()) == [(1.0,), (None,), (3.0,)]
    assert list(_Sheet([[1], [3]], ["x"]).itertuples()) == [(1,), (3,)]
    assert list(_Sheet([[True], [None]], ["x"]).itertuples()) == [(True,), (None,)]
