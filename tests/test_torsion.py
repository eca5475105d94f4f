"""Torsional multi-mass model of the crankshaft; stiff and non-stiff solvers."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from conftest import shared_run

from crankdyn.errors import SceneError
from crankdyn.physics import speed_fluctuation as sf
from crankdyn.physics import torsion as tor
from crankdyn.plugin.registry import default_registry
from crankdyn.report.context import RenderContext
from crankdyn.report.document import _environment
from crankdyn.report.i18n import translator
from crankdyn.scene.units import parse_quantity

REGISTRY = default_registry()


def run(name, changes=None):
    """One computation per scene and worker, shared with the other test files (read only)."""
    return shared_run(name, changes)


# ----------------------------------------------------------------------------- modes


def test_two_disc_natural_frequency_closed_form():
    J1, J2, k = 0.004, 0.12, 4e5
    modes = tor.natural_modes([J1, J2], [k])
    assert modes.omega_rad_s[0] == 0.0
    assert modes.omega_rad_s[1] == pytest.approx(math.sqrt(k * (J1 + J2) / (J1 * J2)), rel=1e-12)
    # node of the elastic mode: amplitudes in inverse ratio of the inertias
    shape = modes.shapes[:, 1]
    assert shape[0] / shape[1] == pytest.approx(-J2 / J1, rel=1e-10)


def test_chain_modes_are_mass_orthogonal_and_damped_as_asked():
    J = np.array([5e-5, 0.004, 0.004, 0.004, 0.004, 0.11])
    k = np.array([3e6, 4e5, 4e5, 4e5, 6e5])
    modes = tor.natural_modes(J, k)
    M = np.diag(J)
    K = tor.stiffness_matrix(k)
    Phi = modes.mass_normalised
    np.testing.assert_allclose(Phi.T @ M @ Phi, np.eye(J.size), atol=1e-10)
    np.testing.assert_allclose(
        Phi.T @ K @ Phi, np.diag(modes.omega_rad_s**2), atol=1e-6 * modes.omega_rad_s.max() ** 2
    )
    C = tor.modal_damping_matrix(J, k, 0.05)
    np.testing.assert_allclose(
        Phi.T @ C @ Phi, np.diag(2 * 0.05 * modes.omega_rad_s), atol=1e-9 * modes.omega_rad_s.max()
    )
    np.testing.assert_allclose(
        C @ np.ones(J.size), 0.0, atol=1e-9 * np.abs(C).max()
    )  # rigid rotation undamped
    # the eigenvalues of the first-order system are the damped modal ones
    full = np.sort_complex(tor.linear_eigenvalues(J, K, C))
    modal = np.sort_complex(tor.modal_eigenvalues(modes.omega_rad_s, 0.05))
    nonzero = full[np.abs(full) > 1e-3 * np.abs(full).max()]
    np.testing.assert_allclose(np.sort_complex(nonzero), modal, rtol=1e-8)


def test_relative_vector_sums_of_an_inline_four():
    # firing order 1-3-4-2: delays 0, 540, 180, 360 deg (cylinders 1..4); a rigid-like mode (all ones)
    phase = np.radians([0.0, 540.0, 180.0, 360.0])
    ones = np.ones(4)
    assert tor.relative_vector_sum(ones, phase, 2.0) == pytest.approx(4.0)  # major order
    assert tor.relative_vector_sum(ones, phase, 4.0) == pytest.approx(4.0)
    for order in (0.5, 1.0, 1.5, 3.0):
        assert tor.relative_vector_sum(ones, phase, order) == pytest.approx(0.0, abs=1e-12)
    assert tor.critical_speed_rpm(2 * math.pi * 100.0, 2.0) == pytest.approx(3000.0)


def test_forced_response_satisfies_the_linear_equations():
    J = np.array([0.004, 0.004, 0.12])
    k = [3e5, 5e5]
    K = tor.stiffness_matrix(k)
    C = tor.modal_damping_matrix(J, k, 0.03)
    period = 4 * np.pi
    alpha = np.arange(720) * (period / 720)
    torque = np.zeros((720, 3))
    torque[:, 0] = 100 + 300 * np.sin(2 * alpha) + 50 * np.cos(5.5 * alpha)
    torque[:, 1] = 100 + 300 * np.sin(2 * alpha + 1.0)
    torque[:, 2] = -200
    omega = 500.0
    x = tor.forced_response(J, K, C, sf.PeriodicSeries.from_samples(torque, period), omega, 2)
    dx, ddx = x.derivative(), x.derivative().derivative()
    a = np.linspace(0, period, 37)
    # M x'' + C x' + K x = T with d/dt = omega d/dalpha
    lhs = (ddx(a) * omega**2) * J + (dx(a) * omega) @ C.T + x(a) @ K.T
    np.testing.assert_allclose(
        lhs, sf.PeriodicSeries.from_samples(torque, period)(a), atol=1e-8 * 400
    )
    assert x.mean[2] == 0.0  # the reference disc's mean twist


# ----------------------------------------------------------------------------- the stage


def test_torsion_example_is_stiff_and_radau_beats_rk45():
    # Acceptance: a stiff torsional case is solved by the implicit solver, while the explicit one
    # needs far more steps (step counts, not times: the suite makes no timing asserts).
    t = run("inline4-torsion").outputs["speed_fluctuation"].results["torsion"]
    assert t["solver"]["method"] == "Radau" and t["solver"]["stiff"] and t["solver"]["automatic"]
    assert t["solver"]["stiffness_ratio"] > sf.STIFFNESS_THRESHOLD
    assert t["steady_state"]["converged"] and t["steady_state"]["cycles"] <= 5
    runs = [r for r in t["solvers"] if not r["reference"]]
    for rtol in {r["rtol"] for r in runs}:
        by = {r["method"]: r for r in runs if r["rtol"] == rtol}
        assert by["Radau"]["success"]
        assert by["RK45"]["steps_needed"] > 5 * by["Radau"]["steps"], (
            rtol,
            by["RK45"],
            by["Radau"],
        )
        # a run is either a success with its error measured, or a failure with its reason
        for record in by.values():
            assert (record["success"] and record["error_relative"] is not None) or (
                not record["success"] and record["error_relative"] is None and record["message"]
            ), record
        assert (
            not by["RK45"]["success"]
            or by["Radau"]["error_relative"] < by["RK45"]["error_relative"]
        )
    # the flywheel of the elastic shaft still moves close to the rigid shaft
    assert t["flywheel_speed_deviation_from_rigid_relative"] < 5e-3
    assert t["flywheel_irregularity"] == pytest.approx(
        run("inline4-torsion").outputs["speed_fluctuation"].results["irregularity"], rel=0.2
    )


def test_stiff_chain_implicit_needs_far_fewer_steps_than_explicit():
    """A synthetic stiff case: a very stiff shaft with small end discs and a smooth torque."""
    period = 4 * np.pi
    alpha = np.arange(360) * (period / 360)
    torque = (200 + 400 * np.sin(2 * alpha))[:, None]
    inertia = sf.inertia_series([0.0, np.pi], 0.6, 0.039, 0.28, 0.003)
    gas = sf.PeriodicSeries.from_samples(torque, period)
    J = np.array([1e-5, inertia.mean_kg_m2, 0.1])
    spans = [1e7, 1e7]
    K = tor.stiffness_matrix(spans)
    C = tor.modal_damping_matrix(J, spans, 0.05)
    model = tor.ShaftModel(gas, [inertia], [1], J, K, C, 200.0, 2)
    omega = 300.0
    z0 = model.quasi_static_state(0.0, omega)
    span = (0.0, period / omega)
    atol = np.concatenate([[1e-9], np.full(2, 1e-12), np.full(3, 1e-5)])
    implicit = sf.run_solver(model, span, z0, "Radau", 1e-5, atol, jac=model.jacobian)
    explicit = sf.run_solver(model, span, z0, "RK45", 1e-5, atol, max_nfev=20000)
    assert implicit.success
    assert explicit.steps_needed > 10 * implicit.steps, (explicit.steps_needed, implicit.steps)
    # the explicit step is held at the stability limit of the fastest mode
    modes = tor.natural_modes(J, spans)
    limit = sf.stable_step_s(tor.modal_eigenvalues(modes.omega_rad_s, 0.05))
    assert explicit.steps_needed > 0.5 * (span[1] / limit)


def test_rigid_shaft_limit_reproduces_the_single_mass_solution():
    changes = {
        "torsion": {
            "span_stiffness": "1e8 N*m/rad",
            "flywheel_stiffness": "1e8 N*m/rad",
            "free_end_inertia": None,
            "free_end_stiffness": None,
            "compare_solvers": False,
        }
    }
    result = run("inline4-torsion", changes)
    r = result.outputs["speed_fluctuation"].results
    t = r["torsion"]
    assert t["flywheel_speed_deviation_from_rigid_relative"] < 2e-4
    assert t["flywheel_irregularity"] == pytest.approx(r["irregularity"], rel=0.02)
    assert t["steady_state"]["converged"]


def _sections(result, language, detail="full"):
    """The flywheel and speed-fluctuation sections only (the whole report is tested elsewhere), as
    the report of ``[report] detail`` shows them (the full one compares the solvers)."""
    t = translator(language, REGISTRY.catalogs)
    report = result.scene.report.model_copy(update={"detail": detail})
    scene = result.scene.model_copy(update={"report": report})
    ctx = RenderContext(
        t=t,
        env=_environment(REGISTRY, result),
        table_step_deg=result.scene.analysis.table_step_deg,
        cycle_deg=result.scene.engine.cycle_deg,
        scene=scene,
    )
    html = []
    for number, stage in enumerate(("flywheel", "speed_fluctuation"), start=9):
        ctx.start_section(number, stage)
        html.append(
            next(s for s in result.plan.order if s.name == stage).presentation.render(
                result.outputs[stage], ctx
            )
        )
    return "".join(html), t, ctx


@pytest.mark.parametrize("language", ["en", "ru"])
def test_torsion_sections_render(language):
    html, t, ctx = _sections(run("inline4-torsion"), language)
    assert not t.missing, t.missing
    assert (
        "Radau" in html and html.count('src="figures/') == 7
    )  # each figure referenced once, with the Campbell diagram
    # tables and figures numbered in the order they appear
    for word in (
        t("report.table_caption", number="X", caption="").split("X")[0],
        t("report.figure_caption", number="X", caption="").split("X")[0],
    ):
        # (a table's continuation label, "Table 10.1 continued" in its rows' data-continued, is no new table)
        numbers = [
            int(n)
            for n in re.findall(r'(?<!data-continued=")' + re.escape(word) + r"10\.(\d+)", html)
        ]
        assert numbers == list(range(1, len(numbers) + 1)), (word, numbers)
    assert len(ctx.conclusions) == 4  # flywheel, critical speeds, torsion, speed fluctuation
    course, _, course_ctx = _sections(run("inline4-torsion"), language, detail="course")
    assert "Radau" not in course and "RK45" not in course and course.count('src="figures/') == 5
    assert len(course_ctx.conclusions) == 4
    assert not any("Radau" in c for c in course_ctx.conclusions)


def test_torsion_without_a_flywheel_uses_the_last_crank():
    result = run(
        "inline4-torsion",
        {
            "flywheel": {
                "required_irregularity": 0.2,
                "rim_mean_diameter": None,
                "max_rim_speed": None,
            },
            "torsion": {"compare_solvers": False},
        },
    )
    t = result.outputs["speed_fluctuation"].results["torsion"]
    assert [n["name"] for n in t["nodes"]] == [
        "free end",
        "crank 1",
        "crank 2",
        "crank 3",
        "crank 4",
    ]
    assert t["reference_node"] == 4


# ----------------------------------------------------------------------------- input


def test_torsional_stiffness_units():
    assert parse_quantity("1.2e5 N*m/rad", "torsional_stiffness") == pytest.approx(1.2e5)
    assert parse_quantity("3 kN*m/deg", "torsional_stiffness") == pytest.approx(
        3000 * 180 / math.pi
    )
    assert parse_quantity("1200 kg*cm^2", "moment_of_inertia") == pytest.approx(0.12)
    with pytest.raises(ValueError, match="not a torsional_stiffness"):
        parse_quantity("5 kg", "torsional_stiffness")


@pytest.mark.parametrize(
    "changes, field",
    [
        ({"torsion": {"load_inertia": "1 kg*m^2"}}, "torsion"),
        ({"torsion": {"span_stiffness": ["4e5 N*m/rad", "4e5 N*m/rad"]}}, "torsion.span_stiffness"),
        ({"torsion": {"span_stiffness": "4e5"}}, "torsion.span_stiffness"),
        ({"torsion": {"damping_ratio": 1.5}}, "torsion.damping_ratio"),
        ({"torsion": {"solver": "Euler"}}, "torsion.solver"),
    ],
)
def test_bad_torsion_tables_are_refused(changes, field):
    with pytest.raises(SceneError) as info:
        run("inline4-torsion", changes)
    assert info.value.problems[0].field == field, [str(p) for p in info.value.problems]


def test_results_keys_are_documented():
    from documented import documentation_text

    readme = documentation_text()
    outputs = run("inline4-torsion").outputs
    r = outputs["speed_fluctuation"].results
    keys = (
        set(outputs["flywheel"].results)
        | set(outputs["flywheel"].results["rim"])
        | set(r)
        | set(r["solver"])
    )
    keys |= set(r["solvers"][0]) | set(r["torsion"]) | set(r["torsion"]["steady_state"])
    keys |= (
        set(r["torsion"]["modes"][0])
        | set(r["torsion"]["harmonics"][0])
        | set(r["torsion"]["solvers"][0])
    )
    keys |= set(r["torsion"]["nodes"][0])
    missing = sorted(k for k in keys if f"`{k}`" not in readme)
    assert not missing, missing
    # the whole document is JSON: no NaN or infinity anywhere
    text = json.dumps(
        {"flywheel": outputs["flywheel"].results, "speed_fluctuation": r}, allow_nan=False
    )
    assert "torsion" in text


def test_critical_speeds_near_the_operating_speed_are_flagged():
    """The in-line 4 at 5600 rpm lies between the order-7 (5348 rpm) and order-6.5 (5760 rpm)
    critical speeds of mode 1. Independently: n_c = 60 f_1 / nu for every listed order with at least 1 %
    of the largest amplitude, kept when within 10 % of 5600 rpm."""
    t = run("inline4-torsion").outputs["speed_fluctuation"].results["torsion"]
    f1 = t["modes"][0]["natural_frequency_Hz"]
    largest = max(h["amplitude_Nm"] for h in t["harmonics"])
    expected = {
        h["order"]
        for h in t["harmonics"]
        if h["amplitude_Nm"] >= 0.01 * largest and abs(60 * f1 / h["order"] / 5600 - 1) <= 0.10
    }
    near = t["critical_speeds_near_operating"]
    assert {c["order"] for c in near if c["mode"] == 1} == expected and {6.5, 7.0} <= expected
    by_order = {c["order"]: c for c in near if c["mode"] == 1}
    assert by_order[7.0]["critical_rpm"] == pytest.approx(60 * f1 / 7, rel=1e-12)
    assert by_order[7.0]["deviation_percent"] == pytest.approx(
        100 * (60 * f1 / 7 / 5600 - 1), rel=1e-12
    )
    assert (
        round(by_order[7.0]["critical_rpm"]) == 5348
        and round(by_order[6.5]["critical_rpm"]) == 5760
    )
    # the table reaches the order the text names as the last significant one
    assert max(h["order"] for h in t["harmonics"]) == pytest.approx(
        max(12.0, t["significant_order"])
    )
    # RK45 stopped by its budget is named so, not as a failure. Whether the default budget (10 x the
    # implicit solvers' evaluations) stops it depends on the machine's floating point (3530 of 3740
    # evaluations on one, over on another); a budget of 1000, below the ~3500 it needs, always does.
    assert all(
        r["outcome"] == "budget" for r in t["solvers"] if r["method"] == "RK45" and not r["success"]
    )
    tight = run("inline4-torsion", {"torsion": {"explicit_budget": 1000, "compare_rtols": [1e-3]}})
    rk45 = [
        r
        for r in tight.outputs["speed_fluctuation"].results["torsion"]["solvers"]
        if r["method"] == "RK45"
    ]
    assert rk45 and all(
        not r["success"] and r["outcome"] == "budget" and "budget" in r["message"] for r in rk45
    )
    html, catalog, ctx = _sections(run("inline4-torsion"), "en")
    assert any("5348" in c and "5760" in c for c in ctx.conclusions)


def test_the_vector_sum_over_cranks_counts_each_cylinder_once():
    """Cranks whose torques are the first one's shifted by their delays: the crank-harmonic sum
    equals the textbook's |Σ a_k e^{iνφ_k}|. A V engine's crank carries two cylinders: its
    harmonic already sums them, so the sum over the cranks is not doubled by summing the
    cylinders again (the sum over cylinders with the crank's amplitude would give twice this)."""
    import numpy as np

    from crankdyn.physics import torsion as tor

    rng = np.random.default_rng(7)
    a, phi, order, c0 = rng.uniform(-1, 1, 5), rng.uniform(0, 4 * np.pi, 5), 2.5, 3.0 - 4.0j
    shifted = c0 * np.exp(-1j * order * phi)
    assert tor.crank_vector_sum(a, shifted) == pytest.approx(
        tor.relative_vector_sum(a, phi, order), rel=1e-12
    )
    # two cylinders a crank, their order-ν harmonics in phase (a bank angle of 360°/ν): the
    # crank's harmonic is twice a cylinder's, and the relative sum is that of the cranks alone
    bank = 2 * np.pi / order
    crank = c0 * np.exp(-1j * order * phi) + c0 * np.exp(-1j * order * (phi + bank))
    single_sum = tor.relative_vector_sum(a, phi, order)
    assert tor.crank_vector_sum(a, crank) == pytest.approx(single_sum, rel=1e-12)
    cylinders = tor.relative_vector_sum(np.repeat(a, 2), np.ravel([phi, phi + bank], "F"), order)
    assert cylinders == pytest.approx(2 * single_sum, rel=1e-12)
