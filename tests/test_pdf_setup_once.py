"""What every layout of a printed report would set up again is set up once a process: the
report's stylesheet parsed once (crankdyn.report.pdf.ParsedStylesheets), and the font
subsetting's arrays typed without a C type string per length (crankdyn.report.weasy)."""

import shutil
import subprocess

import pytest

from crankdyn.report import pdf, weasy

pytest.importorskip("weasyprint")

STYLE = (
    "<style>@page { size: A6; margin: 10mm; @top-right { content: counter(page); } }"
    " p { color: #c00; font-size: 14pt; } .wide { letter-spacing: 3pt; }"
    " .tall { font-size: 30pt; } @media print { p.wide { color: #00c } }</style>"
)
BODY = (
    '<body><p class="wide">Кривошип and crank</p><p class="tall" style="font-size: 8pt">small</p>'
    + "<p>line</p>" * 30
    + "</body>"
)
PAGE = f'<!DOCTYPE html><html lang="uk"><head><meta charset="utf-8">{STYLE}</head>{BODY}</html>'


def test_the_stylesheet_is_taken_from_the_page_and_parsed_once():
    sheets = pdf.ParsedStylesheets()
    html, kept = sheets.taken_from(PAGE, "file:///x/")
    assert "<style>" not in html and "Кривошип" in html and html.startswith("<!DOCTYPE")
    again_html, again = sheets.taken_from(PAGE, "file:///x/")
    assert again_html == html
    assert again["stylesheets"][0] is kept["stylesheets"][0]  # parsed once
    assert again["font_config"] is kept["font_config"]


@pytest.mark.parametrize(
    "rule",
    [
        "p { background: url(a.png) }",
        "@import 'a.css';",
        "@font-face { font-family: A }",
        # weighed against a style attribute differently as an author's and as the user's
        "p { color: red !important }",
        "#tall { font-size: 30pt }",
        "@media print { p#tall { color: red } }",
    ],
)
def test_a_stylesheet_that_loads_anything_or_weighs_differently_stays_in_the_page(rule):
    page = PAGE.replace("</style>", rule + "</style>")
    assert pdf.ParsedStylesheets().taken_from(page, "file:///x/") == (page, {})


def test_a_style_in_the_body_stays_where_it_is():
    page = PAGE.replace("<body>", "<body><style>p { color: blue }</style>")
    html, kept = pdf.ParsedStylesheets().taken_from(page, "file:///x/")
    assert kept and html.count("<style>") == 1 and "<body><style>" in html


@pytest.mark.skipif(shutil.which("pdftotext") is None, reason="poppler-utils not installed")
def test_the_kept_stylesheet_lays_out_the_same_pages(tmp_path):
    """The same pages, words and places as with the stylesheet in the page (a style attribute
    wins over a class's rule both ways: the small line stays small)."""
    weasyprint = weasy.load_weasyprint()
    sheets = pdf.ParsedStylesheets()
    html, kept = sheets.taken_from(PAGE, "file:///x/")
    laid_out = {
        "in the page": weasyprint.HTML(string=PAGE).write_pdf(),
        "kept": weasyprint.HTML(string=html).write_pdf(**kept),
        "kept again": weasyprint.HTML(string=html).write_pdf(
            **sheets.taken_from(PAGE, "file:///x/")[1]
        ),
    }
    texts = {}
    for name, document in laid_out.items():
        path = tmp_path / f"{name}.pdf"
        path.write_bytes(document)
        texts[name] = subprocess.run(
            ["pdftotext", "-bbox", str(path), "-"], capture_output=True, text=True, check=True
        ).stdout
    assert texts["kept"] == texts["in the page"] == texts["kept again"]
    assert texts["kept"].count("<page ") > 1  # 30 lines of 14 pt do not fit an A6 page
    small = texts["kept"].split(">small<")[0].rsplit("yMin=", 1)[1].split('"')
    assert float(small[3]) - float(small[1]) < 12  # yMax - yMin: 8 pt, not 30 pt


class _RecordingFFI:
    def __init__(self):
        self.asked = []

    def new(self, cdecl, init=None):
        self.asked.append(cdecl)
        return (cdecl, init)

    cast = "the ffi's own"


def test_arrays_of_their_items_are_typed_without_their_length():
    ffi = _RecordingFFI()
    wrapped = weasy._ArraysOfTheirItems(ffi)
    assert wrapped.new("hb_codepoint_t[3]", [1, 2, 3]) == ("hb_codepoint_t[]", [1, 2, 3])
    # fewer items than the length (the rest zeros), no items, not an array: as asked
    assert wrapped.new("hb_codepoint_t[4]", [1, 2, 3]) == ("hb_codepoint_t[4]", [1, 2, 3])
    assert wrapped.new("hb_tag_t[100]") == ("hb_tag_t[100]", None)
    assert wrapped.new("unsigned int *", 100) == ("unsigned int *", 100)
    assert wrapped.new("char[4]", b"abcd") == ("char[]", b"abcd")
    assert wrapped.new("int[4]", 0) == ("int[4]", 0)  # not a list of items: as asked
    assert wrapped.cast == "the ffi's own"


def test_weasyprint_subsets_its_fonts_with_such_arrays():
    weasy.load_weasyprint()
    import weasyprint.pdf.fonts as fonts

    assert isinstance(fonts.ffi, weasy._ArraysOfTheirItems)
    weasy._subset_arrays_of_their_items()  # again: not wrapped twice
    assert not isinstance(fonts.ffi.__dict__["_ffi"], weasy._ArraysOfTheirItems)
    array = fonts.ffi.new("unsigned int[3]", [7, 8, 9])
    assert list(array) == [7, 8, 9] and fonts.ffi.sizeof(array) == 12
