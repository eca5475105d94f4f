"""Tick labels of a bearing's polar load diagram stay apart on a tall, narrow diagram."""

from __future__ import annotations

import numpy as np

from crankdyn.report.figures import prepare
from crankdyn.report.i18n import translator
from crankdyn_builtin.bearings.figures import _polar_drawing


def _label_boxes(fig, axis):
    renderer = fig.canvas.get_renderer()
    return [
        label.get_window_extent(renderer)
        for label in axis.get_ticklabels()
        if label.get_visible() and label.get_text()
    ]


def test_a_narrow_diagram_prints_its_horizontal_tick_labels_apart():
    """A main bearing loaded along one axis (±0,25 × ±3,3 MPa, as a boxer twin's) is drawn tall
    and narrow: its horizontal labels "−0,25", "0,00", "0,25" used to run into one another; they
    stand apart, turned a quarter where upright ones would not fit."""
    prepare()
    angle = np.arange(0.0, 720.0, 0.5)
    phi = np.radians(angle)
    t = 0.25e6 * np.sin(phi)
    z = 3.3e6 * np.cos(phi / 2)
    fig = _polar_drawing(translator("ru"), t, z, angle, 0.0, "", 0.0, 0.12, 30.0, ("x", "y"))
    fig.canvas.draw()
    axes = fig.axes[0]
    boxes = sorted(_label_boxes(fig, axes.xaxis), key=lambda box: box.x0)
    assert len(boxes) >= 2, "the horizontal axis keeps a readable scale: two labels at least"
    for left, right in zip(boxes, boxes[1:], strict=False):
        assert left.x1 < right.x0, (left, right)
    # the tall axis keeps its labels as before: one per MPa
    assert len(_label_boxes(fig, axes.yaxis)) >= 5
