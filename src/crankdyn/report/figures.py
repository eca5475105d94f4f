"""matplotlib figures as SVG bytes, in the report's house style.

The Agg backend and text converted to paths make the SVG self-contained: the PDF
renderer needs no font lookup for figures and Cyrillic labels always show.
"""

from __future__ import annotations

import io
import sys

# matplotlib is imported only when a figure is drawn (lazy: heavy optional import), and never
# through pyplot: each figure is a plain ``Figure`` on its own Agg canvas, so a JSON-only run
# pays nothing for plotting and no global figure state builds up between reports.

STYLE = {
    "svg.fonttype": "none",  # text stays text: searchable in the PDF (fonts: the report's, below)
    "font.family": "DejaVu Sans",
    "font.size": 9,
    "axes.grid": True,
    "grid.alpha": 0.35,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "lines.linewidth": 1.4,
    "figure.dpi": 100,
    "svg.hashsalt": "crankdyn",  # stable ids: the same scene gives the same bytes
}


def new_figure(width_cm: float = 16.0, height_cm: float = 8.5, **subplots):
    """(figure, axes) as ``pyplot.subplots`` returns them, on an Agg canvas, without pyplot."""
    import matplotlib  # lazy: heavy optional import
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # lazy: heavy optional import
    from matplotlib.figure import Figure  # lazy: heavy optional import

    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=(width_cm / 2.54, height_cm / 2.54))
        FigureCanvasAgg(fig)
        return fig, fig.subplots(**subplots)


def crank_angle_axis(ax, cycle_deg: float, label: str) -> None:
    ax.set_xlim(0, cycle_deg)
    step = 90 if cycle_deg > 360 else 45
    ax.set_xticks(range(0, int(cycle_deg) + 1, step))
    ax.set_xlabel(label)


def to_svg(fig) -> bytes:
    import matplotlib  # lazy: heavy optional import

    buffer = io.BytesIO()
    with matplotlib.rc_context(STYLE):
        fig.tight_layout()
        fig.savefig(buffer, format="svg", metadata={"Date": None})
    pyplot = sys.modules.get("matplotlib.pyplot")
    if pyplot is not None and getattr(fig.canvas, "manager", None) is not None:
        pyplot.close(fig)  # a plugin drew it with pyplot: release pyplot's reference
    return buffer.getvalue()
