"""Crankshaft speed fluctuation with the variable reduced inertia (single mass)."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from conftest import shared_run

from crankdyn.physics import layout as lay
from crankdyn.physics import speed_fluctuation as sf
from crankdyn.plugin.registry import default_registry
from crankdyn.plugin.scene_inputs import crank_train

REGISTRY = default_registry()


@functools.cache
def inline4():
    return shared_run("inline4-petrol")  # shared with the other test files (read only)


@functools.cache
def problem():
    """The single-mass problem of the bundled in-line four: series, gas torque, exact solution."""
    result = inline4()
    torque = result.outputs["torque"].data["engine_torque"]
    bays = result.outputs["bays"].data["bay_loads"]
    design = result.outputs["flywheel"].data["flywheel"]
    train = crank_train(result.scene, bays)
    inertia = train.series(design.flywheel_inertia_kg_m2 + design.engine_inertia_kg_m2)
    alpha = np.radians(torque.crank_angle_deg)
    gas = sf.gas_torque_Nm(torque.torque_Nm, inertia(alpha)[1], torque.angular_velocity_rad_s)
    series = sf.PeriodicSeries.from_samples(gas, 4 * np.pi)
    exact = sf.periodic_speed(series, inertia, torque.angular_velocity_rad_s)
    return result, train, inertia, series, exact, torque


# ----------------------------------------------------------------------------- reduced inertia


def test_inertia_series_matches_direct_evaluation_and_its_derivative():
    _, train, inertia, _, _, _ = problem()
    alpha = np.linspace(0, 4 * np.pi, 997)
    direct, direct_derivative = sf.reciprocating_inertia_kg_m2(
        alpha[:, None],
        train.phase_rad,
        train.reciprocating_kg,
        train.crank_radius_m,
        train.rod_ratio,
    )
    j, dj = inertia(alpha)
    recip_mean = train.reciprocating_kg.sum() * sf.mean_arm_squared_m2(
        train.crank_radius_m, train.rod_ratio
    )
    constant = inertia.mean_kg_m2 - recip_mean
    np.testing.assert_allclose(j, constant + direct.sum(axis=1), rtol=1e-12)
    np.testing.assert_allclose(dj, direct_derivative.sum(axis=1), atol=1e-12 * np.max(np.abs(dj)))
    # derivative against a central difference of J itself
    h = 1e-5
    numeric = (inertia(alpha + h)[0] - inertia(alpha - h)[0]) / (2 * h)
    np.testing.assert_allclose(dj, numeric, atol=1e-8 * np.max(np.abs(dj)))
    # an in-line four's reciprocating inertia repeats every half revolution
    np.testing.assert_allclose(inertia(alpha + np.pi)[0], j, rtol=1e-12)


def test_gas_torque_recovered_from_output_torque_equals_direct_gas_torque():
    # M_g = M + J'/2 omega^2 must equal the torque of the gas forces alone: sum over cylinders of
    # (p - p0) F_p s'(alpha - phase), computed from the forces stage's gas pressure.
    result, train, inertia, series, _, torque = problem()
    forces = result.outputs["forces"].data["forces"]
    layout = result.outputs["bays"].data["bay_loads"].layout
    alpha = np.radians(torque.crank_angle_deg)
    arm, _ = sf.arm_derivatives(alpha, train.crank_radius_m, train.rod_ratio)
    single = forces.gas_Pa * forces.piston_area_m2 * arm
    step = result.scene.analysis.angle_step_deg
    direct = sum(
        np.roll(single, lay.grid_shift(c.firing_delay_deg, step)) for c in layout.cylinders
    )
    np.testing.assert_allclose(series(alpha), direct, atol=1e-9 * np.max(np.abs(direct)))


# ----------------------------------------------------------------------------- exact solution


def test_periodic_series_interpolates_and_integrates():
    rng = np.random.default_rng(1)
    samples = rng.normal(size=360)
    series = sf.PeriodicSeries.from_samples(samples, 2 * np.pi)
    alpha = np.arange(360) * (2 * np.pi / 360)
    np.testing.assert_allclose(series(alpha), samples, atol=1e-12)
    assert series.mean[0] == pytest.approx(samples.mean())
    x = rng.uniform(0, 2 * np.pi, 50)
    h = 1e-6
    derivative = (series.integral(x + h) - series.integral(x - h)) / (2 * h)
    np.testing.assert_allclose(derivative, series(x) - samples.mean(), atol=1e-6)
    assert abs(series.integral(2 * np.pi)) < 1e-12  # closes after a period


def test_long_series_on_the_grid_and_in_blocks_match_the_closed_form(monkeypatch):
    # f = 2 cos(3a) - sin(1000a) + 0.5 cos(2048a) sampled on 4096 points: the grid evaluation
    # (inverse FFT, taken above _GRID_MIN_WORK) and the blockwise direct sum (small blocks
    # forced) must both give f and its closed-form integral 2 sin(3a)/3 + (cos(1000a) - 1)/1000
    # + 0.5 sin(2048a)/2048.
    n = 4096
    grid = np.arange(n) * (2 * np.pi / n)
    f = lambda a: 2 * np.cos(3 * a) - np.sin(1000 * a) + 0.5 * np.cos(2048 * a)  # noqa: E731
    w = lambda a: (
        2 * np.sin(3 * a) / 3 + (np.cos(1000 * a) - 1) / 1000 + 0.5 * np.sin(2048 * a) / 2048
    )  # noqa: E731
    series = sf.PeriodicSeries.from_samples(f(grid), 2 * np.pi)
    assert (
        grid.size * series.wavenumbers.size >= sf._GRID_MIN_WORK
    )  # the FFT path is the one tested
    np.testing.assert_allclose(series(grid), f(grid), atol=1e-12)
    np.testing.assert_allclose(series.integral(grid), w(grid), atol=1e-12)
    monkeypatch.setattr(
        sf, "_BLOCK_ELEMENTS", 3 * series.wavenumbers.size
    )  # three angles per block
    x = np.random.default_rng(2).uniform(0, 2 * np.pi, 10)
    np.testing.assert_allclose(series(x), f(x), atol=1e-9)
    np.testing.assert_allclose(series.integral(x), w(x), atol=1e-11)
    np.testing.assert_allclose(
        [series.integral(v) for v in x], w(x), atol=1e-11
    )  # one angle at a time


def test_exact_solution_satisfies_the_equation_of_motion():
    # J omega d(omega)/d(alpha) + J'/2 omega^2 = M_g - M_c, checked by central differences
    _, _, inertia, series, exact, torque = problem()
    alpha = np.linspace(0.1, 12.0, 40)
    h = 1e-5
    omega = exact.omega_at(alpha)
    domega = (exact.omega_at(alpha + h) - exact.omega_at(alpha - h)) / (2 * h)
    j, dj = inertia(alpha)
    lhs = j * omega * domega + 0.5 * dj * omega**2
    rhs = series(alpha) - exact.load_torque_Nm
    np.testing.assert_allclose(lhs, rhs, atol=1e-6 * np.max(np.abs(rhs)))
    # periodic, and its time mean is the nominal speed
    assert exact.omega_at(4 * np.pi + 0.3) == pytest.approx(exact.omega_at(0.3), rel=1e-13)
    assert exact.omega_mean_rad_s == pytest.approx(torque.angular_velocity_rad_s, rel=1e-12)
    cycle_time = np.trapezoid(
        1 / exact.omega_at(np.linspace(0, 4 * np.pi, 20001)), dx=4 * np.pi / 20000
    )
    assert cycle_time == pytest.approx(exact.cycle_time_s, rel=1e-9)


def test_energy_method_and_periodic_ode_agree_on_inline4():
    # Acceptance: the flywheel from the energy method and from the periodic solution within 1 %.
    r = inline4().outputs["speed_fluctuation"].results
    assert abs(r["flywheel_inertia_deviation_percent"]) < 1.0
    assert r["flywheel_inertia_ode_kg_m2"] == pytest.approx(
        r["flywheel_inertia_energy_kg_m2"], rel=0.01
    )
    assert abs(r["irregularity_deviation_percent"]) < 1.0
    # and the time-stepping solver reproduces the periodic solution
    solver = r["solver"]
    assert solver["error_relative"] < 1e-5 and solver["periodicity_error"] < 1e-5
    assert solver["irregularity"] == pytest.approx(r["irregularity"], rel=1e-3)


def test_every_solver_converges_to_the_exact_solution():
    records = inline4().outputs["speed_fluctuation"].results["solvers"]
    methods = {r["method"] for r in records}
    assert methods == {"RK45", "Radau", "BDF", "LSODA"}
    for method in methods:
        runs = sorted((r for r in records if r["method"] == method), key=lambda r: -r["rtol"])
        assert all(r["success"] and r["error_relative"] is not None for r in runs)
        assert runs[-1]["error_relative"] < 1e-5  # rtol 1e-7
        assert (
            runs[-1]["error_relative"] < runs[0]["error_relative"]
        )  # tighter tolerance, smaller error
        assert runs[-1]["nfev"] > runs[0]["nfev"]
        assert all(r["time_s"] > 0 for r in runs)


def test_the_run_the_section_quotes_is_a_row_of_its_table():
    # The text quotes the chosen method at SINGLE_MASS_RTOL; that run is in the solver records (the
    # table and figure) once, marked, after its method's other runs, with the quoted figures.
    r = inline4().outputs["speed_fluctuation"].results
    used = [k for k, rec in enumerate(r["solvers"]) if rec.get("used")]
    assert len(used) == 1
    record = r["solvers"][used[0]]
    assert record["method"] == r["solver"]["method"] and record["rtol"] == r["solver"]["rtol"]
    assert (
        record["steps"] == r["solver"]["steps"]
        and record["error_relative"] == r["solver"]["error_relative"]
    )
    following = r["solvers"][used[0] + 1 :]
    assert all(rec["method"] != record["method"] for rec in following)


def test_single_mass_problem_is_not_stiff():
    solver = inline4().outputs["speed_fluctuation"].results["solver"]
    assert solver["method"] == "RK45" and solver["automatic"] and not solver["stiff"]
    assert solver["stiffness_ratio"] < 1 and "not stiff" in solver["reason"]


def test_time_stepping_reproduces_the_exact_solution_directly():
    _, _, inertia, series, exact, _ = problem()
    rhs = sf.single_mass_rhs(series, exact.load_torque_Nm, inertia)
    y0 = [0.0, float(exact.omega_at(0.0))]
    for method in ("RK45", "Radau"):
        run = sf.run_solver(rhs, (0, exact.cycle_time_s), y0, method, 1e-9, [1e-12, 1e-9])
        assert run.success
        assert sf.phase_error(run, exact) < 1e-6  # global error of a whole cycle at rtol 1e-9
        # one cycle in the exact cycle time, to the global error of rtol 1e-9 over a cycle
        assert run.y[0, -1] == pytest.approx(4 * np.pi, abs=2e-6)


def test_stability_polynomial_of_rk45():
    # an order-5 method: R(z) agrees with e^z to z^5 ...
    z = np.array([1e-2, -2e-2, 3e-2j])
    np.testing.assert_allclose(sf._rk45_stability(z), np.exp(z), rtol=0, atol=5e-13)
    # ... and the classical Dormand-Prince boundary on the negative real axis is near -3.3
    assert 3.2 < sf.stable_step_s([-1.0]) < 3.4
    assert sf.stable_step_s([-1e4]) == pytest.approx(sf.stable_step_s([-1.0]) / 1e4)
    # a lightly damped oscillation allows much less than a strongly damped decay
    assert sf.stable_step_s([-0.02 + 1j]) < sf.stable_step_s([-1.0])


def test_a_run_stopped_by_its_budget_reports_its_progress():
    _, _, inertia, series, exact, _ = problem()
    rhs = sf.single_mass_rhs(series, exact.load_torque_Nm, inertia)
    run = sf.run_solver(
        rhs,
        (0, exact.cycle_time_s),
        [0.0, float(exact.omega_at(0.0))],
        "RK45",
        1e-12,
        [1e-15, 1e-12],
        max_nfev=200,
    )
    assert not run.success and 0 < run.progress < 1 and run.nfev >= 200
    assert run.steps_needed > run.steps


@pytest.mark.parametrize("width", [1, 2, 7, 64, 2047, 2048, 36001])
def test_power_sum_is_the_geometric_sum_in_closed_form(width):
    # c_k = r^k: sum_{k=1}^{K} (r z)^k = r z (1 - (r z)^K) / (1 - r z), for K a square, not a
    # square, and one (the blocks of the sum must cover every harmonic exactly once).
    r = 0.999
    coefficients = r ** np.arange(1, width + 1)
    power_sum = sf.PowerSum(coefficients)
    for angle in (0.3, 2.0, -1.1, 40.0):
        z = np.exp(1j * angle)
        q = r * z
        expected = q * (1 - q**width) / (1 - q)
        assert abs(power_sum(z) - expected) <= 1e-12 * max(1.0, abs(expected))


def test_long_single_disc_series_gives_what_the_short_path_gives(monkeypatch):
    # The right-hand side's long-series path (blocked torque sum, the inertia's few harmonics
    # directly) against the short path's one product over all harmonics, on the in-line four.
    _, _, inertia, series, _, _ = problem()
    short = sf.DiscSeries(series, [inertia])
    monkeypatch.setattr(sf, "_BLAS_MAX_WIDTH", 1)
    long = sf.DiscSeries(series, [inertia])
    long_series = sf.PeriodicSeries(series.mean, series.coefficients, series.period_rad)
    assert long._long and not short._long and long_series._first_sum is not None
    for alpha in np.random.default_rng(3).uniform(0, 4 * np.pi, 20):
        m, j, dj = short.scalar(alpha)
        np.testing.assert_allclose(long.scalar(alpha), (m, j, dj), rtol=1e-12, atol=1e-12 * abs(m))
        assert long_series(float(alpha)) == pytest.approx(
            series(float(alpha)), rel=1e-12, abs=1e-12 * abs(m)
        )


def test_the_extreme_speeds_print_apart():
    """A heavy propeller's 0.13 rad/s swing about 272 rad/s prints as 272.20 and 272.33 (five
    significant digits), a V10's 2.6 rad/s about 680 rad/s with the usual four."""
    from crankdyn_builtin.speed_fluctuation.worked import speed_digits

    assert speed_digits(272.33, 272.20) == 5
    assert speed_digits(681.9, 679.3) == 4
    assert speed_digits(100.0, 100.0) == 4  # no swing: the usual digits


def test_a_constant_reduced_inertia_is_drawn_with_ticks_apart():
    """An even-firing V16's J(α) is constant but for rounding (3·10⁻¹² kg·m²): drawn to its
    own limits its axis would print 40.727096 at every tick; a flat J gets limits ±2 % about it
    and ticks of distinct values."""
    from crankdyn.report.i18n import translator
    from crankdyn_builtin.speed_fluctuation.figures import _speed_plot

    angle = np.arange(0.0, 360.0, 1.0)
    f = {
        "crank_angle_deg": angle,
        "omega_rad_s": 94.0 + 0.05 * np.sin(np.radians(16 * angle)),
        "omega_energy_method_rad_s": 94.0 + 0.05 * np.sin(np.radians(16 * angle)),
        "inertia_kg_m2": 40.727096 + 3e-12 * np.sin(np.radians(angle)),
    }
    fig = _speed_plot(f, None, 360.0, translator("en"))
    fig.canvas.draw()
    low, high = fig.axes[1].get_ylim()
    assert low == pytest.approx(0.98 * 40.727096) and high == pytest.approx(1.02 * 40.727096)
    ticks = [tick.get_text() for tick in fig.axes[1].get_yticklabels() if tick.get_text()]
    assert len(ticks) >= 2 and len(set(ticks)) == len(ticks), ticks
    # a 60° V12 with a propeller: 4.94382…4.94388 kg·m² (0.001 %) is drawn flat too, not swung
    # over the axis's height; a 2 % swing keeps limits of its own
    for swing, flat in ((6e-5, True), (0.1, False)):
        f["inertia_kg_m2"] = 4.94385 + swing / 2 * np.sin(np.radians(12 * angle))
        low, high = _speed_plot(f, None, 360.0, translator("en")).axes[1].get_ylim()
        assert bool(low == pytest.approx(0.98 * 4.94385)) is flat, (swing, low, high)


def test_the_worked_irregularity_divides_by_the_mean_speed_the_text_prints():
    """The worked δ = (ω_max − ω_min)/ω_m substitutes ω_m as the section prints it: a generator
    set's 104,65 rad/s beside its 0,5232 range, whose quotient is the δ printed (0,5232/104,6
    would give 0,005002 against the printed 0,005000)."""
    import html as html_lib
    import re

    from conftest import shared_html

    from crankdyn.report.i18n import translator
    from crankdyn_builtin.speed_fluctuation.worked import speed_digits

    assert speed_digits(104.91, 104.39) == 5
    assert translator("uk").number(0.5 * (104.9116 + 104.3884), 5) == "104,65"
    generator = {"engine": {"rpm": 1000, "application": "stationary"}}
    generator["flywheel"] = {"required_irregularity": 0.002}
    page = shared_html("inline4-petrol", generator, "en", ("speed_fluctuation",)).linked_html
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", "", page)).split())
    stated = re.search(r"ωm = \(ωmax \+ ωmin\)/\u2060?2 = ([\d.]+) rad", text).group(1)
    worked = re.search(r"δ = \(ωmax − ωmin\)/ωm = ([\d.]+)/\u2060?([\d.]+) = ([\d.]+)", text)
    assert worked.group(2) == stated, (worked.group(0), stated)
    quotient = float(worked.group(1)) / float(worked.group(2))
    assert quotient == pytest.approx(float(worked.group(3)), abs=0.6 * 10 ** (-6))


def test_the_energy_methods_offset_from_the_exact_speed_is_explained_with_its_size():
    """The speed figure's energy-method curve is centred on (ω_max + ω_min)/2 = πn/30, the exact
    solution's time mean is πn/30: the section says how far apart the two lie (the exact
    solution's time mean less its mid-range) and why, in the figure's own number."""
    import html as html_lib
    import re

    from conftest import shared_html

    result = shared_run("inline4-petrol")
    r = result.outputs["speed_fluctuation"].results
    offset = r["omega_mean_rad_s"] - 0.5 * (r["omega_max_rad_s"] + r["omega_min_rad_s"])
    assert r["omega_mean_rad_s"] == pytest.approx(math.pi * 5600 / 30)  # the given speed
    page = shared_html("inline4-petrol").linked_html
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", "", page)).split())
    said = re.search(
        r"In figure (\d+\.\d+) the energy method's curve lies about ([\d.]+) rad/\u2060?s (above|below)",
        text,
    )
    assert said, "the offset is explained"
    assert float(said.group(2)) == pytest.approx(abs(offset), abs=0.006)
    assert said.group(3) == ("above" if offset > 0 else "below")
    figure = re.search(
        r'<figure data-number="' + re.escape(said.group(1)) + r'">.*?</figure>', page, re.S
    )
    assert figure and "speed" in figure.group(0)
