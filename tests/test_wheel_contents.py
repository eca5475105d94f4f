"""The wheel: built from a copy of the source tree, it carries the licence, the example notebook and
the bundled examples, nothing under an incompatible licence, and its examples load from any folder
through crankdyn.example_path."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
# What setuptools reads to build the wheel; the copy keeps build/ and *.egg-info out of the sources.
SOURCES = [
    "pyproject.toml",
    "LICENSE",
    "docs/pypi-description.md",
    "src",
    "plugins",
    "templates",
    "examples",
]
# Data under the GPL-3.0 and the scenes that read it (examples/diesel6-1600rpm.ind.NOTICE).
SOURCE_TREE_ONLY = ["diesel6-1600rpm.ind", "diesel-rk-trace.toml", "inline6-diesel-trace.toml"]


def _copy_sources(target: Path) -> None:
    ignore = shutil.ignore_patterns("build", "*.egg-info", "__pycache__", "plugin-example")
    for name in SOURCES:
        source = ROOT / name
        if source.is_dir():
            shutil.copytree(source, target / name, ignore=ignore)
        else:
            (target / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target / name)


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    work = tmp_path_factory.mktemp("wheel")
    _copy_sources(work / "source")
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    built = subprocess.run(
        [
            sys.executable,
            "-m",
            "build",
            "--wheel",
            "--no-isolation",
            "--outdir",
            str(work / "dist"),
            str(work / "source"),
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
        check=False,
    )
    assert built.returncode == 0, built.stdout[-3000:] + built.stderr[-3000:]
    wheels = list((work / "dist").glob("crankdyn-*.whl"))
    assert len(wheels) == 1, wheels
    return wheels[0]


def _names(wheel: Path) -> list[str]:
    with zipfile.ZipFile(wheel) as archive:
        return archive.namelist()


@pytest.mark.long
def test_the_wheel_carries_the_licence_and_the_notebook(wheel):
    names = _names(wheel)
    licences = [n for n in names if n.endswith(".dist-info/licenses/LICENSE")]
    assert len(licences) == 1, names
    with zipfile.ZipFile(wheel) as archive:
        assert archive.read(licences[0]).decode("utf-8").startswith("MIT License")
    assert "crankdyn/examples/api-notebook.ipynb" in names
    assert "crankdyn/examples/petrol-1cyl.toml" in names


@pytest.mark.long
def test_the_wheel_leaves_out_the_gpl_trace_and_its_scenes(wheel):
    names = _names(wheel)
    for name in SOURCE_TREE_ONLY:
        assert not [n for n in names if n.endswith("/" + name)], name
    assert not [n for n in names if n.endswith(".ind") or n.endswith(".NOTICE")], names
    # ... while the source tree keeps them, with the notice next to the data
    assert (ROOT / "examples" / "diesel6-1600rpm.ind").is_file()
    assert "GPL-3.0" in (ROOT / "examples" / "diesel6-1600rpm.ind.NOTICE").read_text(
        encoding="utf-8"
    )


@pytest.mark.long
def test_the_wheel_metadata_has_a_short_description_and_urls(wheel):
    with zipfile.ZipFile(wheel) as archive:
        metadata_name = next(n for n in archive.namelist() if n.endswith(".dist-info/METADATA"))
        metadata = archive.read(metadata_name).decode("utf-8")
    header, _, description = metadata.partition("\n\n")
    assert "Author: crankdyn contributors" in header
    assert "Classifier: License :: OSI Approved :: MIT License" in header
    assert "Project-URL: Documentation, https://" in header
    assert (
        description.strip()
        == (ROOT / "docs" / "pypi-description.md").read_text(encoding="utf-8").strip()
    )
    # a package index shows it without the repository: no relative links or pictures
    assert "](docs/" not in description and "](./" not in description and "<img" not in description


@pytest.mark.long
def test_examples_of_the_installed_wheel_load_from_any_folder(wheel, tmp_path):
    target = tmp_path / "installed"
    with zipfile.ZipFile(wheel) as archive:
        archive.extractall(target)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    # The unpacked wheel comes first on the path; the dependencies are this environment's.
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    env["PYTHONPATH"] = str(target)
    code = (
        "import crankdyn, pathlib\n"
        "path = crankdyn.example_path('petrol-1cyl')\n"
        "scene = crankdyn.load(path)\n"
        "print(pathlib.Path(crankdyn.__file__).parent)\n"
        "print(path)\n"
        "print(scene.engine.rpm)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code],
        cwd=elsewhere,
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    package, path, rpm = done.stdout.split()
    assert Path(package) == target / "crankdyn"
    assert Path(path) == target / "crankdyn" / "examples" / "petrol-1cyl.toml"
    expected_rpm = __import__("tomllib").loads(
        (ROOT / "examples" / "petrol-1cyl.toml").read_text("utf-8")
    )
    assert float(rpm) == expected_rpm["engine"]["rpm"]


@pytest.mark.long
def test_the_wheel_carries_every_module_of_the_core(wheel):
    """Every module under src/crankdyn (each package of the layer contract, the old paths' shims)
    is in the wheel: a package left out of ``[tool.setuptools] packages`` is caught here."""
    names = set(_names(wheel))
    core = ROOT / "src" / "crankdyn"
    modules = {"crankdyn/" + p.relative_to(core).as_posix() for p in core.rglob("*.py")}
    assert {"crankdyn/plugin/__init__.py", "crankdyn/scene/units.py"} <= modules
    assert sorted(modules - names) == []
