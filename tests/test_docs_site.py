"""The documentation site builds in strict mode (broken links, unknown pages and a reference out of
step with the code fail it), and its scene and results.json references come from the code."""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"

pytest.importorskip(
    "mkdocs", reason="mkdocs is in the test extra; without it the site cannot be built"
)
pytest.importorskip("mkdocstrings", reason="mkdocstrings-python builds the API reference")


def _hook():
    spec = importlib.util.spec_from_file_location(
        "docs_reference_hook", ROOT / "docs" / "hooks" / "reference.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    built = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
        check=False,
    )
    assert built.returncode == 0, built.stdout[-4000:] + built.stderr[-4000:]
    return out


def _text(html_file: Path) -> str:
    return html_file.read_text(encoding="utf-8")


@pytest.mark.long
def test_the_scene_reference_lists_every_field_of_the_scene_model(site):
    from crankdyn.scene.model import Cycle, Engine, Masses, ReportMeta

    page = _text(site / "scene" / "index.html")
    for model in (ReportMeta, Engine, Masses, Cycle, Cycle.model_fields["rounding"].annotation):
        for field in model.model_fields:
            if field != "rounding":
                assert f"<code>{field}</code>" in page, (model.__name__, field)
    # ranges and units come from the validators: engine.bore is a length in mm, at most 2 m
    assert "quantity (length), e.g. in mm; &gt; 0 mm, ≤ 2000 mm" in page


@pytest.mark.long
def test_the_results_reference_has_a_section_per_registered_stage(site):
    from crankdyn.plugin.registry import default_registry

    page = _text(site / "results" / "index.html")
    registry = default_registry()
    for stage in registry.stages.values():
        assert f"<code>{stage.name}</code> — " in page, stage.name
        for column in stage.answer_columns:
            assert f"<code>{column.column}</code>" in page, (stage.name, column.column)


@pytest.mark.long
def test_the_api_reference_is_built_from_the_docstrings(site):
    page = _text(site / "api-reference" / "index.html")
    from crankdyn.bundled import example_path

    # the docstring's opening words, as the page shows them (markup and roles stripped)
    opening = " ".join(example_path.__doc__.replace("``", "").split()[:8])
    assert opening in " ".join(re.sub(r"<[^>]+>", "", page).split())
    assert 'id="crankdyn.api.load"' in page and 'id="crankdyn.api.sweep"' in page


def test_a_field_without_a_meaning_fails_the_build(monkeypatch):
    hook = _hook()
    real = hook._descriptions

    def without_rpm(name):
        descriptions = real(name)
        if name == "scene-fields.toml":
            descriptions["engine"].pop("rpm")
        return descriptions

    monkeypatch.setattr(hook, "_descriptions", without_rpm)
    with pytest.raises(hook.PluginError, match=r"\[engine\] has no meaning for the field 'rpm'"):
        hook.scene_reference()


def test_a_meaning_for_a_field_the_code_lacks_fails_the_build(monkeypatch):
    hook = _hook()
    real = hook._descriptions

    def with_extra(name):
        descriptions = real(name)
        if name == "scene-fields.toml":
            descriptions["masses"]["flywheel_mass"] = "not a field"
        if name == "results-keys.toml":
            descriptions["no_such_stage"] = {"x": "y"}
        return descriptions

    monkeypatch.setattr(hook, "_descriptions", with_extra)
    with pytest.raises(
        hook.PluginError, match=r"'flywheel_mass' is no field of crankdyn.scene.model.Masses"
    ):
        hook.scene_reference()
    with pytest.raises(hook.PluginError, match=r"\[no_such_stage\] is no stage of the registry"):
        hook.results_reference()


def test_the_readme_is_short_and_its_test_command_is_the_ci_one():
    lines = README.read_text(encoding="utf-8").splitlines()
    assert len(lines) <= 150, len(lines)
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    command = next(line for line in ci.splitlines() if line.startswith("bash .ci/setup.sh"))
    tests = command.split(" && ", 1)[1]
    assert any(tests in line for line in lines), tests


def test_the_readme_links_resolve():
    text = README.read_text(encoding="utf-8")
    targets = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text)
    local = [t for t in targets if "://" not in t]
    assert local
    for target in local:
        assert (ROOT / target).exists(), target
