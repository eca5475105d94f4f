"""The ``speed_fluctuation`` stage's section: ``render``, the tables and the conclusions of its text."""

from __future__ import annotations

from crankdyn.plugin.scene_inputs import engine_layout
from crankdyn.plugin.types import StageOutput, Symbol
from crankdyn.report.typeset import symbol_html
from crankdyn.scene import options
from crankdyn_builtin.speed_fluctuation.worked import speed_digits, worked_speed_fluctuation

from .figures import _error_figure, _speed_figure, last_crank, no_flywheel
from .options import TorsionOptions
from .solver_text import _digits_that_differ, _sci, _solver_table
from .torsion_section import _torsion_parts

#: The significant digits of the coefficient of cyclic irregularity a course note states: the
#: flywheel section's (the δ the flywheel is designed with and the abstract names), so that one
#: δ is printed alike in the abstract, the sections and the conclusions.
ADOPTED_DELTA_DIGITS = 3
#: The significant digits a course note gives the exact periodic solution's δ with (speeds that
#: differ by under a percent hold no more); the flywheel stage raises its flywheel when that δ
#: shows above [δ] at these digits, so that no printed exact δ exceeds [δ] unremarked.
EXACT_DELTA_DIGITS = 4


def _energy_offset_text(ctx, r, number: str) -> str | None:
    """Why the energy method's speed curve lies above or below the exact one in the speed
    figure: it is centred on (ω_max + ω_min)/2 = πn/30, the exact solution's time mean Φ/T is
    πn/30; None where the offset does not show in the speeds' printed digits."""
    omega_n = r["omega_mean_rad_s"]
    offset = omega_n - 0.5 * (r["omega_max_rad_s"] + r["omega_min_rad_s"])
    digits = speed_digits(r["omega_max_rad_s"], r["omega_min_rad_s"])
    if ctx.num(omega_n, digits) == ctx.num(omega_n - offset, digits):
        return None
    return ctx.t(
        "speed_fluctuation.energy_offset_" + ("above" if offset > 0 else "below"),
        number=number,
        offset=ctx.num(abs(offset), 2),
        omega_n=ctx.num(omega_n, digits),
    )


def _course_digits(ctx, exact: float, energy: float, digits: int, most: int) -> int:
    """``digits`` if the exact and the energy method's δ print differently with them, else
    ``most`` (the digits that show their difference)."""
    return digits if ctx.num(exact, digits) != ctx.num(energy, digits) else max(digits, most)


def _exceeds_text(ctx, r, digits: int) -> str | None:
    """The sentence saying that the exact periodic solution exceeds the required δ and how large
    the flywheel would have to be (the exact solution's own, ``flywheel_inertia_ode_kg_m2``;
    δ falls about as 1/J); None when the requirement is met or there is none."""
    required, needed = r.get("required_irregularity"), r.get("flywheel_inertia_ode_kg_m2")
    used = r.get("flywheel_inertia_kg_m2")
    # an excess that the δ printed (three significant digits) does not show is none
    shown = float(f"{r['irregularity']:.{ADOPTED_DELTA_DIGITS}g}")
    if required is None or needed is None or not used or shown <= required or needed <= used:
        return None
    return ctx.t(
        "speed_fluctuation.exceeds",
        exact=ctx.num(r["irregularity"], digits),
        excess=ctx.num(100.0 * (r["irregularity"] / required - 1.0), 2),
        required=ctx.t.number_g(required, 6),
        delta=ctx.num(r["irregularity_energy"], ADOPTED_DELTA_DIGITS),
        used=ctx.num(used),
        growth=ctx.num(100.0 * (needed / used - 1.0), 2),
        inertia=ctx.num(needed),
    )


def _raised_conclusion(ctx, r) -> str | None:
    """The conclusion with a flywheel raised to the exact solution's: that solution gives [δ]
    with it; None for a flywheel of the energy method or a chosen one."""
    if not r.get("flywheel_raised"):
        return None
    return ctx.t(
        "speed_fluctuation.conclusion_course_raised",
        flywheel=ctx.num(r["flywheel_inertia_kg_m2"]),
        delta=ctx.num(r["irregularity"], ADOPTED_DELTA_DIGITS),
        required=ctx.t.number_g(r["required_irregularity"], 6),
        # to the exact solution's digits: at the adopted ones it could print as that δ beside a
        # difference of the two
        energy=ctx.num(r["irregularity_energy"], EXACT_DELTA_DIGITS),
        deviation=ctx.num(r["irregularity_deviation_percent"], 2),
    )


def _chain_end(torsion) -> dict:
    """How the torsional chain ends, for its texts: ``bare``, the keys' ending of a chain without
    a flywheel disc (:func:`no_flywheel`), and ``last``, its last crank, then the reference disc."""
    if not torsion:
        return {"bare": "", "last": 0}
    return {"bare": no_flywheel(torsion), "last": last_crank(torsion)}


def _conclude(ctx, r, course: bool) -> tuple[int, bool, str | None]:
    """Conclude on δ (a course note with the flywheel section's digits) and on a δ above [δ];
    (δ's significant digits, whether the exact and the energy method's δ print alike, the
    sentence of a δ above [δ] or None)."""
    t = ctx.t
    digits = _digits_that_differ(r["irregularity_deviation_percent"] / 100)
    alike = False
    if course:  # δ from speeds that differ by under a percent: four digits are all it holds
        digits = EXACT_DELTA_DIGITS
        alike = ctx.num(r["irregularity"], digits) == ctx.num(r["irregularity_energy"], digits)
        exact_digits = _course_digits(
            ctx, r["irregularity"], r["irregularity_energy"], ADOPTED_DELTA_DIGITS, digits
        )
        exceeds = _exceeds_text(ctx, r, exact_digits)
        ctx.conclude(
            exceeds
            or _raised_conclusion(ctx, r)
            or t(
                "speed_fluctuation.conclusion_course",
                delta=ctx.num(r["irregularity_energy"], ADOPTED_DELTA_DIGITS),
                exact=ctx.num(r["irregularity"], exact_digits),
                deviation=ctx.num(r["irregularity_deviation_percent"], 2),
            )
        )
    else:
        exceeds = _exceeds_text(ctx, r, digits)
        ctx.conclude(
            t(
                "speed_fluctuation.conclusion",
                delta=ctx.num(r["irregularity"], digits),
                energy=ctx.num(r["irregularity_energy"], digits),
                deviation=ctx.num(r["irregularity_deviation_percent"], 2),
                method=r["solver"]["method"],
            )
        )
        if exceeds:
            ctx.conclude(exceeds)
    return digits, alike, exceeds


def render(output: StageOutput, ctx) -> str:
    """The section: the speed over the cycle and the single-mass solver study, then the torsional
    model when the scene has one, and the conclusions."""
    t = ctx.t
    r = output.results
    # a course note gives the results; the solvers' comparison is the full report's study
    course = ctx.scene is not None and ctx.scene.report.detail == "course"
    figure_speed = _speed_figure(output.tables.arrays("speed_fluctuation"), r, ctx)
    energy_offset = _energy_offset_text(ctx, r, ctx.last_figure_number)
    table_single = figure_single = None
    if not course:
        table_single = _solver_table(
            ctx,
            r["solvers"],
            t("speed_fluctuation.single_table_caption"),
            "speed_fluctuation.see_single_table",
        )
        figure_single = _error_figure(
            ctx,
            r["solvers"],
            t("speed_fluctuation.single_figure_caption"),
            "solvers_single",
            "speed_fluctuation.see_single_figure",
        )

    torsion = r["torsion"]
    ctx.title = None if torsion else t("speed_fluctuation.title_rigid")  # promise no torsion
    parts = _torsion_parts(ctx, output, torsion, course) if torsion is not None else {}
    digits, alike, exceeds = _conclude(ctx, r, course)
    return ctx.render_template(
        "sections/speed_fluctuation.html.j2",
        r=r,
        torsion=torsion,
        **_chain_end(torsion),
        omega_digits=speed_digits(r["omega_max_rad_s"], r["omega_min_rad_s"]),
        delta_digits=digits,
        cylinders=ctx.scene.engine.cylinders,
        cranks=engine_layout(ctx.scene).cranks,
        course=course,
        adopted_digits=ADOPTED_DELTA_DIGITS,
        alike=alike,
        flywheel_difference=_printed_difference_percent(r),
        sci=lambda value: _sci(value, t.decimal_separator),
        figure_speed=figure_speed,
        energy_offset=energy_offset,
        table_single=table_single,
        figure_single=figure_single,
        worked=worked_speed_fluctuation(ctx, r),
        exceeds=exceeds,
        **parts,
    )


#: The torsional model's letters (meanings: symbol.speed_fluctuation.<key> in i18n/): i numbers
#: the discs, s the modes.
_I = {"en": "i"}

SYMBOLS = {
    "disc_inertia": Symbol("J", _I, "unit.kg_m2", html="<i>J</i><sub><i>i</i></sub>"),
    "disc_inertia_derivative": Symbol(
        "J", _I, "unit.kg_m2_rad", html="<i>J</i>′<sub><i>i</i></sub>"
    ),
    "disc_angle": Symbol("θ", _I, "speed_fluctuation.unit_rad", html="<i>θ</i><sub><i>i</i></sub>"),
    "disc_speed": Symbol("θ\u0307", _I, "unit.rad_s", html="<i>θ\u0307</i><sub><i>i</i></sub>"),
    "disc_acceleration": Symbol(
        "θ\u0308", _I, "unit.rad_s2", html="<i>θ\u0308</i><sub><i>i</i></sub>"
    ),
    "disc_angles": Symbol("θ", {}, "speed_fluctuation.unit_rad", html="<b><i>θ</i></b>"),
    "disc_speeds": Symbol("θ\u0307", {}, "unit.rad_s", html="<b><i>θ\u0307</i></b>"),
    "disc_gas_torque": Symbol(
        "M", {"en": "g", "uk": "г", "ru": "г"}, "unit.Nm", html="<i>M</i><sub>{sub},<i>i</i></sub>"
    ),
    "stiffness_matrix": Symbol("K", {}, "speed_fluctuation.unit_N_m_rad", html="<b>K</b>"),
    "damping_matrix": Symbol("C", {}, "speed_fluctuation.unit_N_m_s_rad", html="<b>C</b>"),
    "inertia_matrix": Symbol("M", {}, "unit.kg_m2", html="<b>M</b>"),
    "mode_matrix": Symbol("Φ", {}, "", html="<b>Φ</b>"),
    "kronecker": Symbol("δ", {}, "", html="<i>δ</i><sub><i>i</i><i>N</i></sub>"),
    "mode_shape": Symbol("v", {"en": "s"}, "", html="<b><i>v</i></b><sub><i>s</i></sub>"),
    "span_stiffness": Symbol(
        "c", _I, "speed_fluctuation.unit_N_m_rad", html="<i>c</i><sub><i>i</i></sub>"
    ),
    "natural_frequency_Hz": Symbol(
        "f", {"en": "s"}, "speed_fluctuation.unit_Hz", html="<i>f</i><sub><i>s</i></sub>"
    ),
    "natural_frequency": Symbol("ω", {"en": "s"}, "unit.rad_s", html="<i>ω</i><sub><i>s</i></sub>"),
    "damping_ratio": Symbol("ζ", {}, ""),
}


def _printed_difference_percent(r) -> float | None:
    """The exact solution's flywheel over the energy method's, less one, in per cent, from the two
    as the text prints them (four digits), so that the reader's division gives the same."""
    ode, energy = r.get("flywheel_inertia_ode_kg_m2"), r.get("flywheel_inertia_energy_kg_m2")
    if ode is None or not energy:
        return None
    return 100 * (float(f"{ode:.4g}") / float(f"{energy:.4g}") - 1)


def input_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The [torsion] table's given data for the table of the task's data: the spans' stiffnesses,
    the discs and couplings at the shaft's ends and the damping, where the assignment gives them
    (a stage's data the note uses first in its last section are given with the rest)."""
    if "torsion" not in scene.plugin_tables():
        return []
    opts = options(scene, "torsion", TorsionOptions)
    t = ctx.t
    stiffness, inertia = t("speed_fluctuation.unit_N_m_rad"), t("unit.kg_m2")
    spans = opts.span_stiffness if isinstance(opts.span_stiffness, list) else [opts.span_stiffness]
    rows = [
        (
            t("speed_fluctuation.input_span_stiffness"),
            symbol_html("speed_fluctuation.span_stiffness", t.language, ctx.symbols),
            "; ".join(t.number_g(c, 4) for c in spans),
            stiffness,
        )
    ]
    for key, unit in (
        ("flywheel_stiffness", stiffness),
        ("free_end_inertia", inertia),
        ("free_end_stiffness", stiffness),
        ("load_inertia", inertia),
        ("coupling_stiffness", stiffness),
    ):
        value = getattr(opts, key)
        if value is not None:
            # an aircraft engine's span ends at its propeller (the flywheel of the note)
            name = f"speed_fluctuation.input_{key}"
            if scene.engine.application == "aircraft" and t.has(name + "_propeller"):
                name += "_propeller"
            rows.append((t(name), "", t.number_g(value, 4), unit))
    if "damping_ratio" in opts.model_fields_set:
        rows.append(
            (
                t("speed_fluctuation.input_damping_ratio"),
                symbol_html("speed_fluctuation.damping_ratio", t.language, ctx.symbols),
                t.number_g(opts.damping_ratio, 4),
                "",
            )
        )
    return rows
