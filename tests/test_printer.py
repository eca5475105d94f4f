"""The PDF printer process the command line starts before computing (crankdyn.report.printer):
the same PDF as printing in-process, the figures served from the report's process, and every way
it can fail ends with the PDF made in-process (or the report's own error), no process left.

Each case runs in a fresh interpreter: the printer is forked only by a process with no other
thread (a pytest-xdist worker has some) and before WeasyPrint is imported."""

from pathlib import Path

import pytest
from child_processes import run_fresh

pytestmark = pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="the printer is forked")

# the fresh interpreter imports the tests folder's helpers from here
SETUP = f"TESTS = {str(Path(__file__).resolve().parent)!r}\n" + """
import os, sys
from crankdyn.report import printer
from crankdyn.report.context import FigureFile

SVG = (b'<svg xmlns="http://www.w3.org/2000/svg" width="100" height="50" viewBox="0 0 100 50">'
       b'<text x="5" y="30" font-size="12">kinematics</text></svg>')
HTML = '<h1>crankdyn</h1><p>Figure 1</p><img src="figures/fig_1.svg"><p>after it</p>'

sys.path.insert(0, TESTS)
from child_processes import children
"""


def run(code: str):
    return run_fresh(SETUP, code, timeout=120, says_ok=False)


def test_the_printer_makes_the_same_pdf_and_asks_for_each_figure():
    out = run("""
    assert printer.prestart()
    assert "weasyprint" not in sys.modules  # loaded by the printer, not here
    asked = []
    class Figure(FigureFile):
        @property
        def svg(self):
            asked.append(self.name)
            return SVG
    pdf = printer.print_pdf(HTML, [Figure("fig_1.svg")])
    assert asked == ["fig_1.svg"], asked
    assert not children()  # the printer has exited and was waited for
    from crankdyn.report.pdf import html_to_pdf
    assert pdf == html_to_pdf(HTML, [FigureFile("fig_1.svg", SVG)])
    assert printer.print_pdf(HTML, []) is None  # one printer, used once
    print("ok")
    """)
    assert out.stdout.strip() == "ok"


def test_a_dead_printer_leaves_the_pdf_to_the_report():
    run("""
    import signal
    assert printer.prestart()
    os.kill(printer._printer[0], signal.SIGKILL)
    assert printer.print_pdf(HTML, [FigureFile("fig_1.svg", SVG)]) is None
    assert not children()
    """)


def test_a_figure_that_fails_fails_the_report_as_without_a_printer():
    run("""
    assert printer.prestart()
    class Broken(FigureFile):
        @property
        def svg(self):
            raise ValueError("the figure's own error")
    try:
        printer.print_pdf(HTML, [Broken("fig_1.svg")])
    except ValueError as exc:
        assert "own error" in str(exc)
    else:
        raise AssertionError("the figure's error was lost")
    assert not children()
    """)


def test_an_error_in_the_printer_gives_the_pdf_back_to_the_report():
    run("""
    import crankdyn.report.pdf as pdf_module
    html_to_pdf, parent = pdf_module.html_to_pdf, os.getpid()
    def failing_in_the_printer(html, figures=()):
        if os.getpid() != parent and html != "<p>crankdyn</p>":  # the page, not the warm-up
            raise RuntimeError("WeasyPrint failed")
        return html_to_pdf(html, figures)
    pdf_module.html_to_pdf = failing_in_the_printer
    assert printer.prestart()
    assert printer.print_pdf(HTML, [FigureFile("fig_1.svg", SVG)]) is None  # the report prints it
    assert not children()
    # and a printer not used is stopped
    assert printer.prestart()
    printer.discard()
    assert not children()
    assert printer.print_pdf(HTML, []) is None
    """)


def test_the_command_line_prints_through_the_printer_and_leaves_no_process(tmp_path, examples):
    scene = examples / "kinematics-only.toml"
    run(f"""
    from crankdyn import pipeline
    from crankdyn.report import printer
    used = []
    print_pdf = printer.print_pdf
    def counting(html, figures):
        pdf = print_pdf(html, figures)
        used.append(pdf is not None)
        return pdf
    printer.print_pdf = counting
    from crankdyn.cli import main
    assert main(["report", {str(scene)!r}, "--format", "pdf,json", "-o", {str(tmp_path)!r}, "-q"]) == 0
    assert used == [True], used
    assert not children()
    # a refused scene: the printer started for it is stopped, nothing written
    bad = {str(tmp_path / "bad.toml")!r}
    open(bad, "w").write("[engine]\\nbore = -1\\n")
    assert main(["report", bad, "--format", "pdf", "-o", {str(tmp_path / "bad")!r}, "-q"]) == 2
    assert not children()
    assert not os.path.exists({str(tmp_path / "bad")!r})
    """)
    assert (tmp_path / "report.pdf").read_bytes().startswith(b"%PDF")
