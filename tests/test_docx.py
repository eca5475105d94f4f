"""The Word export: report.docx has the HTML report's structure, with native tables and equations,
set as the PDF sets them (equations, worked substitutions, tables, pages)."""

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
from crankdyn.output.pipeline import write_report
from crankdyn.plugin.registry import default_registry
from crankdyn.report import docx as word
from crankdyn.scene.model import load_scene

pytestmark = pytest.mark.skipif(shutil.which("pandoc") is None, reason="pandoc is not installed")


@pytest.fixture(autouse=True)
def _no_layout_pass_in_fast_tests(request, monkeypatch):
    """The default suite checks the Word XML itself; the LibreOffice layout pass runs under
    -m slow."""
    if request.node.get_closest_marker("slow") is None:
        monkeypatch.setenv("CRANKDYN_DOCX_LAYOUT", "0")


W = "{http://schemas.openxmlformats.org/wordprocessingml/2006/main}"


def _write(example: str, out: Path, language: str | None = None) -> Path:
    overrides = {"report": {"language": language}} if language else None
    write_report(
        load_scene(examples_dir() / f"{example}.toml", overrides),
        default_registry(),
        out,
        ["html", "docx"],
    )
    return out


@pytest.fixture(scope="module")
def kinematics(tmp_path_factory) -> Path:
    with pytest.MonkeyPatch.context() as patch:  # the fast checks: no LibreOffice layout pass
        patch.setenv("CRANKDYN_DOCX_LAYOUT", "0")
        return _write("kinematics-only", tmp_path_factory.mktemp("docx"), "uk")


def _html_structure(html: str) -> dict:
    """What the HTML report shows: tables, figures, equations and the headings outside the contents list
    (not the title blocks of the ESKD frame, which are the PDF's page furniture and not in the Word file).
    """
    html = re.sub(r'<div class="eskd-block.*?</table></div>', "", html, flags=re.S)
    html = re.sub(
        r'<table class="signatures">.*?</table>', "", html, flags=re.S
    )  # lines, not a grid
    body = re.sub(r"<nav\b.*?</nav>", "", html, flags=re.S)
    headings = [
        (int(level) - 1, unescape(re.sub(r"<[^>]+>", "", re.sub(r"<br\s*/?>", "\n", text))).strip())
        for level, text in re.findall(r"<h([2-4])\b[^>]*>(.*?)</h\1>", body, re.S)
    ]
    tables = len(
        re.findall(r"<table\b(?:(?!</table>).)*?<tr\b", html, re.S)
    )  # an empty table shows nothing
    return {
        "tables": tables,
        "figures": len(re.findall(r"<img\b", html)),
        "equations": len(re.findall(r'class="equation"', html)),
        "headings": headings,
    }


def _docx_structure(path: Path) -> dict:
    import docx

    document = docx.Document(str(path))
    headings = [
        (int(p.style.name.split()[-1]), p.text.strip())
        for p in document.paragraphs
        if re.fullmatch(r"Heading [1-3]", p.style.name)
    ]
    # a table split where a page ends ("Table N continued" over the rest) is one table
    numbers = [t._tbl.find(f"{W}tblPr/{W}tblCaption") for t in document.tables]
    tables = len({n.get(f"{W}val") for n in numbers if n is not None}) + sum(
        n is None for n in numbers
    )
    return {
        "tables": tables,
        "figures": len(document.inline_shapes),
        # an equation on several lines is several paragraphs, all but the last kept with the next
        "equations": sum(
            1
            for p in document.paragraphs
            if p.style.name == "Equation"
            and "<m:oMath>" in p._p.xml
            and "<w:keepNext/>" not in p._p.xml
        ),
        "headings": headings,
    }


def _check_structure(out: Path) -> dict:
    html = _html_structure((out / "report.html").read_text(encoding="utf-8"))
    assert _docx_structure(out / "report.docx") == html
    return html


def test_docx_has_the_structure_of_the_html(kinematics):
    html = _check_structure(kinematics)
    assert (
        html["tables"] >= 2
        and html["figures"] >= 2
        and html["equations"] >= 5
        and len(html["headings"]) >= 3
    )


def test_docx_styles_page_and_fields(kinematics):
    import docx
    from docx.shared import Mm, Pt

    document = docx.Document(str(kinematics / "report.docx"))
    normal = document.styles["Normal"]
    assert normal.font.name == "Times New Roman" and normal.font.size == Pt(14)
    assert normal.paragraph_format.line_spacing == 1.5
    for name in (
        "Heading 1",
        "Heading 2",
        "Heading 3",
        "Caption",
        "Table Caption",
        "Image Caption",
    ):
        assert document.styles[name] is not None
    section = document.sections[0]
    # DSTU 3008 margins, as the PDF has them: left 30, right 15, top and bottom 20 mm (1 mm = 36000 EMU).
    assert [
        round(v / Mm(1))
        for v in (
            section.left_margin,
            section.right_margin,
            section.top_margin,
            section.bottom_margin,
        )
    ] == [30, 15, 20, 20]
    # the page number top right (DSTU 3008:2015), in a header as the PDF has it; none on the title page
    number = section.header.paragraphs[0]._p.xml
    assert (
        " PAGE " in number
        and 'w:val="right"' in number
        and section.different_first_page_header_footer
    )
    assert not section.footer.paragraphs or " PAGE " not in section.footer.paragraphs[0]._p.xml
    xml = zipfile.ZipFile(kinematics / "report.docx").read("word/document.xml").decode("utf-8")
    assert 'TOC \\o "1-3"' in xml
    # Every table repeats its header row on each page; captions are numbered as in the PDF.
    for table in document.tables[1:]:  # the first is the title page's signature table (no header)
        assert table.rows[0]._tr.find(f"{W}trPr/{W}tblHeader") is not None
    captions = [
        p.text for p in document.paragraphs if p.style.name in ("Table Caption", "Image Caption")
    ]
    assert captions and all(re.match(r"^\w+ \w+\.\d+ ", c) for c in captions)


# a batch of Word files: in the slow tier, which CI runs
@pytest.mark.slow
def test_batch_writes_one_docx_per_variant(tmp_path):
    from crankdyn.batch.variants import run_batch

    (tmp_path / "variants.csv").write_text("variant,engine.rpm\na,2000\nb,4000\n", encoding="utf-8")
    report = run_batch(
        tmp_path / "variants.csv",
        examples_dir() / "kinematics-only.toml",
        tmp_path / "out",
        formats=["docx"],
        jobs=1,
        progress=False,
    )
    assert not report.failures
    assert sorted(p.parent.name for p in (tmp_path / "out").glob("*/report.docx")) == ["a", "b"]


@pytest.mark.slow
@pytest.mark.parametrize("example", sorted(p.stem for p in examples_dir().glob("*.toml")))
def test_every_bundled_example_docx_matches_its_html(example, tmp_path):
    _check_structure(_write(example, tmp_path))


# ------------------------------------------------------------ equations, blocks, tables, pages

M = "{http://schemas.openxmlformats.org/officeDocument/2006/math}"


def _omml(markup: str, size: int = 28):
    from xml.etree import ElementTree

    from crankdyn.report import docx_math

    xml = docx_math.omml(word.parse_html(f"<span>{markup}</span>").children[0], size)
    return ElementTree.fromstring(f'<w:p xmlns:w="{W[1:-1]}" xmlns:m="{M[1:-1]}">{xml}</w:p>')


def _delimiters(tree) -> list[tuple[str, str, list[str]]]:
    """Each m:d: its opening and closing characters and the order of its properties."""
    out = []
    for d in tree.iter(f"{M}d"):
        props = list(d.find(f"{M}dPr"))
        values = {p.tag: p.get(f"{M}val") for p in props}
        out.append(
            (values.get(f"{M}begChr"), values.get(f"{M}endChr"), [p.tag[len(M) :] for p in props])
        )
    return out


def test_brackets_bars_and_braces_are_delimiter_elements():
    tree = _omml(
        "<i>s</i><sub>п</sub> = <i>R</i> [(1 − cos <i>α</i>) + (1 − cos <i>β</i>)/<i>λ</i>], "
        "|⁠<i>f</i><sub><i>n</i></sub> − <i>b</i><sub><i>n</i></sub>|⁠ {<i>x</i>}"
    )
    found = _delimiters(tree)
    assert sorted((b, e) for b, e, _ in found) == sorted(
        [("[", "]"), ("(", ")"), ("(", ")"), ("|", "|"), ("{", "}")]
    )
    # the schema's order: LibreOffice reads an end character written before the separator as ")"
    assert all(order[:3] == ["begChr", "sepChr", "endChr"] for _, _, order in found)
    # the square bracket holds both round ones; no bracket or bar is left as a character
    square = next(
        d for d in tree.iter(f"{M}d") if d.find(f"{M}dPr/{M}begChr").get(f"{M}val") == "["
    )
    assert len(list(square.iter(f"{M}d"))) == 3
    texts = "".join(t.text or "" for t in tree.iter(f"{M}t"))
    assert not set("()[]{}|\u2060") & set(texts)


def test_a_bracket_without_its_pair_stays_a_character():
    tree = _omml("= 0,046·[cos(30°)/cos 8,9°")  # one line of a formula broken across lines
    assert [(b, e) for b, e, _ in _delimiters(tree)] == [("(", ")")]
    assert "[" in "".join(t.text or "" for t in tree.iter(f"{M}t"))


def test_conjugate_and_powers_are_scripts_and_runs_have_the_body_size():
    tree = _omml(
        "<i>b</i><sub><i>n</i></sub><sup>*</sup> + (<i>α</i> + <i>β</i>)<sup>2</sup> + 1,5·10⁻³"
    )
    subsup = tree.find(f".//{M}sSubSup")
    assert (
        subsup is not None and "".join(t.text for t in subsup.find(f"{M}sup").iter(f"{M}t")) == "*"
    )
    assert "".join(t.text for t in subsup.find(f"{M}e").iter(f"{M}t")) == "b"
    powers = list(tree.iter(f"{M}sSup"))
    assert [p.find(f"{M}e")[0].tag for p in powers] == [f"{M}d", f"{M}r"]  # (α + β)², 10⁻³
    assert "".join(t.text for t in powers[1].find(f"{M}sup").iter(f"{M}t")) == "−3"
    sizes = {r.find(f"{W}rPr/{W}sz").get(f"{W}val") for r in tree.iter(f"{M}r")}
    assert sizes == {"28"}  # 14 pt, the body text's size
    # the brackets Word draws itself: the same size, the control properties last in m:dPr
    controls = [d.find(f"{M}dPr")[-1] for d in tree.iter(f"{M}d")]
    assert controls and all(c.tag == f"{M}ctrlPr" for c in controls)
    assert {c.find(f"{W}rPr/{W}sz").get(f"{W}val") for c in controls} == {"28"}


def _sample_html(long_equation: str) -> str:
    row = "".join(
        f"<td>{-1.5 * k:.3f}".replace(".", ",").replace("-", "−") + "</td>" for k in range(16)
    )
    return f"""<html lang="uk"><body>
<section class="title-page"><div class="ministry">Міністерство</div>
<div class="doc-kind">Пояснювальна записка</div>
<table class="signatures"><tr><td>Виконав: студент</td></tr>
<tr><td class="line"><span class="blank wide"></span> <span class="hint">(підпис)</span></td></tr>
</table><div class="city-year">2026</div></section>
<section class="assignment"><div class="ministry">Кафедра</div>
<h2 class="unnumbered">Завдання</h2><p>Дата видачі <span class="blank"></span></p></section>
<section class="abstract"><h2 class="unnumbered">Реферат</h2>
<p class="counts">Пояснювальна записка: <a class="pagecount"
href="#document-end"></a> с., 2 рис.</p>
</section>
<section class="chapter" id="sec-1"><h2>1 Кінематика</h2>
<div class="equation"><span class="formula"><span
class="eq-part"><i>R</i> = <i>S</i>/2 = 46 мм</span>
</span><span class="eqno">(1.1)</span></div>
<div class="equation"><span class="formula">{long_equation}</span><span class="eqno">(1.2)</span>
</div>
<p class="where"><span class="where-word">де </span><span class="where-lines"><span
class="where-line"><i>R</i> – радіус кривошипа, м;</span><br><span class="where-line"><i>S</i> –
хід поршня, м.</span></span></p>
<div class="worked"><p class="worked-line"><span class="eq-part"><i>s</i> = <i>R</i>[(1 − cos
<i>α</i>)] =</span><br class="eq-break"><span class="eq-part"><span
class="eq-carry">= </span>0,046·[(1
− cos 30°)] = 7,96 мм</span></p></div>
<div class="table-block"><table class="data" data-number="1.1">
<caption>Таблиця 1.1 – Кінематика</caption>
<thead><tr><th><i>α</i>, °</th><th>Назва</th><th><i>s</i>, мм</th></tr></thead>
<tbody><tr><td>0</td><td class="text">ВМТ</td><td>0,00</td></tr>
<tr><td>30</td><td class="text">—</td><td>−7,96</td></tr>
</tbody></table></div></section>
<section class="chapter" id="sec-2"><h2>2 Сили</h2>
<div class="table-block long landscape"><p class="see">Сили наведено в табл. 2.1.</p>
<table class="data wide" data-number="2.1"><caption>Таблиця 2.1 – Сили</caption>
<thead><tr>{"".join(f"<th><i>z</i><sub>{k}</sub></th>" for k in range(16))}</tr></thead>
<tbody><tr>{row}</tr><tr>{row}</tr></tbody></table></div><p>Після таблиці.</p></section>
<p class="colophon" id="document-end">Створено програмою crankdyn 0.1.0, 2026-11-30.</p>
</body></html>"""


@pytest.fixture(scope="module")
def sample_docx(tmp_path_factory) -> Path:
    long = ", &nbsp; ".join(
        f'<span class="eq-part"><i>x</i><sub>{k}</sub> = <i>R</i>(1 − cos {k}<i>α</i>) '
        f"+ <i>λ</i>(1 − cos<sup>2</sup> <i>β</i>) = {k},{k}5 мм</span>"
        for k in range(1, 4)
    )
    path = tmp_path_factory.mktemp("sample") / "report.docx"
    path.write_bytes(word.report_docx(_sample_html(long), [], "uk", layout=False))
    return path


@pytest.mark.parametrize("language", ["ru", "uk", "en"])
def test_the_page_number_stands_where_the_pdf_puts_it(language, tmp_path):
    """GOST 7.32-2017 puts a Russian note's page number at the bottom centre, DSTU 3008:2015 a
    Ukrainian (and the English) one top right: the Word file follows the PDF's stylesheet, and
    the title page has none."""
    from docx import Document

    from crankdyn.report.assets import report_css

    css = re.sub(r"/\*.*?\*/", "", report_css(language), flags=re.S)
    # the last rule of the page that shows the number wins, as in CSS
    shown = [
        m.group(1)
        for m in re.finditer(r"@(top-right|bottom-center)\s*\{\s*content:\s*counter", css)
    ]
    hidden = [
        m.group(1) for m in re.finditer(r"@(top-right|bottom-center)\s*\{\s*content:\s*none", css)
    ]
    pdf_place = shown[-1]
    assert pdf_place == ("bottom-center" if language == "ru" else "top-right")
    assert pdf_place in hidden  # not on the title page

    path = tmp_path / "report.docx"
    path.write_bytes(word.report_docx(_sample_html("<i>x</i> = 1"), [], language, layout=False))
    section = Document(str(path)).sections[0]
    assert section.different_first_page_header_footer
    header = "".join(p._p.xml for p in section.header.paragraphs)
    footer = "".join(p._p.xml for p in section.footer.paragraphs)
    if pdf_place == "bottom-center":
        assert " PAGE " in footer and 'w:val="center"' in footer and " PAGE " not in header
    else:
        assert " PAGE " in header and 'w:val="right"' in header and " PAGE " not in footer


def test_no_break_spaces_survive_in_list_items(tmp_path):
    """A conclusion's "(табл.\u00a06.3)" and "8,675\u202fМПа" keep their no-break spaces as the
    characters themselves in the list item's text, so Word and LibreOffice never end a line
    with "(табл."."""
    html = (
        '<html lang="uk"><body><section class="chapter" id="sec-conclusions">'
        '<h2 class="unnumbered">Висновки</h2><ol class="conclusions">'
        "<li>Шийка сприймає <i>q</i>\u00a0=\u00a08,675\u202fМПа (табл.\u00a06.3).</li>"
        "<li>Див. рис.\u00a02.1 і с.\u00a045.</li></ol></section></body></html>"
    )
    path = tmp_path / "report.docx"
    path.write_bytes(word.report_docx(html, [], "uk", layout=False))
    xml = zipfile.ZipFile(path).read("word/document.xml").decode("utf-8")
    items = re.findall(r"<w:p>(?:(?!</w:p>).)*?<w:numPr>.*?</w:p>", xml, flags=re.S)
    assert len(items) == 2, items
    texts = ["".join(re.findall(r"<w:t(?: [^>]*)?>([^<]*)</w:t>", item)) for item in items]
    assert "\u00a0=\u00a08,675\u202fМПа (табл.\u00a06.3)." in texts[0], texts[0]
    assert "рис.\u00a02.1 і с.\u00a045." in texts[1], texts[1]
    # a run whose text starts or ends with a space keeps it (xml:space="preserve")
    runs = re.findall(r"<w:t( xml:space=\"preserve\")?>([^<]*)</w:t>", "".join(items))
    assert all(preserve for preserve, text in runs if text != text.strip()), runs


def _paragraphs(path: Path):
    import docx

    return docx.Document(str(path)).paragraphs


def test_equations_number_at_the_right_margin_long_ones_on_several_lines(sample_docx):
    equations = [p for p in _paragraphs(sample_docx) if p.style.name == "Equation"]
    xml = [p._p.xml for p in equations]
    # (1.1) on one line: a tab to the centre, the formula, a tab to the right margin, the number
    assert re.search(r"<w:tab/>.*<m:oMath>.*</m:oMath>.*<w:tab/>.*\(1\.1\)", xml[0], re.S)
    # (1.2): three parts too wide for a line together, on lines of their own; the number on the last
    long = [x for x in xml[1:]]
    assert len(long) >= 2 and all("<m:oMath>" in x for x in long)
    assert "(1.2)" in long[-1] and not any("(1.2)" in x for x in long[:-1])
    assert all("<w:keepNext/>" in x for x in long[:-1])
    from crankdyn.report import docx_blocks, docx_math

    for x in long:  # every line's estimated width within the line, at no less than 10 pt
        sizes = {int(v) for v in re.findall(r'<w:sz w:val="(\d+)"/>', x)}
        assert min(sizes) >= docx_blocks.SMALLEST_EQUATION_SIZE
    assert docx_math.CHAR_EM > 0


def test_equations_are_set_at_the_body_text_size(sample_docx):
    """Every run and bracket of a formula that fits its line is as large as the Normal style's
    text (styles.xml); a long formula's parts are no smaller than the smallest equation size."""
    from crankdyn.report import docx_blocks

    with zipfile.ZipFile(sample_docx) as package:
        styles = package.read("word/styles.xml").decode("utf-8")
        xml = package.read("word/document.xml").decode("utf-8")
    normal = re.search(r'<w:style [^>]*w:styleId="Normal".*?</w:style>', styles, flags=re.S).group(
        0
    )
    body = int(re.search(r'<w:sz w:val="(\d+)"\s*/>', normal).group(1))
    assert body == 28  # 14 pt, DSTU 3008's text
    formulas = re.findall(r"<m:oMath>.*?</m:oMath>", xml, flags=re.S)
    sizes = [[int(v) for v in re.findall(r'<w:sz w:val="(\d+)"/>', f)] for f in formulas]
    assert sizes and all(sizes)
    assert set(sizes[0]) == {body}  # (1.1) fits its line
    assert all(min(s) >= docx_blocks.SMALLEST_EQUATION_SIZE for s in sizes)
    runs = sum(f.count("<m:r>") for f in formulas)
    assert sum(len(s) for s in sizes) >= runs  # every run carries its size


def test_where_lines_and_worked_substitutions_are_left_aligned_lines(sample_docx):
    paragraphs = _paragraphs(sample_docx)
    where = [p for p in paragraphs if p.style.name == "Where"]
    assert [p.text.split("–")[0].strip() for p in where] == ["де\tR", "S"]
    worked = [p for p in paragraphs if p.style.name == "Worked Line"]
    assert [p.text[:8] for p in worked] == ["s = R[(1", "= 0,046·"]
    import docx

    styles = docx.Document(str(sample_docx)).styles
    for name in ("Where", "Worked Line"):
        assert styles[name].paragraph_format.alignment == 0  # left, never justified
        assert all("<w:br/>" not in p._p.xml for p in paragraphs if p.style.name == name)


def _cell_alignments(table) -> list[list[str]]:
    return [
        [(c._tc.find(f"{W}p/{W}pPr/{W}jc").get(f"{W}val")) for c in row.cells] for row in table.rows
    ]


def test_tables_numbers_right_text_centred_header_repeated(sample_docx):
    import docx

    document = docx.Document(str(sample_docx))
    assert len(document.tables) == 2  # the signature block is lines, not a table
    first = document.tables[0]
    assert _cell_alignments(first) == [
        ["center"] * 3,
        ["right", "center", "right"],
        ["right", "center", "right"],
    ]
    assert first.rows[0]._tr.find(f"{W}trPr/{W}tblHeader") is not None
    assert all(r._tr.find(f"{W}trPr/{W}tblHeader") is None for r in first.rows[1:])
    widths = [int(c.get(f"{W}w")) for c in first._tbl.findall(f"{W}tblGrid/{W}gridCol")]
    assert (
        widths[1] < widths[0] * 3 and sum(widths) <= word.TEXT_WIDTH
    )  # from the content, not the page
    # every number fits its column whole: the column is at least as wide as its longest number
    wide = document.tables[1]
    size = int(wide._tbl.find(f".//{W}r/{W}rPr/{W}sz").get(f"{W}val"))
    for k, col in enumerate(wide._tbl.findall(f"{W}tblGrid/{W}gridCol")):
        longest = max(len(row.cells[k].text) for row in wide.rows)
        assert int(col.get(f"{W}w")) >= longest * 0.5 * size * 10, (k, longest)


def test_column_widths_wrap_the_long_text_not_every_column():
    from crankdyn.report import docx_blocks

    node = word.parse_html(
        "<table><thead><tr><th>Величина</th><th>Значення</th></tr></thead><tbody>"
        + "<tr><td>Відстань від центра кривошипної головки до центра мас шатуна</td><td>1</td></tr>"
        + "<tr><td>Файл</td><td>diesel-1600rpm-indicator.ind</td></tr></tbody></table>"
    ).children[0]
    rows = [[c for c in r.children if c.tag in ("th", "td")] for r in node.walk() if r.tag == "tr"]
    width = 6000  # twips: neither column's longest text fits beside the other's
    widths = docx_blocks.column_widths(rows, 1, 22, width)
    em = 220 * 0.5  # a narrow character at 11 pt, in twips
    assert sum(widths) == pytest.approx(width, abs=2)  # the whole width, shared out
    assert widths[0] > len("кривошипної") * em + 100
    assert widths[1] > len("diesel-1600rpm-indicator.ind") * 0.5 * em
    # a narrow table stays as wide as its content
    assert sum(docx_blocks.column_widths(rows[:1], 1, 22, width)) < width / 2
    # the row whose text wraps is kept on one page, the others may not be (see docx_blocks.table)
    xml, _ = docx_blocks.table(node, width, False)
    rows_xml = re.findall(r"<w:tr>.*?</w:tr>", xml)
    assert ["<w:cantSplit/>" in r for r in rows_xml] == [False, True, False]


def test_wide_table_in_a_landscape_section(sample_docx):
    import docx

    document = docx.Document(str(sample_docx))
    orientations = [(s.orientation, s.page_width > s.page_height) for s in document.sections]
    assert [wide for _, wide in orientations] == [False, True, False]
    assert orientations[1][0] == 1  # WD_ORIENT.LANDSCAPE
    # the wide table is in the landscape section: the section break before it, the next one after it
    body = document.element.body
    kinds = [
        (
            "table"
            if el.tag == f"{W}tbl"
            else "break"
            if el.find(f"{W}pPr/{W}sectPr") is not None
            else ""
        )
        for el in body
    ]
    kinds = [k for k in kinds if k]
    assert kinds == ["table", "break", "table", "break"]
    # only the title page has no page number
    assert [s.different_first_page_header_footer for s in document.sections] == [True, False, False]


def test_title_page_and_parts_start_new_pages(sample_docx):
    paragraphs = _paragraphs(sample_docx)
    breaks = [
        p.text
        for p in paragraphs
        if "<w:pageBreakBefore/>" in p._p.xml
        or (p.style.name == "heading 1" and '<w:pageBreakBefore w:val="0"/>' not in p._p.xml)
    ]
    assert breaks == ["Кафедра", "Реферат", "1 Кінематика", "2 Сили"]
    # the heading under the department's line stays on that line's page; unnumbered ones centred
    task = next(p for p in paragraphs if p.text == "Завдання")
    assert (
        '<w:pageBreakBefore w:val="0"/>' in task._p.xml and '<w:jc w:val="center"/>' in task._p.xml
    )
    import docx

    assert (
        docx.Document(str(sample_docx)).styles["Heading 1"].font.all_caps
    )  # as the PDF prints them
    # the signature block: lines without borders
    signature = [p for p in paragraphs if p.style.name == "Signature"]
    assert [p.text.strip() for p in signature][0] == "Виконав: студент" and signature[
        1
    ].text.endswith("(підпис)")
    assert "<w:tbl>" not in "".join(p._p.xml for p in signature) and "<w:u " in signature[1]._p.xml
    # a blank to write on is an underlined space, as the PDF's line
    issued = next(p for p in paragraphs if p.text.startswith("Дата видачі"))
    assert issued.text.endswith("\u00a0") and "<w:u " in issued._p.xml
    # the abstract's page count is a NUMPAGES field
    counts = next(p for p in paragraphs if p.text.startswith("Пояснювальна записка:"))
    assert " NUMPAGES " in counts._p.xml and "CRANKDYN" not in counts._p.xml
    # the program's stamp is on the screen's page only, as in the PDF
    assert not [p.text for p in paragraphs if "crankdyn" in p.text]


# ------------------------------------------------------------ LibreOffice's pages (-m slow)

needs_libreoffice = pytest.mark.skipif(
    shutil.which("soffice") is None or shutil.which("pdftotext") is None,
    reason="LibreOffice (soffice) or poppler-utils is not installed",
)
WORDS = {"uk": ("Таблиця", "Рисунок"), "ru": ("Таблица", "Рисунок")}


def _libreoffice_pdf(docx_path: Path, folder: Path) -> Path:
    from crankdyn.report import docx_pages

    pdf = docx_pages.to_pdf(
        docx_path, folder, shutil.which("soffice"), docx_pages.profile(folder / "profile")
    )
    assert pdf is not None
    return pdf


def _first_line_top(pdf: Path, page: int) -> float | None:
    """The top of the page's first line of text, as a share of the page's height."""
    box = subprocess.run(
        ["pdftotext", "-bbox-layout", "-f", str(page), "-l", str(page), str(pdf), "-"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    height = float(re.search(r'<page width="[\d.]+" height="([\d.]+)"', box).group(1))
    tops = [float(y) for y in re.findall(r'<line xMin="[\d.]+" yMin="([\d.]+)"', box)]
    tops = [t for t in tops if t / height > 0.06]  # not the running page number in the top margin
    return min(tops) / height if tops else None


def _figure_above(pdf: Path, page: int, png: Path) -> bool:
    """Whether a picture (ink with no text: the Word file's figures are raster images) stands
    above the page's first line of text."""
    import numpy as np
    from PIL import Image

    top = _first_line_top(pdf, page)
    ink = np.asarray(Image.open(png).convert("L")) < 240  # a figure's thin light lines count
    rows = np.flatnonzero(
        ink[int(0.07 * ink.shape[0]) : int((top or 0) * ink.shape[0]) - 2].any(axis=1)
    )
    return top is not None and rows.size > 10


def _equation_to_text_heights(pdf: Path) -> list[float]:
    """Per numbered equation on the pages: the height of its "=" and "+" glyphs' boxes over the
    height of its number's box ("(2.1)", body text), as pdftotext -bbox measures them. At the
    body text's size about 1; LibreOffice's default Math size (12 pt against 14) makes it 6/7."""
    box = subprocess.run(
        ["pdftotext", "-bbox", str(pdf), "-"], capture_output=True, text=True, check=True
    ).stdout
    word_box = (
        r'<word xMin="([\d.]+)" yMin="([\d.]+)" xMax="([\d.]+)" yMax="([\d.]+)">([^<]*)</word>'
    )
    ratios = []
    for page in box.split("<page ")[1:]:
        words = [
            (float(a), float(b), float(c), float(d), t)
            for a, b, c, d, t in re.findall(word_box, page)
        ]
        for x0, y0, _, y1, number in words:
            if not re.fullmatch(r"\(\d+\.\d+\)", number):
                continue
            middle = (y0 + y1) / 2
            signs = [
                w
                for w in words
                if w[4] in ("=", "+") and w[2] < x0 and abs((w[1] + w[3]) / 2 - middle) < 8
            ]
            if signs:
                ratios.append(sorted(w[3] - w[1] for w in signs)[len(signs) // 2] / (y1 - y0))
    return ratios


def _latin_words_added(text: str, html: str) -> list[str]:
    """Latin words on the pages that the report's HTML does not show: pandoc's or Word's own
    texts ("Figure", "Contents"). A symbol and its indices ("p<sub>jII</sub>") are one word in
    the HTML with its inline tags taken out and may be two in an equation on the pages ("p jII");
    a title may be printed in capitals."""
    from test_note import ALLOWED_LATIN

    body = re.sub(r"<(script|style|svg)\b.*?</\1>", " ", html.split("<body", 1)[-1], flags=re.S)
    body = re.sub(r"</?(?:i|b|sub|sup|span)\b[^>]*>", "", body)  # inline: no word boundary
    shown = " ".join(re.findall(r"[A-Za-z]+", unescape(re.sub(r"<[^>]+>", " ", body)))).lower()
    return [
        w
        for w in re.findall(r"(?<![\w])[A-Za-z]{2,}(?![\w])", text)
        if w not in ALLOWED_LATIN and w.lower() not in shown
    ]


def _words_broken_at_line_ends(pages: list[str], html: str) -> list[str]:
    """Lines ending with a word parted by a hyphen that is not its own: machine hyphenation
    ("та-/нгенціальна") or a name parted on the title page ("Пет-/ров"). A compound may break at
    its own hyphen ("кривошипно-/шатунного", the student's "three-/cylinder"): the report's text
    has the part before it followed by the hyphen and a letter."""
    from conftest import as_read

    shown = " ".join(unescape(re.sub(r"<[^>]+>", "", as_read(html.split("<body", 1)[-1]))).split())
    broken = []
    for page in pages:  # (a table's line holds its other columns after the broken word)
        for line in page.splitlines():
            end = re.search(r"(?<![\w-])(\w+)[-\u2010]$", line.rstrip())
            if end is None:
                continue
            compound = rf"(?<![\w-]){re.escape(end.group(1))}-\w"
            if not re.search(compound, shown, flags=re.IGNORECASE):  # (a heading in capitals)
                broken.append(line.strip()[-40:])
    return broken


def _check_typography_and_language(
    pages: list[str], html: str, example: str, language: str
) -> None:
    """The checks of the WeasyPrint PDF's text (tests/test_note.py) on LibreOffice's pages: no
    machine hyphenation, no decimal point inside a number, no Latin word but the allowed ones
    and the student's own texts."""
    from test_note import _decimal_points, _latin_words

    text = "\f".join(pages)
    broken = _words_broken_at_line_ends(pages, html)
    assert not broken, broken
    scene = load_scene(examples_dir() / f"{example}.toml")
    scene_texts = [v for v in scene.report.model_dump().values() if isinstance(v, str)]
    scene_texts.append(scene.engine.name)
    sources = re.findall(r'<ol class="references">(.*?)</ol>', html, flags=re.S)
    own = scene_texts + [unescape(re.sub(r"<[^>]+>", " ", sources[0]))] if sources else scene_texts
    points = [p for p in _decimal_points(text) if not any(p.split()[-1] in v for v in own)]
    assert not points, points[:10]
    assert not _latin_words(html, scene_texts), sorted(set(_latin_words(html, scene_texts)))
    added = _latin_words_added(text, html)
    assert not added, sorted(set(added))


def _check_libreoffice_pages(out: Path, language: str, tmp_path: Path) -> tuple[Path, list[str]]:
    """The LibreOffice PDF of report.docx passes the checks of the WeasyPrint PDF (page_layout)."""
    from page_layout import layout_problems, page_images, page_texts

    from crankdyn.report.i18n import translator

    # (LibreOffice's PDF has no word joiners: "0/0" where the HTML keeps "0/\u20600" together)
    html = (out / "report.html").read_text(encoding="utf-8").replace("\u2060", "")
    pdf = _libreoffice_pdf(out / "report.docx", tmp_path / "lo")
    pages = page_texts(pdf, "")  # the Word file has no ESKD frame
    text = "\f".join(pages)
    assert "^" not in text and "_" not in text, [
        ln for ln in text.splitlines() if "^" in ln or "_" in ln
    ][:5]
    assert not re.search(r"\de[-+−]?0\d", text), re.findall(r".{20}\de[-+−]?0\d.{5}", text)[:5]
    assert "¿" not in text and "�" not in text
    # the layout pass's LibreOffice sets the equations at the body text's size
    heights = sorted(_equation_to_text_heights(pdf))
    assert heights and heights[len(heights) // 2] > 0.95, heights
    table_word, figure_word = WORDS[language]
    t = translator(language, default_registry().catalogs)
    problems = layout_problems(
        pdf,
        pages,
        html,
        tmp_path / "pages",
        table_word=table_word,
        figure_word=figure_word,
        continued=lambda number: t("doc.continued", number=number),
    )
    images = page_images(pdf, tmp_path / "pages")
    # a figure caption first in the page's text under its picture (a raster image: no text) is
    # in place
    problems = [
        p
        for p in problems
        if not (m := re.match(r"page (\d+) starts with the caption '(Рисунок|Figure)", p))
        or not _figure_above(pdf, int(m.group(1)), images[int(m.group(1)) - 1])
    ]
    # The abstract counts the document's pages, figures and tables.
    abstract = next(p for p in pages if re.search(r"^\s*(РЕФЕРАТ)\s*$", p, flags=re.M))
    counts = [int(n) for n in re.findall(r"(\d+)\s", abstract.split(":", 1)[1])[:3]]
    figures = set(re.findall(rf"{figure_word}\s+([0-9A-ZА-Я]+\.\d+)\s+[–—]", text))
    tables = set(re.findall(rf"{table_word}\s+([0-9A-ZА-Я]+\.\d+)\s+[–—]", text))
    assert counts == [len(pages), len(figures), len(tables)], (counts, abstract[:200])
    # The contents: every entry with the page its heading starts.
    contents = next(p for p in pages if re.search(r"\.{5,}\s*\d+\s*$", p, flags=re.M))
    entries = re.findall(r"^\s*(\S.*?)\s*\.{3,}\s*(\d+)\s*$", contents, flags=re.M)
    assert len(entries) >= 4, contents
    numbers = [int(n) for _, n in entries]
    assert numbers == sorted(numbers) and numbers[-1] <= len(pages), entries
    for title, number in entries:  # (an entry's last line when it wraps)
        words = " ".join(title.split()[:2]).upper()
        assert words in " ".join(pages[int(number) - 1].split()).upper(), (title, number)
    return pdf, problems


def _side_by_side(word_pdf: Path, pdf: Path, page_word: int, page_pdf: int, target: Path) -> None:
    from PIL import Image

    images = []
    for source, page, name in ((word_pdf, page_word, "word"), (pdf, page_pdf, "pdf")):
        stem = target.parent / f"{target.stem}-{name}"
        subprocess.run(
            [
                "pdftoppm",
                "-r",
                "50",
                "-png",
                "-singlefile",
                "-f",
                str(page),
                "-l",
                str(page),
                str(source),
                str(stem),
            ],
            check=True,
            timeout=120,
        )
        images.append(Image.open(f"{stem}.png").convert("RGB"))
        Path(f"{stem}.png").unlink()
    sheet = Image.new(
        "RGB", (sum(i.width for i in images) + 10, max(i.height for i in images)), "gray"
    )
    sheet.paste(images[0], (0, 0))
    sheet.paste(images[1], (images[0].width + 10, 0))
    sheet.save(target)


@pytest.mark.slow
@needs_libreoffice
@pytest.mark.parametrize("language", ["uk", "ru"])
@pytest.mark.parametrize("example", sorted(p.stem for p in examples_dir().glob("*.toml")))
def test_libreoffice_pages_of_every_bundled_example_pass_the_pdf_checks(
    example, language, tmp_path
):
    out = tmp_path / "out"
    write_report(
        load_scene(examples_dir() / f"{example}.toml", {"report": {"language": language}}),
        default_registry(),
        out,
        ["html", "docx"],
    )
    _check_structure(out)
    pdf, problems = _check_libreoffice_pages(out, language, tmp_path)
    html = (out / "report.html").read_text(encoding="utf-8")
    from page_layout import page_texts

    _check_typography_and_language(page_texts(pdf, ""), html, example, language)
    assert not problems, problems


@pytest.mark.slow
@needs_libreoffice
@pytest.mark.parametrize(
    "example, word_page",
    [("inline6-diesel-trace", "Таблиця 2.1"), ("petrol-1cyl-uk", "Таблиця 5.1")],
)
def test_word_and_pdf_pages_side_by_side(example, word_page, tmp_path):
    """Page images of the Word file (through LibreOffice) and the PDF, side by side in
    tests/artifacts:
    the page with a given table's caption in each."""
    out = tmp_path / "out"
    write_report(
        load_scene(examples_dir() / f"{example}.toml", {"report": {"language": "uk"}}),
        default_registry(),
        out,
        ["html", "pdf", "docx"],
    )
    word_pdf = _libreoffice_pdf(out / "report.docx", tmp_path / "lo")
    pages = {}
    for name, source in (("word", word_pdf), ("pdf", out / "report.pdf")):
        text = subprocess.run(
            ["pdftotext", "-layout", str(source), "-"], capture_output=True, text=True, check=True
        ).stdout.split("\f")
        pages[name] = next(
            i for i, page in enumerate(text, 1) if re.search(rf"{word_page} [–—]", page)
        )
    ARTIFACTS.mkdir(exist_ok=True)
    target = ARTIFACTS / f"word-vs-pdf-{example}.png"
    _side_by_side(word_pdf, out / "report.pdf", pages["word"], pages["pdf"], target)
    assert target.stat().st_size > 10000


def test_a_table_going_on_over_a_page_break_is_split_under_its_label():
    from crankdyn.report import docx_blocks, docx_pages

    rows = "".join(f"<tr><td>{a}</td><td>{a / 7:.2f}</td></tr>" for a in range(0, 390, 30))
    node = word.parse_html(
        f'<table data-number="2.1"><thead><tr><th>α, °</th><th>s, мм</th></tr></thead>'
        f"<tbody>{rows}</tbody></table>"
    ).children[0]
    table, _ = docx_blocks.table(node, word.TEXT_WIDTH, False, "Продовження таблиці 2.1")
    xml = f"<w:body><w:p/>{table}<w:p/></w:body>"
    # LibreOffice's pages: rows 0…150 on the first, the header again and 180…360 on the next
    page_rows = [f"{angle} {angle / 7:.2f}" for angle in range(0, 390, 30)]
    pages = [["Таблиця 2.1", "α, ° s, мм", *page_rows[:6]], ["α, ° s, мм", *page_rows[6:]]]
    split, made = docx_pages.split_tables(xml, pages)
    assert made == 1
    parts = docx_pages.table_parts(split)
    assert [(p.number, len(p.head), len(p.body), p.first_row) for p in parts] == [
        ("2.1", 1, 6, 0),
        ("2.1", 1, 7, 6),
    ]
    between = split[parts[0].end : parts[1].start]
    assert "<w:pageBreakBefore/>" in between and ">Продовження таблиці 2.1<" in between
    # the next layout finds the rest under its label: nothing more to split
    labelled = [pages[0], ["Продовження таблиці 2.1", *pages[1]]]
    assert docx_pages.split_tables(split, labelled)[1] == 0
    # a break leaving fewer than three rows for the next page takes three there
    late = [["α, ° s, мм", *page_rows[:12]], ["α, ° s, мм", page_rows[12]]]
    parts = docx_pages.table_parts(docx_pages.split_tables(xml, late)[0])
    assert [len(p.body) for p in parts] == [10, 3]


def test_contents_get_the_pages_their_headings_start_and_the_page_count_its_value():
    from crankdyn.report import docx_pages

    entry = '<w:p><w:pPr><w:pStyle w:val="TOC1"/></w:pPr><w:r><w:t>{}</w:t></w:r></w:p>'
    xml = (
        entry.format("Вступ")
        + entry.format("1 Вихідні дані")
        + '<w:p><w:r><w:instrText xml:space="preserve"> NUMPAGES </w:instrText></w:r>'
        '<w:r><w:fldChar w:fldCharType="separate"/></w:r><w:r><w:t></w:t></w:r></w:p>'
    )
    pages = [
        ["ЗМІСТ", "Вступ....3", "1 Вихідні дані....4"],
        ["Текст"],
        ["ВСТУП", "Текст"],
        ["1 ВИХІДНІ ДАНІ"],
        ["Кінець"],
    ]
    filled = docx_pages.fill_contents(xml, pages)
    assert re.findall(r"<w:tab/></w:r><w:r><w:t>(\d+)</w:t>", filled) == ["3", "4"]
    assert "<w:r><w:t>5</w:t></w:r></w:p>" in filled  # five pages


def test_the_layout_pass_leaves_out_the_running_page_number_at_the_top_or_the_bottom(monkeypatch):
    """LibreOffice's pages as pdftotext reads them: a Ukrainian note's number ends the first line
    (top right), a Russian note's is the last line (bottom centre); either is left out, so the
    first and last lines a table's continuation is found by are the text's own."""
    import subprocess

    from crankdyn.report import docx_pages

    pages = [
        "Title page\n",
        "                                     2\nТаблица 1.1 – Исходные данные\n1 2 3\n",
        "Продолжение таблицы 1.1\n4 5 6\n\n                    3\n",
        "7 8 9\n    14\n",  # a last line that is a number but not this page's stays
    ]

    def fake_run(*args, **kwargs):
        return subprocess.CompletedProcess(args, 0, stdout="\f".join(pages) + "\f", stderr="")

    monkeypatch.setattr(docx_pages.subprocess, "run", fake_run)
    assert docx_pages.page_texts(Path("report.pdf")) == [
        ["Title page"],
        ["Таблица 1.1 – Исходные данные", "1 2 3"],
        ["Продолжение таблицы 1.1", "4 5 6"],
        ["7 8 9", "14"],
    ]


def test_a_short_table_keeps_on_one_page_and_a_long_one_may_break():
    """Up to SHORT_TABLE_ROWS body rows every row but the last keeps with the next (the table
    moves whole to the next page); a longer one keeps only its first and last rows together."""
    from crankdyn.report import docx_blocks

    def kept(rows: int) -> list[bool]:
        body = "".join(f"<tr><td>{k}</td><td>{k / 7:.2f}</td></tr>" for k in range(rows))
        node = word.parse_html(
            f"<table><thead><tr><th>k</th><th>x</th></tr></thead><tbody>{body}</tbody></table>"
        ).children[0]
        xml, _ = docx_blocks.table(node, word.TEXT_WIDTH, False)
        return ["<w:keepNext/>" in r for r in re.findall(r"<w:tr>.*?</w:tr>", xml, flags=re.S)]

    short = kept(docx_blocks.SHORT_TABLE_ROWS)
    assert short == [True] * docx_blocks.SHORT_TABLE_ROWS + [False]  # the header row first
    long = kept(docx_blocks.SHORT_TABLE_ROWS + 8)
    assert long[:3] == [True] * 3 and long[-3:] == [True, True, False]
    assert not any(long[3:-3])


def test_a_number_grouped_with_no_break_spaces_is_one_word_for_the_column_width():
    """ "−19 891" (a narrow no-break space between its groups) cannot break in Word: a column
    is at least as wide as the whole number, as it is for a plain word of that length."""
    from crankdyn.report import docx_blocks

    grouped = docx_blocks._longest_word("\u221219\u202f891")
    assert grouped == pytest.approx(docx_blocks.text_ems("\u221219\u202f891"))
    assert docx_blocks._longest_word("19 891") < grouped  # an ordinary space may break
    assert docx_blocks._longest_word("8,675\u00a0МПа") == docx_blocks.text_ems("8,675\u00a0МПа")


def test_a_square_root_over_a_bracket_is_a_word_radical():
    """q = √((z + c)² + t²): the root sign and its bracket become one m:rad over the bracket's
    content (Word draws the sign and its bar over the whole radicand); a root sign with no
    bracket after it stays a character."""
    from crankdyn.report import docx_math

    node = word.parse_html(
        "<span><i>q</i> = √((<i>z</i> + <i>c</i>)<sup>2</sup> + <i>t</i><sup>2</sup>)</span>"
    ).children[0]
    xml = docx_math.omml(node, 28)
    (radicand,) = re.findall(r"<m:rad>.*?<m:deg/><m:e>(.*)</m:e></m:rad>", xml, flags=re.S)
    assert "√" not in xml and '<m:degHide m:val="1"/>' in xml
    letters = re.findall(r"<m:t[^>]*>([^<]*)</m:t>", radicand)
    assert "".join(letters).replace(" ", "") == "z+c2+t2"  # the whole radicand, no outer bracket
    assert radicand.count("<m:d>") == 1  # (z + c) keeps its own bracket
    plain = word.parse_html("<span>√2 · <i>A</i></span>").children[0]
    assert "<m:rad>" not in docx_math.omml(plain, 28) and "√" in docx_math.omml(plain, 28)
