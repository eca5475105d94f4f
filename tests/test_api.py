"""The Python API: crankdyn.load/run/sweep, Result, docs/api.md and the example notebook."""

from __future__ import annotations

import contextlib
import io
import json
import re
from pathlib import Path

import pytest

import crankdyn
from crankdyn.output.pipeline import write_report
from crankdyn.plugin.registry import default_registry
from crankdyn.scene.model import load_scene

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "api.md"
KINEMATICS_ONLY = ROOT / "examples" / "kinematics-only.toml"


@pytest.fixture(scope="module")
def doc_output(tmp_path_factory) -> str:
    """Everything docs/api.md's code blocks print, run one after the other from the repository root."""
    import os

    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S)
    assert len(blocks) >= 5
    namespace: dict = {}
    buffer = io.StringIO()
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        with contextlib.redirect_stdout(buffer):
            for block in blocks:
                exec(compile(block, str(DOC), "exec"), namespace)  # noqa: S102 - our own documentation
    finally:
        os.chdir(cwd)
    return buffer.getvalue()


def test_doc_example_prints_the_numbers_of_results_json(doc_output, tmp_path):
    # results.json of the same scene, written by the command line's pipeline.
    write_report(
        load_scene(ROOT / "examples" / "petrol-1cyl.toml"), default_registry(), tmp_path, ["json"]
    )
    document = json.loads((tmp_path / "results.json").read_text(encoding="utf-8"))
    printed = re.findall(r"^(\w+)\.(\w+) = ([-+0-9.eE]+)$", doc_output, re.M)
    assert len(printed) >= 5
    for stage, key, number in printed:
        assert float(number) == document[stage][key], (stage, key)


def test_doc_example_prints_the_problems_and_the_sweep(doc_output):
    assert (
        "problem: engine.rpm = -5" in doc_output and "problem: engine.bore = '82 kg'" in doc_output
    )
    # balancing keeps its report number: 6, after input data, kinematics, the mechanism scheme, the indicator
    # diagram and the forces
    assert "<h2>6. " in doc_output or "<h2>6." in doc_output
    sweep_lines = [
        line for line in doc_output.splitlines() if re.match(r"^\s+0\.(25|28|32)\s+\d+", line)
    ]
    assert len(sweep_lines) == 9


@pytest.fixture(scope="module")
def base_scene():
    return crankdyn.load(KINEMATICS_ONLY, {"engine.rod_length": None, "engine.rod_ratio": 0.25})


def test_sweep_3x3_equals_nine_separate_runs(base_scene):
    ratios, speeds = [0.24, 0.28, 0.32], [1500, 3000, 6000]
    table = crankdyn.sweep(
        base_scene, {"engine.rod_ratio": ratios, "engine.rpm": speeds}, stages=["kinematics"]
    )
    assert len(table) == 9
    stroke_m = 0.100
    for i, row in table.iterrows():
        ratio, rpm = ratios[i // 3], speeds[i % 3]
        assert (row["engine.rod_ratio"], row["engine.rpm"]) == (ratio, rpm)
        single = crankdyn.run(
            crankdyn.load(
                KINEMATICS_ONLY, engine__rod_length=None, engine__rod_ratio=ratio, engine__rpm=rpm
            ),
            stages=["kinematics"],
        )
        for column, name in (
            ("v_max_m_s", "v_max_m_s"),
            ("j_max_m_s2", "j_max_m_s2"),
            ("j_min_m_s2", "j_min_m_s2"),
            ("v_mean_m_s", "mean_piston_speed_m_s"),
        ):
            assert row[column] == single.values[f"kinematics.{name}"]
        # Independent check: mean piston speed S*n/30; j_max = R*w^2*(1 + lambda) at TDC.
        assert row["v_mean_m_s"] == pytest.approx(stroke_m * rpm / 30, rel=1e-12)
        omega = rpm * 2 * 3.141592653589793 / 60
        assert row["j_max_m_s2"] == pytest.approx(stroke_m / 2 * omega**2 * (1 + ratio), rel=1e-9)
    # Columns of stages that did not run are left out, as in the batch answer key.
    assert "p_max_MPa" not in table.columns


def test_overrides_validate_like_the_scene_and_print_nothing(capsys):
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load(
            KINEMATICS_ONLY,
            {
                "engine.rpm": 0,
                "engine.bore": "80 kg",
                "engine.colour": "red",
                "analysis.stages": ["warp_drive"],
            },
        )
    fields = {p.field for p in caught.value.problems}
    assert {"engine.rpm", "engine.bore", "engine.colour"} <= fields
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load(
            KINEMATICS_ONLY, {"analysis.stages": ["warp_drive"]}
        )  # checked against the plugins too
    assert caught.value.problems[0].field == "analysis.stages"
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load(KINEMATICS_ONLY, {"engine..rpm": 1, "engine": {}, "engine.rpm": 2})
    assert len(caught.value.problems) >= 2
    assert capsys.readouterr() == ("", "")


def test_keyword_and_dict_overrides_agree():
    a = crankdyn.load(KINEMATICS_ONLY, {"engine.rpm": 4200, "engine.bore": "84 mm"})
    b = crankdyn.load(KINEMATICS_ONLY, engine__rpm=4200, engine__bore="84 mm")
    c = crankdyn.load(
        crankdyn.load(KINEMATICS_ONLY), **{"engine.rpm": 4200, "engine.bore": "84 mm"}
    )
    assert a.engine == b.engine == c.engine
    assert a.engine.rpm == 4200 and a.engine.bore == pytest.approx(0.084)


@pytest.fixture(scope="module")
def petrol():
    return crankdyn.run(ROOT / "examples" / "petrol-1cyl.toml")


def test_result_tables_values_figures(petrol):
    import matplotlib.figure
    import pandas as pd

    kinematics = petrol.tables["kinematics"]
    assert isinstance(kinematics, pd.DataFrame) and "crank_angle_deg" in kinematics.columns
    assert petrol.values["kinematics.v_max_m_s"] == pytest.approx(
        kinematics["piston_velocity_m_s"].max(), rel=1e-3
    )
    assert crankdyn.api.unit_of("kinematics.v_max_m_s") == "m/s"
    assert petrol.figures._figures is None  # figures are drawn on first access only
    kinematics_only = crankdyn.run(
        KINEMATICS_ONLY
    )  # three figures: cheaper to draw than the petrol engine's
    assert all(isinstance(f, matplotlib.figure.Figure) for f in kinematics_only.figures.values())
    assert len(kinematics_only.figures) >= 2 and kinematics_only.figures._figures is not None


def test_write_gives_the_files_of_the_report_command(petrol, tmp_path):
    written = petrol.write(tmp_path / "api", formats=["json", "csv"])
    write_report(
        load_scene(ROOT / "examples" / "petrol-1cyl.toml"),
        default_registry(),
        tmp_path / "cli",
        ["json", "csv"],
    )
    names = sorted(p.relative_to(tmp_path / "api").as_posix() for p in written)
    manifest = (
        ".crankdyn-manifest.json"  # both record what they wrote, for the next run into the folder
    )
    assert (tmp_path / "api" / manifest).is_file() and (tmp_path / "cli" / manifest).is_file()
    assert names == sorted(
        p.relative_to(tmp_path / "cli").as_posix()
        for p in (tmp_path / "cli").rglob("*.*")
        if p.name != manifest
    )
    api_doc = json.loads((tmp_path / "api" / "results.json").read_text())
    cli_doc = json.loads((tmp_path / "cli" / "results.json").read_text())
    for doc in (api_doc, cli_doc):  # run times (and the error-vs-time study) differ from run to run
        doc.pop("timing_s"), doc.pop("numerics")
    assert api_doc == cli_doc
    with pytest.raises(crankdyn.SceneError):
        petrol.write(tmp_path / "bad", formats=["doc"])


def test_section_uses_the_report_templates_in_the_chosen_language(petrol):
    from crankdyn.report.i18n import translator

    for language in ("uk",):  # English: docs/api.md
        html = petrol.section("balancing", language=language)
        title = translator(language, default_registry().catalogs)("balancing.title")
        assert title in html and html.startswith('<section class="crankdyn-section"><h2>')
        assert html._repr_html_() == html
    with pytest.raises(KeyError):
        petrol.section("flywheel")


def test_summary_shows_main_values_and_leave_out_reasons(petrol):
    summary = petrol._repr_html_()
    assert "v_max_m_s" in summary and f"{petrol.values['kinematics.v_max_m_s']:.6g}" in summary
    for name in petrol.skipped:
        assert name in summary
    assert petrol.skipped and "Calculations left out" in summary


# the example notebook run whole: in the slow tier, which CI runs
@pytest.mark.slow
def test_example_notebook_runs_and_shows_html_first():
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    path = ROOT / "examples" / "api-notebook.ipynb"
    notebook = nbformat.read(path, as_version=4)
    nbclient.NotebookClient(
        notebook,
        timeout=120,
        kernel_name="python3",
        resources={"metadata": {"path": str(path.parent)}},
    ).execute()
    outputs = [cell.outputs for cell in notebook.cells if cell.cell_type == "code" and cell.outputs]
    assert outputs, "no cell produced output"
    assert "text/html" in outputs[0][0].get("data", {})
    assert "crankdyn-result" in outputs[0][0]["data"]["text/html"]


def test_the_sweep_command_module_does_not_shadow_the_api_function():
    """`crankdyn.sweep` stays the API function after the `crankdyn sweep` command's module is loaded
    (a submodule named ``sweep`` would replace the package attribute on import)."""
    import crankdyn
    import crankdyn.batch.sweep  # noqa: F401

    assert callable(crankdyn.sweep) and crankdyn.sweep.__module__ == "crankdyn.api"


def test_an_aircraft_engines_section_from_the_api_names_its_propeller():
    """The API renders a section with the report's own texts: an aircraft engine's energy-method
    section is the propeller's, as in its note."""
    scene = crankdyn.load(
        ROOT / "examples" / "radial9-aircraft.toml", {"flywheel.inertia": "8 kg m^2"}
    )
    result = crankdyn.run(scene, ["flywheel"])
    html = str(result.section("flywheel", language="en"))
    assert "Speed fluctuation with the propeller by the energy method" in html
