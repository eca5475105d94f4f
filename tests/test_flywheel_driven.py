"""A driven machine's (a compressor's) excess work is a share of the work it takes in per cycle."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from crankdyn.physics import flywheel as fw
from crankdyn_builtin.flywheel.compute import _excess_results


def _torque(mean_Nm: float):
    angle_deg = np.arange(0.0, 720.0, 0.5)
    torque = mean_Nm + 40.0 * np.sin(np.radians(angle_deg))
    return SimpleNamespace(crank_angle_deg=angle_deg, torque_Nm=torque, strokes=4)


@pytest.mark.parametrize("mean_Nm", [11.31, -11.31])
def test_excess_work_share_is_of_the_work_done_or_taken_in(mean_Nm):
    """M = M_m + 40 sin α over 720°: W = 40 (1 − cos α) swings by ΔL = 80 J, and the work per
    cycle is |M_m|·4π, so ΔL is 80 / (11.31·4π) = 56.3 % of it, whether the shaft gives that work
    (an engine) or takes it in (a compressor, M_m < 0: printed as 0 % before)."""
    torque = _torque(mean_Nm)
    excess = fw.excess_work(np.radians(torque.crank_angle_deg), torque.torque_Nm)
    r = _excess_results(excess, torque)
    assert r["excess_work_J"] == pytest.approx(80.0, rel=1e-4)
    assert r["excess_work_relative"] == pytest.approx(80.0 / (11.31 * 4 * math.pi), rel=1e-4)
