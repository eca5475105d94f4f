"""The report's print stylesheet (templates/report.css, ``@media print``) on paper: an
equation's number and a "where" list laid out as a reader of a hand-in expects."""

from __future__ import annotations

import pytest

from crankdyn.report.assets import report_css

pytest.importorskip("weasyprint")

#: A formula of twelve parts, too wide for one line (it wraps between parts, as the report's do).
_PARTS = ", &nbsp; ".join(
    f'<span class="eq-part"><i>a</i><sub>{k}</sub> = {k}.5 mm</span>' for k in range(12)
)


def _boxes(body: str, language: str = "en"):
    """Every text box of ``body`` laid out for print with the report's stylesheet:
    (text, left, right, baseline) in CSS pixels."""
    from crankdyn.report.pdf import load_weasyprint

    html = (
        f'<html lang="{language}"><head><style>{report_css(language)}</style></head>'
        f"<body>{body}</body></html>"
    )
    document = load_weasyprint().HTML(string=html).render()
    found = []

    def walk(box) -> None:
        box = getattr(box, "_box", box)  # an absolutely positioned box's placeholder
        text = getattr(box, "text", None)
        if text and text.strip():
            found.append(
                (text, box.position_x, box.position_x + box.width, box.position_y + box.baseline)
            )
        for child in getattr(box, "children", ()):
            walk(child)

    for page in document.pages:
        walk(page._page_box)
    return document, found


def _content_right(document) -> float:
    page = document.pages[0]._page_box
    return page.content_box_x() + page.width


def test_an_equations_number_stands_at_the_right_margin_on_its_last_line():
    body = f'<div class="equation"><span class="formula">{_PARTS}</span><span class="eqno">(2.1)</span></div>'
    document, boxes = _boxes(body)
    number = next(b for b in boxes if b[0] == "(2.1)")
    formula = [b for b in boxes if b[0] != "(2.1)" and not b[0].isdigit()]  # less the subscripts
    last_baseline = max(b[3] for b in formula)
    first_baseline = min(b[3] for b in formula)
    assert last_baseline > first_baseline  # the formula takes more than one line
    assert number[3] == pytest.approx(last_baseline, abs=0.5)  # on the formula's last line
    assert number[2] == pytest.approx(_content_right(document), abs=0.5)  # at the right margin
    assert max(b[2] for b in formula) < number[1]  # no formula text under the number


@pytest.mark.parametrize("language, word", [("en", "where "), ("uk", "де "), ("ru", "где ")])
def test_the_explanations_of_a_where_list_start_in_one_column(language, word):
    body = (
        f'<p class="where"><span class="where-word">{word}</span><span class="where-lines">'
        '<span class="where-line"><i>R</i> – crank radius, mm;</span><br>'
        '<span class="where-line"><i>S</i> – piston stroke, mm;</span><br>'
        f'<span class="where-line"><i>L</i> – {"rod length " * 30}mm.</span></span></p>'
    )
    _, boxes = _boxes(body, language)
    word_box = next(b for b in boxes if b[0].strip() == word.strip())
    symbols = [b for b in boxes if b[0] in {"R", "S", "L"}]
    assert len(symbols) == 3
    assert max(b[1] for b in symbols) - min(b[1] for b in symbols) < 0.5  # one column
    assert symbols[0][3] == pytest.approx(word_box[3], abs=0.5)  # "where" on the first's line
    assert word_box[2] <= symbols[0][1] + 0.01  # before it, not over it
    wrapped = [b for b in boxes if "rod length" in b[0]]
    assert len({round(b[3]) for b in wrapped}) > 1  # the long explanation wraps ...
    assert min(b[1] for b in wrapped[1:]) >= symbols[0][1] - 0.5  # ... under its own column


@pytest.mark.parametrize("css_class", ["skipped", "plausibility", "check-ok", "note"])
def test_a_sentence_paragraph_of_a_section_starts_with_the_paragraph_indent(css_class):
    """A paragraph of running text that carries a class (what the note leaves out, a
    plausibility verdict, a check) starts indented as the section's plain paragraphs do."""
    words = " ".join(["word"] * 40)
    body = (
        f'<section class="chapter"><p>Plain {words}</p>'
        f'<p class="{css_class}">Classed {words}</p></section>'
    )
    _, boxes = _boxes(body)
    first_x = {
        text.split()[0]: left
        for text, left, _, _ in boxes
        if text.split()[0] in ("Plain", "Classed")
    }
    lines_x = sorted({round(left, 1) for _, left, _, _ in boxes})
    assert first_x["Plain"] > lines_x[0]  # the plain paragraph is indented
    assert first_x["Classed"] == pytest.approx(first_x["Plain"])


def test_a_long_supervisors_name_keeps_its_role_and_blank_on_its_line():
    """The assignment's sign line ended with "Руководитель ____" and put "проф. Кузнецов Н. И."
    alone under it: the role, its blank and the name break as one part."""
    from conftest import shared_html

    page = shared_html("petrol-1cyl", {"report": {"supervisor": "проф. Кузнецов Н. И."}}, "ru").html
    line = next(p for p in page.split('<p class="sign-line">')[1:] if "Кузнецов" in p)
    part = line[line.index('<span class="sign-part">') :]
    assert part.index("Руководитель") < part.index("Кузнецов") < part.index("</span></span>")
    body = f'<div class="assignment"><p class="sign-line">{line.split("</p>")[0]}</p></div>'
    _, boxes = _boxes(body, "ru")
    baselines = {
        round(b, 1) for text, _, _, b in boxes if "Руководитель" in text or "Кузнецов" in text
    }
    assert len(baselines) == 1  # on one line, whichever it is
