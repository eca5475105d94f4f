"""A mechanism drawing adds its artists with the axes' autoscaling held off and autoscales once
at the end: the drawing and its limits are those of autoscaling after every artist, as
matplotlib does by itself."""

from __future__ import annotations

import contextlib

import pytest
from test_scheme_labels import _positions

from crankdyn.report import mechanism_drawing as md
from crankdyn.report.figures import add_axes_mm, new_drawing, to_svg


def _drawn(positions) -> tuple[bytes, tuple, tuple]:
    fig = new_drawing(120.0, 90.0)
    ax = add_axes_mm(fig, 5.0, 5.0, 110.0, 80.0)
    md.draw_mechanism(ax, positions, 3)
    limits = (ax.get_xlim(), ax.get_ylim())
    data = tuple(ax.dataLim.bounds)
    return to_svg(fig), limits, data


@pytest.mark.parametrize("example", ["v8-petrol", "planetary-kinematics"])
def test_one_autoscale_draws_what_autoscaling_after_each_artist_draws(example, monkeypatch):
    positions = _positions(example)
    once = _drawn(positions)
    monkeypatch.setattr(md, "_autoscaled_once", lambda ax: contextlib.nullcontext())
    assert _drawn(positions) == once


def test_the_axes_autoscale_as_before_after_a_drawing():
    positions = _positions("petrol-1cyl")
    fig = new_drawing(120.0, 90.0)
    ax = add_axes_mm(fig, 5.0, 5.0, 110.0, 80.0)
    ax.set_autoscalex_on(False)
    md.draw_mechanism(ax, positions, 0)
    assert not ax.get_autoscalex_on() and ax.get_autoscaley_on()
