"""The command line: examples, plugins listing, check, formats."""

from __future__ import annotations

import os
import tomllib

from conftest import run_cli

from crankdyn.cli import main

EXPECTED_EXAMPLES = {
    "petrol-1cyl",
    "diesel-1cyl",
    "diesel-rk-trace",
    "two-stroke-1cyl",
    "kinematics-only",
}


def test_example_list(capsys):
    assert main(["example", "--list"]) == 0
    names = {line.split()[0] for line in capsys.readouterr().out.splitlines() if line.strip()}
    assert EXPECTED_EXAMPLES <= names


def test_example_written_with_its_data_file_and_runs(tmp_path, capsys):
    target = tmp_path / "my.toml"
    assert main(["example", "diesel-rk-trace", "-o", str(target)]) == 0
    assert tomllib.loads(target.read_text(encoding="utf-8"))["engine"]["bore"] == "83 mm"
    assert (tmp_path / "diesel6-1600rpm.ind").is_file()
    assert main(["check", str(target)]) == 0
    assert (
        "stages: kinematics, drawing, indicator, forces, bays, torque, balancing, bearings"
        in capsys.readouterr().out
    )
    assert (
        main(["report", str(target), "-o", str(tmp_path / "out"), "--format", "json,csv", "-q"])
        == 0
    )
    assert sorted(p.name for p in (tmp_path / "out" / "tables").iterdir()) == [
        "balancing.csv",
        "bearings.csv",
        "bearings_wear.csv",
        "forces.csv",
        "indicator.csv",
        "kinematics.csv",
        "numerics_kinematics_forms.csv",
        "numerics_steps.csv",
        "torque.csv",
    ]


def test_an_example_reuses_an_identical_data_file_and_keeps_a_different_one(tmp_path, capsys):
    assert main(["example", "diesel-rk-trace", "-o", str(tmp_path / "a.toml")]) == 0
    data = next(p for p in tmp_path.iterdir() if p.suffix != ".toml")
    # the second example shares the data file: identical bytes are reused, not refused
    assert main(["example", "inline6-diesel-trace", "-o", str(tmp_path / "b.toml")]) == 0
    data.write_text("my own trace", encoding="utf-8")
    assert main(["example", "inline6-diesel-trace", "-o", str(tmp_path / "c.toml")]) == 2
    assert data.name in capsys.readouterr().err
    assert data.read_text(encoding="utf-8") == "my own trace" and not (tmp_path / "c.toml").exists()


def test_unknown_example(capsys):
    assert main(["example", "no-such-engine", "-o", "x.toml"]) == 2
    assert "available" in capsys.readouterr().err


def test_stages_option_runs_prerequisites(tmp_path, capsys):
    target = tmp_path / "p.toml"
    assert main(["example", "petrol-1cyl", "-o", str(target)]) == 0
    assert (
        main(
            [
                "report",
                str(target),
                "-o",
                str(tmp_path / "o"),
                "--format",
                "json",
                "--stages",
                "indicator",
            ]
        )
        == 0
    )
    import json

    doc = json.loads((tmp_path / "o" / "results.json").read_text())
    assert doc["stages_run"] == ["kinematics", "indicator"]
    assert doc["stages_skipped"]["forces"] == "not requested"


def test_plugins_listing_via_subprocess():
    done = run_cli("plugins")
    assert done.returncode == 0, done.stderr
    assert "crank_slider" in done.stdout and "builtin_kinematics" in done.stdout
    assert "requires=kinematics,gas_pressure" in done.stdout
    assert "languages: en, ru, uk" in done.stdout


def test_the_command_tunes_the_collector_and_main_alone_does_not(monkeypatch, capsys):
    """``crankdyn`` (cli.run) collects less often and freezes before exit; main(), used in-process, does not."""
    import sys

    import pytest

    from crankdyn import cli

    calls = []
    monkeypatch.setattr(
        cli.gc, "set_threshold", lambda *limits: calls.append(("threshold", limits))
    )
    monkeypatch.setattr(cli.gc, "freeze", lambda: calls.append(("freeze",)))
    assert main(["example", "--list"]) == 0
    assert calls == []
    monkeypatch.setattr(sys, "argv", ["crankdyn", "example", "no-such-engine", "-o", "x.toml"])
    with pytest.raises(SystemExit) as ended:
        cli.run()
    assert ended.value.code == 2
    assert calls[0][0] == "threshold" and calls[0][1][0] == cli.YOUNG_GENERATION_THRESHOLD
    assert calls[-1] == ("freeze",)


def test_the_command_keeps_blas_to_one_thread_unless_the_user_chose(monkeypatch):
    """``crankdyn`` sets OPENBLAS_NUM_THREADS=1 before numpy is imported; a user's own value stays."""
    from crankdyn import cli

    assert _the_command_sets(cli.BLAS_THREADS_ENV, None) == "1"
    assert _the_command_sets(cli.BLAS_THREADS_ENV, "4") == "4"


def test_the_command_leaves_pydantics_plugins_out_unless_the_user_chose():
    """``crankdyn`` runs without pydantic's plugins (no scan of the installed packages' entry
    points); a user's own value, an empty one included, stays."""
    from crankdyn import cli

    assert _the_command_sets(cli.PYDANTIC_PLUGINS_ENV, None) == "__all__"
    assert _the_command_sets(cli.PYDANTIC_PLUGINS_ENV, "") == ""


def _the_command_sets(name: str, users_value: str | None) -> str:
    """The value of environment variable ``name`` the ``crankdyn`` command runs with (``cli.run``,
    before numpy is imported), when the user set it to ``users_value`` (None: not set)."""
    import subprocess
    import sys

    probe = (
        "import os, sys; sys.argv = ['crankdyn', 'example', '--list'];"
        "import crankdyn.cli as c; assert 'numpy' not in sys.modules, 'numpy imported before run()';"
        f"c.main = lambda: print(os.environ.get({name!r})) or 0; c.run()"
    )
    env = {k: v for k, v in os.environ.items() if k != name}
    if users_value is not None:
        env[name] = users_value
    return subprocess.run(
        [sys.executable, "-c", probe], env=env, capture_output=True, text=True, check=True
    ).stdout.strip()


def test_the_command_documents_matplotlib_artists_briefly_unless_the_user_chose():
    """``crankdyn`` skips the property lists matplotlib writes into its artists' docstrings at
    import (≈ 0.1 s of a report); a program importing crankdyn gets them, and so do artist
    classes defined after the figures' import."""
    import subprocess
    import sys

    from crankdyn import cli
    from crankdyn.report import figures

    assert cli.ARTIST_DOCSTRINGS_ENV == figures.ARTIST_DOCSTRINGS_ENV
    assert _the_command_sets(cli.ARTIST_DOCSTRINGS_ENV, None) == "brief"
    assert _the_command_sets(cli.ARTIST_DOCSTRINGS_ENV, "full") == "full"
    env = {k: v for k, v in os.environ.items() if k != cli.ARTIST_DOCSTRINGS_ENV}
    docs = (
        "import matplotlib.artist as a; from crankdyn.report.figures import import_matplotlib\n"
        "full = a.kwdoc; import_matplotlib(); import matplotlib.lines as l\n"
        "class Mine(l.Line2D): pass\n"
        "print(a.kwdoc is full, 'markerfacecolor' in l.Line2D.set.__doc__, 'markerfacecolor' in Mine.set.__doc__)"
    )
    for value, listed in (("brief", "False"), ("full", "True"), (None, "True")):
        if value is not None:
            env[cli.ARTIST_DOCSTRINGS_ENV] = value
        else:
            env.pop(cli.ARTIST_DOCSTRINGS_ENV, None)
        out = subprocess.run(
            [sys.executable, "-c", docs], env=env, capture_output=True, text=True, check=True
        )
        assert out.stdout.split() == ["True", listed, "True"], (value, out.stdout)


def test_the_installed_command_is_run():
    from importlib.metadata import entry_points

    (script,) = entry_points(group="console_scripts", name="crankdyn")
    assert script.value == "crankdyn.cli:run"


def test_output_piped_into_a_reader_that_stops_early_is_not_an_error():
    """`crankdyn plugins | head -1`: the closed pipe ends the command quietly, as other tools do.
    The pipe's reading end is closed before the command writes, so every write meets it closed."""
    import os
    import subprocess
    import sys

    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        done = subprocess.run(
            [sys.executable, "-m", "crankdyn", "plugins"],
            stdout=write_end,
            stderr=subprocess.PIPE,
            text=True,
            timeout=120,
        )
    finally:
        os.close(write_end)
    assert done.returncode == 0, done.stderr
    assert "internal error" not in done.stderr and "Exception ignored" not in done.stderr


def test_check_names_the_tables_of_stages_left_out(tmp_path, capsys):
    """A planetary mechanism's [balancing] and [bearings] tables are read by nothing (their
    stages concern crank-slider engines): check says so instead of passing them over."""
    from conftest import example_data, write_scene

    data = example_data("planetary-kinematics")
    data["balancing"] = {}
    data["bearings"] = {}
    scene = write_scene(tmp_path / "planetary.toml", data)
    assert main(["check", str(scene)]) == 0
    out = capsys.readouterr().out
    assert "table [balancing] is not used: stage balancing is left out" in out
    assert "table [bearings] is not used: stage bearings is left out" in out
    assert "table [rod_dynamics] is not used" not in out


def test_an_internal_error_says_where_debug_goes(monkeypatch, capsys):
    """--debug belongs before the command: the hint names the command run, after it."""
    import crankdyn.cli as cli

    def broken(args):
        raise RuntimeError("boom")

    monkeypatch.setattr(cli, "_example", broken)
    assert main(["example", "--list"]) == cli.EXIT_INTERNAL
    err = capsys.readouterr().err
    assert "internal error: RuntimeError: boom" in err
    assert "run again as 'crankdyn --debug example …' for the traceback" in err
