"""All benchmarks in one command: compute per stage, HTML and PDF, error against run time, overhead.

Run from the repository root:

    python3 benchmarks/run_all.py                 # everything (about a minute)
    python3 benchmarks/run_all.py --quick         # fewer repeats, no PDF
    python3 benchmarks/run_all.py --examples petrol-1cyl,v8-petrol --repeat 10

Prints tables; writes nothing. Timings are the best of ``--repeat`` runs (time.perf_counter).
Not part of the test suite: timing asserts belong here, not in tests.

1. compute time of every stage for each bundled example (the report's own step);
2. HTML (with figures) and PDF (WeasyPrint) time for the examples named by --report;
3. error against run time: the angle-step study and the piston-kinematics forms of the numerics
   stage (measured on the scene, against references that do not use the method under test), and
   any solver studies plugins register with the crankdyn_error_probes hook;
4. overhead of the pipeline against a bare numpy evaluation of the same kinematics and force
   formulas, written out below (goal: the pipeline's compute part within 2x of bare numpy).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import plan, run_plan
from crankdyn.plugin.contracts import GAS_PRESSURE, KINEMATICS
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.report.pdf import html_to_pdf
from crankdyn.scene.model import load_scene

EXAMPLES = [
    "petrol-1cyl",
    "diesel-1cyl",
    "two-stroke-1cyl",
    "diesel-rk-trace",
    "kinematics-only",
    "inline4-petrol",
    "inline6-diesel-trace",
    "v8-petrol",
    "radial9-aircraft",
]
GOALS = {"compute_s": 0.050, "html_s": 2.0, "overhead": 2.0}


def best_of(fn, repeat: int):
    best, value = float("inf"), None
    for _ in range(max(1, repeat)):
        start = time.perf_counter()
        value = fn()
        best = min(best, time.perf_counter() - start)
    return best, value


def table(title: str, header: list[str], rows: list[list], widths: list[int] | None = None) -> None:
    if not rows:
        return
    widths = widths or [
        max([len(str(h))] + [len(str(r[i])) for r in rows]) for i, h in enumerate(header)
    ]
    print(f"\n{title}")
    print(
        "  ".join(
            f"{h:>{w}}" if i else f"{h:<{w}}"
            for i, (h, w) in enumerate(zip(header, widths, strict=True))
        )
    )
    print("  ".join("-" * w for w in widths))
    for row in rows:
        print(
            "  ".join(
                f"{c:>{w}}" if i else f"{c:<{w}}"
                for i, (c, w) in enumerate(zip(row, widths, strict=True))
            )
        )


def ms(seconds: float) -> str:
    return f"{seconds * 1e3:.2f}"


# --------------------------------------------------------------------------- 1. compute per stage
def compute_per_stage(registry, names, repeat):
    stage_names: list[str] = []
    per_example = {}
    for name in names:
        scene = load_scene(examples_dir() / f"{name}.toml")
        the_plan = plan(scene, registry)
        run_plan(scene, the_plan)  # warm imports and caches
        best: dict[str, float] = {}
        for _ in range(repeat):
            result = run_plan(scene, the_plan)
            for stage, seconds in result.timing_s.items():
                best[stage] = min(best.get(stage, float("inf")), seconds)
        per_example[name] = best
        stage_names += [s for s in best if s not in stage_names]
    rows = []
    for name, best in per_example.items():
        compute = sum(v for k, v in best.items() if not k.startswith("numerics"))
        verdict = "ok" if compute < GOALS["compute_s"] else "over 50 ms"
        rows.append(
            [name]
            + [ms(best[s]) if s in best else "—" for s in stage_names]
            + [ms(compute), verdict]
        )
    table(
        f"1. Compute time per stage, ms (best of {repeat}; 'compute' = all stages but the numerics study, goal < 50 ms)",
        ["example"] + stage_names + ["compute", "verdict"],
        rows,
    )


# --------------------------------------------------------------------------- 2. HTML and PDF
def report_times(registry, names, repeat, pdf: bool):
    rows = []
    for name in names:
        scene = load_scene(examples_dir() / f"{name}.toml")
        result = run_plan(scene, plan(scene, registry))
        html_s, rendered = best_of(lambda: render_html(result, registry), max(1, repeat // 4))  # noqa: B023 - called within this iteration
        pdf_s = best_of(lambda: html_to_pdf(rendered.html), 1)[0] if pdf else None  # noqa: B023 - called within this iteration
        rows.append(
            [
                name,
                ms(html_s),
                ms(pdf_s) if pdf_s is not None else "skipped",
                str(len(rendered.figures)),
                "ok" if html_s < GOALS["html_s"] else "over 2 s",
            ]
        )
    table("2. Report rendering, ms", ["example", "HTML", "PDF", "figures", "HTML verdict"], rows)


# --------------------------------------------------------------------------- 3. error against run time
def error_against_time(registry, names):
    for name in names:
        scene = load_scene(examples_dir() / f"{name}.toml")
        result = run_plan(scene, plan(scene, registry))
        output = result.outputs.get("numerics") or result.outputs.get("numerics_kinematics")
        if output is None:
            print(f"\n3. {name}: no numerics study ({result.plan.skipped.get('numerics')})")
            continue
        r = output.results
        if "steps" in r:
            rows = [
                [f"{s['angle_step_deg']:g}", str(s["points"]), ms(s["time_s"])]
                + [
                    f"{s[q + '_error_relative']:.2e}"
                    for q in (
                        "mean_torque",
                        "indicated_work",
                        "tangential_max",
                        "tangential_min",
                        "resultant_max",
                    )
                ]
                + [
                    f"{s['theoretical_work_error_relative']:.2e}"
                    if "theoretical_work_error_relative" in s
                    else "—"
                ]
                for s in r["steps"]
            ]
            table(
                f"3a. {name}: error against run time over the angle step (reference: {r['reference_method']}, "
                f"{ms(r['reference_time_s'])} ms; relative errors)",
                [
                    "step, deg",
                    "N",
                    "time, ms",
                    "M_mean",
                    "L_i",
                    "t_max",
                    "t_min",
                    "q_max",
                    "L theor.",
                ],
                rows,
            )
            for step, why in r["steps_refused"].items():
                print(f"   step {step} deg refused: {why}")
        rows = [
            [
                row["form"] + (f" {row['terms']}" if row["terms"] else ""),
                f"{row['displacement_error_max_m']:.2e}",
                f"{row['acceleration_error_max_m_s2']:.2e}",
                f"{row['time_per_evaluation_s'] * 1e6:.1f}",
            ]
            for row in r.get("kinematics_forms", [])
        ]
        if rows:
            table(
                f"3b. {name}: piston kinematics forms ({r['kinematics_forms'][0]['points']} angles; errors "
                "against the exact form in extended precision)",
                ["form", "max |ds|, m", "max |dj|/w^2, m", "time, us"],
                rows,
            )
        for study in (r.get("solvers") or {}).values():
            rows = [
                [p["method"], p["setting"], f"{p['error']:.2e} {p['error_unit']}", ms(p["time_s"])]
                for p in study["points"]
            ]
            if rows:
                table(
                    f"3c. {name}: {study['title']}",
                    ["method", "setting", "error", "time, ms"],
                    rows,
                )
            else:
                print(f"\n3c. {name}: {study['title']}: {study.get('refused', 'no points')}")


# --------------------------------------------------------------------------- 4. overhead
def bare_numpy(alpha_deg, pressure_Pa, R, lam, omega, bore, p0, m_recip, m_rot):
    """Kinematics and forces of one cylinder written out in numpy (Poda 2007 eqs. 9-11, 17-25, 34-36)."""
    a = np.radians(alpha_deg)
    sin_a, cos_a = np.sin(a), np.cos(a)
    sin_b = lam * sin_a
    cos_b = np.sqrt(1.0 - sin_b * sin_b)
    s = R * (2.0 * np.sin(0.5 * a) ** 2 + lam * sin_a * sin_a / (1.0 + cos_b))
    v = R * omega * sin_a * (1.0 + lam * cos_a / cos_b)
    j = R * omega**2 * (cos_a - sin_a * sin_b / cos_b + lam * cos_a**2 / cos_b**3)
    area = 0.25 * np.pi * bore**2
    p_j = -m_recip * j / area
    p1 = pressure_Pa - p0 + p_j
    k = p1 / cos_b
    t = k * (sin_a * cos_b + cos_a * sin_b)
    z = k * (cos_a * cos_b - sin_a * sin_b)
    n = p1 * sin_b / cos_b
    c = -(omega**2) * R * m_rot / area
    q = np.hypot(z + c, t)
    torque = t * R * area
    return {
        "s": s,
        "v": v,
        "j": j,
        "t": t,
        "z": z,
        "n": n,
        "q": q,
        "torque": torque,
        "mean_torque": float(np.mean(torque)),
        "t_max": float(t.max()),
        "q_max": float(q.max()),
    }


def bare_numpy_same_outputs(alpha_deg, pressure_Pa, R, lam, omega, bore, p0, m_recip, m_rot, l_cm):
    """Everything the kinematics and forces stages compute, in plain numpy and scipy (no tables).

    Both kinematic forms, rod angle, angular velocity and acceleration, motion of the rod's centre
    of mass, every force component, the extremes on the grid and the exact extremes of v and j by
    Brent's method (as the kinematics stage reports them).
    """
    from scipy.optimize import brentq

    out = bare_numpy(alpha_deg, pressure_Pa, R, lam, omega, bore, p0, m_recip, m_rot)
    a = np.radians(alpha_deg)
    sin_a, cos_a = np.sin(a), np.cos(a)
    sin_b = lam * sin_a
    cos_b = np.sqrt(1.0 - sin_b * sin_b)
    out["s2"] = R * ((1 + lam / 4) - (cos_a + lam / 4 * np.cos(2 * a)))
    out["v2"] = R * omega * (sin_a + lam / 2 * np.sin(2 * a))
    out["j2"] = R * omega**2 * (cos_a + lam * np.cos(2 * a))
    beta_rate = omega * lam * cos_a / cos_b
    beta_acc = -(omega**2) * lam * (1 - lam**2) * sin_a / cos_b**3
    out["beta"] = np.arcsin(sin_b)
    out["cm"] = (
        R * sin_a - l_cm * sin_b,
        R * cos_a + l_cm * cos_b,
        R * omega * cos_a - l_cm * beta_rate * cos_b,
        -R * omega * sin_a - l_cm * beta_rate * sin_b,
        -R * omega**2 * sin_a - l_cm * (beta_acc * cos_b - beta_rate**2 * sin_b),
        -R * omega**2 * cos_a - l_cm * (beta_acc * sin_b + beta_rate**2 * cos_b),
    )
    area = 0.25 * np.pi * bore**2
    out["p_jI"] = -m_recip * R * omega**2 * cos_a / area
    out["p_jII"] = -m_recip * R * omega**2 * lam * np.cos(2 * a) / area
    for key in ("t", "z", "n", "q", "torque"):
        values = out[key]
        out[key + "_extremes"] = (int(np.argmax(values)), int(np.argmin(values)))

    def accel(x):
        cb = np.sqrt(1 - (lam * np.sin(x)) ** 2)
        return np.cos(x) - np.sin(x) * lam * np.sin(x) / cb + lam * np.cos(x) ** 2 / cb**3

    def jerk_bracket(x):
        cb = np.sqrt(1 - (lam * np.sin(x)) ** 2)
        return (
            1
            + lam * np.cos(x) / cb
            + 3 * lam * np.cos(x) / cb**3
            - 3 * lam**3 * np.cos(x) ** 3 / cb**5
        )

    out["v_max_angle"] = brentq(accel, 0.0, 0.5 * np.pi, xtol=1e-300, rtol=4 * np.finfo(float).eps)
    grid = np.linspace(0.5 * np.pi, np.pi, 2049)
    values = jerk_bracket(grid)
    roots = [
        brentq(jerk_bracket, grid[i], grid[i + 1])
        for i in np.nonzero(np.diff(np.signbit(values)))[0]
    ]
    out["j_min"] = min([accel(np.pi)] + [accel(r) for r in roots])
    return out


def overhead(registry, repeat):
    from crankdyn.physics.forces import rod_mass_split_kg

    rows = []
    for name, step in (("petrol-1cyl", 1.0), ("petrol-1cyl", 0.1), ("two-stroke-1cyl", 1.0)):
        scene = load_scene(
            examples_dir() / f"{name}.toml",
            {"analysis": {"angle_step_deg": step, "table_step_deg": 30}},
        )
        stages = {s.name: s for s in registry.stages.values()}
        gas = (
            run_plan(scene, plan(scene, registry, ["indicator"]))
            .outputs["indicator"]
            .data[GAS_PRESSURE]
        )
        kin_stage, forces_stage = stages["kinematics"], stages["forces"]

        def pipeline():
            motion = kin_stage.run(scene, {})  # noqa: B023 - called within this iteration
            return forces_stage.run(scene, {KINEMATICS: motion.data[KINEMATICS], GAS_PRESSURE: gas})  # noqa: B023 - called within this iteration

        e, m = scene.engine, scene.masses
        rec, rot = rod_mass_split_kg(m.rod, e.rod_length_m, scene.rod_cm_from_big_end_m)
        args = (
            scene.crank_angles_deg,
            gas.pressure_Pa,
            e.crank_radius_m,
            e.rod_ratio_value,
            e.angular_velocity_rad_s,
            e.bore,
            e.crankcase_pressure,
            m.piston_group + rec,
            rot + m.crank_pin + 2 * m.crank_web,
        )
        pipeline()
        bare_numpy(*args)
        t_pipe, out = best_of(pipeline, repeat)
        t_bare, bare = best_of(lambda: bare_numpy(*args), repeat)  # noqa: B023 - called within this iteration
        t_same, _ = best_of(
            lambda: bare_numpy_same_outputs(*args, scene.rod_cm_from_big_end_m), repeat
        )  # noqa: B023 - called within this iteration
        frame = out.tables["forces"]
        agree = max(
            abs(out.results["mean_torque_Nm"] - bare["mean_torque"]) / abs(bare["mean_torque"]),
            float(np.max(np.abs(frame["tangential_Pa"].to_numpy() - bare["t"])))
            / abs(bare["t_max"]),
        )
        ratio = t_pipe / t_same
        rows.append(
            [
                f"{name} @ {step:g} deg",
                str(len(scene.crank_angles_deg)),
                ms(t_pipe),
                ms(t_same),
                ms(t_bare),
                f"{ratio:.1f}x",
                f"{t_pipe / t_bare:.1f}x",
                f"{agree:.1e}",
                "ok" if ratio <= GOALS["overhead"] else "over 2x",
            ]
        )
    table(
        "4. Pipeline (kinematics + forces stages) against bare numpy of the same formulas "
        f"(best of {repeat}; goal: within {GOALS['overhead']:g}x of 'same outputs')",
        [
            "case",
            "N",
            "pipeline, ms",
            "same outputs, ms",
            "arrays only, ms",
            "ratio",
            "vs arrays",
            "max rel diff",
            "verdict",
        ],
        rows,
    )
    print(
        "   'same outputs': both kinematic forms, rod and centre-of-mass motion, all force components, grid and\n"
        "   exact extremes (Brent) in plain numpy/scipy; 'arrays only': s, v, j and the forces. The stages add the\n"
        "   pandas tables (CSV), argument checks in every physics call and the results dictionaries."
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument(
        "--examples", default=",".join(EXAMPLES), help="comma-separated bundled examples"
    )
    parser.add_argument(
        "--report", default="petrol-1cyl,v8-petrol", help="examples whose HTML/PDF are timed"
    )
    parser.add_argument(
        "--errors",
        default="petrol-1cyl,radial9-aircraft,kinematics-only",
        help="examples whose error-against-time studies are printed",
    )
    parser.add_argument("--repeat", type=int, default=10)
    parser.add_argument("--quick", action="store_true", help="3 repeats, no PDF")
    parser.add_argument("--no-pdf", action="store_true")
    args = parser.parse_args()
    repeat = 3 if args.quick else args.repeat
    registry = default_registry()
    start = time.perf_counter()
    print(f"crankdyn benchmarks (best of {repeat} unless stated)")
    compute_per_stage(registry, [n for n in args.examples.split(",") if n], repeat)
    report_times(
        registry,
        [n for n in args.report.split(",") if n],
        repeat,
        pdf=not (args.quick or args.no_pdf),
    )
    error_against_time(registry, [n for n in args.errors.split(",") if n])
    overhead(registry, max(repeat, 5))
    print(f"\nall benchmarks: {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
