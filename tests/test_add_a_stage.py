"""The recipe of docs/architecture.md, "add a stage": a throw-away plugin written to a temporary
folder — hook implementations, a section template, catalogs in en/uk/ru, a declared figure and
table, and an answer-key column with a translated label — is registered, runs, and shows its
section, its figure file, its table, its answer column (labelled in the batch's language in
answer_key.xlsx) and its translations, with nothing under src/ or templates/ touched."""

from __future__ import annotations

import hashlib
import importlib
import io
import textwrap
from pathlib import Path

import pytest
from conftest import modified
from openpyxl import load_workbook

from crankdyn.batch import answer_key
from crankdyn.batch import variants as batch
from crankdyn.cli import examples_dir
from crankdyn.output import writers as outputs
from crankdyn.output.pipeline import run_and_render
from crankdyn.plugin.registry import collect, plugin_manager
from crankdyn.scene.model import scene_from_dict

ROOT = Path(__file__).resolve().parents[1]

PLUGIN = '''
"""A throw-away stage: the piston stroke from the crank radius, and the piston's travel over one
turn as a figure (no prerequisite, so the test renders no other section's figures)."""
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import AnswerColumn, Catalog, Stage, StageOutput, StagePresentation, Symbol

HERE = Path(__file__).resolve().parent


def run(scene, inputs):
    radius = scene.engine.crank_radius_m
    angle_deg = np.arange(0.0, 360.0, 10.0)
    travel = {"crank_angle_deg": angle_deg, "travel_m": radius * (1.0 - np.cos(np.radians(angle_deg)))}
    return StageOutput(results={"stroke_m": float(2.0 * radius)}, tables={"travel": travel})


def render(output, ctx):
    travel = output.tables["travel"]
    fig, ax = plt.subplots(figsize=(12 / 2.54, 6 / 2.54))
    ax.plot(travel["crank_angle_deg"], travel["travel_m"] * 1e3)
    ax.set_xlabel(ctx.t("throwaway.axis_angle"))
    ax.set_ylabel(ctx.t("throwaway.axis_travel"))
    figure = ctx.figure(fig, ctx.t("throwaway.figure_caption"), "throwaway_travel")
    ctx.conclude(ctx.t("throwaway.conclusion", stroke=ctx.num(output.results["stroke_m"] * 1e3)))
    return ctx.render_template("sections/throwaway.html.j2", r=output.results, figure=figure)


STAGE = Stage(name="throwaway", requires=(), provides=(), applies=lambda scene: None, run=run,
              default=False, tables=("travel",),
              answer_columns=(AnswerColumn("throwaway_stroke_mm", "stroke_m", "mm", factor=1e3,
                                           label_key="throwaway.answer.stroke"),),
              presentation=StagePresentation(
                  title_key="throwaway.title", render=render, template_dir=HERE / "templates",
                  figures=("throwaway_travel",),
                  symbols={"travel": Symbol("h", {"en": "t"}, "unit.mm")}))


@hookimpl
def crankdyn_stages():
    return [STAGE]


@hookimpl
def crankdyn_catalogs():
    return [Catalog(language=p.stem.rsplit(".", 1)[-1], path=p) for p in sorted((HERE / "i18n").glob("*.toml"))]
'''

TEMPLATE = (
    "<p class=\"throwaway\">{{ _('throwaway.body', stroke=num(r.stroke_m * 1000)) }}</p>\n"
    "{{ eq('<i>h</i><sub>t</sub> = <i>R</i>(1 − cos <i>α</i>)') }}\n{{ figure }}\n"
)

# title, body, conclusion, figure caption, axis labels, the answer column's label, the meaning of its symbol h_t
CATALOGS = {
    "en": (
        "Stroke of the crank mechanism",
        "The piston travels {stroke} mm between its dead centres.",
        "The measured stroke is {stroke} mm.",
        "Piston travel over one turn",
        "Crank angle, °",
        "Travel, mm",
        "Piston stroke, mm",
        "travel of the piston from TDC",
    ),
    "uk": (
        "Хід кривошипно-шатунного механізму",
        "Поршень проходить {stroke} мм між мертвими точками.",
        "Виміряний хід становить {stroke} мм.",
        "Переміщення поршня за один оберт",
        "Кут повороту, °",
        "Переміщення, мм",
        "Хід поршня, мм",
        "переміщення поршня від ВМТ",
    ),
    "ru": (
        "Ход кривошипно-шатунного механизма",
        "Поршень проходит {stroke} мм между мёртвыми точками.",
        "Измеренный ход равен {stroke} мм.",
        "Перемещение поршня за один оборот",
        "Угол поворота, °",
        "Перемещение, мм",
        "Ход поршня, мм",
        "перемещение поршня от ВМТ",
    ),
}
KEYS = (
    "title",
    "body",
    "conclusion",
    "figure_caption",
    "axis_angle",
    "axis_travel",
    "answer.stroke",
)


def _tree_digest(*folders: Path) -> str:
    digest = hashlib.sha256()
    for folder in folders:
        for path in sorted(
            p for p in folder.rglob("*") if p.is_file() and "__pycache__" not in p.parts
        ):
            digest.update(str(path.relative_to(ROOT)).encode() + path.read_bytes())
    return digest.hexdigest()


def _write_plugin(folder: Path) -> None:
    package = folder / "throwaway_crankdyn_plugin"
    (package / "templates" / "sections").mkdir(parents=True)
    (package / "i18n").mkdir()
    (package / "__init__.py").write_text("", encoding="utf-8")
    (package / "plugin.py").write_text(textwrap.dedent(PLUGIN), encoding="utf-8")
    (package / "templates" / "sections" / "throwaway.html.j2").write_text(
        TEMPLATE, encoding="utf-8"
    )
    for language, texts in CATALOGS.items():
        lines = "".join(f'{key} = "{text}"\n' for key, text in zip(KEYS, texts[:-1], strict=True))
        # the meaning of its symbol: symbol.<stage>.<key>
        (package / "i18n" / f"throwaway.{language}.toml").write_text(
            f'[throwaway]\n{lines}\n[symbol.throwaway]\ntravel = "{texts[-1]}"\n', encoding="utf-8"
        )


def test_a_plugin_from_a_temporary_folder_adds_section_answer_column_and_translations(
    tmp_path, monkeypatch
):
    before = _tree_digest(ROOT / "src", ROOT / "templates")
    _write_plugin(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    plugin = importlib.import_module("throwaway_crankdyn_plugin.plugin")
    registry = collect(plugin_manager(extra_plugins=[plugin]))
    assert registry.owner["stage:throwaway"] and "throwaway" in registry.stages

    for language in ("en", "uk", "ru"):
        scene = scene_from_dict(
            modified("kinematics-only", {"report": {"language": language}}), base_dir=examples_dir()
        )
        result, files = run_and_render(scene, registry, ["html", "csv"], stages=["throwaway"])
        assert result.stages_run == ["throwaway"]
        # The independent value: the scene's own stroke = 100 mm.
        assert result.outputs["throwaway"].results["stroke_m"] == pytest.approx(0.100, rel=1e-9)
        html = files["report.html"].decode("utf-8")
        title, body, conclusion, caption, *_, label, meaning = CATALOGS[language]
        assert title in html and '<p class="throwaway">' in html
        stroke = "100.0" if language == "en" else "100,0"  # the report's number format per language
        # the report keeps a number on the line of its unit (a narrow no-break space)
        seen = html.replace("\u202f", " ").replace("\u00a0", " ")
        assert body.format(stroke=stroke) in seen and conclusion.format(stroke=stroke) in seen
        # its own letter h_t (Stage.symbols): in the list of symbols, and in the "where" line under its equation
        row = '<span class="symbol"><i>h</i><sub>t</sub></span> – <span class="meaning">' + meaning
        assert html.count(row) == 1 and html.index(row) < html.index('<p class="throwaway">')
        assert html.index(
            '<span class="where-line"><i>h</i><sub>t</sub> – ' + meaning
        ) > html.index('<p class="throwaway">')
        for other in set(CATALOGS) - {language}:
            assert CATALOGS[other][0] not in html and CATALOGS[other][3] not in html

        # Its declared figure and table: the figure file, referred to under its caption; the CSV.
        assert [name for name in files if name.startswith("figures/")] == [
            "figures/fig_2_1_throwaway_travel.svg"
        ]
        assert 'src="figures/fig_2_1_throwaway_travel.svg"' in html and caption in html
        assert (
            files["tables/throwaway_travel.csv"]
            .decode("utf-8")
            .startswith("crank_angle_deg,travel_m\n")
        )

        # The answer key of a batch (the code path of crankdyn batch): the column is there, and the
        # workbook labels it in the batch's language above its name; the CSV has the name only.
        columns = answer_key.answer_columns(registry)
        assert [c.name for c in columns if c.stage == "throwaway"] == ["throwaway_stroke_mm"]
        answers = batch.answers(outputs.results_document(result), registry)
        assert answers["throwaway_stroke_mm"] == pytest.approx(100.0, rel=1e-9)
        assert answers["v_max_m_s"] is None  # the built-in stages did not run: empty cells
        key = batch.key_files(
            [],
            [batch.Outcome(1, "v1", True, answers=answers)],
            [batch.Variant(1, "v1", {}, {"variant": "v1"})],
            ("csv", "xlsx"),
            language=language,
            registry=registry,  # the batch's registry: with the plugin
        )
        labels, names, values = [
            [c.value for c in row]
            for row in load_workbook(io.BytesIO(key["answer_key.xlsx"]))["answer key"].iter_rows()
        ]
        assert names == ["variant", "row", "throwaway_stroke_mm"] and labels == [
            "variant",
            "row",
            label,
        ]
        assert values[2] == pytest.approx(100.0, rel=1e-9)
        assert (
            key["answer_key.csv"].decode("utf-8").splitlines()[0]
            == "variant,row,throwaway_stroke_mm"
        )

    assert _tree_digest(ROOT / "src", ROOT / "templates") == before
