"""The numerics stage: error against run time measured on the scene, with independent references."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from conftest import as_read, modified, shared_html, shared_run

import crankdyn.plugin_types as plugin_types
from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import Runner, check_scene, run_scene
from crankdyn.errors import SceneError
from crankdyn.physics import indicator as ind
from crankdyn.physics import series
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.registry import collect, default_registry, plugin_manager
from crankdyn.report.context import RenderContext
from crankdyn.report.document import _environment
from crankdyn.report.i18n import translator
from crankdyn.scene.model import scene_from_dict
from crankdyn_builtin.numerics import compute, options, reference, steps
from crankdyn_builtin.numerics.section import _course_coarse, _error_words

REGISTRY = default_registry()
ENGINE_EXAMPLES = [
    "petrol-1cyl",
    "diesel-1cyl",
    "two-stroke-1cyl",
    "diesel-rk-trace",
    "inline4-petrol",
    "inline6-diesel-trace",
    "v8-petrol",
    "radial9-aircraft",
    "offset-crank-engine",
]
FAST = {"numerics": {"steps_deg": [10], "repeats": 1}}
# The examples as they are, but with no time budget: which steps run must not depend on the load
# of the machine (the budget itself is tested below).
UNLIMITED = {"numerics": {"time_budget_s": 3600}}


def run(name, changes=None):
    """One computation per scene and test process, shared with the other test files (read only)."""
    return shared_run(name, changes)


def render_section(result, stage="numerics", language="en", detail="full"):
    """Only the stage's own section (the whole report is tested in test_leave_out), as the report
    of ``[report] detail`` shows it: the full study, or a course note's statement."""
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
    ctx.start_section(7, stage)
    look = next(s for s in result.plan.order if s.name == stage).presentation
    html = look.render(result.outputs[stage], ctx)
    return html, ctx, t


@pytest.mark.parametrize("name", ENGINE_EXAMPLES)
def test_every_engine_example_measures_its_error_against_run_time(name):
    result = run(name, UNLIMITED)
    assert "numerics" in result.stages_run and "numerics_kinematics" in result.plan.skipped
    assert result.stages_run[-1] == "numerics"  # it judges the sections before it
    r = result.outputs["numerics"].results
    # independent of the method under test; a mechanism known only by its displacement gets
    # the integrals and t from the pointwise model and q_max from a 0.05-deg run ("mixed")
    assert r["reference_method"] == (
        "quadrature" if result.scene.engine.mechanism == "crank_slider" else "mixed"
    )
    scene_step = result.scene.analysis.angle_step_deg
    steps = {s["angle_step_deg"]: s for s in r["steps"]}
    assert scene_step in steps and 0.1 in steps and len(steps) >= 6
    for s in r["steps"]:
        assert s["time_s"] > 0 and s["points"] == round(
            result.scene.engine.cycle_deg / s["angle_step_deg"]
        )
        for q in compute.QUANTITIES:
            assert math.isfinite(s[f"{q}_error_relative"])
    # The re-run at the scene's step reproduces the numbers the other sections print.
    forces = result.outputs["forces"].results
    mean = (
        result.outputs["torque"].results["mean_Nm"]
        if "torque" in result.outputs
        else result.scene.engine.cylinders * forces["mean_torque_Nm"]
    )
    shown = {
        "mean_torque_Nm": mean,
        "indicated_work_J": result.outputs["indicator"].results["indicated_work_J"],
        "tangential_max_Pa": forces["tangential_max_Pa"],
        "tangential_min_Pa": forces["tangential_min_Pa"],
        "resultant_max_Pa": forces["resultant_max_Pa"],
    }
    for key, value in shown.items():
        assert r["at_scene_step"][key] == pytest.approx(value, rel=1e-12, abs=1e-9)
        assert steps[scene_step][key] == r["at_scene_step"][key]
    # Converges to the reference: at 0.1 deg the integrals agree to 1e-5, the extremes to 1e-4,
    # and the finest step is better than the coarsest.
    fine, coarse = steps[0.1], steps[max(steps)]
    assert (
        fine["mean_torque_error_relative"] < 1e-5 and fine["indicated_work_error_relative"] < 1e-5
    )
    assert (
        max(
            fine[f"{q}_error_relative"]
            for q in ("tangential_max", "tangential_min", "resultant_max")
        )
        < 1e-4
    )
    for q in ("mean_torque", "indicated_work"):
        assert fine[f"{q}_error_relative"] < coarse[f"{q}_error_relative"]
    # the reference is far more accurate than anything it judges
    assert max(r["reference_uncertainty_relative"].values()) < 1e-8
    # the section states the error of the printed numbers, with its measured figures
    html, ctx, t = render_section(result)
    assert not t.missing
    assert html.count('src="figures/') == (
        2 if result.scene.engine.mechanism == "crank_slider" else 1
    )
    assert 'data-part="steps"' in html
    assert f"Δα = {scene_step:g}°, the printed numbers carry these errors" in html
    assert ctx.conclusions and "mean torque ±" in ctx.conclusions[0]


def test_reference_quadrature_matches_the_closed_form_of_the_theoretical_diagram():
    """The Gauss-Legendre reference against the closed-form work of the sharp diagram (p_i' + pumping)."""
    scene = run("petrol-1cyl").scene
    model = reference.PointwiseModel(scene)
    params = model._params
    model.pressure = lambda a: ind.theoretical_pressure_Pa(
        a, model.volume(a), model.clearance, params
    )
    work, _ = model.integrals()
    closed = (
        ind.theoretical_mean_indicated_pressure_Pa(params)
        + params.intake_pressure_Pa
        - params.exhaust_pressure_Pa
    ) * model.swept
    assert work == pytest.approx(closed, rel=1e-10)
    # ...while the trapezoidal rule of the pipeline at 1 deg is off by ~1e-4: the reference is not it
    steps = {
        s["angle_step_deg"]: s
        for s in run("petrol-1cyl", UNLIMITED).outputs["numerics"].results["steps"]
    }
    assert 1e-5 < steps[1.0]["theoretical_work_error_relative"] < 1e-3


def test_mean_torque_reference_is_virtual_work():
    """Two independent integrals of the pointwise model: mean torque and indicated work / cycle angle."""
    model = reference.PointwiseModel(run("petrol-1cyl").scene)
    work, mean = model.integrals()
    assert mean == pytest.approx(work / (4 * math.pi), rel=1e-9)


def test_pointwise_model_from_displacement_alone_matches_the_analytic_one():
    """The generic model (numerical derivatives of displacement_at, t by virtual work) against the
    crank-slider formulas: the reference for other mechanisms is as good as the analytic one."""
    result = run("petrol-1cyl")
    analytic = reference.PointwiseModel(result.scene)
    generic = reference.PointwiseModel(
        result.scene.model_copy(
            update={
                "engine": result.scene.engine.model_copy(
                    update={"mechanism": "offset_crank_slider"}
                )
            }
        ),
        result.outputs["kinematics"].data["kinematics"],
    )
    assert generic.analytic is False
    a = np.linspace(0.0, 720.0, 2001)
    np.testing.assert_allclose(
        generic.arm(a), analytic.arm(a), rtol=0, atol=1e-10 * analytic.radius
    )
    np.testing.assert_allclose(
        generic.acceleration(a),
        analytic.acceleration(a),
        rtol=0,
        atol=1e-7 * analytic.radius * analytic.omega**2,
    )
    t_generic, q_generic, _ = generic.forces(a)
    t_analytic, _, _ = analytic.forces(a)
    assert q_generic is None
    np.testing.assert_allclose(
        t_generic, t_analytic, rtol=0, atol=1e-6 * np.max(np.abs(t_analytic))
    )
    for g, h in zip(generic.integrals(), analytic.integrals(), strict=True):
        assert g == pytest.approx(h, rel=1e-9)


def test_articulated_reference_sums_master_and_slave_work():
    r = run("radial9-aircraft", UNLIMITED).outputs["numerics"].results
    reference = r["reference"]["mean_torque_Nm"]
    pipeline = next(s for s in r["steps"] if s["angle_step_deg"] == 0.1)["mean_torque_Nm"]
    assert pipeline == pytest.approx(reference, rel=1e-6)
    # the slaves make a real difference: nine times the master's work is not the answer
    work = r["reference"]["indicated_work_J"]
    assert abs(reference - 9 * work / (4 * math.pi)) / reference > 1e-3


def test_scene_copy_at_another_step_is_faithful():
    # the scene of the run below (shared with the other tests here): a run of its own only for the scene
    # would be the costliest in this file (the radial's full numerics study)
    scene = run("radial9-aircraft", UNLIMITED).scene
    copy = steps.scene_with_step(scene, 0.5)
    assert copy.analysis.angle_step_deg == 0.5 and copy.analysis.table_step_deg == 0.5
    assert copy.plugin_tables() == scene.plugin_tables() and copy.base_dir == scene.base_dir
    assert copy.engine == scene.engine and copy.cycle == scene.cycle and copy.masses == scene.masses
    with pytest.raises(SceneError, match="must divide the cycle"):
        steps.scene_with_step(scene, 7.0)
    with pytest.raises(
        SceneError, match="firing delays"
    ):  # 30 deg does not divide the 40-deg banks
        steps.run_at_step(scene, 30.0, repeats=1, runner=Runner(REGISTRY))
    # The study moves 30 and 15 deg onto the engine's 40-deg grid: 20 and 40/3 deg, none refused.
    results = run("radial9-aircraft", UNLIMITED).outputs["numerics"].results
    assert results["steps_refused"] == {}
    studied = [row["angle_step_deg"] for row in results["steps"]]
    assert studied[:3] == pytest.approx([20.0, 40 / 3, 10.0], rel=1e-15)


@pytest.mark.parametrize("ratio", [0.001, 0.28, 0.99])
def test_kinematics_forms_against_independent_errors(ratio):
    radius = 0.04
    rows = {
        (r["form"], r["terms"]): r for r in reference.kinematics_forms(radius, ratio, repeats=1)
    }
    # the grid holds 90 deg, where every truncated form has its largest displacement error
    for terms in (3, 4, 5):
        expected = series.displacement_truncation_error_max_m(radius, ratio, terms)
        for form in ("series", "harmonic"):
            assert rows[(form, terms)]["displacement_error_max_m"] == pytest.approx(
                expected, rel=1e-9, abs=1e-15 * radius
            )
    assert rows[("two_term", 2)]["displacement_error_max_m"] == pytest.approx(
        series.displacement_truncation_error_max_m(radius, ratio, 2), rel=1e-9, abs=1e-15 * radius
    )
    assert rows[("exact", None)]["displacement_error_max_m"] < 1e-14 * radius  # a few ulp of 2R
    assert rows[("exact", None)]["acceleration_error_max_m_s2"] < 1e-12 * radius
    errors = [
        rows[k]["displacement_error_max_m"]
        for k in (("two_term", 2), ("series", 3), ("series", 4), ("series", 5))
    ]
    assert all(b < a or a < 1e-15 * radius for a, b in zip(errors, errors[1:], strict=False))
    assert all(r["time_per_evaluation_s"] > 0 for r in rows.values())


def test_two_term_error_agrees_with_the_kinematics_stage():
    result = run("petrol-1cyl")
    rows = result.outputs["numerics"].results["kinematics_forms"]
    two_term = next(r for r in rows if r["form"] == "two_term")
    assert two_term["displacement_error_max_m"] == pytest.approx(
        result.outputs["kinematics"].results["two_term_displacement_error_max_m"], rel=1e-9
    )


def test_kinematics_only_scene_gets_the_kinematics_part():
    result = run("kinematics-only")
    assert result.stages_run == ["kinematics", "drawing", "numerics_kinematics"]
    assert "numerics" in result.plan.skipped and "no [cycle]" in result.plan.skipped["numerics"]
    r = result.outputs["numerics_kinematics"].results
    assert {row["form"] for row in r["kinematics_forms"]} == {
        "two_term",
        "series",
        "harmonic",
        "exact",
    }
    html, _, t = render_section(result, "numerics_kinematics", "uk")
    assert (
        not t.missing and 'data-part="kinematics-forms"' in html and 'data-part="steps"' not in html
    )


class FakeClock:
    """A clock that only the timed functions advance: each call costs what its script says."""

    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now

    def function(self, costs):
        costs = iter(costs)

        def fn():
            self.now += next(costs)

        return fn


def test_best_times_autoranges_and_keeps_the_best_repeat_per_call():
    clock = FakeClock()
    # f costs 1 ms per call, but 5 ms in its first (autorange) call, as under load; g costs 0.3 ms.
    f_costs = [5e-3] + [1e-3] * 10  # autorange: 1 call (>= 1 ms) per repeat; then 3 more repeats
    g_costs = [3e-4] * 100
    timings = steps.best_times(
        [clock.function(f_costs), clock.function(g_costs)], 4, min_time_s=1e-3, clock=clock
    )
    assert [t.repeats for t in timings] == [4, 4]
    assert timings[0].loops == 1 and timings[0].best_s == pytest.approx(
        1e-3
    )  # the slow repeat is not kept
    # g: 1 call (0.3 ms) and 2 calls (0.6 ms) are too short, 5 calls (1.5 ms) are enough (timeit's 1, 2, 5, 10 ...)
    assert timings[1].loops == 5 and timings[1].best_s == pytest.approx(3e-4)


def test_best_times_takes_the_repeats_in_turns():
    clock, order = FakeClock(), []

    def timed(name):
        def fn():
            order.append(name)
            clock.now += 1e-3

        return fn

    steps.best_times([timed("a"), timed("b")], 3, min_time_s=1e-3, clock=clock)
    # autorange of each, then two rounds over both (backwards, forwards), each timed repeat after one
    # untimed call
    assert order == ["a", "b"] + ["b", "b", "a", "a"] + ["a", "a", "b", "b"]


def test_best_times_stops_once_the_minima_have_settled():
    clock = FakeClock()
    # a steady 1 ms per call: after the autorange repeat, no round lowers the best, so three quiet
    # rounds end the timing at 4 repeats of the 15 allowed
    steady = clock.function([1e-3] * 100)
    timings = steps.best_times([steady], 15, min_time_s=1e-3, clock=clock, settled_rounds=3)
    assert timings[0].repeats == 4 and timings[0].best_s == pytest.approx(1e-3)
    # a machine under load: the time keeps falling by more than 1 % a round for 8 rounds, so the
    # timing goes on until three rounds in a row lower nothing
    falling = [2e-3 * 0.9**k for k in range(8)]
    loaded = clock.function([c for c in falling for _ in (0, 1)] + [falling[-1]] * 100)
    timings = steps.best_times([loaded], 15, min_time_s=1e-3, clock=clock, settled_rounds=3)
    assert timings[0].repeats == 11 and timings[0].best_s == pytest.approx(falling[-1])
    # without settled_rounds every repeat is taken
    assert (
        steps.best_times([clock.function([1e-3] * 100)], 6, min_time_s=1e-3, clock=clock)[0].repeats
        == 6
    )


def test_step_times_are_the_formulas_with_the_overhead_apart():
    result = run("petrol-1cyl", UNLIMITED)
    r = result.outputs["numerics"].results
    assert r["steps_timed"] == "formulas" and r["steps_timing_repeats"] > 1
    assert options.NumericsOptions().repeats > 1
    assert r["per_call_overhead_s"] > 0
    for row in r["steps"]:
        # the whole re-run costs the formulas plus at least the fixed overhead
        assert row["rerun_time_s"] >= row["time_s"] + r["per_call_overhead_s"] * (1 - 1e-9)
        assert row["timing_loops"] >= 1
    for language in ("en", "uk", "ru"):
        html, ctx, t = render_section(result, "numerics", language)
        assert not t.missing and f" {r['steps_timing_repeats']} " in html
        assert (
            "timeit" not in html
        )  # how the time is measured, in words: no software names in the note
        assert ctx.num(r["per_call_overhead_s"] * 1e3, 2) in html


def test_options_table_steps_repeats_and_budget():
    r = (
        run("petrol-1cyl", {"numerics": {"steps_deg": [10, 5], "repeats": 1}})
        .outputs["numerics"]
        .results
    )
    assert [s["angle_step_deg"] for s in r["steps"]] == [10.0, 5.0, 1.0]
    r = run("petrol-1cyl", {"numerics": {"time_budget_s": 1e-9}}).outputs["numerics"].results
    assert [s["angle_step_deg"] for s in r["steps"]] == [1.0]
    assert (
        all("time budget" in why for why in r["steps_refused"].values())
        and len(r["steps_refused"]) == 8
    )
    scene = scene_from_dict(
        modified("petrol-1cyl", {"numerics": {"repeats": 0, "step": 1}}), base_dir=examples_dir()
    )
    with pytest.raises(SceneError) as info:
        check_scene(scene, REGISTRY)
    assert {p.field for p in info.value.problems} == {"numerics.repeats", "numerics.step"}


def test_solver_probes_add_rows():
    """Probes come from the documented ``crankdyn_error_probes`` hook of any plugin."""
    calls = []

    def study(scene, runner):
        assert isinstance(runner, Runner) and "forces" in runner.stages
        calls.append(scene.engine.rpm)
        return [
            plugin_types.ProbePoint(
                "RK45", f"rtol = 1e-{k}", 10.0**-k, "rad/s", 1e-3 * k, "analytic"
            )
            for k in (3, 6, 9)
        ]

    def refused(scene, runner):
        raise SceneError([])

    class ProbePlugin:
        @hookimpl
        def crankdyn_error_probes(self):
            return [
                plugin_types.ErrorProbe("test-solver", "Test solver", lambda s: True, study),
                plugin_types.ErrorProbe("test-refused", "Refusing solver", lambda s: True, refused),
                plugin_types.ErrorProbe("test-not-here", "Other", lambda s: False, study),
            ]

    registry = collect(plugin_manager(extra_plugins=[ProbePlugin()]))
    assert set(registry.error_probes) == {"test-solver", "test-refused", "test-not-here"}
    result = run_scene(
        scene_from_dict(modified("petrol-1cyl", FAST), base_dir=examples_dir()), registry
    )
    solvers = result.outputs["numerics"].results["solvers"]
    assert set(solvers) == {"test-solver", "test-refused"} and calls == [5600]
    assert [p["setting"] for p in solvers["test-solver"]["points"]] == [
        "rtol = 1e-3",
        "rtol = 1e-6",
        "rtol = 1e-9",
    ]
    html, _, t = render_section(result)
    assert not t.missing and "Test solver: error against run time" in html
    assert "Refusing solver: not studied" in html
    # without the plugin, no solver rows
    plain = run_scene(
        scene_from_dict(modified("petrol-1cyl", FAST), base_dir=examples_dir()), REGISTRY
    )
    assert "solvers" not in plain.outputs["numerics"].results


def test_a_stage_marked_last_comes_after_the_others_it_does_not_need():
    """Stage.last (used by numerics) orders a summary after every stage ready at the same time."""
    from crankdyn.engine.orchestrator import plan
    from crankdyn.plugin.registry import Registry
    from crankdyn.plugin.types import Stage, StageOutput, StagePresentation

    def stage(name, requires=(), provides=(), last=False):
        return Stage(
            name=name,
            requires=requires,
            provides=provides,
            applies=lambda s: None,
            run=lambda s, i: StageOutput(),
            last=last,
            presentation=StagePresentation(title_key="x", render=lambda o, c: None),
        )

    registry = Registry(
        stages={
            s.name: s
            for s in (
                stage("aaa_summary", requires=("a",), last=True),
                stage("bbb", provides=("a",)),
                stage("ccc", requires=("a",), provides=("c",)),
                stage("zzz", requires=("c",)),
            )
        }
    )
    scene = run("kinematics-only").scene
    assert [s.name for s in plan(scene, registry).order] == ["bbb", "ccc", "zzz", "aaa_summary"]
    # without the hint the name decides, as before
    registry.stages["aaa_summary"] = stage("aaa_summary", requires=("a",))
    assert [s.name for s in plan(scene, registry).order] == ["bbb", "aaa_summary", "ccc", "zzz"]


def test_a_course_note_states_the_step_and_its_errors_without_run_time():
    """``detail = "course"``: the step and the errors of the main results at it, against the
    coarsest step studied; no run time, table, figure, solver or series comparison."""
    result = run("inline4-petrol", UNLIMITED)
    r = result.outputs["numerics"].results
    html, ctx, t = render_section(result, detail="course")
    assert not t.missing and not ctx.figures and "<table" not in html
    coarse = max(r["steps"], key=lambda s: s["angle_step_deg"])
    assert "At the step of this report, Δα = 1°" in html
    worst = max(compute.QUANTITIES, key=lambda q: coarse[f"{q}_error_relative"])
    # one plain clause: what the coarsest step would cost, and to which result
    assert (
        f"With a coarser step, Δα = {coarse['angle_step_deg']:g}°, the relative "
        f"error of {t(f'numerics.q_{worst}')} would grow to "
        f"{ctx.num(100 * coarse[f'{worst}_error_relative'], 2)} %." in html
    )
    for word in (" ms", "second", "shorten", "calculation time", "At this step the calculation"):
        assert word not in html
    for word in ("RK45", "Radau", "BDF", "LSODA", "Jacobian", "series", "Maclaurin"):
        assert word not in html
    kinematics_only = run("kinematics-only", UNLIMITED)
    assert render_section(kinematics_only, "numerics_kinematics", detail="course")[0] is None


@pytest.mark.parametrize(
    ("language", "expected"),
    [
        (
            "en",
            "With a coarser step, Δα = 30°, the relative error of M_m would grow to 1.2 %.",
        ),
        (
            "ru",
            "При более грубом шаге Δα = 30° относительная погрешность M_ср возросла бы до 1,2 %.",
        ),
        (
            "uk",
            "За грубішого кроку Δα = 30° відносна похибка M_сер зросла б до 1,2 %.",
        ),
    ],
)
def test_a_course_note_states_what_a_coarser_step_costs_in_errors_only(language, expected):
    """A coarse step with errors of 1,234 % (of the mean torque) and 0,5 % and a run time of
    seconds: the note states the larger error to two digits, the result it is of, and no time."""
    result = run("inline4-petrol", UNLIMITED)
    _, ctx, _ = render_section(result, detail="course", language=language)
    errors = {f"{q}_error_relative": 0.0 for q in compute.QUANTITIES}
    coarse = {"angle_step_deg": 30.0, "time_s": 2.345, **errors}
    coarse["mean_torque_error_relative"] = 0.01234
    coarse["tangential_max_error_relative"] = 0.005
    assert _course_coarse(coarse, ctx) == expected


def test_a_course_note_bounds_an_error_below_a_thousandth_instead_of_printing_it():
    """6,7·10⁻⁶ MPa reads as a program's precision: below 0,001 the note says "below 0.001"; an
    error of 0,006 74 is "up to 0.0067" (two digits)."""
    result = run("inline4-petrol", UNLIMITED)
    _, ctx, _ = render_section(result, detail="course")
    assert _error_words(ctx, 6.7e-6) == "below 0.001"
    assert _error_words(ctx, 0.00674) == "up to 0.0067"
    assert _error_words(ctx, 12.34) == "up to 12"


def test_sorted_distinct_equals_numpy_unique():
    rng = np.random.default_rng(7)
    for _ in range(300):
        values = np.round(rng.uniform(0.0, 720.0, rng.integers(0, 60)), rng.integers(0, 3))
        values = np.concatenate([values, values[: rng.integers(0, 5)]])  # repeated knots
        assert np.array_equal(reference._sorted_distinct(values), np.unique(values))


@pytest.mark.parametrize(
    ("kinematics", "said"),
    [
        ("exact", "Piston kinematics: exact closed forms (no truncation error)."),
        ("approximate", "Piston kinematics: the textbook two-term series [1, eq. 9–11]"),
    ],
)
def test_the_appendix_states_the_piston_kinematics_method_once(kinematics, said):
    """The appendix of numerical parameters names the kinematics the mechanism's own stage used,
    once: the stage's note says it (with its source), the appendix's opening sentence does not
    say it again."""
    html = shared_html("petrol-1cyl", {"analysis": {"kinematics": kinematics}}).html
    text = re.sub(r"<[^>]+>", "", as_read(html))
    appendix = text[text.rindex("Numerical parameters of the calculation and accuracy checks") :]
    assert appendix.count("Piston kinematics") == 1
    assert said in appendix
