"""The three steps of the rounded indicator diagram, each a function of its own:
their values at the construction's nodes against the values the construction prescribes."""

import dataclasses

import numpy as np
import pytest
from test_physics_indicator import (
    CRANK_RADIUS_M,
    PISTON_AREA_M2,
    diesel,
    exact_displacement_m,
    rounding_for,
    spark,
)

from crankdyn.physics import indicator as ind


def _setup():
    params = spark(4)
    rounding = rounding_for(params)
    clearance = PISTON_AREA_M2 * 2 * CRANK_RADIUS_M / (params.compression_ratio - 1)

    def volume(a_deg):
        return clearance + PISTON_AREA_M2 * exact_displacement_m(np.asarray(a_deg))

    lines = ind._Lines(
        ind._function_volume(volume, 720.0), ind._firing_tdc_deg(params), clearance, params
    )
    return params, rounding, lines, volume, clearance


def test_gas_exchange_step_is_halfway_at_the_exhaust_tdc():
    """Smoothstep from p_r to p_a between 700 and 20 deg: (p_r + p_a)/2 at 0 deg, the ends unchanged."""
    params, rounding, _, _, _ = _setup()
    alpha = np.array([0.0, 699.0, 21.0])
    before = np.full(3, -1.0)
    p = ind._gas_exchange_step(alpha, before, params, rounding, ind._firing_tdc_deg(params), 720.0)
    assert p[0] == pytest.approx(
        0.5 * (params.exhaust_pressure_Pa + params.intake_pressure_Pa), rel=1e-15
    )
    assert p[1] == -1.0 and p[2] == -1.0  # outside the window the diagram is left as it was


def test_exhaust_drop_passes_the_mean_of_expansion_end_and_exhaust_pressure_at_bdc():
    params, rounding, lines, _, _ = _setup()
    tdc = ind._firing_tdc_deg(params)
    alpha = np.array([tdc + 180.0, tdc + 100.0])
    p = ind._exhaust_drop(alpha, np.zeros(2), lines, rounding, 720.0, psi_j=30.0)
    expected = 0.5 * (ind.expansion_end_pressure_Pa(params) + params.exhaust_pressure_Pa)
    assert p[0] == pytest.approx(expected, rel=1e-12) and p[1] == 0.0


def test_combustion_rounding_peaks_at_the_prescribed_fraction_of_p_z():
    """Z' at peak_angle_after_tdc_deg has p = fraction x p_z, and it is the curve's maximum."""
    params, rounding, lines, _, _ = _setup()
    tdc = ind._firing_tdc_deg(params)
    alpha = tdc + np.linspace(-10.0, 60.0, 7001)
    p, psi_j = ind._combustion_rounding(alpha, np.zeros_like(alpha), lines, rounding, 720.0)
    peak = rounding.peak_pressure_fraction * params.max_pressure_Pa
    at_peak = np.argmin(np.abs(alpha - (tdc + rounding.peak_angle_after_tdc_deg)))
    assert p[at_peak] == pytest.approx(peak, rel=1e-12)
    assert (
        p.max() == pytest.approx(peak, rel=1e-12)
        and rounding.peak_angle_after_tdc_deg < psi_j < 180.0
    )


def _high_compression():
    """The spark engine at ε = 12: its expansion line 12° after TDC lies below 0.85·p_z."""
    params = dataclasses.replace(spark(4), compression_ratio=12.0)
    rounding = rounding_for(params)
    clearance = PISTON_AREA_M2 * 2 * CRANK_RADIUS_M / (params.compression_ratio - 1)

    def volume(a_deg):
        return clearance + PISTON_AREA_M2 * exact_displacement_m(np.asarray(a_deg))

    # the theoretical pressure at Z′ from the polytrope p_z (V_c/V)^n₂, V by the exact kinematics
    at_peak = params.max_pressure_Pa * (clearance / volume(12.0)) ** params.expansion_index
    return params, rounding, clearance, volume, float(at_peak)


def test_a_peak_above_the_theoretical_diagram_is_lowered_inside_it():
    """p_z′ = 0.97 of the theoretical pressure at Z′; from TDC to the exhaust opening the rounded
    diagram nowhere exceeds the theoretical one, and it is smooth at the junction J."""
    params, rounding, clearance, volume, at_peak = _high_compression()
    assert rounding.peak_pressure_fraction * params.max_pressure_Pa > at_peak  # the case tested
    alpha = np.arange(0.0, 720.0, 0.05)
    v = volume(alpha)
    peak = ind.peak_pressure_Pa(alpha, v, clearance, params, rounding, volume_function=volume)
    assert peak == pytest.approx(0.97 * at_peak, rel=1e-9)
    p = ind.rounded_pressure_Pa(alpha, v, clearance, params, rounding, volume_function=volume)
    theoretical = ind.theoretical_pressure_Pa(alpha, v, clearance, params)
    tdc = ind._firing_tdc_deg(params)
    after = (alpha >= tdc) & (alpha <= tdc + 130.0)
    assert np.all(p[after] <= theoretical[after] * (1 + 1e-12))
    assert p[after].max() == pytest.approx(peak, rel=1e-6)
    slope = np.diff(p[after]) / 0.05
    # no corner: the slope changes by under 5 % of its largest value from one 0.05° step to the
    # next (a peak on the expansion line would drop from zero slope to the line's at once)
    assert np.max(np.abs(np.diff(slope))) < 0.05 * np.max(np.abs(slope))


@pytest.mark.parametrize("rho", [1.1, 1.4, 1.8])
def test_a_diesels_peak_two_thirds_along_its_isobar_keeps_the_diagram_inside(rho):
    """Poda 2007 §3.1: a diesel's Z′ about 2/3 along the isobar z′z, at V_c(1 + ⅔(ρ − 1)); the
    angle there, independently, by bisecting the exact crank-slider travel. At p_z′ = p_z the
    rounded diagram peaks there and nowhere exceeds the theoretical one from TDC to the exhaust's
    opening, with no corner."""
    from scipy.optimize import brentq

    params = dataclasses.replace(diesel(4), pre_expansion_ratio=rho)
    clearance = PISTON_AREA_M2 * 2 * CRANK_RADIUS_M / (params.compression_ratio - 1)

    def volume(a_deg):
        return clearance + PISTON_AREA_M2 * exact_displacement_m(np.asarray(a_deg))

    target = clearance * (1.0 + 2.0 / 3.0 * (rho - 1.0))
    expected = brentq(lambda psi: float(volume(360.0 + psi)) - target, 1e-9, 90.0, xtol=1e-12)
    alpha = np.arange(0.0, 720.0, 0.05)
    v = volume(alpha)
    angle = ind.isobar_peak_angle_deg(alpha, v, clearance, params, volume_function=volume)
    assert angle == pytest.approx(expected, abs=1e-8)
    rounding = dataclasses.replace(
        rounding_for(params), peak_pressure_fraction=1.0, peak_angle_after_tdc_deg=angle
    )
    peak = ind.peak_pressure_Pa(alpha, v, clearance, params, rounding, volume_function=volume)
    assert peak == params.max_pressure_Pa  # on the isobar: p_z itself, nothing lowered
    p = ind.rounded_pressure_Pa(alpha, v, clearance, params, rounding, volume_function=volume)
    theoretical = ind.theoretical_pressure_Pa(alpha, v, clearance, params)
    after = (alpha >= 360.0) & (alpha <= 490.0)
    assert np.all(p[after] <= theoretical[after] * (1 + 1e-12))
    assert p[after].max() == pytest.approx(params.max_pressure_Pa, rel=1e-6)
    slope = np.diff(p[after]) / 0.05
    assert np.max(np.abs(np.diff(slope))) < 0.05 * np.max(np.abs(slope))
    # without an isobar there is no such point
    assert (
        ind.isobar_peak_angle_deg(
            alpha, v, clearance, dataclasses.replace(params, pre_expansion_ratio=1.0)
        )
        is None
    )


@pytest.mark.parametrize("advance_deg, delay_deg", [(30.0, 3.3), (22.0, 2.4), (40.0, 14.0)])
def test_burning_from_c_prime_stays_above_the_compression_line(advance_deg, delay_deg):
    """Once visible combustion starts at C' the pressure cannot lag behind the compression
    polytrope: the curve C'-C'' was one cubic from C' (the line's value and slope) to p_c + rise
    at TDC and sagged below the line (by 4 % at 30° advance); it lies on or above it now, joins
    it with value and slope at C', rises monotonically, and reaches p_c + rise at TDC."""
    params, rounding, lines, _, _ = _setup()
    rounding = dataclasses.replace(
        rounding, ignition_advance_deg=advance_deg, combustion_delay_deg=delay_deg
    )
    tdc = ind._firing_tdc_deg(params)
    psi_c1 = -(advance_deg - delay_deg)
    psi = np.linspace(psi_c1, 0.0, 4001)
    p, _ = ind._combustion_rounding(tdc + psi, np.zeros_like(psi), lines, rounding, 720.0)
    # the compression polytrope p_a (V_a / V)^n1 itself, independently of the lines' code
    volume = lines.volume_at(tdc + psi)[0]
    ratio = params.compression_ratio
    compression = params.intake_pressure_Pa * (ratio * lines.clearance_volume_m3 / volume) ** (
        params.compression_index
    )
    assert np.all(p >= compression * (1 - 1e-12))
    assert p[0] == pytest.approx(compression[0], rel=1e-12)
    assert np.all(np.diff(p) >= 0)
    assert p[-1] == pytest.approx(
        ind.compression_end_pressure_Pa(params) + rounding.pressure_rise_to_tdc_Pa, rel=1e-12
    )
