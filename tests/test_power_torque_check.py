"""The torque check by the textbook's eq. (47): M_i = 9555 N_i/n. The exact constant is 30000/π
(M = N/ω), so the torque from the power differs from the torque from the work, W/(2π·revolutions),
by exactly 9555/(30000/π) − 1: the only deviation when the torque is right, as the report says."""

from __future__ import annotations

import math

import pytest

from crankdyn.physics import crankshaft as cs


def test_indicated_power_of_a_four_stroke_four_cylinder():
    # 340 J per cylinder and cycle, 4 cylinders, a cycle every 2 revolutions at 6000 rpm: 50 cycles/s
    assert cs.indicated_power_kW(340.0, 4, 4, 6000.0) == pytest.approx(340.0 * 4 * 50 / 1000)


@pytest.mark.parametrize(("work_J", "cylinders", "strokes", "rpm"), [(340.0, 1, 4, 5600.0), (1200.0, 6, 2, 1600.0)])
def test_power_torque_differs_from_the_work_torque_only_by_the_rounded_constant(work_J, cylinders, strokes, rpm):
    from_work = work_J * cylinders / (2 * math.pi * strokes / 2)
    from_power = cs.torque_from_power_Nm(work_J, cylinders, strokes, rpm)
    assert from_power / from_work == pytest.approx(9555.0 / (30000.0 / math.pi), rel=1e-12)
