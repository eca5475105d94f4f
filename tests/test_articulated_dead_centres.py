"""True dead centres of articulated (slave) rods, the actual firing intervals and the torque period.

Independent reference, written here: the slave-rod linkage solved directly in Cartesian coordinates. Master
axis along x, crank pin B = R (cos a, sin a), master rod angle b with sin b = lambda sin a, the slave pin
C = B + r (cos(g1 - b), sin(g1 - b)), slave axis u = (cos g, sin g). The slave piston pin S = s u with
|S - C| = l, the larger root of s^2 - 2 s (C.u) + |C|^2 - l^2 = 0. Its TDC (largest s) is the root of
ds/da, taken by a central difference and Brent's method; the shift is a_TDC - g.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import modified
from scipy import optimize

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.registry import default_registry
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()


def slave_travel(a, R, L, r, g1, g, l):
    b = math.asin(R / L * math.sin(a))
    cx, cy = R * math.cos(a) + r * math.cos(g1 - b), R * math.sin(a) + r * math.sin(g1 - b)
    p = cx * math.cos(g) + cy * math.sin(g)
    return p + math.sqrt(p * p - (cx * cx + cy * cy) + l * l)


def dead_centre(R, L, r, g1, g, l, guess, h=1e-4):
    def slope(a):
        return (slave_travel(a + h, R, L, r, g1, g, l) - slave_travel(a - h, R, L, r, g1, g, l)) / (
            2 * h
        )

    return optimize.brentq(slope, guess - 0.3, guess + 0.3, xtol=1e-14)


@pytest.fixture(scope="module")
def radial():
    data = modified("radial9-aircraft", {"analysis": {"stages": ["torque"]}})
    return run_scene(scene_from_dict(data, base_dir=examples_dir()), REGISTRY)


def test_dead_centre_shifts_against_a_direct_solve(radial):
    e = radial.scene.engine
    bays = radial.outputs["bays"].results
    R, L, r = e.crank_radius_m, e.rod_length_m, bays["pin_radius_m"]
    shifts = []
    for s in bays["slaves"]:
        g, g1, l = (
            math.radians(s["bank_angle_deg"]),
            math.radians(s["pin_angle_deg"]),
            s["slave_rod_length_m"],
        )
        tdc = dead_centre(R, L, r, g1, g, l, g)
        bdc = dead_centre(R, L, r, g1, g, l, g + math.pi)
        assert abs(s["tdc_shift_deg"] - math.degrees(tdc - g)) < 1e-7, s["cylinder"]
        assert abs(s["bdc_shift_deg"] - math.degrees(bdc - g - math.pi)) < 1e-7, s["cylinder"]
        shifts.append(abs(s["tdc_shift_deg"]))
    assert 3.5 < max(shifts) < 4.5  # measured on this engine: up to 3.9 deg


def test_actual_firing_intervals_and_torque_period(radial):
    bays = radial.outputs["bays"].results
    intervals = bays["firing_intervals_deg"]
    assert sum(intervals) == pytest.approx(720.0, abs=1e-9)
    assert bays["firing_intervals_nominal_deg"] == [80.0] * 9
    assert max(abs(x - 80.0) for x in intervals) > 1.0  # uneven at the true dead centres
    true = bays["firing_angles_true_deg"]
    order = bays["firing_order"]
    for k, label in enumerate(
        order
    ):  # each interval is the gap between consecutive true firing angles
        gap = (true[order[(k + 1) % 9]] - true[label]) % 720.0
        assert intervals[k] == pytest.approx(gap, abs=1e-9)
    assert radial.outputs["torque"].results["period_deg"] == 720.0
    assert "bays.note_true_intervals" in [key for key, _ in radial.outputs["bays"].notes]


@pytest.mark.parametrize(
    "example, period", [("inline4-petrol", 180.0), ("v8-petrol", 90.0), ("petrol-1cyl", 720.0)]
)
def test_torque_period_of_even_engines(example, period):
    data = modified(example, {"flywheel": None, "analysis": {"stages": ["torque"]}})
    result = run_scene(scene_from_dict(data, base_dir=examples_dir()), REGISTRY)
    torque = result.outputs["torque"]
    assert torque.results["period_deg"] == period
    values = (
        torque.tables["torque"]["output_torque_Nm"].to_numpy()
        if "torque" in torque.tables
        else None
    )
    if values is not None:  # the torque repeats after the period (and not after half of it)
        shift = round(period / result.scene.analysis.angle_step_deg)
        assert np.max(np.abs(np.roll(values, shift) - values)) < 1e-9 * np.ptp(values)
        if period < 720:
            assert np.max(np.abs(np.roll(values, shift // 2) - values)) > 1e-3 * np.ptp(values)
