"""A note says what holds for its engine's kind: a two-stroke's gas exchange is the scavenging near
BDC (no pumping strokes, no intake and exhaust lines), a single crank has no running torque, an
articulated-rod radial's rods are not all central; its letters mean one thing each; its numbers
are printed to the digits the data justify and one value is printed alike wherever it appears."""

from __future__ import annotations

import re

import pytest
from conftest import as_read, shared_html

#: A two-stroke's gas exchange, per language.
SCAVENGING = {"en": "scavenging", "uk": "продування", "ru": "продувк"}
PUMPING_ALREADY = {"en": "already takes off the pumping strokes",
                   "uk": "насосні ходи в ній уже враховано",
                   "ru": "насосные ходы в ней уже учтены"}


def _text(html: str) -> str:
    body = html.split("<body", 1)[1]
    body = re.sub(r"<(script|style|svg)\b.*?</\1>", " ", body, flags=re.S)
    return " ".join(as_read(re.sub(r"<[^>]+>", " ", body)).split())


@pytest.mark.parametrize("language", ["en", "uk", "ru"])
def test_a_two_strokes_mechanical_losses_are_its_scavenging_not_pumping_strokes(language):
    two = _text(shared_html("two-stroke-1cyl", {"engine": {"effective_power": "5 kW"}},
                            language).linked_html)
    four = _text(shared_html("petrol-1cyl-uk", None, language).linked_html)
    effective = re.search(r"N\s*e\s*= 5 \S+, .{0,300}", two).group(0)
    assert PUMPING_ALREADY[language] not in effective, effective
    assert SCAVENGING[language] in effective, effective
    assert PUMPING_ALREADY[language] in four


@pytest.mark.parametrize("two_stroke, title", [(True, "продування поблизу НМТ (збільшено)"),
                                               (False, "впуск і випуск (збільшено)")])
def test_the_low_pressure_inset_of_a_two_stroke_shows_its_scavenging(two_stroke, title):
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    from crankdyn.plugins import default_registry
    from crankdyn.report.i18n import translator
    from crankdyn_builtin.indicator.figures import _pv_figure

    volume = np.linspace(0.05, 0.5, 50)
    pressure = 0.1 + 4.0 * (0.05 / volume) ** 1.3
    fig = _pv_figure(volume, pressure, pressure * 0.98, [], translator("uk", default_registry().catalogs),
                     two_stroke=two_stroke)
    titles = [ax.get_title() for ax in fig.axes[0].child_axes]
    assert titles == [title]


def _legend_texts(rendered, key: str) -> list[str]:
    figure = next(f for f in rendered.figures if f.key == key).figure
    return [text.get_text() for ax in figure.axes if ax.get_legend()
            for text in ax.get_legend().get_texts()]


@pytest.mark.parametrize("detail, expected, absent", [
    ("course", "чисельне інтегрування", "RK45"), ("full", "RK45", "чисельне інтегрування")])
def test_a_course_notes_speed_figure_names_no_solver(detail, expected, absent):
    legend = " | ".join(_legend_texts(
        shared_html("inline4-petrol", {"report": {"detail": detail}}, "uk"), "speed"))
    assert expected in legend and absent not in legend, legend


def _symbol_rows(html: str) -> list[str]:
    return re.findall(r'<p class="symbol-row"><span class="symbol">(.*?)</span> – ', html)


def test_the_torque_non_uniformity_is_a_formula_and_listed_among_the_symbols():
    html = shared_html("v8-petrol", None, "ru").linked_html
    assert "<i>μ</i>" in _symbol_rows(html)
    assert re.search(r'<i>μ</i> = \(<i>M</i><sub>max</sub> − <i>M</i><sub>min</sub>\)/'
                     r'<i>M</i><sub>ср</sub>\s=\s\d', html)


def test_the_ignition_delay_time_is_not_the_number_of_strokes():
    html = shared_html("diesel-1cyl", None, "uk").linked_html
    rows = _symbol_rows(html)
    assert "<i>τ</i>" in rows and "<i>τ</i><sub>з</sub>" in rows, rows
    assert re.search(r"6·<i>n</i>·<i>τ</i><sub>з</sub> за <i>τ</i><sub>з</sub>\s=\s\d", html)
    assert not re.search(r"<i>τ</i>\s=\s\d", html)


def test_the_number_of_cylinders_takes_no_letter_of_the_running_index():
    html = shared_html("v8-petrol", None, "uk").linked_html
    row = re.search(r"<tr[^>]*><td[^>]*>Кількість циліндрів</td>(.*?)</tr>", html).group(1)
    assert "<i>i</i>" not in row, row


def test_the_counterweights_force_is_listed_among_the_symbols():
    html = shared_html("v8-petrol", None, "uk").linked_html
    assert re.search(r"<i>Q</i> = <i>F</i> \+ Σ<i>C</i>", html)
    assert "<i>Q</i>" in _symbol_rows(html)
