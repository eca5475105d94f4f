"""The mechanisms are documented: their scene keys and results.json keys in the documentation's
scene and results.json references."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from documented import documentation_text

from crankdyn.cli import examples_dir, main
from crankdyn.plugin.registry import default_registry

ROOT = Path(__file__).resolve().parent.parent
DOCUMENTATION = documentation_text()
EXAMPLES = ["offset-crank-engine", "planetary-kinematics", "vane-engine-kinematics"]


@pytest.mark.parametrize("example", EXAMPLES)
def test_results_keys_of_the_mechanism_examples_are_documented(tmp_path, example):
    out = tmp_path / example
    assert (
        main(
            [
                "report",
                str(examples_dir() / f"{example}.toml"),
                "-o",
                str(out),
                "--format",
                "json",
                "-q",
            ]
        )
        == 0
    )
    document = json.loads((out / "results.json").read_text(encoding="utf-8"))
    for stage in ("offset_crank", "planetary", "vane", "rod_dynamics"):
        for key, value in document.get(stage, {}).items():
            assert f"`{key}`" in DOCUMENTATION, f"{stage}.{key} not documented"
            if isinstance(value, dict):
                for sub in value:
                    assert f"`{sub}`" in DOCUMENTATION, f"{stage}.{key}.{sub} not documented"


def test_scene_keys_of_the_mechanisms_are_documented():
    registry = default_registry()
    for name in ("offset_crank_slider", "planetary", "vane_crank_rocker"):
        assert f"`{name}`" in DOCUMENTATION
        for field in registry.mechanisms[name].params_model.model_fields:
            assert f"`{field}`" in DOCUMENTATION, (name, field)
    for field in registry.stages["rod_dynamics"].options_model.model_fields:
        assert f"`{field}`" in DOCUMENTATION
    assert "`rod_moment_of_inertia`" in DOCUMENTATION and "`[rod_dynamics]`" in DOCUMENTATION


def test_mechanism_examples_are_listed_and_written(tmp_path, capsys):
    assert main(["example", "--list"]) == 0
    names = {line.split()[0] for line in capsys.readouterr().out.splitlines() if line.strip()}
    assert set(EXAMPLES) <= names
    target = tmp_path / "mine.toml"
    assert main(["example", "planetary-kinematics", "-o", str(target)]) == 0
    assert main(["check", str(target)]) == 0
    assert "stages: planetary, drawing, rod_dynamics" in capsys.readouterr().out
