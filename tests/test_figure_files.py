"""Figures stored once: report.html refers to figures/*.svg, --self-contained inlines them, the PDF
gets them from memory through the safe URL fetcher."""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.output.pipeline import render_files
from crankdyn.plugin.registry import default_registry
from crankdyn.report.context import FigureFile
from crankdyn.report.pdf import BlockedResource, _asset_root, _fetcher, figure_urls, html_to_pdf
from crankdyn.scene.model import load_scene

REGISTRY = default_registry()


@pytest.fixture(scope="module")
def kinematics_run():
    scene = load_scene(examples_dir() / "kinematics-only.toml")
    return run_scene(scene, REGISTRY, ["kinematics"])  # one stage: a few figures, rendered quickly


def test_html_refers_to_each_figure_once_and_self_contained_inlines_them(kinematics_run):
    files = render_files(kinematics_run, REGISTRY, ["html"])
    html = files["report.html"].decode("utf-8")
    figures = sorted(name for name in files if name.startswith("figures/"))
    assert figures and "data:image/svg+xml" not in html
    assert (
        sorted(re.findall(r'src="(figures/[^"]+)"', html)) == figures
    )  # each referenced exactly once
    inline = render_files(kinematics_run, REGISTRY, ["html"], self_contained=True)
    assert list(inline) == ["report.html"]
    page = inline["report.html"].decode("utf-8")
    assert page.count("data:image/svg+xml;base64,") == len(figures) and 'src="figures/' not in page


def test_fetcher_serves_only_the_rendered_figures_from_memory():
    base = _asset_root().as_uri() + "/"
    svg = b'<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"/>'
    fetcher = _fetcher(figure_urls([FigureFile("fig_1_1_a.svg", svg)], base))

    def fetch(url):
        return fetcher.fetch(url) if hasattr(fetcher, "fetch") else fetcher(url)

    got = fetch(base + "figures/fig_1_1_a.svg")
    body = got.read() if hasattr(got, "read") else got["string"]
    assert body == svg
    for url in (
        base + "figures/other.svg",
        base + "figures/../../../../etc/passwd",
        "file:///etc/hostname",
    ):
        with pytest.raises(Exception) as caught:
            fetch(url)
        assert (
            caught.type is BlockedResource or "figures/other.svg" in url
        )  # a missing asset may also fail


@pytest.mark.skipif(shutil.which("pdftotext") is None, reason="poppler-utils not installed")
def test_pdf_draws_the_referenced_figure(tmp_path):
    svg = (
        b'<svg xmlns="http://www.w3.org/2000/svg" width="300" height="40">'
        b'<text x="5" y="20" font-size="14">FIGUREMARKER</text></svg>'
    )
    pdf = html_to_pdf(
        '<html><body><p>x</p><img src="figures/fig_1_1_m.svg"></body></html>',
        [FigureFile("fig_1_1_m.svg", svg)],
    )
    (tmp_path / "r.pdf").write_bytes(pdf)
    text = subprocess.run(
        ["pdftotext", str(tmp_path / "r.pdf"), "-"], capture_output=True, text=True
    ).stdout
    assert "FIGUREMARKER" in text
