"""The PDF printer process the command line starts before computing (crankdyn.report.printer):
the same PDF as printing in-process, the figures served from the report's process, and every way
it can fail ends with the PDF made in-process (or the report's own error), no process left.

Each case runs in a pytest process of its own (``in_fresh_process``): the printer is forked only
by a process with no other thread (a pytest-xdist worker has some) and before WeasyPrint is
imported."""

import os
import signal
import sys

import pytest
from child_processes import children, in_fresh_process

from crankdyn.report import printer
from crankdyn.report.context import FigureFile

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="the printer is forked")

SVG = (
    b'<svg xmlns="http://www.w3.org/2000/svg" width="100" height="50" viewBox="0 0 100 50">'
    b'<text x="5" y="30" font-size="12">kinematics</text></svg>'
)
HTML = '<h1>crankdyn</h1><p>Figure 1</p><img src="figures/fig_1.svg"><p>after it</p>'


@in_fresh_process
def test_the_printer_makes_the_same_pdf_and_asks_for_each_figure():
    assert printer.prestart()
    assert "weasyprint" not in sys.modules  # loaded by the printer, not here
    asked = []

    class Figure(FigureFile):
        @property
        def svg(self):
            asked.append(self.name)
            return SVG

    pdf = printer.print_pdf(HTML, [Figure("fig_1.svg")])
    assert asked == ["fig_1.svg"]
    assert not children()  # the printer has exited and was waited for
    from crankdyn.report.pdf import html_to_pdf

    assert pdf == html_to_pdf(HTML, [FigureFile("fig_1.svg", SVG)])
    assert printer.print_pdf(HTML, []) is None  # one printer, used once


@in_fresh_process
def test_a_dead_printer_leaves_the_pdf_to_the_report():
    assert printer.prestart()
    os.kill(printer._printer[0], signal.SIGKILL)
    assert printer.print_pdf(HTML, [FigureFile("fig_1.svg", SVG)]) is None
    assert not children()


@in_fresh_process
def test_a_figure_that_fails_fails_the_report_as_without_a_printer():
    assert printer.prestart()

    class Broken(FigureFile):
        @property
        def svg(self):
            raise ValueError("the figure's own error")

    with pytest.raises(ValueError, match="own error"):
        printer.print_pdf(HTML, [Broken("fig_1.svg")])
    assert not children()


@in_fresh_process
def test_an_error_in_the_printer_gives_the_pdf_back_to_the_report(monkeypatch):
    import crankdyn.report.pdf as pdf_module

    html_to_pdf, parent = pdf_module.html_to_pdf, os.getpid()

    def failing_in_the_printer(html, figures=(), **options):
        if os.getpid() != parent and html != "<p>crankdyn</p>":  # the page, not the warm-up
            raise RuntimeError("WeasyPrint failed")
        return html_to_pdf(html, figures, **options)

    monkeypatch.setattr(pdf_module, "html_to_pdf", failing_in_the_printer)
    assert printer.prestart()
    assert printer.print_pdf(HTML, [FigureFile("fig_1.svg", SVG)]) is None  # the report prints it
    assert not children()
    # and a printer not used is stopped
    assert printer.prestart()
    printer.discard()
    assert not children()
    assert printer.print_pdf(HTML, []) is None


# a whole PDF report from the command line: in the slow tier, which CI runs
@pytest.mark.slow
@in_fresh_process
def test_the_command_line_prints_through_the_printer_and_leaves_no_process(tmp_path, monkeypatch):
    used = []
    print_pdf = printer.print_pdf

    def counting(html, figures):
        pdf = print_pdf(html, figures)
        used.append(pdf is not None)
        return pdf

    monkeypatch.setattr(printer, "print_pdf", counting)
    from crankdyn.cli import examples_dir, main

    scene = examples_dir() / "kinematics-only.toml"
    assert main(["report", str(scene), "--format", "pdf,json", "-o", str(tmp_path), "-q"]) == 0
    assert used == [True]
    assert not children()
    assert (tmp_path / "report.pdf").read_bytes().startswith(b"%PDF")
    # a refused scene: the printer started for it is stopped, nothing written
    bad = tmp_path / "bad.toml"
    bad.write_text("[engine]\nbore = -1\n", encoding="utf-8")
    assert main(["report", str(bad), "--format", "pdf", "-o", str(tmp_path / "bad"), "-q"]) == 2
    assert not children()
    assert not (tmp_path / "bad").exists()


def test_a_pdf_is_laid_out_with_fewer_collections_and_the_settings_come_back():
    import gc

    from crankdyn.report import pdf

    before = gc.get_threshold()
    with pdf.fewer_collections():
        assert gc.get_threshold() == pdf.LAYOUT_GC_THRESHOLDS
    assert gc.get_threshold() == before
    try:
        with pdf.fewer_collections():
            raise RuntimeError("a failed layout")
    except RuntimeError:
        pass
    assert gc.get_threshold() == before


def test_the_printer_loads_none_of_the_reports_own_code():
    """The printer runs while the report's process and its stage child use both cores: what it
    imports to lay out a page (the stylesheets, the PDF module) takes no numpy, Jinja or plugin
    types, which the report's process has and the printer does not need."""
    import subprocess

    probe = (
        "import sys\n"
        "from crankdyn.report import pdf, printer\n"
        "from crankdyn.report.assets import report_css\n"
        "assert '@page' in report_css('uk')\n"
        "heavy = [m for m in ('numpy', 'jinja2', 'pydantic', 'crankdyn.report.context')"
        " if m in sys.modules]\n"
        "print(heavy)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, check=True, timeout=60
    )
    assert done.stdout.strip() == "[]"
