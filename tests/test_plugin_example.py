"""The example third-party plugin (examples/plugin-example, a Scotch yoke): installed into a
fresh virtual environment with one pip install, it appears in `crankdyn plugins` and makes a
report through the command line; in-process, its rod-less PistonMotion goes through the force stage."""

from __future__ import annotations

import json
import os
import shutil
import site
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import modified

from crankdyn.engine.orchestrator import check_scene, run_scene
from crankdyn.errors import MISSING, SceneError
from crankdyn.plugin.registry import collect, plugin_manager
from crankdyn.report.document import render_html
from crankdyn.scene.model import scene_from_dict

PLUGIN_DIR = Path(__file__).resolve().parent.parent / "examples" / "plugin-example"


def _clean_venv_seeing_this_one(venv: Path, env: dict) -> Path:
    """A new virtual environment whose only other packages are this environment's (crankdyn, its
    dependencies, pip and setuptools): not the machine's system site-packages, which a fresh
    machine does not have. A ``.pth`` line runs ``site.addsitedir`` so that this environment's own
    ``.pth`` files (an editable crankdyn) work there too."""
    subprocess.run(
        [sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True, env=env, timeout=120
    )
    python = venv / "bin" / "python"
    inner = subprocess.run(
        [str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        check=True,
        capture_output=True,
        text=True,
        env=env,
        timeout=60,
    ).stdout.strip()
    outer = [p for p in site.getsitepackages() if Path(p).is_dir()]
    lines = [f"import site; site.addsitedir({p!r})" for p in outer]
    (Path(inner) / "_outer_environment.pth").write_text("\n".join(lines) + "\n", encoding="utf-8")
    return python


@pytest.mark.slow  # a fresh virtual environment: in the slow tier, which CI runs
@pytest.mark.long
def test_plugin_installs_into_a_clean_venv_and_reports_through_the_cli(tmp_path):
    source = tmp_path / "plugin-example"
    # Build from a copy, so that setuptools' build/ and *.egg-info never land in the repository.
    shutil.copytree(
        PLUGIN_DIR, source, ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__")
    )
    venv = tmp_path / "venv"
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "PIP_"))}
    env["PYTHONWARNINGS"] = "ignore"
    python = _clean_venv_seeing_this_one(venv, env)
    pip = subprocess.run(
        [
            str(python),
            "-m",
            "pip",
            "install",
            "--no-deps",
            "--no-build-isolation",
            "--no-index",
            "--quiet",
            str(source),
        ],
        check=False,
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert pip.returncode == 0, pip.stdout + pip.stderr

    # The crankdyn command of the new environment (the package itself is this environment's, reused).
    listing = subprocess.run(
        [str(python), "-m", "crankdyn", "plugins"],
        check=False,
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert listing.returncode == 0, listing.stderr
    lines = listing.stdout.splitlines()
    assert any(line.split()[:2] == ["scotch_yoke", "[scotch_yoke]"] for line in lines), (
        listing.stdout
    )
    assert any(
        "requires=- provides=kinematics" in line and line.split()[0] == "scotch_yoke"
        for line in lines
    )

    out = tmp_path / "report"
    done = subprocess.run(
        [
            str(python),
            "-m",
            "crankdyn",
            "report",
            str(source / "scotch-yoke.toml"),
            "-o",
            str(out),
            "--format",
            "html,json,csv",
            "--lang",
            "uk",
            "-q",
        ],
        check=False,
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    doc = json.loads((out / "results.json").read_text(encoding="utf-8"))
    assert doc["mechanism"] == "scotch_yoke" and doc["stages_run"] == ["scotch_yoke", "drawing"]
    assert doc["scotch_yoke"]["v_max_m_s"] == pytest.approx(0.04 * 1500 * np.pi / 30, rel=1e-12)
    html = (out / "report.html").read_text(encoding="utf-8")
    assert 'data-stage="scotch_yoke"' in html
    assert "Кінематика кулісного механізму" in html  # the plugin's own Ukrainian catalog
    # The plugin's geometry hook gives it the scheme, the positions figure and the animation.
    assert 'data-stage="drawing"' in html and 'class="mech-animation"' in html
    assert doc["drawing"]["crank_angles_deg"]["v_max"] == pytest.approx(90.0, abs=1e-3)
    assert (out / "tables" / "scotch_yoke.csv").is_file()
    # Nothing was built inside the repository's copy of the plugin.
    assert not (PLUGIN_DIR / "build").exists() and not list(PLUGIN_DIR.rglob("*.egg-info"))


# ----------------------------------------------------------------------------- in-process


@pytest.fixture(scope="module")
def yoke_registry():
    sys.path.insert(0, str(PLUGIN_DIR / "src"))
    try:
        from crankdyn_scotch_yoke import plugin
    finally:
        sys.path.pop(0)
    manager = plugin_manager()
    if not manager.is_registered(plugin):
        manager.register(plugin)
    return collect(manager)


def _yoke_engine_scene():
    data = modified("petrol-1cyl", {"engine": {"mechanism": "scotch_yoke"}})
    return scene_from_dict(data)


def test_rodless_mechanism_goes_through_the_force_stage(yoke_registry):
    result = run_scene(_yoke_engine_scene(), yoke_registry)
    # the drawing stage asks the run's registry: the yoke, registered here, is drawn too
    assert result.stages_run[:4] == ["scotch_yoke", "drawing", "indicator", "forces"]
    motion = result.outputs["scotch_yoke"].data["kinematics"]
    assert motion.rod_angle_rad is None
    f = result.outputs["forces"].tables["forces"]
    total = f["total_Pa"].to_numpy()
    # no rod: no side force, the whole axial force on the pin; t R = p1 ds/dalpha (virtual work)
    assert np.all(f["side_Pa"].to_numpy() == 0.0)
    np.testing.assert_allclose(f["rod_Pa"], total, rtol=0, atol=0)
    np.testing.assert_allclose(
        f["tangential_Pa"] * motion.crank_radius_m,
        total * motion.torque_arm_m,
        atol=1e-9 * np.max(np.abs(total)) * motion.crank_radius_m,
    )
    forces = result.outputs["forces"].results
    assert abs(forces["inertia_work_relative"]) < 1e-12
    assert abs(forces["mean_torque_deviation_percent"]) < 0.05


def test_plugin_report_in_process_uses_only_its_catalogs(yoke_registry):
    data = {
        "engine": {
            "mechanism": "scotch_yoke",
            "strokes": 2,
            "rpm": 1500,
            "bore": "60 mm",
            "stroke": "80 mm",
        },
        "scotch_yoke": {"table_step_deg": 45},
    }
    result = run_scene(scene_from_dict(data), yoke_registry)
    html = {}
    for language in ("en", "uk", "ru"):
        rendered = render_html(result, yoke_registry, language)
        html[language] = rendered.linked_html
        assert not rendered.missing_translations, (language, rendered.missing_translations)
        # its own letters s, v, j (Stage.symbols) explained under its first equation, from its catalogs
        meaning = {"en": "piston velocity", "uk": "швидкість поршня", "ru": "скорость поршня"}[
            language
        ]
        assert f'<span class="where-line"><i>v</i> – {meaning}, ' in rendered.linked_html
    with pytest.raises(Exception, match="scotch_yoke.table_step"):
        run_scene(scene_from_dict({**data, "scotch_yoke": {"table_step": 45}}), yoke_registry)
    # no connecting rod: the given data and the assignment name no L and no λ
    assert "Crank radius" in html["en"]
    assert "Connecting-rod length" not in html["en"] and "λ = " not in html["en"]


def test_a_scene_without_a_rod_is_valid_for_the_yoke_only(yoke_registry):
    """The yoke declares no rod (``Mechanism(needs_rod=False)``); a crank-slider has one, so
    the same scene naming it is refused, naming the field and what is allowed."""
    engine = {"strokes": 2, "rpm": 1500, "bore": "60 mm", "stroke": "80 mm"}
    yoke = scene_from_dict({"engine": {**engine, "mechanism": "scotch_yoke"}})
    assert not yoke.engine.has_rod and not yoke_registry.mechanisms["scotch_yoke"].needs_rod
    check_scene(yoke, yoke_registry)
    slider = scene_from_dict({"engine": {**engine, "mechanism": "crank_slider"}})
    with pytest.raises(SceneError) as refused:
        check_scene(slider, yoke_registry)
    (problem,) = refused.value.problems
    assert problem.field == "engine.rod_length" and problem.value is MISSING
    assert "rod_ratio" in problem.allowed and "'crank_slider' mechanism" in problem.allowed
    # a part of a run that needs the rod all the same names the field, never a TypeError
    with pytest.raises(SceneError, match="engine.rod_ratio"):
        _ = yoke.engine.rod_ratio_value
    # [masses] describes a connecting rod (its mass split by its length): it asks for one
    masses = {"piston_group": "0.4 kg", "rod": "0.3 kg", "rod_cm_fraction": 0.3}
    with pytest.raises(SceneError) as refused:
        scene_from_dict({"engine": {**engine, "mechanism": "scotch_yoke"}, "masses": masses})
    (problem,) = refused.value.problems
    assert problem.field == "engine.rod_length" and "[masses]" in problem.allowed
