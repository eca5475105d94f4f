"""The command line as a user meets it: what a success prints, the help, --lang, the sweep's
messages and the programs a format needs."""

from __future__ import annotations

import json
import shlex
import sys

import pytest

from crankdyn import cli
from crankdyn.cli import examples_dir, main

COMMANDS = ("report", "check", "example", "plugins", "explore", "serve", "batch", "sweep")


def _help_text(capsys, *command: str) -> str:
    with pytest.raises(SystemExit) as ended:
        main([*command, "--help"])
    assert ended.value.code == 0
    return capsys.readouterr().out


# --------------------------------------------------------------------------- what a success prints


def test_a_report_lists_the_stages_left_out_only_when_verbose(tmp_path, capsys):
    scene = str(examples_dir() / "petrol-1cyl.toml")
    request = ["report", scene, "--format", "json", "--stages", "kinematics"]
    assert main([*request, "-o", str(tmp_path / "a")]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[0].startswith(f"crankdyn: 1 files in {tmp_path / 'a'}")
    assert "results.json" in out and "left out" not in out
    results = json.loads((tmp_path / "a" / "results.json").read_text(encoding="utf-8"))
    skipped = results["stages_skipped"]
    assert "forces" in skipped

    assert main([*request, "-o", str(tmp_path / "b"), "-v"]) == 0
    listed = [line for line in capsys.readouterr().out.splitlines() if "left out" in line]
    assert listed == [f"  stage {name} left out: {reason}" for name, reason in skipped.items()]


def test_quiet_wins_over_verbose(tmp_path, capsys):
    scene = str(examples_dir() / "kinematics-only.toml")
    assert main(["report", scene, "-o", str(tmp_path / "o"), "--format", "json", "-q", "-v"]) == 0
    assert capsys.readouterr().out == ""


# --------------------------------------------------------------------------- help


@pytest.mark.parametrize("command", COMMANDS)
def test_every_command_has_help_with_examples_that_the_command_line_accepts(command, capsys):
    text = _help_text(capsys, command)
    assert "examples:" in text
    examples = [line.split("#")[0].strip() for line in text.split("examples:", 1)[1].splitlines()]
    examples = [line for line in examples if line.startswith("crankdyn ")]
    assert examples, text
    for line in examples:
        words = shlex.split(line)[1:]
        assert words[0] == command, line
        cli._parser().parse_args(words)  # exits (SystemExit) on an option the command lacks


def test_the_main_help_shows_a_first_report(capsys):
    text = _help_text(capsys)
    for command in COMMANDS:
        assert command in text
    firsts = [shlex.split(line)[1:] for line in text.splitlines() if line.startswith("  crankdyn ")]
    assert [words[0] for words in firsts] == ["example", "check", "report"]
    for words in firsts:
        cli._parser().parse_args(words)


def test_report_help_lists_every_format_and_language(capsys):
    from crankdyn.output.writers import FORMATS
    from crankdyn.report.i18n import available_languages

    assert cli.REPORT_FORMATS == FORMATS
    assert cli.report_languages() == available_languages()
    text = " ".join(_help_text(capsys, "report").split())
    assert ",".join(FORMATS) in text and "docx needs pandoc" in text
    assert "any case: " + ", ".join(available_languages()) in text
    assert "--verbose" in text


# --------------------------------------------------------------------------- --lang


@pytest.mark.parametrize("given, code", [("UK", "uk"), ("En", "en"), (" ru ", "ru")])
def test_lang_is_read_in_any_case(given, code):
    assert cli.report_language(given) == code


@pytest.mark.parametrize(
    "given, meant",
    [
        ("ua", "uk"),
        ("UA", "uk"),
        ("ukr", "uk"),
        ("Ukrainian", "uk"),
        ("uk-UA", "uk"),
        ("rus", "ru"),
        ("Russian", "ru"),
        ("ru_RU", "ru"),
        ("eng", "en"),
        ("English", "en"),
        ("en-GB", "en"),
        ("en_US", "en"),
        ("enn", "en"),
    ],
)
def test_a_language_name_users_often_type_gets_the_code_it_means(given, meant):
    with pytest.raises(cli.UsageError) as refused:
        cli.report_language(given)
    message = str(refused.value)
    assert message.startswith(f"--lang {given!r}: not a report language; did you mean {meant!r}?")
    assert "(available: en, ru, uk)" in message


def test_a_language_nothing_resembles_gets_the_list_alone():
    with pytest.raises(cli.UsageError) as refused:
        cli.report_language("de")
    message = str(refused.value)
    assert "did you mean" not in message and "available: en, ru, uk" in message


@pytest.mark.parametrize(
    "command",
    [
        ["report", "SCENE"],
        ["check", "SCENE"],
        ["serve", "SCENE"],
        ["batch", "variants.csv", "--base", "SCENE"],
        ["sweep", "SCENE", "--set", "engine.rpm=1000,2000"],
    ],
)
def test_a_wrong_lang_is_named_as_the_option_in_every_command(
    command, tmp_path, capsys, monkeypatch
):
    monkeypatch.chdir(tmp_path)
    words = [str(examples_dir() / "petrol-1cyl.toml") if w == "SCENE" else w for w in command]
    assert main([*words, "--lang", "ua"]) == 2
    err = capsys.readouterr().err
    assert "--lang 'ua'" in err and "did you mean 'uk'?" in err
    assert "report.language" not in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_check_takes_lang(capsys):
    """The example's title fields are English: a check in Russian warns that they are."""
    scene = str(examples_dir() / "petrol-1cyl.toml")
    assert main(["check", scene, "--lang", "RU"]) == 0
    captured = capsys.readouterr()
    assert "the report is in ru" in captured.err
    assert "stage flywheel left out" in captured.out


# --------------------------------------------------------------------------- sweep problems


def test_a_sweep_reports_a_problem_shared_by_every_value_once(tmp_path, capsys):
    scene = str(examples_dir() / "petrol-1cyl.toml")
    assert main(["sweep", scene, "--set", "engine.bore=76:88:4", "-o", str(tmp_path / "s")]) == 2
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if "engine.bore" in line]
    assert lines == [
        "  - engine.bore = 76, 80, 84, 88: a bare number has no unit; write the "
        "length with its unit, e.g. '82 mm'"
    ]
    assert "1 problem(s)" in err
    assert not (tmp_path / "s").exists()


def test_a_sweep_value_with_a_problem_of_its_own_is_named_alone(tmp_path, capsys):
    scene = str(examples_dir() / "petrol-1cyl.toml")
    out = str(tmp_path / "s")
    assert main(["sweep", scene, "--set", "engine.bore=80 mm,-5 mm", "-o", out]) == 2
    lines = [line for line in capsys.readouterr().err.splitlines() if "engine.bore" in line]
    assert len(lines) == 1 and "-5" in lines[0] and "80" not in lines[0]


# ------------------------------------------------------------------ programs a format needs


@pytest.fixture
def no_pandoc(monkeypatch):
    """A machine without pandoc: none on PATH and no pypandoc wheel."""
    from crankdyn.report import docx

    real = docx.shutil.which
    monkeypatch.setattr(
        docx.shutil,
        "which",
        lambda name, *a, **k: None if name == "pandoc" else real(name, *a, **k),
    )
    monkeypatch.setitem(sys.modules, "pypandoc", None)


def _never_called(calls: list):
    def record(*args, **kwargs):
        calls.append(args)
        raise AssertionError("computed although a program the format needs is missing")

    return record


def test_a_word_report_without_pandoc_stops_before_computing(
    no_pandoc, tmp_path, capsys, monkeypatch
):
    import crankdyn.output.pipeline

    calls: list = []
    monkeypatch.setattr(crankdyn.output.pipeline, "write_report", _never_called(calls))
    scene = str(examples_dir() / "petrol-1cyl.toml")
    assert main(["report", scene, "-o", str(tmp_path / "o"), "--format", "json,docx"]) == 2
    err = capsys.readouterr().err
    assert "--format docx needs pandoc" in err and "apt-get install pandoc" in err
    assert "pip install pypandoc-binary" in err
    assert calls == [] and not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    "command, runner",
    [
        (["batch", "variants.csv", "--base", "SCENE"], "crankdyn.batch.variants.run_batch"),
        (["sweep", "SCENE", "--set", "engine.rpm=1000,2000"], "crankdyn.batch.sweep.run_sweep"),
    ],
)
def test_a_batch_or_sweep_of_word_files_without_pandoc_stops_before_running(
    command, runner, no_pandoc, tmp_path, capsys, monkeypatch
):
    calls: list = []
    monkeypatch.setattr(runner, _never_called(calls))
    words = [str(examples_dir() / "petrol-1cyl.toml") if w == "SCENE" else w for w in command]
    assert main([*words, "-o", str(tmp_path / "o"), "--format", "docx"]) == 2
    assert "--format docx needs pandoc" in capsys.readouterr().err
    assert calls == [] and not (tmp_path / "o").exists()
