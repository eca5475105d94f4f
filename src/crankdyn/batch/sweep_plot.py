"""The plot of a sweep: one result column over the grid.

x is a swept field (the first, or ``--plot-x``); with one swept field the plot is one line, with
more there is one line per combination of the others' values (the legend names them). A point
that failed leaves a gap. Drawn in the report's house style (text stays text in the SVG).
"""

from __future__ import annotations

import io
import itertools
import math

import numpy as np

from ..plugin.registry import Registry
from ..report.figures import STYLE, new_figure, to_svg
from .answer_key import answer_columns
from .variants import Outcome, _registry_or_default


def _series(sweep, outcomes: list[Outcome]) -> tuple[int, np.ndarray]:
    """(index of the x axis, the plotted column over the grid as an array of the axes' shape, NaN where missing)."""
    names = [a.name for a in sweep.axes]
    x_index = names.index(sweep.plot_x) if sweep.plot_x else 0
    shape = tuple(len(a.values) for a in sweep.axes)
    grid = np.full(shape, np.nan)
    for outcome in outcomes:
        value = outcome.answers.get(sweep.plot_y) if outcome.ok else None
        if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value):
            grid[np.unravel_index(outcome.row - 1, shape)] = value
    return x_index, grid


def _label(axis) -> str:
    return f"{axis.name}, {axis.unit}" if axis.unit else axis.name


def _unit_of(column: str, registry: Registry) -> str:
    return next((c.declared.unit for c in answer_columns(registry) if c.name == column), "")


def draw(sweep, outcomes: list[Outcome], registry: Registry | None = None):
    """The matplotlib Figure of ``sweep.plot_y`` over the grid, or None when no point has a value;
    the column's unit from ``registry`` (the run's plugins; by default the installed ones)."""
    x_index, grid = _series(sweep, outcomes)
    if np.isnan(grid).all():
        return None
    x_axis = sweep.axes[x_index]
    others = [a for k, a in enumerate(sweep.axes) if k != x_index]
    numeric = all(n is not None for n in x_axis.numbers)
    xs = np.array(x_axis.numbers if numeric else range(len(x_axis.values)), dtype=float)
    moved = np.moveaxis(grid, x_index, -1)  # the other axes first, x last
    fig, ax = new_figure(16.0, 9.0)
    for combination in itertools.product(*(range(len(a.values)) for a in others)):
        ys = moved[combination] if combination else moved
        label = ", ".join(
            f"{a.name} = {a.cell(k)}{' ' + a.unit if a.unit else ''}"
            for a, k in zip(others, combination, strict=True)
        )
        ax.plot(xs, ys, marker="o", markersize=3.5, label=label or None)
    if not numeric:
        ax.set_xticks(xs, [str(v) for v in x_axis.values])
    ax.set_xlabel(_label(x_axis))
    unit = _unit_of(sweep.plot_y, _registry_or_default(registry))
    ax.set_ylabel(f"{sweep.plot_y}, {unit}" if unit else sweep.plot_y)
    if others:
        ax.legend(fontsize=7, frameon=False)
    return fig


def plot_files(
    sweep, outcomes: list[Outcome], formats: list[str], registry: Registry | None = None
) -> tuple[dict[str, bytes], str]:
    """``sweep-<column>.svg``/``.png`` and a note for the user ("" when the plot was drawn)."""
    import matplotlib  # lazy: heavy optional import

    fig = draw(sweep, outcomes, registry)
    if fig is None:
        return {}, (
            f"no point has a value of {sweep.plot_y} (its stage did not run for this scene): "
            "no plot written"
        )
    stem = f"sweep-{sweep.plot_y}"
    files = {}
    if "png" in formats:
        buffer = io.BytesIO()
        with matplotlib.rc_context(STYLE):
            fig.tight_layout()
            fig.savefig(buffer, format="png", dpi=150, metadata={"Software": None})
        files[f"{stem}.png"] = buffer.getvalue()
    if "svg" in formats:
        files[f"{stem}.svg"] = to_svg(fig)
    return files, ""
