"""A report's PDF laid out in two processes (crankdyn.report.pdf_parts): the same pages, page
numbers, contents, page count, bookmarks and links as one layout; documents it cannot split,
and a part that fails, give the one-layout PDF."""

import os
import shutil
import subprocess

import pytest
from child_processes import children, in_fresh_process

from crankdyn.report import pdf_parts
from crankdyn.report.pdf import html_to_pdf

pytestmark = [
    pytest.mark.skipif(not hasattr(os, "fork"), reason="the second part is forked"),
    pytest.mark.skipif(shutil.which("pdftotext") is None, reason="poppler-utils not installed"),
]
pikepdf = pytest.importorskip("pikepdf")

STYLE = """<style>
@page { size: A5; margin: 15mm; @top-right { content: counter(page); } }
@page :first { @top-right { content: none; } }
@page wide { size: A5 landscape; }
section.chapter { page-break-before: always; }
.title-page, .abstract { page-break-after: always; }
nav.contents a::after { content: leader('.') target-counter(attr(href), page); }
a.pagecount::after { content: target-counter(attr(href), page); }
table.wide { page: wide; }
</style>"""

#: Chapters of 1, 3, 2, 2 and 2 pages (a block of 140 mm takes an A5 page of 180 mm); the
#: fourth is its heading's page and a turned page.
CHAPTER_PAGES = (1, 3, 2, 2, 2)


def _report() -> str:
    chapters = []
    for number, pages in enumerate(CHAPTER_PAGES, start=1):
        body = "".join(f'<div style="height: 140mm">{number}.{k} text</div>' for k in range(pages))
        if number == 4:
            body = "<table class='wide'><tr><td>turned</td></tr></table>"
        chapters.append(
            f'<section class="chapter" id="sec-{number}"><h2>{number} Chapter {number}</h2>'
            f"{body}</section>\n"
        )
    contents = "".join(
        f'<li><a href="#sec-{n}">{n} Chapter {n}</a></li>' for n in range(1, len(CHAPTER_PAGES) + 1)
    )
    return (
        f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>T</title>{STYLE}'
        '</head><body><section class="title-page"><h1>Title</h1></section>'
        '<section class="abstract"><h2>Abstract</h2><p>Pages: '
        '<a class="pagecount" href="#document-end"></a>.</p></section>'
        f'<nav class="contents"><h2>Contents</h2><ul>{contents}</ul></nav>\n'
        + "".join(chapters)
        + '<p class="colophon" id="document-end">end</p></body></html>'
    )


def _pages(pdf: bytes, tmp_path, name: str) -> list[str]:
    path = tmp_path / name
    path.write_bytes(pdf)
    done = subprocess.run(
        ["pdftotext", "-layout", str(path), "-"], capture_output=True, text=True, check=True
    )
    return done.stdout.split("\f")[:-1]


def _links_and_outline(pdf: bytes):
    import io

    document = pikepdf.open(io.BytesIO(pdf))
    index = {page.obj.objgen: i for i, page in enumerate(document.pages)}

    def where(destination):
        return index[destination[0].objgen], round(float(destination[3]))

    def tree(items):
        return [
            (item.title, where(item.destination), item.is_closed, tree(item.children))
            for item in items
        ]

    with document.open_outline() as outline:
        bookmarks = tree(outline.root)
    assert bookmarks[0][0] == "Title" and len(bookmarks[0][3]) == 2 + len(CHAPTER_PAGES)
    names = {
        name: where(destination)
        for name, destination in pikepdf.NameTree(document.Root.Names.Dests).items()
    }
    links = [
        (i, str(annotation.Dest), [round(float(v)) for v in annotation.Rect])
        for i, page in enumerate(document.pages)
        for annotation in page.obj.get("/Annots", [])
    ]
    return bookmarks, names, links


def _a_quiet_machine(monkeypatch):
    monkeypatch.setattr(os, "getloadavg", lambda: (0.2, 0.2, 0.2))


@pytest.mark.slow  # three layouts in a fresh process: in the slow tier, which CI runs
@in_fresh_process
def test_two_parts_give_the_pages_of_one_layout(tmp_path, monkeypatch):
    _a_quiet_machine(monkeypatch)
    laid_out_apart = []
    parallel_pdf = pdf_parts.parallel_pdf
    monkeypatch.setattr(
        pdf_parts,
        "parallel_pdf",
        lambda parts, render: laid_out_apart.append(parts) or parallel_pdf(parts, render),
    )
    html = _report()
    whole = html_to_pdf(html)
    apart = html_to_pdf(html, parallel=True)
    assert len(laid_out_apart) == 1 and not children()
    # both parts hold chapters: the second is laid out by the child
    assert laid_out_apart[0].first and 'id="sec-5"' in laid_out_apart[0].second
    pages = _pages(apart, tmp_path, "apart.pdf")
    assert pages == _pages(whole, tmp_path, "whole.pdf")
    # the numbers themselves: 3 front pages (title, abstract, contents), then the chapters
    starts = [4]
    for count in CHAPTER_PAGES[:-1]:
        starts.append(starts[-1] + count)
    total = 3 + sum(CHAPTER_PAGES)
    assert len(pages) == total
    for number, start in enumerate(starts, start=1):
        assert f"{number} Chapter {number}" in pages[start - 1]
        assert pages[start - 1].split()[0] == str(start)  # the page's own number, top right
        contents_line = next(
            line for line in pages[2].splitlines() if f"{number} Chapter {number}" in line
        )
        assert contents_line.rstrip().endswith(f". {start}")
    assert f"Pages: {total}." in pages[1]
    assert "1 Chapter 1" not in pages[0] and not pages[0].split()[0].isdigit()  # no number
    assert _links_and_outline(apart) == _links_and_outline(whole)


@pytest.mark.slow  # a third layout in a fresh process: in the slow tier, which CI runs
@in_fresh_process
def test_a_part_that_fails_leaves_the_pdf_to_one_layout(tmp_path, monkeypatch):
    def failing(sock, render, html):
        raise RuntimeError("the child's layout failed")

    monkeypatch.setattr(pdf_parts, "_second_part", failing)
    _a_quiet_machine(monkeypatch)
    html = _report()
    apart = html_to_pdf(html, parallel=True)
    assert not children()
    assert _pages(apart, tmp_path, "apart.pdf") == _pages(html_to_pdf(html), tmp_path, "w.pdf")


@pytest.mark.slow  # a third layout in a fresh process: in the slow tier, which CI runs
@in_fresh_process
def test_a_busy_machine_lays_out_in_one_process(tmp_path, monkeypatch):
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1})
    monkeypatch.setattr(os, "getloadavg", lambda: (3.0, 1.0, 1.0))  # two cores, three busy
    assert pdf_parts.machine_busy(2) and not pdf_parts.can_split_processes()
    laid_out_apart = []
    monkeypatch.setattr(pdf_parts, "parallel_pdf", lambda *args: laid_out_apart.append(args))
    html = _report()
    pages = _pages(html_to_pdf(html, parallel=True), tmp_path, "busy.pdf")
    assert not laid_out_apart and len(pages) == 3 + sum(CHAPTER_PAGES)
    monkeypatch.setattr(os, "getloadavg", lambda: (2.9, 5.0, 5.0))  # the last minute counts
    assert not pdf_parts.machine_busy(2) and pdf_parts.can_split_processes()


def test_documents_whose_pages_depend_on_each_other_are_not_split():
    html = _report()
    assert pdf_parts.split(html) is not None
    one_chapter = html.replace('<section class="chapter"', '<section class="part"', 4)
    assert pdf_parts.split(one_chapter) is None
    framed = html.replace("<body>", '<body><div class="eskd-sheet"></div>')
    assert pdf_parts.split(framed) is None
    cross_reference = html.replace("<h2>3 Chapter 3</h2>", '<h2><a href="#sec-1">3</a></h2>')
    assert pdf_parts.split(cross_reference) is None
    roman = html.replace("(attr(href), page)", "(attr(href), page, upper-roman)")
    assert pdf_parts.split(roman) is None
    total = html.replace("@page {", "@page { @bottom-right { content: counter(pages); }")
    assert pdf_parts.split(total) is None
    dangling = html.replace('href="#sec-2"', 'href="#nowhere"')
    assert pdf_parts.split(dangling) is None


@pytest.mark.slow  # three layouts in a fresh process: in the slow tier, which CI runs
@in_fresh_process
def test_the_printer_lays_out_in_parts_and_serves_both_their_figures(tmp_path, monkeypatch):
    from crankdyn.report import printer
    from crankdyn.report.context import FigureFile

    svg = (
        b'<svg xmlns="http://www.w3.org/2000/svg" width="100" height="50" viewBox="0 0 100 50">'
        b'<text x="5" y="30" font-size="12">%s</text></svg>'
    )
    html = _report()
    for chapter in (1, 5):  # one figure in each part
        html = html.replace(
            f"{chapter}.0 text", f'<img src="figures/fig_{chapter}.svg"> {chapter}.0 text'
        )
    parts = pdf_parts.split(html)
    assert "fig_1.svg" in parts.first and "fig_5.svg" in parts.second
    asked = []

    class Figure(FigureFile):
        @property
        def svg(self):
            asked.append(self.name)
            return svg % self.name.encode()

    figures = [Figure("fig_1.svg"), Figure("fig_5.svg")]
    join, joined = pdf_parts.join, tmp_path / "joined"

    def joining(*args):  # in the printer process: a mark that the parts were joined
        joined.touch()
        return join(*args)

    monkeypatch.setattr(pdf_parts, "join", joining)
    _a_quiet_machine(monkeypatch)
    assert printer.prestart()
    pdf = printer.print_pdf(html, figures)
    assert pdf is not None and not children() and joined.exists()
    assert sorted(asked) == ["fig_1.svg", "fig_5.svg"]
    pages = _pages(pdf, tmp_path, "printed.pdf")
    assert pages == _pages(html_to_pdf(html, figures), tmp_path, "here.pdf")
    assert "fig_1.svg" in pages[3] and "fig_5.svg" in pages[-2]  # each figure drawn on its page
