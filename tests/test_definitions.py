"""One definition per quantity: both definitions reported and named, each checked
against an independent value.

* C_II: the textbook's lambda*C_I and the exact second harmonic A_2*C_I of the inertia force. A_2 is
  computed here from the exact piston acceleration j/(R w^2) = cos a + lam cos 2a / b + lam^3 sin^2 2a / (4 b^3),
  b = sqrt(1 - lam^2 sin^2 a) (differentiate s = R(1 - cos a) + L(1 - b) twice), by the periodic
  trapezoidal rule (exact for a trigonometric polynomial, spectrally accurate here).
* delta: for omega(phi) = w0 (1 + e cos phi) the mid-range speed is w0 and the time mean
  2 pi / closed-integral d(phi)/omega = w0 sqrt(1 - e^2), so delta = 2e and 2e / sqrt(1 - e^2).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import modified

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.physics import irregularity as irr
from crankdyn.plugin.registry import default_registry
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()


def exact_second_harmonic(lam, points=4096):
    a = 2 * np.pi * np.arange(points) / points
    b = np.sqrt(1 - lam**2 * np.sin(a) ** 2)
    j = np.cos(a) + lam * np.cos(2 * a) / b + lam**3 * np.sin(2 * a) ** 2 / (4 * b**3)
    return 2 * np.mean(j * np.cos(2 * a))


def test_second_order_both_definitions():
    result = run_scene(
        scene_from_dict(
            modified("inline4-petrol", {"flywheel": None, "analysis": {"stages": ["balancing"]}}),
            base_dir=examples_dir(),
        ),
        REGISTRY,
    )
    r = result.outputs["balancing"].results
    lam = result.scene.engine.rod_ratio_value
    assert r["second_order_N"] == pytest.approx(lam * r["first_order_N"], rel=1e-14)
    assert r["second_order_exact_N"] == pytest.approx(
        exact_second_harmonic(lam) * r["first_order_N"], rel=1e-13
    )
    assert r["second_order_difference_relative"] == pytest.approx(
        exact_second_harmonic(lam) / lam - 1, rel=1e-10
    )
    # the exact one is what the order table calls P_II
    assert next(o for o in r["orders"] if o["order"] == 2)["amplitude_N"] == pytest.approx(
        r["second_order_exact_N"]
    )


@pytest.mark.parametrize("e", [1e-3, 0.05, 0.3])
def test_irregularity_both_ways_on_a_closed_form_speed(e):
    w0 = 300.0
    phi = 2 * np.pi * np.arange(4096) / 4096
    omega = w0 * (1 + e * np.cos(phi))
    w_max, w_min = w0 * (1 + e), w0 * (1 - e)
    mean = irr.time_mean_speed_rad_s(omega)
    assert mean == pytest.approx(w0 * math.sqrt(1 - e * e), rel=1e-13)
    assert irr.irregularity_midrange(w_max, w_min) == pytest.approx(2 * e, rel=1e-13)
    assert irr.irregularity_time_mean(w_max, w_min, mean) == pytest.approx(
        2 * e / math.sqrt(1 - e * e), rel=1e-12
    )


def test_speed_fluctuation_reports_both_deltas():
    result = run_scene(
        scene_from_dict(
            modified("inline4-petrol", {"analysis": {"stages": ["speed_fluctuation"]}}),
            base_dir=examples_dir(),
        ),
        REGISTRY,
    )
    out = result.outputs["speed_fluctuation"]
    r = out.results
    w_max, w_min, w_mean = r["omega_max_rad_s"], r["omega_min_rad_s"], r["omega_mean_rad_s"]
    assert r["irregularity"] == pytest.approx((w_max - w_min) / (0.5 * (w_max + w_min)), rel=1e-14)
    assert r["irregularity_time_mean"] == pytest.approx((w_max - w_min) / w_mean, rel=1e-14)
    assert w_mean == pytest.approx(
        result.scene.engine.angular_velocity_rad_s, rel=1e-9
    )  # the time mean is the scene's
    assert "speed_fluctuation.note_irregularity" in [key for key, _ in out.notes]
