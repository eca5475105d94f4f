"""The main journals' running torques are drawn as the textbook's specific tangential forces t_k
(MPa) with the torques they are, t_k·F_p·R in N·m, on a second axis: the tables and the
conclusions give them in N·m."""

from __future__ import annotations

import io
import math

import pytest
from conftest import shared_run

from crankdyn.report.i18n import translator
from crankdyn_builtin.torque.figures import _journals_figure


def test_the_journal_torque_figure_reads_in_newton_metres_too():
    run = shared_run("inline4-petrol", None, ("torque",))
    f = run.outputs["torque"].tables["torque"]
    engine = run.scene.engine
    factor = math.pi * engine.bore**2 / 4 * engine.crank_radius_m
    assert run.outputs["torque"].results["torque_per_specific_force_m3"] == pytest.approx(factor)
    fig = _journals_figure(f, 4, 720.0, translator("en"), factor)
    fig.savefig(io.BytesIO(), format="svg")  # the secondary axis takes its limits when drawn
    (main,) = [a for a in fig.axes if a.get_ylabel().startswith("t_k")]
    (right,) = [a for a in main.child_axes if a.get_ylabel().startswith("t_k·F_p·R")]
    assert (
        right.get_ylabel() == "t_k·F_p·R, N·m"
    )  # the same quantity scaled, not M_k (a cylinder's)
    # 1 MPa of t_k on the left is F_p·R·1e6 N·m on the right
    low, high = main.get_ylim()
    assert right.get_ylim() == pytest.approx((low * factor * 1e6, high * factor * 1e6))
