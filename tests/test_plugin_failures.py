"""A third-party plugin that fails is named: its import, a hook, a stage's ``applies``, ``run`` or
``render`` raising or returning what the hook types do not allow, or a stage that never ends, is
reported as ``plugin X (stage Y): what happened`` with exit 2 and nothing written. A plugin that
cannot be imported is listed as broken by ``crankdyn plugins`` and the other commands work without
it (or refuse, naming it, when the scene needs what it may provide)."""

from __future__ import annotations

import dataclasses
import math
import os
import pickle
import subprocess
import sys
import textwrap
import types
from pathlib import Path

import numpy as np
import pytest
from conftest import example_data, modified, write_scene

import crankdyn.api
import crankdyn.plugin.registry
from crankdyn import cli
from crankdyn.engine.orchestrator import run_scene
from crankdyn.errors import PluginError, PluginFailure, Problem, SceneError, StageTimeLimit
from crankdyn.output.pipeline import run_and_render
from crankdyn.plugin.contracts import KINEMATICS, PistonMotion
from crankdyn.plugin.guard import (
    DEFAULT_STAGE_TIMEOUT_S,
    MAX_STAGE_TIMEOUT_S,
    check_stage_output,
    stage_time_limit,
)
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.registry import collect, plugin_manager
from crankdyn.plugin.types import Catalog, Mechanism, Stage, StageOutput, StagePresentation
from crankdyn.scene.model import scene_from_dict

SCENE = "kinematics-only"


def _stroke(scene, inputs) -> StageOutput:
    return StageOutput(results={"stroke_m": 2 * inputs[KINEMATICS].crank_radius_m})


def _stage(name: str = "extra", render=lambda output, ctx: "<p>extra</p>", **changes) -> Stage:
    """A stage after the kinematics that works; ``changes`` (and ``render``) replace its parts
    with broken ones."""
    fields = dict(
        name=name,
        requires=(KINEMATICS,),
        provides=(),
        applies=lambda scene: None,
        run=_stroke,
        presentation=StagePresentation(title_key="extra.title", render=render),
    )
    fields.update(changes)
    return Stage(**fields)


def _plugin(name: str, stages=(), mechanisms=(), stages_hook=None) -> types.ModuleType:
    """A plugin module named ``name`` registering ``stages`` and ``mechanisms`` (or, with
    ``stages_hook``, whatever that function returns or raises)."""
    module = types.ModuleType(name)
    module.crankdyn_stages = hookimpl(stages_hook or (lambda: list(stages)))
    module.crankdyn_mechanisms = hookimpl(lambda: list(mechanisms))
    return module


def _registry(*plugins):
    return collect(plugin_manager(extra_plugins=plugins))


def _scene(changes: dict | None = None):
    return scene_from_dict(modified(SCENE, changes or {}))


def _failure(registry, stages=("extra",), formats=("json",), scene=None) -> PluginFailure:
    with pytest.raises(PluginFailure) as caught:
        run_and_render(scene or _scene(), registry, list(formats), list(stages))
    return caught.value


# --------------------------------------------------------------------------- the stage's calls
def test_a_working_throwaway_stage_runs_so_the_failures_below_are_its_breakages():
    registry = _registry(_plugin("fine_plugin", [_stage()]))
    result, files = run_and_render(_scene(), registry, ["json"], ["extra"])
    # the scene's stroke, 100 mm, is twice the crank radius the kinematics stage found
    assert result.outputs["extra"].results["stroke_m"] == pytest.approx(0.100, rel=1e-12)
    assert "results.json" in files


@pytest.mark.parametrize(
    ("changes", "expected"),
    [
        (dict(applies=lambda scene: 1 / 0), "applies raised ZeroDivisionError: division by zero"),
        (dict(applies=lambda scene: 42), "applies returned 42; expected None"),
        (dict(applies=lambda scene: False), "applies returned False; expected None"),
        (dict(run=lambda scene, inputs: {}["missing"]), "run raised KeyError: 'missing'"),
        (dict(run=lambda scene, inputs: None), "run returned None; expected a StageOutput"),
        (
            dict(run=lambda scene, inputs: StageOutput(data={"stray": 1})),
            "run returned data with the keys ['stray']; the stage declares provides=[]",
        ),
        (
            dict(run=lambda scene, inputs: StageOutput(results={"x": object()})),
            "results['x']: <object object",
        ),
        (
            dict(run=lambda scene, inputs: StageOutput(results={1: 2.0})),
            "results: the key 1 is not a str",
        ),
        (
            dict(
                run=lambda scene, inputs: StageOutput(tables={"extra": {"a": [1, 2], "b": [1]}}),
                tables=("extra",),
            ),
            "tables['extra']: columns of different lengths [1, 2]",
        ),
        (
            dict(run=lambda scene, inputs: StageOutput(tables={"other": {"a": [1]}})),
            "tables['other']: not declared in Stage.tables",
        ),
        (
            dict(run=lambda scene, inputs: StageOutput(notes=["extra.note"])),
            "notes = ['extra.note']",
        ),
    ],
)
def test_a_stage_that_raises_or_returns_garbage_is_named(changes, expected):
    failure = _failure(_registry(_plugin("bad_plugin", [_stage(**changes)])))
    assert str(failure).startswith("plugin 'bad_plugin' (stage 'extra'): ")
    assert expected in str(failure)
    assert (failure.plugin, failure.where) == ("bad_plugin", "stage 'extra'")


@pytest.mark.parametrize(
    ("render", "expected"),
    [
        (lambda output, ctx: output.results["absent"], "render raised KeyError: 'absent'"),
        (lambda output, ctx: 5, "render returned 5; expected the section's HTML as a str, or None"),
    ],
)
def test_a_section_that_fails_to_render_is_named(render, expected):
    failure = _failure(_registry(_plugin("bad_render", [_stage(render=render)])), formats=["html"])
    assert str(failure) == f"plugin 'bad_render' (stage 'extra'): {expected}"


def test_a_scene_error_a_stage_raises_is_the_scenes_and_passes_as_it_is():
    def refuse(scene, inputs):
        raise SceneError(Problem("extra.gap", 3, "at most 2"))

    with pytest.raises(SceneError) as caught:
        registry = _registry(_plugin("strict", [_stage(run=refuse)]))
        run_and_render(_scene(), registry, ["json"], ["extra"])
    assert "extra.gap = 3: at most 2" in str(caught.value)


def _nan_motion(scene, inputs):
    angles = np.arange(0.0, 720.0, 10.0)
    velocity = np.sin(np.radians(angles))
    velocity[[3, 7]] = np.nan
    zeros = np.zeros_like(angles)
    motion = PistonMotion(angles, zeros, velocity, zeros, None, 0.05, 314.0, "exact")
    return StageOutput(data={KINEMATICS: motion})


def _yoke_plugin(run) -> types.ModuleType:
    def applies(scene):
        return None if scene.engine.mechanism == "nan_yoke" else "not a yoke"

    stage = Stage(
        name="yoke_kinematics",
        requires=(),
        provides=(KINEMATICS,),
        applies=applies,
        run=run,
        presentation=StagePresentation(title_key="yoke.title", render=lambda output, ctx: None),
    )
    return _plugin("yoke_plugin", [stage], [Mechanism(name="nan_yoke", summary="a yoke")])


def test_contract_data_holding_nan_or_of_the_wrong_type_is_named():
    scene = _scene({"engine": {"mechanism": "nan_yoke"}})
    failure = _failure(_registry(_yoke_plugin(_nan_motion)), ["yoke_kinematics"], scene=scene)
    assert str(failure).startswith(
        "plugin 'yoke_plugin' (stage 'yoke_kinematics'): run returned "
        "data['kinematics']: piston_velocity_m_s = "
    )
    assert "2 value(s) not finite (NaN or infinite)" in str(failure)
    listed = _yoke_plugin(lambda scene, inputs: StageOutput(data={KINEMATICS: [1.0]}))
    failure = _failure(_registry(listed), ["yoke_kinematics"], scene=scene)
    assert "data['kinematics']: [1.0] is not a crankdyn.plugin.contracts.PistonMotion" in str(
        failure
    )


@pytest.mark.parametrize("name", ["petrol-1cyl", "kinematics-only"])
def test_the_built_in_stages_outputs_pass_the_checks_a_third_party_output_gets(name):
    registry = crankdyn.plugin.registry.default_registry()
    result = run_scene(scene_from_dict(example_data(name)), registry)
    assert len(result.outputs) >= 2
    for stage in result.plan.order:
        check_stage_output(stage, result.study_output(stage.name), "builtin")  # raises if not


def test_a_built_in_stages_own_error_stays_an_internal_error():
    registry = crankdyn.plugin.registry.default_registry()
    assert not any(PluginFailure.__name__ in repr(s) for s in registry.stages.values())
    stage = registry.stages["kinematics"]
    with pytest.raises(AttributeError):  # not a PluginFailure: the program's own fault
        stage.run(None, {})


# --------------------------------------------------------------------------- hooks and imports
def _scene_error():
    raise SceneError(Problem("x", 1, "none"))


@pytest.mark.parametrize(
    ("hook", "expected"),
    [
        (lambda: 1 / 0, "the hook raised ZeroDivisionError: division by zero"),
        (lambda: 5, "the hook returned 5; expected a list"),
        (lambda: sys.exit(3), "the hook raised SystemExit: 3"),
        (_scene_error, "the hook raised SceneError: invalid scene: 1 problem(s) - x = 1: none"),
        (lambda: [object()], "the hook returned <object object"),
        (
            lambda: [_stage(requires="kinematics")],
            "stage 'extra': requires = 'kinematics'; expected a tuple of str",
        ),
        (
            lambda: [_stage(run="not a function")],
            "stage 'extra': run = 'not a function'; expected a function",
        ),
    ],
)
def test_a_plugin_whose_hook_fails_is_left_out_and_listed_as_broken(hook, expected):
    registry = _registry(
        _plugin("hooked", stages_hook=hook), _plugin("fine_plugin", [_stage("fine")])
    )
    assert registry.broken["hooked"].startswith("plugin 'hooked' (hook crankdyn_stages): ")
    assert expected in registry.broken["hooked"]
    assert "fine" in registry.stages and "kinematics" in registry.stages  # the others work
    assert not any(owner == "hooked" for owner in registry.owner.values())


class _Options:
    """Not a pydantic model."""


def test_a_plugin_whose_catalog_or_model_is_unusable_is_left_out(tmp_path):
    bad_toml = tmp_path / "extra.en.toml"
    bad_toml.write_text('[extra]\ntitle = "Extra\n', encoding="utf-8")
    not_texts = tmp_path / "other.en.toml"
    not_texts.write_text("[other]\ntitle = 5\n", encoding="utf-8")
    cataloged = [types.ModuleType(name) for name in ("bad_toml", "not_texts", "missing")]
    for module, path in zip(
        cataloged, (bad_toml, not_texts, tmp_path / "absent.toml"), strict=True
    ):
        module.crankdyn_catalogs = hookimpl(lambda path=path: [Catalog("en", path)])
    mechanism = Mechanism(name="m", summary="m", params_model=_Options)
    modelled = _plugin("modelled", mechanisms=[mechanism])
    rod = _plugin("rod", mechanisms=[Mechanism(name="r", summary="r", needs_rod="no")])
    registry = _registry(*cataloged, modelled, rod)
    assert "mechanism 'r': needs_rod = 'no'; expected True or False" in registry.broken["rod"]
    assert "not a readable TOML file (TOMLDecodeError: " in registry.broken["bad_toml"]
    assert "other.title = 5 is not a text" in registry.broken["not_texts"]
    assert "absent.toml' is not a file" in registry.broken["missing"]
    assert (
        "params_model = <class 'test_plugin_failures._Options'>; expected a pydantic"
        in registry.broken["modelled"]
    )
    assert all(str(c.path) not in {str(bad_toml), str(not_texts)} for c in registry.catalogs)
    assert registry.catalogs  # the built-in ones


def _install(site: Path, name: str, source: str) -> None:
    """A distribution ``name`` with one module and a ``crankdyn`` entry point, as pip leaves it."""
    (site / f"{name}.py").write_text(textwrap.dedent(source), encoding="utf-8")
    info = site / f"{name}-0.1.dist-info"
    info.mkdir(parents=True)
    metadata = f"Metadata-Version: 2.1\nName: {name}\nVersion: 0.1\n"
    (info / "METADATA").write_text(metadata, encoding="utf-8")
    (info / "entry_points.txt").write_text(f"[crankdyn]\n{name} = {name}\n", encoding="utf-8")


BROKEN_IMPORT = """
    import crankdyn_friction_dependency_not_installed
"""


@pytest.fixture()
def broken_install(tmp_path, monkeypatch):
    site = tmp_path / "site"
    site.mkdir()
    _install(site, "friction_plugin", BROKEN_IMPORT)
    monkeypatch.syspath_prepend(str(site))
    return site


def test_a_plugin_that_fails_to_import_is_listed_and_the_others_work(
    broken_install, tmp_path, capsys
):
    registry = crankdyn.plugin.registry.default_registry()
    assert registry.broken == {
        "friction_plugin": (
            "plugin 'friction_plugin' (import): import raised ModuleNotFoundError: "
            "No module named 'crankdyn_friction_dependency_not_installed'"
        )
    }
    assert "kinematics" in registry.stages

    assert cli.main(["plugins"]) == 0
    listing = capsys.readouterr().out
    assert "broken (failed to load, left out):" in listing
    assert "friction_plugin" in listing.split("broken")[1] and "ModuleNotFoundError" in listing
    assert "kinematics" in listing.split("broken")[0]

    scene = write_scene(tmp_path / "s.toml", example_data(SCENE))
    out = tmp_path / "out"
    assert cli.main(["report", str(scene), "-o", str(out), "--format", "json", "-q"]) == 0
    assert (out / "results.json").is_file()
    assert "warning: plugin 'friction_plugin' (import)" in capsys.readouterr().err

    # a stage it might have provided: refused, naming the broken plugin; nothing written
    refused = tmp_path / "refused"
    assert (
        cli.main(
            ["report", str(scene), "-o", str(refused), "--format", "json", "--stages", "friction"]
        )
        == 2
    )
    err = capsys.readouterr().err
    assert "stages = 'friction': unknown stage" in err
    assert "installed but not loaded: plugin 'friction_plugin' (import)" in err
    assert "Traceback" not in err
    assert not refused.exists()
    # a mechanism it might have provided: the same
    yoke = write_scene(
        tmp_path / "yoke.toml", modified(SCENE, {"engine": {"mechanism": "friction_yoke"}})
    )
    assert cli.main(["check", str(yoke)]) == 2
    err = capsys.readouterr().err
    assert "engine.mechanism = 'friction_yoke': unknown mechanism" in err
    assert "installed but not loaded: plugin 'friction_plugin' (import)" in err


def test_an_entry_point_that_raises_at_import_through_importlib_metadata(monkeypatch):
    import importlib.metadata

    class Failing:
        name, group = "exploding", "crankdyn"

        def load(self):
            raise RuntimeError("configuration file missing")

    real = importlib.metadata.entry_points

    def entry_points(**selection):
        found = real(**selection)
        return [*found, Failing()] if selection.get("group") == "crankdyn" else found

    monkeypatch.setattr(importlib.metadata, "entry_points", entry_points)
    registry = crankdyn.plugin.registry.default_registry()
    assert registry.broken == {
        "exploding": "plugin 'exploding' (import): import raised "
        "RuntimeError: configuration file missing"
    }
    assert "kinematics" in registry.stages


# ---------------------------------------------------------------- the command line and the API
def test_the_command_line_names_the_plugin_with_exit_2_and_writes_nothing(
    tmp_path, monkeypatch, capsys
):
    registry = _registry(_plugin("bad_render", [_stage(render=lambda output, ctx: 1 / 0)]))
    monkeypatch.setattr(crankdyn.plugin.registry, "default_registry", lambda: registry)
    scene = write_scene(tmp_path / "s.toml", example_data(SCENE))
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine", encoding="utf-8")
    code = cli.main(
        ["report", str(scene), "-o", str(out), "--format", "html,json", "--stages", "extra"]
    )
    err = capsys.readouterr().err
    assert code == 2
    assert err == (
        "crankdyn: plugin 'bad_render' (stage 'extra'): render raised "
        "ZeroDivisionError: division by zero\n"
    )
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]


def test_the_python_api_raises_the_documented_error_naming_the_plugin(monkeypatch):
    registry = _registry(_plugin("bad_run", [_stage(run=lambda scene, inputs: 1 / 0)]))
    monkeypatch.setattr(crankdyn.api, "_registry", lambda: registry)
    scene = crankdyn.api.load(modified(SCENE, {}))
    with pytest.raises(PluginError) as caught:
        crankdyn.api.run(scene, stages=["extra"])
    assert isinstance(caught.value, PluginFailure)
    assert str(caught.value) == (
        "plugin 'bad_run' (stage 'extra'): run raised ZeroDivisionError: division by zero"
    )


@pytest.mark.parametrize("value", ["0", "-1", "nan", "inf", "1e400", str(MAX_STAGE_TIMEOUT_S * 2)])
def test_timeout_outside_its_range_is_refused(value, tmp_path, capsys):
    scene = write_scene(tmp_path / "s.toml", example_data(SCENE))
    assert cli.main(["report", str(scene), "-o", str(tmp_path / "out"), "--timeout", value]) == 2
    assert f"at most {MAX_STAGE_TIMEOUT_S:g}" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_the_command_lines_limits_are_the_guards():
    assert cli.DEFAULT_STAGE_TIMEOUT_S == DEFAULT_STAGE_TIMEOUT_S
    assert cli.MAX_STAGE_TIMEOUT_S == MAX_STAGE_TIMEOUT_S
    with pytest.raises(ValueError):
        with stage_time_limit(math.inf):
            pass


def test_a_named_failure_survives_the_way_back_from_a_forked_child():
    failure = StageTimeLimit("slow_plugin", "stage 'slow'", "run did not finish")
    back = pickle.loads(pickle.dumps(failure))
    assert type(back) is StageTimeLimit and str(back) == str(failure)
    assert back.plugin == "slow_plugin"


# ---------------------------------------------------------------- a stage that never ends
HANGING = """
    import time

    from crankdyn.plugin.hooks import hookimpl
    from crankdyn.plugin.types import Stage, StageOutput, StagePresentation


    def _forever(*args):
        while True:  # a stage that never returns
            time.sleep(0.05)


    def _applies(scene):
        return None


    def _quick(scene, inputs):
        return StageOutput(results={"done": True})


    def _stage(name, run=_quick, render=lambda output, ctx: "<p>slow</p>", last=False):
        return Stage(name=name, requires=("kinematics",), provides=(), applies=_applies,
                     run=run, last=last,
                     presentation=StagePresentation(title_key="slow.title", render=render))


    @hookimpl
    def crankdyn_stages():
        return [_stage("slow", run=_forever), _stage("slow_render", render=_forever),
                _stage("slow_study", run=_forever, last=True)]
"""


def _environment(site: Path) -> dict:
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    env["PYTHONPATH"] = os.pathsep.join([str(site), *filter(None, [env.get("PYTHONPATH")])])
    return env


@pytest.mark.slow  # waits out a time limit: in the slow tier, which CI runs
@pytest.mark.parametrize(
    ("stage", "step", "formats"),
    [
        ("slow", "run", "json"),  # the stages run in the command's process
        ("slow", "run", "html,json"),  # in a forked child while the rendering gets ready
        (
            "slow_study",
            "run",
            "html,json",
        ),  # a study, in a forked child while the report is rendered
        ("slow_render", "render", "html"),
    ],
)
def test_a_stage_that_never_ends_stops_report_at_the_limit_naming_it(
    stage, step, formats, tmp_path
):
    site = tmp_path / "site"
    site.mkdir()
    _install(site, "slow_plugin", HANGING)
    scene = write_scene(tmp_path / "s.toml", example_data(SCENE))
    out = tmp_path / "out"
    # the subprocess's own timeout only keeps a failing test from hanging the suite
    command = [
        sys.executable,
        "-m",
        "crankdyn",
        "report",
        str(scene),
        "-o",
        str(out),
        "--format",
        formats,
        "--stages",
        stage,
        "--timeout",
        "1",
    ]
    done = subprocess.run(
        command, capture_output=True, text=True, env=_environment(site), timeout=300
    )
    assert done.returncode == 2, done.stderr
    assert done.stderr == (
        f"crankdyn: plugin 'slow_plugin' (stage '{stage}'): {step} did not "
        "finish within the limit of 1 s a stage may take "
        "(crankdyn report --timeout SECONDS)\n"
    )
    assert not out.exists()


@pytest.mark.slow  # waits out a time limit: in the slow tier, which CI runs
def test_a_plugin_whose_import_never_ends_is_stopped_and_listed_as_broken(tmp_path):
    site = tmp_path / "site"
    site.mkdir()
    _install(site, "stuck_plugin", "import time\nwhile True:\n    time.sleep(0.05)\n")
    script = textwrap.dedent("""
        from crankdyn.plugin.guard import stage_time_limit
        from crankdyn.plugin.registry import default_registry

        with stage_time_limit(1):
            registry = default_registry()
        print(registry.broken["stuck_plugin"])
        print("kinematics" in registry.stages)
    """)
    done = subprocess.run(
        [sys.executable, "-c", script],
        capture_output=True,
        text=True,
        env=_environment(site),
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout == (
        "plugin 'stuck_plugin' (import): import did not finish within the "
        "limit of 1 s a stage may take (crankdyn report --timeout SECONDS)\n"
        "True\n"
    )


@pytest.mark.slow  # waits out a time limit: in the slow tier, which CI runs
def test_check_applies_the_same_limit(tmp_path):
    site = tmp_path / "site"
    site.mkdir()
    _install(site, "slow_plugin", HANGING)
    scene = write_scene(tmp_path / "s.toml", modified(SCENE, {"analysis": {"stages": ["slow"]}}))
    done = subprocess.run(
        [sys.executable, "-m", "crankdyn", "check", str(scene), "--timeout", "1"],
        capture_output=True,
        text=True,
        env=_environment(site),
        timeout=300,
    )
    assert done.returncode == 2, done.stderr
    assert (
        "plugin 'slow_plugin' (stage 'slow'): run did not finish within the limit of 1 s"
        in done.stderr
    )


def test_the_python_api_stops_a_stage_that_never_ends_within_a_time_limit(tmp_path):
    site = tmp_path / "site"
    site.mkdir()
    _install(site, "slow_plugin", HANGING)
    script = textwrap.dedent(f"""
        import crankdyn
        from crankdyn.errors import StageTimeLimit
        from crankdyn.plugin.guard import stage_time_limit

        scene = crankdyn.load({str(tmp_path / "s.toml")!r})
        try:
            with stage_time_limit(1):
                crankdyn.run(scene, stages=["slow"])
        except StageTimeLimit as exc:
            print(exc.plugin, exc.where)
    """)
    write_scene(tmp_path / "s.toml", example_data(SCENE))
    done = subprocess.run(
        [sys.executable, "-c", script],
        capture_output=True,
        text=True,
        env=_environment(site),
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout == "slow_plugin stage 'slow'\n"


def test_dataclass_replace_keeps_the_guard_on_a_registered_stage():
    registry = _registry(_plugin("bad_plugin", [_stage(applies=lambda scene: 7)]))
    registered = registry.stages["extra"]
    stage = dataclasses.replace(
        registered,
        presentation=dataclasses.replace(registered.presentation, title_key="other.title"),
    )
    with pytest.raises(PluginFailure, match="applies returned 7"):
        stage.applies(_scene())
