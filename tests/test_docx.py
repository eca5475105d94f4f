"""The Word export (issue 20): report.docx has the HTML report's structure, with native tables and equations."""

from __future__ import annotations

import re
import shutil
import subprocess
import zipfile
from html import unescape
from pathlib import Path

import pytest
from conftest import ARTIFACTS

from crankdyn.cli import examples_dir
from crankdyn.pipeline import write_report
from crankdyn.plugins import default_registry
from crankdyn.report import docx as word
from crankdyn.scene import load_scene

pytestmark = pytest.mark.skipif(shutil.which("pandoc") is None, reason="pandoc is not installed")
W = "{http://schemas.openxmlformats.org/wordprocessingml/2006/main}"


def _write(example: str, out: Path, language: str | None = None) -> Path:
    overrides = {"report": {"language": language}} if language else None
    write_report(load_scene(examples_dir() / f"{example}.toml", overrides), default_registry(), out, ["html", "docx"])
    return out


@pytest.fixture(scope="module")
def kinematics(tmp_path_factory) -> Path:
    return _write("kinematics-only", tmp_path_factory.mktemp("docx"), "uk")


def _html_structure(html: str) -> dict:
    """What the HTML report shows: tables, figures, equations and the headings outside the contents list
    (not the title blocks of the ESKD frame, which are the PDF's page furniture and not in the Word file)."""
    html = re.sub(r'<div class="eskd-block.*?</table></div>', "", html, flags=re.S)
    body = re.sub(r"<nav\b.*?</nav>", "", html, flags=re.S)
    headings = [(int(level) - 1, unescape(re.sub(r"<[^>]+>", "", re.sub(r"<br\s*/?>", "\n", text))).strip())
                for level, text in re.findall(r"<h([2-4])\b[^>]*>(.*?)</h\1>", body, re.S)]
    tables = len(re.findall(r"<table\b(?:(?!</table>).)*?<tr\b", html, re.S))  # an empty table shows nothing
    return {"tables": tables, "figures": len(re.findall(r"<img\b", html)),
            "equations": len(re.findall(r'class="equation"', html)), "headings": headings}


def _docx_structure(path: Path) -> dict:
    import docx

    document = docx.Document(str(path))
    xml = zipfile.ZipFile(path).read("word/document.xml").decode("utf-8")
    headings = [(int(p.style.name.split()[-1]), p.text.strip()) for p in document.paragraphs
                if re.fullmatch(r"Heading [1-3]", p.style.name)]
    return {"tables": len(document.tables), "figures": len(document.inline_shapes),
            "equations": len(re.findall(r"<m:oMath>", xml)), "headings": headings}


def _check_structure(out: Path) -> dict:
    html = _html_structure((out / "report.html").read_text(encoding="utf-8"))
    assert _docx_structure(out / "report.docx") == html
    return html


def test_docx_has_the_structure_of_the_html(kinematics):
    html = _check_structure(kinematics)
    assert html["tables"] >= 2 and html["figures"] >= 2 and html["equations"] >= 5 and len(html["headings"]) >= 3


def test_docx_styles_page_and_fields(kinematics):
    import docx
    from docx.shared import Mm, Pt

    document = docx.Document(str(kinematics / "report.docx"))
    normal = document.styles["Normal"]
    assert normal.font.name == "Times New Roman" and normal.font.size == Pt(14)
    assert normal.paragraph_format.line_spacing == 1.5
    for name in ("Heading 1", "Heading 2", "Heading 3", "Caption", "Table Caption", "Image Caption"):
        assert document.styles[name] is not None
    section = document.sections[0]
    # DSTU 3008 margins, as the PDF has them: left 30, right 15, top and bottom 20 mm (1 mm = 36000 EMU).
    assert [round(v / Mm(1)) for v in (section.left_margin, section.right_margin, section.top_margin,
                                       section.bottom_margin)] == [30, 15, 20, 20]
    # the page number top right (DSTU 3008:2015), in a header as the PDF has it; none on the title page
    number = section.header.paragraphs[0]._p.xml
    assert " PAGE " in number and 'w:val="right"' in number and section.different_first_page_header_footer
    assert not section.footer.paragraphs or " PAGE " not in section.footer.paragraphs[0]._p.xml
    xml = zipfile.ZipFile(kinematics / "report.docx").read("word/document.xml").decode("utf-8")
    assert 'TOC \\o "1-3"' in xml
    # Every table repeats its header row on each page; captions are numbered as in the PDF.
    for table in document.tables[1:]:  # the first is the title page's signature table (no header)
        assert table.rows[0]._tr.find(f"{W}trPr/{W}tblHeader") is not None
    captions = [p.text for p in document.paragraphs if p.style.name in ("Table Caption", "Image Caption")]
    assert captions and all(re.match(r"^\w+ \w+\.\d+ ", c) for c in captions)


def test_formula_markup_becomes_mathml():
    node = word.parse_html("<span><i>m</i><sub>s</sub> = 0.5 kg, <i>R&omega;</i><sup>2</sup>"
                           "<i>x</i><sub>1</sub><sup>3</sup> 1,5&middot;10⁻³</span>").children[0]
    assert word.formula_mathml(node) == (
        '<math display="inline"><mrow><msub><mi>m</mi><mrow><mi mathvariant="normal">s</mi></mrow></msub>'
        '<mo>=</mo><mn>0.5</mn><mi mathvariant="normal">kg</mi><mo>,</mo><mi>R</mi>'
        '<msup><mi>ω</mi><mrow><mn>2</mn></mrow></msup>'
        '<msubsup><mi>x</mi><mrow><mn>1</mn></mrow><mrow><mn>3</mn></mrow></msubsup>'
        '<mtext>1,5</mtext><mo>·</mo><msup><mn>10</mn><mn>−3</mn></msup></mrow></math>')


def test_batch_writes_one_docx_per_variant(tmp_path):
    from crankdyn.batch import run_batch

    (tmp_path / "variants.csv").write_text("variant,engine.rpm\na,2000\nb,4000\n", encoding="utf-8")
    report = run_batch(tmp_path / "variants.csv", examples_dir() / "kinematics-only.toml", tmp_path / "out",
                       formats=["docx"], jobs=1, progress=False)
    assert not report.failures
    assert sorted(p.parent.name for p in (tmp_path / "out").glob("*/report.docx")) == ["a", "b"]


@pytest.mark.slow
@pytest.mark.parametrize("example", sorted(p.stem for p in examples_dir().glob("*.toml")))
def test_every_bundled_example_docx_matches_its_html(example, tmp_path):
    _check_structure(_write(example, tmp_path))


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("soffice") is None, reason="LibreOffice (soffice) is not installed")
def test_libreoffice_converts_the_docx_to_pdf(tmp_path):
    out = _write("petrol-1cyl", tmp_path, "uk")
    done = subprocess.run(["soffice", f"-env:UserInstallation=file://{tmp_path}/lo-profile", "--headless",
                           "--convert-to", "pdf", "--outdir", str(tmp_path), str(out / "report.docx")],
                          capture_output=True, text=True, timeout=300)
    pdf = tmp_path / "report.pdf"
    assert done.returncode == 0 and pdf.exists(), done.stderr
    pages = int(re.search(r"Pages:\s+(\d+)", subprocess.run(["pdfinfo", str(pdf)], capture_output=True,
                                                             text=True).stdout).group(1))
    assert pages >= 10
    # Keep a picture of the first calculation page (after the title page and the contents) as an artifact.
    ARTIFACTS.mkdir(exist_ok=True)
    subprocess.run(["pdftoppm", "-r", "60", "-png", "-f", "3", "-l", "3", "-singlefile", str(pdf),
                    str(ARTIFACTS / "docx-petrol-uk-page3")], check=True, timeout=120)
    assert (ARTIFACTS / "docx-petrol-uk-page3.png").stat().st_size > 1000
