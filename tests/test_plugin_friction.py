"""Mistakes a plugin author makes are reported, not passed over: a ``requires`` key no registered
stage provides (a typo) refuses the plan, naming the stage, the key and the known keys; ``crankdyn
report`` warns about catalog keys missing in its language; a batch warns, once, about an answer-key
column whose key its stage's results lack."""

from __future__ import annotations

import dataclasses

import pytest
from conftest import example_data, write_scene

import crankdyn.batch.variants
import crankdyn.plugin.registry
from crankdyn.batch.answer_key import KeyColumn, absent, unanswered
from crankdyn.cli import examples_dir, main, missing_translations_line
from crankdyn.engine.orchestrator import plan
from crankdyn.errors import PluginError
from crankdyn.plugin.registry import Registry, default_registry
from crankdyn.plugin.types import (
    SERVICE_RUNNER,
    AnswerColumn,
    Stage,
    StageOutput,
    StagePresentation,
)
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()


def _stage(requires, applies=lambda scene: None, name="friction"):
    return Stage(
        name=name,
        requires=tuple(requires),
        provides=(),
        applies=applies,
        run=lambda scene, inputs: StageOutput(results={"x": 1.0}),
        presentation=StagePresentation(title_key="friction.title", render=lambda output, ctx: ""),
    )


def _with(*stages: Stage) -> Registry:
    registry = dataclasses.replace(
        REGISTRY, stages=dict(REGISTRY.stages), owner=dict(REGISTRY.owner)
    )
    for stage in stages:
        registry.stages[stage.name] = stage
        registry.owner["stage:" + stage.name] = "test"
    return registry


def test_a_requirement_no_registered_stage_provides_refuses_the_plan():
    scene = scene_from_dict(example_data("petrol-1cyl"))
    with pytest.raises(PluginError) as caught:
        plan(scene, _with(_stage(["kinematics", "force"])))
    message = str(caught.value)
    assert (
        "stage 'friction' requires 'force', which no registered stage provides; did you mean 'forces'?"
        in message
    )
    assert "Known keys" in message and "forces" in message.split("Known keys")[1]
    assert "'kinematics'" not in message  # a key that is provided is not named as unknown
    with pytest.raises(PluginError, match="Stage.services, not Stage.requires"):
        plan(scene, _with(_stage([SERVICE_RUNNER])))


def test_a_requirement_provided_by_a_stage_that_does_not_apply_still_leaves_the_stage_out():
    # kinematics-only has no cycle: the stages providing the gas pressure and the forces do not apply
    scene = scene_from_dict(example_data("kinematics-only"))
    the_plan = plan(scene, _with(_stage(["forces"])))
    assert "friction" not in [s.name for s in the_plan.order]
    assert "needs 'forces'" in the_plan.skipped["friction"]


def test_the_command_line_says_so_in_one_message_with_exit_2(tmp_path, monkeypatch, capsys):
    scene = write_scene(tmp_path / "s.toml", example_data("kinematics-only"))
    monkeypatch.setattr(
        crankdyn.plugin.registry, "default_registry", lambda: _with(_stage(["force"]))
    )
    assert main(["report", str(scene), "-o", str(tmp_path / "out"), "--format", "json", "-q"]) == 2
    err = capsys.readouterr().err
    assert "stage 'friction' requires 'force'" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()


# ------------------------------------------------------------------ missing translations (crankdyn report)


def test_the_report_command_warns_once_about_keys_missing_in_its_language(
    tmp_path, monkeypatch, capsys
):
    # the stage's title_key is in no catalog: the report is written, with a warning naming it
    scene = write_scene(tmp_path / "s.toml", example_data("kinematics-only"))
    monkeypatch.setattr(
        crankdyn.plugin.registry, "default_registry", lambda: _with(_stage(["kinematics"]))
    )
    assert main(["report", str(scene), "-o", str(tmp_path / "out"), "--format", "html", "-q"]) == 0
    warnings = [line for line in capsys.readouterr().err.splitlines() if "no translation" in line]
    assert warnings == [
        "crankdyn: warning: the report in 'en' has no translation for 1 key(s): friction.title"
    ]
    assert (tmp_path / "out" / "report.html").is_file()


def test_a_report_without_missing_keys_gives_no_warning(tmp_path, capsys):
    scene = write_scene(tmp_path / "s.toml", example_data("kinematics-only"))
    assert (
        main(
            [
                "report",
                str(scene),
                "-o",
                str(tmp_path / "out"),
                "--format",
                "html",
                "-q",
                "--lang",
                "uk",
            ]
        )
        == 0
    )
    assert "no translation" not in capsys.readouterr().err


def test_the_missing_keys_line_names_ten_and_counts_the_rest():
    line = missing_translations_line("ru", {f"k{i:02d}" for i in range(13)})
    assert line.endswith("k00, k01, k02, k03, k04, k05, k06, k07, k08, k09 and 3 more")
    assert "'ru'" in line and "13 key(s)" in line


# ------------------------------------------------------------------ answer-key columns whose key is absent


def test_an_answer_column_whose_key_is_not_in_the_results_is_warned_about_once_per_batch(
    tmp_path, monkeypatch, capsys
):
    kinematics = REGISTRY.stages["kinematics"]
    typo = dataclasses.replace(
        kinematics,
        answer_columns=(*kinematics.answer_columns, AnswerColumn("v_top_m_s", "v_top_m_s", "m/s")),
    )
    typo_registry = _with(typo)
    # the batch command builds its run's registry from the installed plugins; forked workers
    # inherit it
    monkeypatch.setattr(crankdyn.batch.variants, "default_registry", lambda: typo_registry)
    variants = tmp_path / "v.csv"
    variants.write_text("variant,engine.rpm\na,4000\nb,5000\n", encoding="utf-8")
    out = tmp_path / "out"
    assert (
        main(
            [
                "batch",
                str(variants),
                "--base",
                str(examples_dir() / "kinematics-only.toml"),
                "-o",
                str(out),
                "--format",
                "json",
                "--jobs",
                "1",
                "-q",
            ]
        )
        == 0
    )
    warnings = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert len(warnings) == 1 and warnings[0].startswith(
        "crankdyn batch: warning: answer-key column 'v_top_m_s' left out: no variant's 'kinematics' results hold "
        "'v_top_m_s' (a typo in AnswerColumn.key"
    )
    header = (out / "answer_key.csv").read_text(encoding="utf-8").splitlines()[0]
    assert "v_max_m_s" in header and "v_top_m_s" not in header


def test_a_key_absent_in_some_variants_only_or_of_a_stage_that_did_not_run_is_not_warned_about():
    columns = [
        KeyColumn("forces", AnswerColumn("p_MPa", "peak.p_Pa")),
        KeyColumn("kinematics", AnswerColumn("v", "v")),
    ]
    ran = {
        "stages_run": ["forces", "kinematics"],
        "forces": {"peak": {"p_Pa": None}},
        "kinematics": {},
    }
    assert absent(ran, columns) == ["v"]  # a key present with no number is not absent
    assert (
        absent({"stages_run": ["kinematics"], "kinematics": {"v": 1.0}}, columns) == []
    )  # forces did not run
    assert unanswered(columns, [(["kinematics"], ["v"]), (["kinematics"], [])]) == []
    [warning] = unanswered(columns, [(["kinematics"], ["v"]), (["forces"], [])])
    assert warning.startswith(
        "answer-key column 'v' left out: no variant's 'kinematics' results hold 'v'"
    )


@pytest.mark.parametrize("example", ["diesel-rk-trace.toml", "petrol-1cyl.toml"])
def test_every_answer_column_of_a_bundled_example_is_in_its_results_or_stated_as_not_given(example):
    """The batch's warning is for a typo, not for a result a scene does not give: a measured
    pressure trace has no end-of-compression pressure, and the indicator stage states it as None
    (the cell stays empty without a warning) instead of leaving the key out."""
    from crankdyn.batch.answer_key import answer_columns
    from crankdyn.engine.orchestrator import run_scene
    from crankdyn.output.writers import results_document
    from crankdyn.scene.model import load_scene

    document = results_document(run_scene(load_scene(examples_dir() / example), REGISTRY, None, ()))
    assert absent(document, answer_columns(REGISTRY)) == []
    p_c = document["indicator"]["compression_end_pressure_Pa"]
    assert p_c is None if "trace" in example else 1e6 < p_c < 5e6  # a petrol engine's: 1-2 MPa
