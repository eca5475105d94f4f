"""The output folder never loses a user's file: edited outputs, foreign manifests, links, names taken.

crankdyn replaces or removes a file only when it is byte-for-byte what crankdyn wrote there; it
writes nothing through a link below the output folder; a refused run writes nothing at all.
"""

from __future__ import annotations

import json
import os
import shutil
import warnings
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from crankdyn.cli import examples_dir, main
from crankdyn.errors import OutputError
from crankdyn.output.manifest import MANIFEST, KeptFileWarning, write_outputs

SCENE = examples_dir() / "kinematics-only.toml"


def _snapshot(folder: Path) -> dict[str, object]:
    """Every entry below ``folder``: a file's bytes, a link's target, a folder's marker."""
    entries: dict[str, object] = {}
    for path in sorted(folder.rglob("*")):
        key = str(path.relative_to(folder))
        if path.is_symlink():
            entries[key] = ("link", os.readlink(path))
        elif path.is_dir():
            entries[key] = "dir"
        else:
            entries[key] = path.read_bytes()
    return entries


def _report(out: Path, *extra: str) -> int:
    return main(["report", str(SCENE), "-o", str(out), "-q", *extra])


def test_an_edited_output_survives_a_rerun_that_no_longer_writes_it(tmp_path, capsys):
    out = tmp_path / "out"
    assert _report(out, "--format", "json,csv") == 0
    edited = out / "tables" / "kinematics.csv"
    edited.write_text("my corrected table\n", encoding="utf-8")
    assert _report(out, "--format", "json") == 0
    assert edited.read_text(encoding="utf-8") == "my corrected table\n"
    err = capsys.readouterr().err
    assert (
        "warning: kept" in err
        and "kinematics.csv" in err
        and "changed since crankdyn wrote it" in err
    )
    assert (
        "tables/kinematics.csv"
        not in json.loads((out / MANIFEST).read_text(encoding="utf-8"))["files"]
    )


def test_an_edited_output_is_not_overwritten_without_force(tmp_path, capsys):
    out = tmp_path / "out"
    assert _report(out, "--format", "json,csv") == 0
    (out / "results.json").write_text('{"mine": 1}', encoding="utf-8")
    before = _snapshot(out)
    capsys.readouterr()
    assert _report(out, "--format", "json,csv") == 2
    err = capsys.readouterr().err
    assert "results.json: changed since crankdyn wrote it" in err and "--force" in err
    assert "Traceback" not in err
    assert _snapshot(out) == before  # nothing written, nothing removed
    assert _report(out, "--format", "json,csv", "--force") == 0
    assert json.loads((out / "results.json").read_text(encoding="utf-8"))["mechanism"]


def test_a_manifest_copied_from_another_folder_deletes_nothing(tmp_path, capsys):
    first = tmp_path / "first"
    assert _report(first, "--format", "json,csv") == 0
    copy = tmp_path / "copy"
    shutil.copytree(first, copy)
    # The user's own files, listed by a manifest crankdyn wrote for the first folder.
    (copy / "tables" / "kinematics.csv").write_text("lab measurements\n", encoding="utf-8")
    (copy / "lab-journal.txt").write_text("notes", encoding="utf-8")
    document = json.loads((copy / MANIFEST).read_text(encoding="utf-8"))
    document["files"]["lab-journal.txt"] = document["files"]["results.json"]
    (copy / MANIFEST).write_text(json.dumps(document), encoding="utf-8")
    assert _report(copy, "--format", "json", "--force") == 0
    assert (copy / "lab-journal.txt").read_text(encoding="utf-8") == "notes"
    assert (copy / "tables" / "kinematics.csv").read_text(encoding="utf-8") == "lab measurements\n"


def test_a_manifest_without_the_marker_is_ignored(tmp_path):
    out = tmp_path / "out"
    (out / "data").mkdir(parents=True)
    (out / "data" / "measurements.csv").write_text("1,2\n", encoding="utf-8")
    (out / MANIFEST).write_text(
        json.dumps({"crankdyn_version": "0.1.0", "files": ["data/measurements.csv"]}),
        encoding="utf-8",
    )
    write_outputs(out, {"results.json": b"{}\n"})
    assert (out / "data" / "measurements.csv").read_text(encoding="utf-8") == "1,2\n"


def test_nothing_is_written_through_a_linked_folder(tmp_path, capsys):
    user_data = tmp_path / "user-data"
    user_data.mkdir()
    (user_data / "kinematics.csv").write_text("the user's\n", encoding="utf-8")
    out = tmp_path / "out"
    out.mkdir()
    (out / "tables").symlink_to(Path("..") / "user-data")
    for extra in ((), ("--force",)):
        assert _report(out, "--format", "json,csv", *extra) == 2
        err = capsys.readouterr().err
        assert "tables" in err and "link" in err
        assert _snapshot(user_data) == {"kinematics.csv": b"the user's\n"}
        assert sorted(p.name for p in out.iterdir()) == ["tables"]


def test_a_linked_file_is_refused_and_with_force_the_link_is_replaced_not_followed(
    tmp_path, capsys
):
    target = tmp_path / "precious.json"
    target.write_text("keep", encoding="utf-8")
    out = tmp_path / "out"
    out.mkdir()
    (out / "results.json").symlink_to(target)
    assert _report(out, "--format", "json") == 2
    assert "symbolic link" in capsys.readouterr().err
    assert _report(out, "--format", "json", "--force") == 0
    assert not (out / "results.json").is_symlink()
    assert target.read_text(encoding="utf-8") == "keep"


def test_a_users_file_with_an_output_name_is_kept_unless_identical_or_forced(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "results.json").write_text("mine", encoding="utf-8")
    with pytest.raises(OutputError, match="results.json: not written by crankdyn"):
        write_outputs(out, {"results.json": b"new", "other.csv": b"x"})
    assert sorted(p.name for p in out.iterdir()) == ["results.json"]
    (out / "results.json").write_bytes(b"new")  # byte-for-byte what would be written: reused
    write_outputs(out, {"results.json": b"new"})
    (out / "results.json").write_bytes(b"mine")
    write_outputs(out, {"results.json": b"new"}, force=True)
    assert (out / "results.json").read_bytes() == b"new"


def test_output_option_naming_a_file_is_refused(tmp_path, capsys):
    not_a_folder = tmp_path / "report"
    not_a_folder.write_text("x", encoding="utf-8")
    assert _report(not_a_folder, "--format", "json") == 2
    err = capsys.readouterr().err
    assert "not a folder" in err and "internal error" not in err
    assert not_a_folder.read_text(encoding="utf-8") == "x"


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0, reason="root may write anywhere")
def test_an_unwritable_output_folder_is_refused(tmp_path, capsys):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o555)
    try:
        assert _report(locked / "out", "--format", "json") == 2
        assert "internal error" not in capsys.readouterr().err
    finally:
        locked.chmod(0o755)


def test_a_run_stopped_half_way_leaves_its_files_recognised(tmp_path, monkeypatch):
    """The manifest written before the files lists both states, so a rerun may replace them."""
    out = tmp_path / "out"
    write_outputs(out, {"a.csv": b"old a", "b.csv": b"old b"})
    from crankdyn.output import manifest

    real_write = manifest._Folder.write

    def stop_at_b(self, name, payload):
        if name == "b.csv":
            raise KeyboardInterrupt
        real_write(self, name, payload)

    monkeypatch.setattr(manifest._Folder, "write", stop_at_b)
    with pytest.raises(KeyboardInterrupt):
        write_outputs(out, {"a.csv": b"new a", "b.csv": b"new b"})
    monkeypatch.setattr(manifest._Folder, "write", real_write)
    assert (out / "a.csv").read_bytes() == b"new a" and (out / "b.csv").read_bytes() == b"old b"
    write_outputs(out, {"c.csv": b"c"})  # both are crankdyn's, in either state: removed
    assert sorted(p.name for p in out.iterdir()) == [MANIFEST, "c.csv"]


# ------------------------------------------------------------------ random folder histories

NAMES = [
    "report.html",
    "results.json",
    "tables/a.csv",
    "tables/b.csv",
    "figures/f1.svg",
    "figures/deep/f2.svg",
]
_output_sets = st.lists(st.sampled_from(NAMES), unique=True, min_size=1, max_size=len(NAMES))
_steps = st.lists(
    st.one_of(
        st.tuples(st.just("run"), _output_sets, st.integers(0, 3)),
        st.tuples(st.just("edit"), st.sampled_from(NAMES), st.integers(0, 3)),
        st.tuples(st.just("delete"), st.sampled_from(NAMES), st.just(0)),
        st.tuples(
            st.just("add"),
            st.sampled_from(NAMES + ["mine.txt", "tables/mine.csv"]),
            st.integers(0, 3),
        ),
        st.tuples(st.just("link_file"), st.sampled_from(NAMES), st.just(0)),
        st.tuples(
            st.just("link_folder"),
            st.sampled_from(["tables", "figures", "figures/deep"]),
            st.just(0),
        ),
        st.tuples(st.just("foreign_manifest"), st.just(""), st.just(0)),
    ),
    min_size=1,
    max_size=12,
)


@settings(
    max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(steps=_steps)
def test_random_histories_never_touch_a_file_crankdyn_did_not_write(tmp_path_factory, steps):
    root = tmp_path_factory.mktemp("history")
    out, outside = root / "out", root / "outside"
    outside.mkdir()
    (outside / "a.csv").write_bytes(b"outside")
    user_files: dict[str, bytes] = {}  # written or edited by the user, never by crankdyn since
    for step, (action, subject, variant) in enumerate(steps):
        path = out / subject if isinstance(subject, str) else out
        if action == "run":
            payloads = {name: f"{name} {variant}".encode() for name in subject}
            before = _snapshot(out) if out.exists() else None
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", KeptFileWarning)
                    write_outputs(out, payloads)
            except OutputError:
                assert (
                    _snapshot(out) if out.exists() else None
                ) == before  # a refusal writes nothing
            else:
                for name, payload in payloads.items():
                    assert (out / name).read_bytes() == payload
                    # a user's file is replaced only by identical bytes: no change
                    assert user_files.pop(name, payload) == payload, (name, steps[: step + 1])
        elif action == "delete":
            if path.is_file() and not path.is_symlink() and not _below_link(out, subject):
                path.unlink()
                user_files.pop(subject, None)
        elif action in ("edit", "add"):
            if _below_link(out, subject) or path.is_symlink() or path.is_dir():
                continue
            if action == "edit" and not path.is_file():
                continue
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(f"user {step} {variant}".encode())
            user_files[subject] = path.read_bytes()
        elif action == "link_file":
            if path.exists() or path.is_symlink() or _below_link(out, subject):
                continue
            path.parent.mkdir(parents=True, exist_ok=True)
            path.symlink_to(outside / "a.csv")
        elif action == "link_folder":
            if path.exists() or path.is_symlink() or _below_link(out, subject):
                continue
            path.parent.mkdir(parents=True, exist_ok=True)
            path.symlink_to(outside)
        elif action == "foreign_manifest":
            out.mkdir(exist_ok=True)
            listed = {name: [{"size": 1, "sha256": "0" * 64}] for name in NAMES + ["mine.txt"]}
            (out / MANIFEST).write_text(
                json.dumps(
                    {
                        "format": "crankdyn output manifest",
                        "format_version": 2,
                        "folder": str(root / "elsewhere"),
                        "files": listed,
                    }
                ),
                encoding="utf-8",
            )
        for name, content in user_files.items():
            assert (out / name).read_bytes() == content, (name, steps[: step + 1])
        assert _snapshot(outside) == {"a.csv": b"outside"}


def _below_link(out: Path, name: str) -> bool:
    parts = Path(name).parts[:-1]
    return any((out.joinpath(*parts[: i + 1])).is_symlink() for i in range(len(parts)))


def test_a_sweep_keeps_an_edited_answer_key_and_refuses_before_computing(tmp_path, capsys):
    out = tmp_path / "study"
    args = [
        "sweep",
        str(SCENE),
        "--set",
        "engine.rpm=1000:2000:2",
        "-o",
        str(out),
        "--key",
        "csv",
        "-q",
        "--stages",
        "kinematics",
    ]
    assert main(args) == 0
    key = out / "answer_key.csv"
    key.write_text("marked by hand\n", encoding="utf-8")
    capsys.readouterr()
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "answer_key.csv: changed since crankdyn wrote it" in err and "--force" in err
    assert key.read_text(encoding="utf-8") == "marked by hand\n"
    assert main([*args, "--force"]) == 0
    assert key.read_text(encoding="utf-8").startswith("variant")
