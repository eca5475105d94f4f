"""Tests for crankdyn.physics.indicator (theoretical and rounded indicator diagrams)."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from crankdyn.physics.indicator import (
    CycleParameters,
    RoundingParameters,
    clearance_volume_m3,
    compression_end_pressure_Pa,
    crank_angle_from_volume_approx_deg,
    crank_angle_from_volume_exact_deg,
    cylinder_volume_m3,
    default_combustion_delay_deg,
    expansion_end_pressure_Pa,
    indicated_work_J,
    mean_indicated_pressure_Pa,
    pressure_ratio,
    pumping_work_J,
    rounded_pressure_Pa,
    theoretical_mean_indicated_pressure_Pa,
    theoretical_pressure_Pa,
)

# Engine geometry used throughout: D = 83 mm, S = 92 mm, lambda = 0.3
BORE_M = 0.083
CRANK_RADIUS_M = 0.046
ROD_RATIO = 0.3
ROD_LENGTH_M = CRANK_RADIUS_M / ROD_RATIO
PISTON_AREA_M2 = math.pi * BORE_M**2 / 4.0
SWEPT_VOLUME_M3 = PISTON_AREA_M2 * 2.0 * CRANK_RADIUS_M


def exact_displacement_m(angle_deg, radius=CRANK_RADIUS_M, lam=ROD_RATIO):
    """s = R(1 - cos a) + L(1 - sqrt(1 - lam^2 sin^2 a)), computed independently.

    Written without cancellation (1 - cos a = 2 sin^2(a/2),
    1 - sqrt(1 - x) = x / (1 + sqrt(1 - x))) so that tiny angles keep full precision.
    """
    a = np.radians(angle_deg)
    rod = radius / lam
    x = lam**2 * np.sin(a) ** 2
    return radius * 2.0 * np.sin(0.5 * a) ** 2 + rod * x / (1.0 + np.sqrt(1.0 - x))


def two_term_displacement_m(angle_deg, radius=CRANK_RADIUS_M, lam=ROD_RATIO):
    """Poda eq. (9), s = R[(1 + lam/4) - (cos a + lam/4 cos 2a)], without cancellation."""
    a = np.radians(angle_deg)
    return radius * (2.0 * np.sin(0.5 * a) ** 2 + 0.5 * lam * np.sin(a) ** 2)


def test_displacement_helpers_match_the_textbook_forms():
    a = np.linspace(0.0, 180.0, 37)
    r, lam = CRANK_RADIUS_M, ROD_RATIO
    ar = np.radians(a)
    plain = r * (1 - np.cos(ar)) + r / lam * (1 - np.sqrt(1 - lam**2 * np.sin(ar) ** 2))
    eq9 = r * ((1 + lam / 4) - (np.cos(ar) + lam / 4 * np.cos(2 * ar)))
    np.testing.assert_allclose(exact_displacement_m(a), plain, rtol=0, atol=1e-15)
    np.testing.assert_allclose(two_term_displacement_m(a), eq9, rtol=0, atol=1e-15)


def volume_of(angle_deg, clearance):
    return clearance + PISTON_AREA_M2 * exact_displacement_m(angle_deg)


def spark(strokes=4):
    return CycleParameters(
        strokes=strokes,
        ignition="spark",
        compression_ratio=9.5,
        intake_pressure_Pa=0.085e6,
        compression_index=1.37,
        max_pressure_Pa=6.5e6,
        pre_expansion_ratio=1.0,
        expansion_index=1.25,
        exhaust_pressure_Pa=0.11e6,
    )


def diesel(strokes=4):
    return CycleParameters(
        strokes=strokes,
        ignition="diesel",
        compression_ratio=17.0,
        intake_pressure_Pa=0.09e6,
        compression_index=1.37,
        max_pressure_Pa=9.0e6,
        pre_expansion_ratio=1.4,
        expansion_index=1.25,
        exhaust_pressure_Pa=0.11e6,
    )


def rounding_for(params, rpm=2000.0):
    advance = 22.0 if params.ignition == "spark" else 20.0
    delay = default_combustion_delay_deg(params.ignition, advance, rpm)
    if params.strokes == 4:
        return RoundingParameters(
            advance,
            delay,
            0.5e6,
            0.85,
            12.0,
            exhaust_opens_before_bdc_deg=50.0,
            exhaust_closes_after_tdc_deg=20.0,
            intake_opens_before_tdc_deg=20.0,
            intake_closes_after_bdc_deg=60.0,
        )
    return RoundingParameters(advance, delay, 0.5e6, 0.85, 12.0, exhaust_opens_before_bdc_deg=30.0)


def cycle_of(params):
    return 720.0 if params.strokes == 4 else 360.0


def fine_grid(params, step_per_deg=100):
    n = int(cycle_of(params)) * step_per_deg
    return np.arange(n) / step_per_deg


PARAM_SETS = [spark, diesel]
PARAM_IDS = ["spark", "diesel"]


# ---------------------------------------------------------------------------
# Volumes and cycle parameters
# ---------------------------------------------------------------------------
def test_clearance_volume_eq14():
    assert clearance_volume_m3(0.5e-3, 11.0) == pytest.approx(0.05e-3, rel=1e-15)
    with pytest.raises(ValueError, match="compression_ratio"):
        clearance_volume_m3(0.5e-3, 1.0)
    with pytest.raises(ValueError, match="swept_volume_m3"):
        clearance_volume_m3(-1.0, 10.0)


def test_cylinder_volume():
    v = cylinder_volume_m3(np.array([0.0, 0.092]), PISTON_AREA_M2, 3e-5)
    assert v[0] == 3e-5
    assert v[1] == pytest.approx(3e-5 + SWEPT_VOLUME_M3, rel=1e-14)
    with pytest.raises(ValueError, match="piston_displacement_m"):
        cylinder_volume_m3(-0.01, PISTON_AREA_M2, 3e-5)


def test_derived_pressures():
    p = diesel()
    p_c = 0.09e6 * 17.0**1.37
    assert compression_end_pressure_Pa(p) == pytest.approx(p_c, rel=1e-14)
    assert expansion_end_pressure_Pa(p) == pytest.approx(9e6 * (1.4 / 17.0) ** 1.25, rel=1e-14)
    assert pressure_ratio(p) == pytest.approx(9e6 / p_c, rel=1e-14)
    # spark: p_b = p_z / eps^n2
    assert expansion_end_pressure_Pa(spark()) == pytest.approx(6.5e6 / 9.5**1.25, rel=1e-14)


@pytest.mark.parametrize(
    "changes, name",
    [
        (dict(strokes=3), "strokes"),
        (dict(ignition="hcci"), "ignition"),
        (dict(compression_ratio=1.0), "compression_ratio"),
        (dict(pre_expansion_ratio=1.2), "pre_expansion_ratio"),
        (dict(max_pressure_Pa=1.0e6), "max_pressure_Pa"),
        (dict(compression_index=1.0), "compression_index"),
        (dict(exhaust_pressure_Pa=None), "exhaust_pressure_Pa"),
    ],
)
def test_cycle_parameters_validation(changes, name):
    fields = dict(
        strokes=4,
        ignition="spark",
        compression_ratio=9.5,
        intake_pressure_Pa=0.085e6,
        compression_index=1.37,
        max_pressure_Pa=6.5e6,
        pre_expansion_ratio=1.0,
        expansion_index=1.25,
        exhaust_pressure_Pa=0.11e6,
    )
    fields.update(changes)
    with pytest.raises(ValueError, match=name):
        CycleParameters(**fields)


def test_two_stroke_needs_no_exhaust_pressure():
    p = CycleParameters(2, "diesel", 16.0, 0.15e6, 1.36, 10e6, 1.3, 1.25)
    assert p.exhaust_pressure_Pa is None


# ---------------------------------------------------------------------------
# Theoretical diagram
# ---------------------------------------------------------------------------
def test_closed_form_by_hand_derivation():
    """Re-derive p_i' by direct integration of the three processes (independent of the module)."""
    p = diesel()
    eps, rho, n1, n2 = 17.0, 1.4, 1.37, 1.25
    v_c = 1.0
    v_h = (eps - 1.0) * v_c
    p_c = 0.09e6 * eps**n1
    w_isobar = 9e6 * (rho - 1.0) * v_c
    w_exp = quad(
        lambda v: 9e6 * (rho * v_c / v) ** n2, rho * v_c, eps * v_c, epsabs=0, epsrel=1e-13
    )[0]
    w_comp = quad(lambda v: p_c * (v_c / v) ** n1, v_c, eps * v_c, epsabs=0, epsrel=1e-13)[0]
    expected = (w_isobar + w_exp - w_comp) / v_h
    assert theoretical_mean_indicated_pressure_Pa(p) == pytest.approx(expected, rel=1e-11)


@pytest.mark.parametrize("make", PARAM_SETS, ids=PARAM_IDS)
@pytest.mark.parametrize("strokes", [4, 2])
def test_numeric_work_matches_closed_form(make, strokes):
    params = make(strokes)
    v_c = clearance_volume_m3(SWEPT_VOLUME_M3, params.compression_ratio)
    alpha = fine_grid(params, step_per_deg=20)
    volume = volume_of(alpha, v_c)
    pressure = theoretical_pressure_Pa(alpha, volume, v_c, params)
    work = indicated_work_J(pressure, volume)
    closed = theoretical_mean_indicated_pressure_Pa(params) * SWEPT_VOLUME_M3
    if strokes == 4:
        # intake line at p_a (+p_a V_h) and exhaust line at p_r (-p_r V_h)
        closed += (params.intake_pressure_Pa - params.exhaust_pressure_Pa) * SWEPT_VOLUME_M3
    assert work == pytest.approx(closed, rel=1e-4)
    # the pumping loop matters at this tolerance, so the test can fail
    if strokes == 4:
        pumping = abs(params.intake_pressure_Pa - params.exhaust_pressure_Pa) * SWEPT_VOLUME_M3
        assert pumping / abs(closed) > 1e-3


@pytest.mark.parametrize("make", PARAM_SETS, ids=PARAM_IDS)
@pytest.mark.parametrize("step_deg", [0.05, 720.0 / 1001])
def test_pumping_work_of_the_theoretical_diagram_is_its_closed_form(make, step_deg):
    """The pumping strokes of the theoretical four-stroke diagram: intake at p_a, exhaust at p_r,
    so W_pump = (p_a − p_r) V_h, and W_i − W_pump is the closed form p_i′ V_h of the compression
    and expansion strokes (eq. 4.4), which the thermal calculation's p_i stands for. A step of
    720/1001° puts the strokes' ends (180°, 540°) between samples: interpolated, not skipped."""
    params = make(4)
    v_c = clearance_volume_m3(SWEPT_VOLUME_M3, params.compression_ratio)
    alpha = np.arange(round(720.0 / step_deg)) * step_deg
    volume = volume_of(alpha, v_c)
    pressure = theoretical_pressure_Pa(alpha, volume, v_c, params)
    pumping = pumping_work_J(pressure, volume, alpha, 4)
    closed = (params.intake_pressure_Pa - params.exhaust_pressure_Pa) * SWEPT_VOLUME_M3
    assert pumping == pytest.approx(closed, rel=1e-3 if step_deg > 0.5 else 1e-6)
    gross = indicated_work_J(pressure, volume) - pumping
    rel = 5e-3 if step_deg > 0.5 else 1e-4
    assert gross == pytest.approx(
        theoretical_mean_indicated_pressure_Pa(params) * SWEPT_VOLUME_M3, rel=rel
    )


def test_a_two_stroke_cycle_has_no_pumping_strokes_and_a_bad_grid_is_refused():
    alpha = np.arange(0.0, 360.0, 1.0)
    assert pumping_work_J(np.ones_like(alpha), np.ones_like(alpha), alpha, 2) == 0.0
    with pytest.raises(ValueError, match="crank_angle_deg"):
        pumping_work_J(
            np.ones_like(alpha), np.ones_like(alpha), alpha, 4
        )  # a 360° grid for a four-stroke


@pytest.mark.parametrize("make", PARAM_SETS, ids=PARAM_IDS)
def test_four_stroke_values_at_corners(make):
    params = make(4)
    v_c = clearance_volume_m3(SWEPT_VOLUME_M3, params.compression_ratio)
    eps = 1e-7
    alpha = np.array(
        [
            0.0,
            90.0,
            180.0,
            180.0 + eps,
            360.0 - eps,
            360.0,
            360.0 + eps,
            540.0 - eps,
            540.0,
            540.0 + eps,
            719.0,
        ]
    )
    p = theoretical_pressure_Pa(alpha, volume_of(alpha, v_c), v_c, params)
    p_a, p_r, p_z = params.intake_pressure_Pa, params.exhaust_pressure_Pa, params.max_pressure_Pa
    p_c = compression_end_pressure_Pa(params)
    p_b = expansion_end_pressure_Pa(params)
    assert p[0] == p_a and p[1] == p_a
    assert p[2] == pytest.approx(p_a, rel=1e-12)
    assert p[3] == pytest.approx(p_a, rel=1e-9)  # compression starts at p_a
    assert p[4] == pytest.approx(p_c, rel=1e-9)  # compression ends at p_c
    assert p[5] == p_z and p[6] == pytest.approx(p_z, rel=1e-9)
    assert p[7] == pytest.approx(p_b, rel=1e-9)
    assert p[8] == pytest.approx(p_b, rel=1e-12)
    assert p[9] == p_r and p[10] == p_r


def test_diesel_isobar_ends_at_rho_vc():
    params = diesel(4)
    v_c = clearance_volume_m3(SWEPT_VOLUME_M3, params.compression_ratio)
    # angle where V = rho V_c, from the exact inversion
    a_z = crank_angle_from_volume_exact_deg(1.4 * v_c, v_c, BORE_M, CRANK_RADIUS_M, ROD_RATIO)
    alpha = 360.0 + np.array([0.5 * a_z, a_z - 1e-7, a_z + 1e-7, a_z + 5.0])
    p = theoretical_pressure_Pa(alpha, volume_of(alpha, v_c), v_c, params)
    assert p[0] == params.max_pressure_Pa
    assert p[1] == pytest.approx(9e6, rel=1e-8)
    assert p[2] == pytest.approx(9e6, rel=1e-8)
    v3 = volume_of(alpha[3], v_c)
    assert p[3] == pytest.approx(9e6 * (1.4 * v_c / v3) ** 1.25, rel=1e-12)
    # the same point written as p_b (V_a / V)^n2 (Poda eq. 13)
    p_b = expansion_end_pressure_Pa(params)
    assert p[3] == pytest.approx(p_b * (17.0 * v_c / v3) ** 1.25, rel=1e-12)


@pytest.mark.parametrize("make", PARAM_SETS, ids=PARAM_IDS)
def test_two_stroke_diagram(make):
    params = make(2)
    v_c = clearance_volume_m3(SWEPT_VOLUME_M3, params.compression_ratio)
    eps = 1e-7
    alpha = np.array([0.0, 180.0, 180.0 + eps, 360.0 - eps, 90.0, 270.0])
    p = theoretical_pressure_Pa(alpha, volume_of(alpha, v_c), v_c, params)
    assert p[0] == params.max_pressure_Pa
    assert p[1] == pytest.approx(expansion_end_pressure_Pa(params), rel=1e-12)
    assert p[2] == pytest.approx(params.intake_pressure_Pa, rel=1e-9)
    assert p[3] == pytest.approx(compression_end_pressure_Pa(params), rel=1e-9)
    # expansion above compression at the same volume (90 and 270 deg share V)
    assert p[4] > p[5]


def test_theoretical_rejects_volume_below_clearance():
    params = spark()
    v_c = clearance_volume_m3(SWEPT_VOLUME_M3, params.compression_ratio)
    with pytest.raises(ValueError, match="volume_m3"):
        theoretical_pressure_Pa(np.array([0.0, 10.0]), np.array([v_c, 0.5 * v_c]), v_c, params)


# ---------------------------------------------------------------------------
# Work and mean pressure
# ---------------------------------------------------------------------------
def test_indicated_work_of_a_rectangle():
    # V from 1 to 3 at p = 5 (forward), back at p = 2: W = (5 - 2) * 2 = 6
    volume = np.array([1.0, 2.0, 3.0, 3.0, 2.0, 1.0])
    pressure = np.array([5.0, 5.0, 5.0, 2.0, 2.0, 2.0])
    # the closing segment (V 1 -> 1) contributes nothing; vertical ones neither
    assert indicated_work_J(pressure, volume) == pytest.approx(6.0, rel=1e-15)
    assert mean_indicated_pressure_Pa(6.0, 2.0) == 3.0
    with pytest.raises(ValueError, match="swept_volume_m3"):
        mean_indicated_pressure_Pa(6.0, 0.0)
    with pytest.raises(ValueError, match="volume_m3"):
        indicated_work_J(pressure, volume[:-1])


# ---------------------------------------------------------------------------
# Rounding
# ---------------------------------------------------------------------------
def _rounded(params, alpha, rounding=None, exact_volume=True):
    v_c = clearance_volume_m3(SWEPT_VOLUME_M3, params.compression_ratio)
    rounding = rounding or rounding_for(params)
    kwargs = {"volume_function": lambda a: volume_of(a, v_c)} if exact_volume else {}
    return rounded_pressure_Pa(alpha, volume_of(alpha, v_c), v_c, params, rounding, **kwargs)


def test_default_combustion_delay():
    assert default_combustion_delay_deg("spark", 20.0, 3000.0) == pytest.approx(2.2)
    assert default_combustion_delay_deg("diesel", 20.0, 1600.0) == pytest.approx(14.4)
    assert default_combustion_delay_deg("diesel", 20.0, 1600.0, 2e-3) == pytest.approx(19.2)
    with pytest.raises(ValueError, match="rpm"):
        default_combustion_delay_deg("diesel", 20.0, 0.0)


@pytest.mark.parametrize("make", PARAM_SETS, ids=PARAM_IDS)
@pytest.mark.parametrize("strokes", [4, 2])
def test_rounded_is_c1_everywhere(make, strokes):
    """Second differences shrink like h^2 (C1, piecewise C2), not like h (a kink)."""
    params = make(strokes)
    cycle = cycle_of(params)
    second = []
    for h in (0.02, 0.002):
        alpha = np.arange(0.0, cycle, h)
        p = _rounded(params, alpha)
        closed = np.concatenate([p[-1:], p, p[:1]])
        second.append(np.max(np.abs(closed[2:] - 2.0 * closed[1:-1] + closed[:-2])))
    # C1: ratio ~ 100; a slope jump would give ~ 10, a value jump ~ 1
    assert second[0] / second[1] > 50.0


@pytest.mark.parametrize("make", PARAM_SETS, ids=PARAM_IDS)
def test_rounded_one_sided_slopes_match_at_named_points(make):
    params = make(4)
    r = rounding_for(params)
    c1 = 360.0 - r.ignition_advance_deg + r.combustion_delay_deg
    points = [
        c1,
        360.0,
        360.0 + r.peak_angle_after_tdc_deg,
        540.0 - r.exhaust_opens_before_bdc_deg,
        540.0,
        540.0 + 0.5 * r.exhaust_opens_before_bdc_deg,
        720.0 - r.intake_opens_before_tdc_deg,
        r.exhaust_closes_after_tdc_deg,
    ]
    h = 1e-4
    for x in points:
        p_left, p_mid, p_right = _rounded(params, np.array([x - h, x, x + h]) % 720.0)
        left = (p_mid - p_left) / h
        right = (p_right - p_mid) / h
        scale = max(abs(left), abs(right), params.max_pressure_Pa * 1e-3)
        assert abs(right - left) / scale < 1e-2, x
        assert abs(p_right - p_left) < 1e-3 * params.max_pressure_Pa, x


@pytest.mark.parametrize("make", PARAM_SETS, ids=PARAM_IDS)
@pytest.mark.parametrize("strokes", [4, 2])
def test_rounded_peak_is_requested_and_not_exceeded(make, strokes):
    params = make(strokes)
    r = rounding_for(params)
    alpha = np.arange(int(cycle_of(params)) * 10) / 10.0  # hits the peak angle exactly
    p = _rounded(params, alpha, r)
    peak = r.peak_pressure_fraction * params.max_pressure_Pa
    tdc = 360.0 if strokes == 4 else 0.0
    assert p.max() == pytest.approx(peak, rel=1e-12)
    assert p.max() <= peak * (1.0 + 1e-12)
    assert alpha[np.argmax(p)] == pytest.approx(tdc + r.peak_angle_after_tdc_deg, abs=1e-9)
    # monotone rise from C' to Z' and fall from Z' to BDC
    c1 = tdc - r.ignition_advance_deg + r.combustion_delay_deg
    psi = (alpha - tdc + 180.0) % cycle_of(params) - 180.0 if strokes == 2 else alpha - tdc
    order = np.argsort(psi)
    psi, q = psi[order], p[order]
    rise = q[(psi >= c1 - tdc) & (psi <= r.peak_angle_after_tdc_deg)]
    fall = q[(psi >= r.peak_angle_after_tdc_deg) & (psi <= 180.0)]
    assert np.all(np.diff(rise) > 0)
    assert np.all(np.diff(fall) < 0)


@pytest.mark.parametrize("make", PARAM_SETS, ids=PARAM_IDS)
def test_rounded_starts_and_ends_on_theoretical_lines(make):
    params = make(4)
    r = rounding_for(params)
    v_c = clearance_volume_m3(SWEPT_VOLUME_M3, params.compression_ratio)
    alpha = np.arange(7200) / 10.0
    p = _rounded(params, alpha, r)
    th = theoretical_pressure_Pa(alpha, volume_of(alpha, v_c), v_c, params)
    c1 = 360.0 - r.ignition_advance_deg + r.combustion_delay_deg
    untouched = ((alpha >= 0.0 + r.exhaust_closes_after_tdc_deg) & (alpha <= c1)) | (
        (alpha >= 540.0 + 0.5 * r.exhaust_opens_before_bdc_deg)
        & (alpha <= 720.0 - r.intake_opens_before_tdc_deg)
    )
    np.testing.assert_allclose(p[untouched], th[untouched], rtol=1e-14)
    # gas exchange: the window 700..20 deg is symmetric about TDC, so 0 deg is its midpoint
    assert p[0] == pytest.approx(
        0.5 * (params.intake_pressure_Pa + params.exhaust_pressure_Pa), rel=1e-12
    )
    assert p[200] == pytest.approx(params.intake_pressure_Pa, rel=1e-12)
    assert p[7000] == pytest.approx(params.exhaust_pressure_Pa, rel=1e-12)
    # C'' : p_c + rise at firing TDC
    assert p[3600] == pytest.approx(compression_end_pressure_Pa(params) + 0.5e6, rel=1e-12)
    # BDC after expansion at (p_b + p_r) / 2
    p_b = expansion_end_pressure_Pa(params)
    assert p[5400] == pytest.approx(0.5 * (p_b + params.exhaust_pressure_Pa), rel=1e-12)
    # the combustion rounding rejoins the expansion line before b'
    b1 = 540.0 - r.exhaust_opens_before_bdc_deg
    window = (alpha > 400.0) & (alpha < b1)
    np.testing.assert_allclose(p[window], th[window], rtol=1e-12)


@pytest.mark.parametrize("make", PARAM_SETS, ids=PARAM_IDS)
@pytest.mark.parametrize("strokes", [4, 2])
def test_rounded_is_grid_independent(make, strokes):
    params = make(strokes)
    n = int(cycle_of(params))
    coarse = np.arange(n, dtype=float)
    fine = np.arange(n * 10) / 10.0
    # exact volume function: identical numbers
    np.testing.assert_array_equal(_rounded(params, coarse), _rounded(params, fine)[::10])
    # volume reconstructed from the caller's samples: agreement to spline accuracy
    p_coarse = _rounded(params, coarse, exact_volume=False)
    p_fine = _rounded(params, fine, exact_volume=False)[::10]
    np.testing.assert_allclose(p_coarse, p_fine, rtol=1e-7, atol=1e-7 * params.max_pressure_Pa)
    np.testing.assert_allclose(
        p_coarse, _rounded(params, coarse), rtol=1e-7, atol=1e-7 * params.max_pressure_Pa
    )


@pytest.mark.parametrize("make", PARAM_SETS, ids=PARAM_IDS)
@pytest.mark.parametrize("strokes", [4, 2])
def test_rounded_mean_pressure_is_plausibly_smaller(make, strokes):
    params = make(strokes)
    v_c = clearance_volume_m3(SWEPT_VOLUME_M3, params.compression_ratio)
    alpha = fine_grid(params, step_per_deg=20)
    volume = volume_of(alpha, v_c)
    theoretical = mean_indicated_pressure_Pa(
        indicated_work_J(theoretical_pressure_Pa(alpha, volume, v_c, params), volume),
        SWEPT_VOLUME_M3,
    )
    rounded = mean_indicated_pressure_Pa(
        indicated_work_J(_rounded(params, alpha), volume), SWEPT_VOLUME_M3
    )
    loss = 1.0 - rounded / theoretical
    assert 0.0 < loss < 0.15


def test_rounded_returns_the_shape_of_the_grid():
    params = spark()
    alpha = np.arange(0.0, 720.0, 5.0)
    v_c = clearance_volume_m3(SWEPT_VOLUME_M3, params.compression_ratio)
    p = rounded_pressure_Pa(alpha, volume_of(alpha, v_c), v_c, params, rounding_for(params))
    assert p.shape == alpha.shape


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(combustion_delay_deg=25.0), "combustion_delay_deg"),  # C' after TDC
        (dict(peak_pressure_fraction=0.3), "pressure_rise_to_tdc_Pa"),  # p_z' below p_c + rise
        (dict(exhaust_opens_before_bdc_deg=170.0), "exhaust_opens_before_bdc_deg"),  # b' before J
        (
            dict(intake_opens_before_tdc_deg=170.0),
            "intake_opens_before_tdc_deg",
        ),  # overlaps exhaust
        (dict(peak_angle_after_tdc_deg=-5.0), "peak_angle_after_tdc_deg"),
        (dict(ignition_advance_deg=0.0), "ignition_advance_deg"),
    ],
)
def test_invalid_rounding_raises(kwargs, name):
    params = spark()
    fields = dict(
        ignition_advance_deg=22.0,
        combustion_delay_deg=2.4,
        pressure_rise_to_tdc_Pa=0.5e6,
        peak_pressure_fraction=0.85,
        peak_angle_after_tdc_deg=12.0,
        exhaust_opens_before_bdc_deg=50.0,
        exhaust_closes_after_tdc_deg=20.0,
        intake_opens_before_tdc_deg=20.0,
        intake_closes_after_bdc_deg=60.0,
    )
    fields.update(kwargs)
    alpha = np.arange(720.0)
    with pytest.raises(ValueError, match=name):
        _rounded(params, alpha, RoundingParameters(**fields))


def test_exhaust_opening_between_peak_and_junction_raises():
    # diesel: the rounding from Z' (12 deg) rejoins the expansion line near 23 deg after TDC;
    # b' at 20 deg after TDC leaves no room for it
    params = diesel()
    r = RoundingParameters(20.0, 5.0, 0.5e6, 0.85, 12.0, exhaust_opens_before_bdc_deg=160.0)
    with pytest.raises(ValueError, match="exhaust_opens_before_bdc_deg"):
        _rounded(params, np.arange(720.0), r)


def test_two_stroke_rejects_valve_angles():
    params = diesel(2)
    r = RoundingParameters(
        20.0,
        5.0,
        0.5e6,
        0.85,
        12.0,
        exhaust_opens_before_bdc_deg=30.0,
        intake_opens_before_tdc_deg=10.0,
    )
    with pytest.raises(ValueError, match="intake_opens_before_tdc_deg"):
        _rounded(params, np.arange(360.0), r)


def test_rounding_without_volume_function_needs_a_covering_grid():
    params = spark()
    v_c = clearance_volume_m3(SWEPT_VOLUME_M3, params.compression_ratio)
    alpha = np.arange(0.0, 720.0, 30.0)
    with pytest.raises(ValueError, match="crank_angle_deg"):
        rounded_pressure_Pa(alpha, volume_of(alpha, v_c), v_c, params, rounding_for(params))


# ---------------------------------------------------------------------------
# Crank angle from volume
# ---------------------------------------------------------------------------
# Below ~1e-3 deg from a dead centre the cylinder volume itself (V_c + F s in double
# precision) no longer resolves the angle to 1e-10 deg, so the round trips stop there.
ANGLES_DEG = np.concatenate(
    [[0.0, 1e-3, 0.01, 0.5], np.linspace(1.0, 179.0, 357), [179.5, 179.9, 180.0]]
)


@pytest.mark.parametrize("lam", [0.2, 0.3105, 0.45])
def test_exact_inversion_round_trips(lam):
    v_c = 3e-5
    volume = v_c + PISTON_AREA_M2 * exact_displacement_m(ANGLES_DEG, lam=lam)
    back = crank_angle_from_volume_exact_deg(volume, v_c, BORE_M, CRANK_RADIUS_M, lam)
    np.testing.assert_allclose(back, ANGLES_DEG, rtol=0, atol=1e-10)


@pytest.mark.parametrize("lam", [0.2, 0.3105, 0.45])
def test_approx_inversion_round_trips_two_term_displacement(lam):
    v_c = 3e-5
    volume = v_c + PISTON_AREA_M2 * two_term_displacement_m(ANGLES_DEG, lam=lam)
    back = crank_angle_from_volume_approx_deg(volume, v_c, BORE_M, CRANK_RADIUS_M, lam)
    np.testing.assert_allclose(back, ANGLES_DEG, rtol=0, atol=1e-9)
    # the textbook's printed eq. (16) gives the same angles away from the dead centres
    mid = (ANGLES_DEG > 5.0) & (ANGLES_DEG < 175.0)
    s_over_r = (volume[mid] - v_c) / (0.25 * math.pi * BORE_M**2 * CRANK_RADIUS_M)
    eq16 = np.degrees(
        np.arccos((np.sqrt(1.0 - 2.0 * lam * (s_over_r - 1.0 - lam / 2.0)) - 1.0) / lam)
    )
    np.testing.assert_allclose(back[mid], eq16, atol=1e-8)


def test_approx_differs_from_exact_by_a_small_high_order_amount():
    v_c = 3e-5
    errors = {}
    for lam in (0.15, 0.3):
        volume = v_c + PISTON_AREA_M2 * exact_displacement_m(ANGLES_DEG, lam=lam)
        approx = crank_angle_from_volume_approx_deg(volume, v_c, BORE_M, CRANK_RADIUS_M, lam)
        errors[lam] = np.max(np.abs(approx - ANGLES_DEG))
    # small: under a degree for lambda = 0.3, and not zero
    assert 1e-4 < errors[0.3] < 1.0
    # the neglected displacement term is O(lambda^3): halving lambda divides by ~8
    ratio = errors[0.3] / errors[0.15]
    assert 6.0 < ratio < 10.0
    assert errors[0.3] < math.degrees(0.3**2)


def test_inversion_rejects_impossible_volume():
    with pytest.raises(ValueError, match="volume_m3"):
        crank_angle_from_volume_exact_deg(1e-6, 3e-5, BORE_M, CRANK_RADIUS_M, 0.3)
    with pytest.raises(ValueError, match="rod_ratio"):
        crank_angle_from_volume_approx_deg(3e-5, 3e-5, BORE_M, CRANK_RADIUS_M, 1.2)
    assert crank_angle_from_volume_exact_deg(3e-5, 3e-5, BORE_M, CRANK_RADIUS_M, 0.3) == 0.0


def test_junction_is_the_first_angle_of_a_monotone_join_closed_form():
    """p(psi) = p_z' - (psi - a)^2 after a peak at psi = 0: the secant from the peak is
    -(psi - a)^2 / psi and the slope -2 (psi - a), so beta = slope / secant = 2 psi / (psi - a)
    (psi > a) is at most 3 exactly from psi = 3 a on; before a the line rises (beta < 0)."""
    import numpy as np

    from crankdyn.physics.indicator import _find_junction_deg

    a, peak = 1.2345, 5.0e6

    def expansion_at(psi):
        psi = np.asarray(psi, dtype=float)
        return peak - (psi - a) ** 2, -2.0 * (psi - a)

    assert abs(_find_junction_deg(0.0, 10.0, peak, expansion_at) - 3 * a) < 1e-9
    assert _find_junction_deg(0.0, 3 * a - 0.05, peak, expansion_at) is None  # not within the limit


@pytest.mark.parametrize("a", [1.2345, 10.0 / 3.0, 12.3456])
def test_junction_scan_stops_at_the_first_passing_chunk_with_the_whole_grid_answer(a):
    """J = 3 a (closed form above) found the same as on the whole 0.01 deg grid, for J in the first
    10 deg chunk, at its edge and beyond it, with only the grid up to J's chunk evaluated."""
    import numpy as np

    from crankdyn.physics.indicator import _find_junction_deg

    peak, evaluated = 5.0e6, []

    def expansion_at(psi):
        psi = np.asarray(psi, dtype=float)
        evaluated.append(psi.size)
        return peak - (psi - a) ** 2, -2.0 * (psi - a)

    whole = 0.01 * np.arange(1, 12001)  # the whole grid to 120 deg: its first passing point
    p, slope = expansion_at(whole)
    beta = slope / ((p - peak) / whole)
    first_on_grid = whole[np.nonzero((p < peak) & (beta >= -1e-12) & (beta <= 3.0 + 1e-12))[0][0]]
    evaluated.clear()
    found = _find_junction_deg(0.0, 120.0, peak, expansion_at)
    assert abs(found - 3 * a) < 1e-9 and found <= first_on_grid
    assert first_on_grid - found < 0.01
    assert evaluated[0] == 1000 and sum(evaluated) < 1000 * (int(3 * a // 10) + 2) + 500
