"""The output folder: a rerun leaves only its own files (never a foreign one); modes follow the umask."""

from __future__ import annotations

import json
import os
import stat

import pytest

from crankdyn.cli import examples_dir, main
from crankdyn.output.manifest import MANIFEST


def _files(folder):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file())


@pytest.fixture()
def umask_022():
    old = os.umask(0o022)
    yield
    os.umask(old)


def test_second_run_with_other_stages_leaves_only_its_files_and_foreign_ones(
    tmp_path, capsys, umask_022
):
    scene, out = examples_dir() / "petrol-1cyl.toml", tmp_path / "out"
    assert main(["report", str(scene), "-o", str(out), "--format", "json,csv", "-q"]) == 0
    first = _files(out)
    assert "tables/torque.csv" in first and "tables/forces.csv" in first
    (out / "my notes.txt").write_text("mine", encoding="utf-8")
    (out / "tables" / "hand-made.csv").write_text("a,b\n", encoding="utf-8")
    assert (
        main(
            [
                "report",
                str(scene),
                "-o",
                str(out),
                "--format",
                "json,csv",
                "--stages",
                "kinematics",
                "-q",
            ]
        )
        == 0
    )
    manifest = json.loads((out / MANIFEST).read_text(encoding="utf-8"))
    second = sorted(manifest["files"])
    assert "tables/torque.csv" not in second and "tables/kinematics.csv" in second
    assert _files(out) == sorted(second + [MANIFEST, "my notes.txt", "tables/hand-made.csv"])
    # Files 0644 and folders 0755 under the usual umask (mkstemp alone would give 0600).
    assert stat.S_IMODE((out / "results.json").stat().st_mode) == 0o644
    assert stat.S_IMODE((out / "tables" / "kinematics.csv").stat().st_mode) == 0o644
    assert stat.S_IMODE((out / "tables").stat().st_mode) == 0o755


def test_a_bad_scene_leaves_an_earlier_report_alone(tmp_path, capsys):
    scene, out = examples_dir() / "kinematics-only.toml", tmp_path / "out"
    assert main(["report", str(scene), "-o", str(out), "--format", "json", "-q"]) == 0
    before = _files(out)
    bad = tmp_path / "bad.toml"
    bad.write_text(
        scene.read_text(encoding="utf-8").replace('"80 mm"', '"2*40 mm"'), encoding="utf-8"
    )
    assert main(["report", str(bad), "-o", str(out), "--format", "json", "-q"]) == 2
    assert _files(out) == before
