"""Tests of the example plugin: its physics against independent values, and the plugin in crankdyn.

Run from this folder after installing the package: python -m pytest -q tests
"""

from __future__ import annotations

import numpy as np
import pytest
from crankdyn_scotch_yoke import physics, plugin

from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.registry import collect, plugin_manager
from crankdyn.scene import scene_from_dict

SCENE = {
    "engine": {
        "mechanism": "scotch_yoke",
        "strokes": 2,
        "rpm": 1500,
        "bore": "60 mm",
        "stroke": "80 mm",
    },
}


def test_velocity_and_acceleration_are_derivatives_of_the_displacement():
    alpha = np.linspace(0.0, 2.0 * np.pi, 721)
    h, radius, omega = 1e-5, 0.04, 157.0
    ds = (
        physics.piston_displacement_m(alpha + h, radius)
        - physics.piston_displacement_m(alpha - h, radius)
    ) / (2 * h)
    np.testing.assert_allclose(
        ds * omega, physics.piston_velocity_m_s(alpha, radius, omega), atol=1e-8
    )
    dv = physics.piston_velocity_m_s(alpha + h, radius, omega) - physics.piston_velocity_m_s(
        alpha - h, radius, omega
    )
    np.testing.assert_allclose(
        dv / (2 * h) * omega,
        physics.piston_acceleration_m_s2(alpha, radius, omega),
        rtol=1e-7,
        atol=1e-4,
    )


def test_the_plugin_runs_in_crankdyn():
    # The built-ins come through their entry points; so does this plugin once the package is
    # installed. Register the module by hand only when the entry point did not (e.g. a source checkout).
    manager = plugin_manager()
    if not manager.is_registered(plugin):
        manager.register(plugin)
    registry = collect(manager)
    result = run_scene(scene_from_dict(SCENE), registry)
    assert "scotch_yoke" in result.stages_run
    r = result.outputs["scotch_yoke"].results
    assert r["v_max_m_s"] == pytest.approx(0.04 * 1500 * np.pi / 30)
