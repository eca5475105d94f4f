"""The answer key's column labels: each stage's ``AnswerColumn.label_key``, translated by the stage's
own catalogs, shown above the column names in ``answer_key.xlsx``; ``answer_key.csv`` keeps the
machine-readable names only. Built from made-up outcomes: no scene is computed here."""

from __future__ import annotations

import csv
import dataclasses
import io

import pytest
from openpyxl import load_workbook

from crankdyn.batch import variants as batch
from crankdyn.batch.answer_key import answer_columns
from crankdyn.batch.variants import Outcome, RunOptions, Variant, batch_language, key_files
from crankdyn.plugin.registry import default_registry
from crankdyn.plugin.types import AnswerColumn, Stage, StageOutput, StagePresentation
from crankdyn.report.i18n import load_catalog_file

REGISTRY = default_registry()
LANGUAGES = ("en", "uk", "ru")


def _own_catalog(stage: Stage, language: str) -> dict[str, str]:
    """The texts of the catalogs in the stage's own plugin folder (next to its templates)."""
    texts: dict[str, str] = {}
    for path in sorted(
        (stage.presentation.template_dir.parent / "i18n").glob(f"*.{language}.toml")
    ):
        texts.update(load_catalog_file(path))
    return texts


def test_every_built_in_answer_column_has_a_label_in_each_language():
    columns = answer_columns(REGISTRY)
    assert len(columns) >= 24
    for column in columns:
        stage = REGISTRY.stages[column.stage]
        key = column.declared.label_key
        assert key and key.startswith(f"{stage.name}."), (
            f"{column.name}: no label_key in the stage's namespace"
        )
        labels = {lang: _own_catalog(stage, lang).get(key) for lang in LANGUAGES}
        assert all(labels.values()), (
            f"{column.name}: {key} missing in {stage.name}'s catalogs: {labels}"
        )
        assert len(set(labels.values())) == 3, (
            f"{column.name}: the same text in two languages: {labels}"
        )
        assert column.name not in labels["en"]  # a human label, not the column name again
        if (
            column.declared.unit
        ):  # the label says its unit (°, MPa, N·m ...), in the language's own words
            assert "," in labels["en"] and "," in labels["uk"] and "," in labels["ru"], labels


def _outcomes():
    variants = [
        Variant(1, "v1", {}, {"variant": "v1", "engine.rpm": "5600"}),
        Variant(2, "v2", {}, {"variant": "v2", "engine.rpm": "6000"}),
        Variant(3, "v3", {}, {"variant": "v3", "engine.rpm": "7000"}),
    ]
    answers = {c.name: 1.5 for c in answer_columns(REGISTRY)}
    outcomes = [
        Outcome(1, "v1", True, answers=dict(answers, p_max_MPa=6.25)),
        Outcome(2, "v2", True, answers=dict(answers, p_max_MPa=6.5)),
        Outcome(3, "v3", False, error="invalid scene"),
    ]
    return ["engine.rpm"], outcomes, variants


@pytest.mark.parametrize(
    "language, label",
    [
        ("uk", "Максимальний тиск циклу, МПа"),
        ("ru", "Максимальное давление цикла, МПа"),
        ("en", "Maximum cycle pressure, MPa"),
    ],
)
def test_the_workbook_shows_the_labels_above_the_column_names(language, label):
    fields, outcomes, variants = _outcomes()
    files = key_files(fields, outcomes, variants, ("csv", "xlsx"), language=language)
    book = load_workbook(io.BytesIO(files["answer_key.xlsx"]))
    sheet = book["answer key"]
    labels, names, *rows = [[c.value for c in row] for row in sheet.iter_rows()]
    assert sheet.freeze_panes == "A3"
    header = next(csv.reader(io.StringIO(files["answer_key.csv"].decode("utf-8"))))
    assert names == header  # the machine-readable names, as in the CSV, on the second row
    assert labels[names.index("p_max_MPa")] == label
    assert labels[:3] == ["variant", "row", "engine.rpm"]  # columns without a label: their name
    assert [r[names.index("p_max_MPa")] for r in rows] == [6.25, 6.5]  # numbers stay numbers
    assert all(
        labels[names.index(c.name)] != c.name for c in answer_columns(REGISTRY)
    )  # every result labelled
    assert [c.value for c in next(book["failures"].iter_rows())] == ["variant", "row", "error"]


def test_the_csv_key_carries_the_column_names_only():
    fields, outcomes, variants = _outcomes()
    text = {
        lang: key_files(fields, outcomes, variants, ("csv",), language=lang)["answer_key.csv"]
        for lang in LANGUAGES
    }
    assert text["en"] == text["uk"] == text["ru"]
    header, *rows = list(csv.reader(io.StringIO(text["uk"].decode("utf-8"))))
    assert header == ["variant", "row", "engine.rpm", *(c.name for c in answer_columns(REGISTRY))]
    assert len(rows) == 2 and not any("МПа" in cell for cell in header)


def test_the_batch_language_and_a_column_without_a_label():
    base = {"report": {"language": "uk"}}
    assert batch_language(base, RunOptions([])) == "uk"
    assert batch_language(base, RunOptions([], language="ru")) == "ru"
    assert batch_language({}, RunOptions([])) == "en"
    assert (
        batch_language({"report": {"language": "xx"}}, RunOptions([])) == "en"
    )  # no catalog: English
    # A third-party stage declaring a column with no label_key: its name is its label.
    plain = Stage(
        name="plain",
        requires=(),
        provides=(),
        applies=lambda s: None,
        run=lambda s, i: StageOutput(),
        answer_columns=(
            AnswerColumn("plain_x_m", "x_m", "m"),
            AnswerColumn("plain_y_m", "y_m", "m", label_key="plain.no_such_text"),
        ),
        presentation=StagePresentation(title_key="plain.title", render=lambda o, c: None),
    )
    registry = dataclasses.replace(REGISTRY, stages={**REGISTRY.stages, "plain": plain})
    labels = batch.answer_labels("uk", registry)
    assert labels["plain_x_m"] == "plain_x_m" and labels["plain_y_m"] == "plain_y_m"
    assert labels["p_max_MPa"] == "Максимальний тиск циклу, МПа"
