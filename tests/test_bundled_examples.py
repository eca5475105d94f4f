"""crankdyn.example_path: the bundled example scenes by name; dir(crankdyn) lists the lazy API."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

import crankdyn
from crankdyn.bundled import example_names

ROOT = Path(__file__).resolve().parent.parent


def test_example_path_names_the_bundled_scene():
    path = crankdyn.example_path("petrol-1cyl")
    assert path.name == "petrol-1cyl.toml"
    assert path.read_bytes() == (ROOT / "examples" / "petrol-1cyl.toml").read_bytes()
    assert crankdyn.example_path("petrol-1cyl.toml") == path


def test_example_path_loads_from_another_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    scene = crankdyn.load(crankdyn.example_path("kinematics-only"))
    assert scene.engine.mechanism == "crank_slider"


def test_example_names_are_the_scenes_of_the_examples_folder():
    assert example_names() == sorted(p.stem for p in (ROOT / "examples").glob("*.toml"))


@pytest.mark.parametrize("name", ["no-such-engine", "../pyproject", "sweeps/bore-rod-ratio", ""])
def test_an_unknown_example_is_refused_naming_it_and_the_choices(name):
    with pytest.raises(ValueError) as info:
        crankdyn.example_path(name)
    message = str(info.value)
    assert repr(name) in message and "petrol-1cyl" in message


def test_a_name_that_is_not_text_is_refused():
    with pytest.raises(ValueError, match="example name must be a text"):
        crankdyn.example_path(3)


def test_dir_lists_the_lazy_names_without_importing_them():
    # A fresh interpreter: in this one the API may already have been imported by another test.
    code = (
        "import sys, crankdyn\n"
        "print(' '.join(dir(crankdyn)))\n"
        "print('crankdyn.api' in sys.modules)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    names, api_imported = done.stdout.splitlines()
    assert {"load", "run", "sweep", "Result", "SceneError", "example_path", "__version__"} <= set(
        names.split()
    )
    assert api_imported == "False"
