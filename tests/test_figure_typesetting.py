"""typeset_figure: every text of a figure typeset for the report's language (axis labels, titles,
annotations, legends, an inset's labels), without making the axes' ticks, whose labels the
locale's formatter writes when the figure is drawn."""

from __future__ import annotations

from crankdyn.report import figures
from crankdyn.report.i18n import translator
from crankdyn.report.typeset import typeset_figure


def test_every_text_but_the_tick_labels_is_typeset_and_no_tick_is_made():
    fig, ax = figures.new_figure(12, 8)
    ax.plot([0.0, 1.0], [0.0, 2.0], label="p_g")
    ax.legend()
    ax.set_xlabel("s_p, mm")
    ax.set_ylabel("j_p, m/s^2")
    ax.set_title("p_z")
    ax.annotate("M_k", (0.5, 1.0))
    fig.suptitle("T_e")
    inset = ax.inset_axes((0.6, 0.6, 0.3, 0.3))
    inset.set_xlabel("V_a")
    axes_ = [axis for axes in (ax, inset) for axis in (axes.xaxis, axes.yaxis)]
    ticks = [(len(axis.majorTicks), len(axis.minorTicks)) for axis in axes_]
    typeset_figure(fig, translator("uk"))
    assert [(len(axis.majorTicks), len(axis.minorTicks)) for axis in axes_] == ticks
    texts = {t.get_text() for t in fig.findobj(lambda a: hasattr(a, "get_text"))}
    for raw in ("p_g", "s_p, mm", "j_p, m/s^2", "p_z", "M_k", "T_e", "V_a"):
        assert raw not in texts, raw
    assert {"$p_{\\mathrm{г}}$", "$M_{\\mathrm{к}}$", "$V_{\\mathrm{a}}$"} <= texts
    svg = figures.to_svg(fig).decode()
    assert "0,5" in svg  # the ticks made when drawn, labelled by the locale's formatter
