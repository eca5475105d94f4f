"""The array forms behind the stages' ``run_many`` give, row by row, what the one-curve forms give:
the indicator's rounding junction, the torque's sampled period, the forces' first extremes."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from crankdyn.physics import indicator as ind
from crankdyn.physics import layout as lay
from crankdyn.physics.extrema import first_argmax, first_argmin
from crankdyn_builtin.forces.compute import _first_extremes
from crankdyn_builtin.torque.compute import sampled_periods_deg

AREA_M2 = math.pi * 0.082**2 / 4.0


def _displacement_m(angle_deg, radius_m, ratio):
    alpha = np.radians(angle_deg)
    return radius_m * (1 - np.cos(alpha) + (1 - np.sqrt(1 - (ratio * np.sin(alpha)) ** 2)) / ratio)


def _diagrams():
    """Spark and diesel diagrams of other peak pressures, peak angles, crank radii and rod
    ratios; the last has its exhaust opening 1 deg after the peak: no junction fits before it."""
    spark = ind.CycleParameters(4, "spark", 9.5, 0.085e6, 1.37, 6.5e6, 1.0, 1.25, 0.11e6)
    diesel = ind.CycleParameters(4, "diesel", 17.0, 0.09e6, 1.37, 9.0e6, 1.4, 1.25, 0.11e6)
    rounding = ind.RoundingParameters(
        22.0,
        8.0,
        0.5e6,
        0.85,
        12.0,
        exhaust_opens_before_bdc_deg=50.0,
        exhaust_closes_after_tdc_deg=20.0,
        intake_opens_before_tdc_deg=20.0,
    )
    rows = []
    for k, (params, radius, ratio, peak_deg, p_z) in enumerate(
        [
            (spark, 0.035, 0.27, 12.0, 6.5e6),
            (spark, 0.041, 0.31, 8.0, 4.8e6),
            (diesel, 0.055, 0.25, 15.0, 9.0e6),
            (diesel, 0.050, 0.29, 10.0, 11.5e6),
            (spark, 0.038, 0.28, 12.0, 5.5e6),
        ]
    ):
        params = dataclasses.replace(params, max_pressure_Pa=p_z)
        given = dataclasses.replace(rounding, peak_angle_after_tdc_deg=peak_deg)
        if k == 4:
            given = dataclasses.replace(
                given,
                exhaust_opens_before_bdc_deg=180.0 - peak_deg - 1.0,
                exhaust_closes_after_tdc_deg=0.0,
                intake_opens_before_tdc_deg=0.0,
            )
        clearance = ind.clearance_volume_m3(AREA_M2 * 2 * radius, params.compression_ratio)
        rows.append((params, given, radius, ratio, float(clearance)))
    return rows


def test_the_junctions_of_many_diagrams_are_each_diagrams_own():
    rows = _diagrams()
    radius = np.array([r[2] for r in rows])[:, None]
    ratio = np.array([r[3] for r in rows])[:, None]
    clearance = np.array([r[4] for r in rows])

    def volume_at(angle_deg, which):
        return clearance[which, None] + AREA_M2 * _displacement_m(
            angle_deg, radius[which], ratio[which]
        )

    junctions = ind.combustion_junctions_deg(
        [r[0] for r in rows], [r[1] for r in rows], clearance, volume_at
    )
    angle = np.arange(0.0, 720.0, 1.0)
    for (params, rounding, r, lam, v_c), junction in zip(rows[:-1], junctions[:-1], strict=False):

        def one(a, r=r, lam=lam, v_c=v_c):
            return v_c + AREA_M2 * _displacement_m(a, r, lam)

        volume = one(angle)
        alone = ind.rounded_pressure_Pa(angle, volume, v_c, params, rounding, volume_function=one)
        given = ind.rounded_pressure_Pa(
            angle, volume, v_c, params, rounding, volume_function=one, junction_deg=junction
        )
        np.testing.assert_array_equal(given, alone)
        # J lies after the peak Z' and before the exhaust opening b'
        exhaust_opens = 180.0 - rounding.exhaust_opens_before_bdc_deg
        assert rounding.peak_angle_after_tdc_deg < junction < exhaust_opens
    assert np.isnan(junctions[-1])
    params, rounding, r, lam, v_c = rows[-1]

    def last(a):
        return v_c + AREA_M2 * _displacement_m(a, r, lam)

    with pytest.raises(ValueError) as alone:
        ind.rounded_pressure_Pa(angle, last(angle), v_c, params, rounding, volume_function=last)
    with pytest.raises(ValueError) as given:
        ind.rounded_pressure_Pa(
            angle,
            last(angle),
            v_c,
            params,
            rounding,
            volume_function=last,
            junction_deg=junctions[-1],
        )
    assert str(given.value) == str(alone.value) and "joins the expansion line" in str(alone.value)


def test_the_junctions_refuse_diagrams_of_mixed_strokes():
    rows = _diagrams()[:2]
    two = dataclasses.replace(rows[1][0], strokes=2)
    with pytest.raises(ValueError, match="strokes"):
        ind.combustion_junctions_deg(
            [rows[0][0], two], [r[1] for r in rows], [1e-5, 1e-5], lambda a, which: 1e-5 + 0 * a
        )


def test_the_periods_of_many_curves_are_each_curves_own():
    angle = np.radians(np.arange(0.0, 720.0, 1.0))
    curves = np.stack(
        [
            np.sin(angle / 2) + 0.3 * np.sin(angle),  # the whole cycle
            np.sin(2 * angle),  # 180 deg
            np.cos(3 * angle) ** 2,  # 60 deg
            np.full(angle.size, 4.0),  # constant: one step
            np.sin(4.5 * angle) + 1e-12 * np.sin(angle / 2),
        ]
    )  # 80 deg within rtol
    periods = sampled_periods_deg(curves, 720.0)
    assert periods.tolist() == [lay.sampled_period_deg(c, 1.0, 720.0) for c in curves]
    assert periods.tolist() == [720.0, 180.0, 60.0, 1.0, 80.0]


def test_the_first_extremes_of_many_curves_are_each_curves_own():
    angle = np.radians(np.arange(0.0, 720.0, 1.0))
    curves = np.stack(
        [
            np.cos(2 * angle),  # ties: four equal maxima and minima (to rounding)
            np.sin(angle / 2) * 3e6,
            -np.abs(np.sin(angle)),
            np.full(angle.size, 2.0),
        ]
    )
    at_max, at_min = _first_extremes(curves)
    assert at_max.tolist() == [first_argmax(c) for c in curves]
    assert at_min.tolist() == [first_argmin(c) for c in curves]
    assert at_max[0] == 0 and at_min[0] == 90  # the first of the tied peaks
    with_nan = curves.copy()
    with_nan[1, 180] = np.nan  # the maximum's own sample missing: the next one counts
    at_max, at_min = _first_extremes(with_nan)
    assert at_max.tolist() == [first_argmax(c) for c in with_nan]
    assert at_min.tolist() == [first_argmin(c) for c in with_nan]
