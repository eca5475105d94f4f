"""The rendered report: structure, languages, escaping, the PDF and its safety."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest
from conftest import shared_html, shared_run

from crankdyn.cli import examples_dir, main
from crankdyn.plugin.registry import default_registry
from crankdyn.report.i18n import core_catalog_dir, load_catalog_file
from crankdyn.report.pdf import BlockedResource, _fetcher, is_allowed

REGISTRY = default_registry()


def _render(name="petrol-1cyl", language="en", changes=None):
    """The example's run and report, computed once per test process and shared with the other test
    files (read only)."""
    return shared_run(name, changes), shared_html(name, changes, language)


@pytest.mark.parametrize(
    "language, table, figure, sep",
    [("en", "Table 2.1 —", "Figure 2.1 —", "."), ("uk", "Таблиця 2.1 –", "Рисунок 2.1 –", ",")],
)
def test_html_structure_and_language(language, table, figure, sep):
    result, rendered = _render(language=language)
    html = rendered.html  # self-contained: the figures inlined
    assert not rendered.missing_translations, rendered.missing_translations
    assert table in html and figure in html
    for stage in ("kinematics", "indicator", "forces"):
        assert f'data-stage="{stage}"' in html
    # One cylinder: no bay or crankshaft sections although those stages ran for their data.
    assert {"bays", "torque"} <= set(result.stages_run)
    assert 'data-stage="bays"' not in html and 'data-stage="torque"' not in html
    for fixed in ("numerics", "conclusions", "references"):
        assert f'data-stage="{fixed}"' in html
    # Equations numbered per section, e.g. (2.1) ... and the contents links every section.
    assert "(2.1)" in html and "(4.1)" in html
    assert html.count('href="#sec-') >= 6
    assert html.count("data:image/svg+xml;base64,") >= 6
    assert f"0{sep}28<" in html  # lambda in the input table, with the language's decimal separator
    assert (
        f"82{sep}000" not in html and f"0{sep}2800</td>" not in html
    )  # the given data without padding zeros
    assert "−" in html  # typographic minus in numbers


def test_catalogs_complete_in_every_language():
    core = {p.stem: load_catalog_file(p) for p in core_catalog_dir().glob("*.toml")}
    plugin_dir = Path(next(iter(REGISTRY.catalogs)).path).parent
    plugin: dict[str, dict] = {}
    for p in plugin_dir.glob("*.toml"):
        plugin.setdefault(p.stem.rsplit(".", 1)[-1], {}).update(load_catalog_file(p))
    for catalogs in (core, plugin):
        english = set(catalogs["en"])
        for lang, texts in catalogs.items():
            assert set(texts) == english, (lang, english ^ set(texts))


def test_kinematics_only_report_leaves_sections_out():
    result, rendered = _render("kinematics-only")
    html = rendered.linked_html  # the text: its figures are not drawn here
    assert 'data-stage="kinematics"' in html
    assert 'data-stage="indicator"' not in html and 'data-stage="forces"' not in html
    # a course note of a mechanism without a working cycle names no engine calculation it leaves
    # out; the full report states each with its reason (in the report's language)
    reason = "the assignment gives no working-cycle (indicator diagram) data"
    assert reason not in html and "not calculated in this note" not in html
    full = shared_html("kinematics-only", {"report": {"detail": "full"}}, "en").linked_html
    assert reason in full


def test_scene_text_is_escaped():
    _, rendered = _render(
        changes={"report": {"title": "<script>alert('x')</script>", "student": "A & B"}}
    )
    html = rendered.linked_html  # the text (the figures, inlined as data: URIs, hold no scene text)
    assert "<script>alert" not in html
    assert "&lt;script&gt;alert" in html
    assert "A &amp; B" in html


def test_url_fetcher_only_reaches_package_assets(tmp_path):
    assert is_allowed("data:image/png;base64,AAAA")
    assert not is_allowed("file:///etc/passwd")
    assert not is_allowed("http://127.0.0.1:9/x.png")
    assert not is_allowed("https://example.org/font.woff")
    assert not is_allowed((tmp_path / "x.png").as_uri())
    fetcher = _fetcher()
    with pytest.raises(BlockedResource):
        fetcher.fetch("file:///etc/hostname") if hasattr(fetcher, "fetch") else fetcher(
            "file:///etc/hostname"
        )


def test_pdf_with_hostile_scene_text_does_not_fetch(tmp_path):
    from crankdyn.report.pdf import html_to_pdf

    html = (
        '<html><body><p>x</p><img src="file:///etc/passwd"><img src="http://127.0.0.1:9/a.png">'
        '<link rel="stylesheet" href="file:///etc/ssl/openssl.cnf"></body></html>'
    )
    pdf = html_to_pdf(html)
    assert pdf.startswith(b"%PDF") and b"root:" not in pdf


# The PDF itself (structure, typography, fonts, page images): tests/test_note.py renders one per language.


def test_results_json_keys_are_documented(tmp_path):
    from documented import documentation_text

    readme = documentation_text()
    for example in ("petrol-1cyl", "diesel-rk-trace", "kinematics-only"):
        out = tmp_path / example
        assert (
            main(
                [
                    "report",
                    str(examples_dir() / f"{example}.toml"),
                    "-o",
                    str(out),
                    "--format",
                    "json",
                    "-q",
                ]
            )
            == 0
        )
        document = json.loads((out / "results.json").read_text(encoding="utf-8"))
        assert [p for p in out.iterdir() if p.name != ".crankdyn-manifest.json"] == [
            out / "results.json"
        ]
        for key, value in document.items():
            assert f"`{key}`" in readme, f"{key} not in the results.json reference"
            if isinstance(value, dict) and key not in ("stages_skipped", "timing_s"):
                for sub in value:
                    generic = re.sub(
                        r"^(total|side|rod|tangential|radial|resultant|torque)_(max|min)_",
                        r"<force>_\2_",
                        sub,
                    )
                    generic = (
                        re.sub(r"_(Pa|Nm)$", "_<unit>", generic)
                        if generic.startswith("<force>")
                        else generic
                    )
                    assert f"`{sub}`" in readme or f"`{generic}`" in readme, (
                        f"{key}.{sub} not in the results.json reference"
                    )


def test_captions_side_by_side_keep_a_gutter():
    """Two captions of a figure row must not read across as one line ("…шатунну шийку (полюс O
    навантаження на шатунний підшипник…"): each caption of a row is padded from its neighbour."""
    import re

    from crankdyn.report.assets import report_css

    rule = re.search(r"\.figure-row > \.figure-block figcaption \{([^}]*)\}", report_css("uk"))
    assert rule and re.search(r"padding: 0 (0\.[5-9]|1(\.\d)?)em", rule.group(1))


@pytest.mark.skipif(
    shutil.which("pdftotext") is None, reason="pdftotext (poppler) is not installed"
)
def test_a_line_breaks_before_an_italic_symbol_where_it_should():
    """A paragraph's first line does not hold the one word "Амплітуду" and go on on the next.
    WeasyPrint cannot break a line just before an italic element there; the PDF's HTML has the word
    space inside the element (report.pdf.spaces_into_inline), and the first line is full."""
    import subprocess

    from crankdyn.report.assets import report_css
    from crankdyn.report.pdf import html_to_pdf, spaces_into_inline

    assert (
        spaces_into_inline("за посібником <i>C</i> і <b><i>θ</i></b>, (<i>α</i>)")
        == "за посібником<i> C</i> і<b><i> θ</i></b>, (<i>α</i>)"
    )
    paragraph = (
        "Амплітуду сили другого порядку можна обчислити двома способами: за посібником "
        "<i>C</i><sub>II</sub> = λ<i>C</i><sub>I</sub> і точно – як другу гармоніку точної сили інерції."
    )
    html = (
        f'<html lang="uk"><head><meta charset="utf-8"><style>{report_css("uk")}</style></head>'
        f'<body><section class="chapter"><p>{paragraph}</p></section></body></html>'
    )
    text = subprocess.run(
        ["pdftotext", "-layout", "-", "-"], input=html_to_pdf(html), capture_output=True, check=True
    ).stdout.decode("utf-8")
    first = text.strip().splitlines()[0].split()
    assert len(first) > 5, first


def test_a_two_stroke_assignment_lists_no_valve_timing_of_a_four_stroke():
    """The exhaust closing, intake opening and intake closing near the dead centres belong to a
    four-stroke cycle; a two-stroke's assignment lists only the exhaust ports' opening."""
    two = shared_html("two-stroke-1cyl", language="en", stages=("indicator",)).linked_html
    four = shared_html("petrol-1cyl", language="en", stages=("indicator",)).linked_html
    for row in ("Exhaust valve closes", "Intake valve opens", "Intake valve closes"):
        assert row not in two and row in four


def test_the_running_torque_is_said_to_grow_towards_the_output_end_only_where_it_does():
    # in-line four: 226, 355, 487, 603 N·m along the journals; in-line three: 248, 454, 363 N·m
    four = shared_html("inline4-petrol", language="en", stages=("torque",)).linked_html
    three = shared_html("inline3-petrol", language="en", stages=("torque",)).linked_html
    assert "grows towards the flywheel end" in four and "not on the last journal" not in four
    assert "grows towards the flywheel end" not in three
    assert "not on the last journal here but on the journal after crank 2" in three


def test_a_radials_conclusions_give_the_crank_pins_load_of_all_its_cylinders():
    """One crank carries every cylinder of a radial: the conclusions state the summed load the
    bay table shows, and not one cylinder's load on the crank."""
    import re

    run = shared_run("radial9-aircraft", stages=("bays",))
    html = shared_html("radial9-aircraft", language="en", stages=("bays",)).linked_html
    bay = run.outputs["bays"].tables.arrays("bay")["pin_load_Pa"]
    single = run.outputs["forces"].results["resultant_max_Pa"]
    conclusions = html[html.index('<ol class="conclusions">') :]
    plain = re.sub(r"<[^>]+>", "", conclusions).replace("\xa0", " ").replace("\u202f", " ")
    said = re.search(r"largest load on the crank pin is q\w* = ([\d.]+) MPa", plain)
    assert said and float(said.group(1)) == pytest.approx(bay.max() / 1e6, rel=1e-3)
    assert bay.max() > 1.2 * single  # the summed load is not one cylinder's
    # one cylinder's load on a crank that carries nine is no result of the engine
    assert "From one cylinder" not in plain and "this cylinder's rod only" not in plain


@pytest.mark.parametrize(
    "language, start", [("uk", "Пояснювальна записка: "), ("en", "Explanatory note: ")]
)
def test_the_abstracts_page_count_is_left_out_of_the_page_on_screen(language, start):
    """Only print has pages: on screen the page count and its unit are hidden together (no
    "записка:  с., 19 рис."), in print the count fills in before its unit."""
    from crankdyn.report.assets import report_css

    html = shared_html("petrol-1cyl", language=language, stages=("kinematics",)).linked_html
    counts = re.search(r'<p class="counts">(.*?)</p>', html, flags=re.S).group(1)
    hidden = re.search(r'<span class="abstract-pages">(.*?)</span>', counts, flags=re.S)
    assert hidden and 'class="pagecount"' in hidden.group(1)
    unit = re.sub(r"<[^>]+>", "", hidden.group(1)).strip()
    assert unit in ("с.,", "pages,")
    on_screen = re.sub(r"<[^>]+>", "", counts.replace(hidden.group(0), ""))
    assert re.match(re.escape(start) + r"\d+ ", on_screen), on_screen
    assert "@media screen { .abstract-pages { display: none; } }" in report_css(language)
