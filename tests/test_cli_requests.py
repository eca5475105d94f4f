"""Wrong command-line requests get their own message (not "invalid scene"); nothing is overwritten."""

from __future__ import annotations

from crankdyn.cli import examples_dir, main


def test_example_does_not_overwrite_an_edited_scene_without_force(tmp_path, capsys):
    target = tmp_path / "mine.toml"
    target.write_text("# my edits\n", encoding="utf-8")
    assert main(["example", "petrol-1cyl", "-o", str(target)]) == 2
    err = capsys.readouterr().err
    assert "exists" in err and "--force" in err and "invalid scene" not in err
    assert target.read_text(encoding="utf-8") == "# my edits\n"
    assert main(["example", "petrol-1cyl", "-o", str(target), "--force"]) == 0
    assert target.read_bytes() == (examples_dir() / "petrol-1cyl.toml").read_bytes()


def test_example_with_a_data_file_checks_that_file_too(tmp_path, capsys):
    (tmp_path / "diesel6-1600rpm.ind").write_text("mine\n", encoding="utf-8")
    assert main(["example", "diesel-rk-trace", "-o", str(tmp_path / "new.toml")]) == 2
    assert "diesel6-1600rpm.ind exists" in capsys.readouterr().err
    assert not (tmp_path / "new.toml").exists()


def test_unknown_example_and_format_list_the_allowed_names(tmp_path, capsys):
    assert main(["example", "steam-engine"]) == 2
    err = capsys.readouterr().err
    assert (
        "unknown example 'steam-engine'" in err
        and "petrol-1cyl" in err
        and "invalid scene" not in err
    )
    assert (
        main(
            [
                "report",
                str(examples_dir() / "kinematics-only.toml"),
                "-o",
                str(tmp_path / "o"),
                "--format",
                "html,odt",
            ]
        )
        == 2
    )
    err = capsys.readouterr().err
    assert (
        "unknown --format odt" in err
        and "html,pdf,json,csv,xlsx" in err
        and "invalid scene" not in err
    )
    assert not (tmp_path / "o").exists()
