"""The flywheel's section: its text, tables and conclusions, and its rows of the given data."""

from __future__ import annotations

from functools import partial

from markupsafe import Markup

from crankdyn.errors import SceneError
from crankdyn.plugin.scene_inputs import engine_layout
from crankdyn.plugin.types import StageOutput
from crankdyn.report.typeset import symbol_html
from crankdyn.scene import options
from crankdyn_builtin.flywheel.worked import irregularity_is_a_result, worked_flywheel

from .compute import RIM_STRENGTHS, is_propeller
from .figures import work_figure
from .options import FlywheelOptions


def render(output: StageOutput, ctx) -> str:
    t = ctx.t
    r = output.results
    f = output.tables.arrays("flywheel")
    figure_work = ctx.figure(
        partial(work_figure, f, r["mean_torque_Nm"], ctx.cycle_deg, t),
        t("flywheel.work_caption" + ("_single" if ctx.scene.engine.cylinders == 1 else "")),
        "excess_work",
        see="flywheel.see_work",
    )
    rim = r["rim"]
    cranks = _cranks(ctx.scene)
    rows = _energy_rows(r, t, ctx.symbols, cranks) + _rim_rows(rim, t)
    table = ctx.table(
        [
            (t("input.quantity"), [x[0] for x in rows], None),
            (t("input.symbol"), [Markup(x[1]) for x in rows], None),
            (
                t("input.value"),
                [x[2] if isinstance(x[2], str) else ctx.num(x[2]) for x in rows],
                None,
            ),
            (t("input.unit"), [x[3] for x in rows], None),
        ],
        caption=t(
            "flywheel.table_caption_raised"
            if r.get("flywheel_raised")
            else "flywheel.table_caption" + ("_given" if r["flywheel_given"] else "")
        ),
        see=(
            ("flywheel.see_table_raised" if rim else "flywheel.see_table_raised_no_rim")
            if r.get("flywheel_raised")
            else "flywheel.see_table"
        ),
    ) + worked_flywheel(ctx, r)
    low_speed = vehicle_low_speed(ctx.scene, r)
    if r.get("own_inertia_sufficient"):
        _conclude_not_needed(ctx, r)
    else:
        _conclude(ctx, r)
        if low_speed is not None:
            # a δ the energy method does not hold for is no result to conclude with
            beyond = low_speed["irregularity"] >= LOWER_SPEED_BEYOND
            ctx.conclusions[-1] += " " + t(
                "flywheel.conclusion_vehicle_low_speed" + ("_beyond" if beyond else ""),
                rpm=t.number_g(low_speed["rpm"], 5),
                delta=t.number_g(low_speed["irregularity"], 3),
                limit=t.number_g(LOWER_SPEED_BEYOND, 2),
            )
        _conclude_rim_too_fast(ctx, r)
    opts = options(ctx.scene, "flywheel", FlywheelOptions)
    # an aircraft engine's propeller takes the flywheel's part: its texts (the title, the
    # finding, the task's row) are the catalogs' _propeller keys, by the translator's variant
    propeller = is_propeller(ctx.scene)
    return ctx.render_template(
        "sections/flywheel.html.j2",
        propeller=propeller,
        flywheel_carriers=FLYWHEEL_CARRIERS,
        vehicle_low_speed=low_speed is not None,
        lower_speed_beyond=LOWER_SPEED_BEYOND,
        r=r,
        cylinders=ctx.scene.engine.cylinders,
        cranks=cranks,
        # a shaft of one crank: "its crank's mass", "the crank's webs" (catalog keys "…_one_crank")
        crank_key=lambda key: crank_key(t, key, cranks),
        rim=rim,
        rim_speed=rim_speed_text(ctx, rim) if rim else None,
        figure_work=figure_work,
        table=table,
        shaft_inertia_given="engine_inertia" in opts.model_fields_set,
        density_given="rim_density" in opts.model_fields_set,
        material=rim_material(rim["density_kg_m3"]) if rim else None,
        raised=raised_params(ctx, r) if r.get("flywheel_raised") else None,
        # J_f names the adopted flywheel: the energy method's, raised by the exact solution, is J′_f
        flywheel_symbol=symbol_html("flywheel.energy_flywheel_inertia", t.language, ctx.symbols)
        if r.get("flywheel_raised")
        else "<i>J</i><sub>f</sub>",
        # the energy method found no flywheel needed (the exact solution may still raise one)
        energy_needs_none=r["required_irregularity"] is not None and _energy_needs_none(r),
    )


def _energy_rows(r: dict, t, symbols, cranks: int | None) -> list[tuple]:
    """The table's rows of the energy method: ΔL, the inertias, [δ], J_0, the flywheel, δ
    (``symbols``: the report's symbol table; ``cranks``: the shaft's, for its own inertia's words)."""
    rows = [
        (t("flywheel.row_excess_work"), "Δ<i>L</i>", r["excess_work_J"], t("unit.J")),
        (
            t(crank_key(t, "flywheel.row_mechanism", cranks)),
            "<i>J</i><sub>m</sub>",
            r["mechanism_inertia_mean_kg_m2"],
            t("flywheel.unit_kg_m2"),
        ),
        (
            t(crank_key(t, "flywheel.row_engine", cranks)),
            "<i>J</i><sub>e</sub>",
            r["engine_inertia_kg_m2"],
            t("flywheel.unit_kg_m2"),
        ),
    ]
    if r["required_irregularity"] is not None:
        # a given value, as the task's data table prints it (0,01, not 0,01000)
        rows += [
            (
                t("flywheel.row_required_delta"),
                "[<i>δ</i>]",
                t.number_g(r["required_irregularity"], 6),
                "—",
            ),
            (
                t("flywheel.row_required_total"),
                "<i>J</i><sub>0</sub>",
                r["required_total_inertia_kg_m2"],
                t("flywheel.unit_kg_m2"),
            ),
            (
                t(
                    "flywheel.row_energy_flywheel"
                    if r.get("flywheel_raised")
                    else "flywheel.row_required_flywheel"
                ),
                # raised by the exact solution: J_f is the adopted flywheel's, the next row
                symbol_html("flywheel.energy_flywheel_inertia", t.language, symbols)
                if r.get("flywheel_raised")
                else "<i>J</i><sub>f</sub>",
                t("flywheel.not_needed")
                if _energy_needs_none(r)
                else r["required_flywheel_inertia_kg_m2"],
                "" if _energy_needs_none(r) else t("flywheel.unit_kg_m2"),
            ),
        ]
    if r.get("flywheel_raised"):
        rows.append(
            (
                t("flywheel.row_adopted_flywheel"),
                "<i>J</i><sub>f</sub>",
                r["flywheel_inertia_kg_m2"],
                t("flywheel.unit_kg_m2"),
            )
        )
    if r["flywheel_given"]:
        rows.append(
            (
                t("flywheel.row_given_flywheel"),
                "<i>J</i><sub>f</sub>",
                r["flywheel_inertia_kg_m2"],
                t("flywheel.unit_kg_m2"),
            )
        )
    if irregularity_is_a_result(r):
        rows.append((t("flywheel.row_delta"), "<i>δ</i>", r["irregularity"], "—"))
    return rows


def _rim_rows(rim: dict | None, t) -> list[tuple]:
    """The table's rows of the flywheel's rim (none when no rim is sized)."""
    if rim is None:
        return []
    return [
        (
            t("flywheel.row_rim_mean_diameter"),
            "<i>D</i><sub>m</sub>",
            rim["mean_diameter_m"] * 1e3,
            t("unit.mm"),
        ),
        (
            t("flywheel.row_rim_thin_mass"),
            "<i>m</i><sub>rim</sub> = 4<i>J</i><sub>rim</sub>/<i>D</i><sub>m</sub><sup>2</sup>",
            rim["thin_rim_mass_kg"],
            t("unit.kg"),
        ),
        (t("flywheel.row_rim_thickness"), "<i>h</i>", rim["thickness_m"] * 1e3, t("unit.mm")),
        (t("flywheel.row_rim_width"), "<i>b</i>", rim["width_m"] * 1e3, t("unit.mm")),
        (
            t("flywheel.row_rim_outer"),
            "<i>D</i><sub>o</sub>",
            rim["outer_diameter_m"] * 1e3,
            t("unit.mm"),
        ),
        (t("flywheel.row_rim_mass"), "<i>m</i>", rim["mass_kg"], t("unit.kg")),
        (t("flywheel.row_rim_speed"), "<i>v</i><sub>o</sub>", rim["speed_m_s"], t("unit.m_s")),
        (
            t("flywheel.row_rim_stress"),
            "<i>σ</i> = <i>ρ</i><sub>mat</sub> <i>v</i><sub>o</sub><sup>2</sup>",
            rim["hoop_stress_Pa"] / 1e6,
            t("unit.MPa"),
        ),
    ]


def _energy_needs_none(r: dict) -> bool:
    """Whether the energy method finds the engine's own inertia enough for [δ] (no flywheel),
    also beside a given flywheel: J_0 − J_m − J_e is then not "a flywheel of 0 kg·m²"."""
    return r["required_flywheel_inertia_kg_m2"] == 0.0


def raised_params(ctx, r: dict) -> dict:
    """The numbers the texts on a flywheel raised to the exact solution's name: the energy
    method's flywheel, the exact δ with it (four digits: they show its excess over [δ]), [δ], the
    growth and the adopted flywheel with its exact δ (which is [δ], to the printed digits)."""
    return {
        "energy": ctx.num(r["required_flywheel_inertia_kg_m2"]),
        "exact": ctx.num(r["energy_flywheel_exact_irregularity"], 4),
        "required": ctx.t.number_g(r["required_irregularity"], 6),
        # from the two flywheels as printed (four digits), so that the reader's division agrees
        "growth": ctx.num(
            100
            * (
                float(f"{r['flywheel_inertia_kg_m2']:.4g}")
                / float(f"{r['required_flywheel_inertia_kg_m2']:.4g}")
                - 1
            ),
            2,
        )
        if r["required_flywheel_inertia_kg_m2"]
        else None,
        "total": ctx.num(r["required_total_inertia_kg_m2"]),
        "own_inertia": ctx.num(r["own_inertia_kg_m2"]),
        "flywheel": ctx.num(r["flywheel_inertia_kg_m2"]),
        "delta": ctx.num(r["required_irregularity"], 3),
    }


def _conclude(ctx, r: dict) -> None:
    """The abstract's and the conclusions' words on the flywheel designed or given."""
    t = ctx.t
    if r.get("flywheel_raised"):
        params = raised_params(ctx, r)
        # the energy method needed none: the flywheel is the exact solution's alone
        from_none = "_from_none" if _energy_needs_none(r) else ""
        ctx.find(t("flywheel.finding_raised" + from_none, **params))
        ctx.conclude(
            t(
                "flywheel.conclusion_raised" + from_none,
                excess=ctx.num(r["excess_work_J"]),
                own=ctx.num(r["own_inertia_kg_m2"]),
                mechanism=ctx.num(r["mechanism_inertia_mean_kg_m2"]),
                shaft=ctx.num(r["engine_inertia_kg_m2"]),
                **params,
            )
        )
        return
    ctx.find(
        t(
            # a given flywheel (or propeller) is no result: δ with it is
            "flywheel.finding" + ("_given" if r["flywheel_given"] else ""),
            # a given value as given (0,2, not 0,2000)
            flywheel=ctx.t.number_g(r["flywheel_inertia_kg_m2"])
            if r["flywheel_given"]
            else ctx.num(r["flywheel_inertia_kg_m2"]),
            delta=ctx.num(r["irregularity"], 3),
        )
    )
    ctx.conclude(
        t(
            "flywheel.conclusion",
            excess=ctx.num(r["excess_work_J"]),
            flywheel=ctx.num(r["flywheel_inertia_kg_m2"]),
            delta=ctx.num(r["irregularity"], 3),
            own=ctx.num(r["own_inertia_kg_m2"]),
            mechanism=ctx.num(r["mechanism_inertia_mean_kg_m2"]),
            shaft=ctx.num(r["engine_inertia_kg_m2"]),
        )
    )


def rim_speed_text(ctx, rim: dict) -> str:
    """The rim's peripheral speed to three significant digits, or as many more (up to six) as
    tell it from the allowed speed it is compared with: 50,04 m/s against 50, not "50,0 m/s
    exceeds the allowable 50 m/s"."""
    speed, limit = rim["speed_m_s"], rim.get("max_speed_m_s")
    digits = 3
    while limit is not None and digits < 6 and float(f"{speed:.{digits}g}") == limit:
        digits += 1
    return ctx.num(speed, digits)


def _conclude_rim_too_fast(ctx, r: dict) -> None:
    """A rim faster than the allowed peripheral speed: the flywheel as sized fails its check, and
    the abstract and the conclusions say so (not only the section)."""
    rim = r.get("rim") or {}
    if rim.get("speed_ok") is not False:
        return
    params = {"speed": rim_speed_text(ctx, rim), "limit": ctx.t.number_g(rim["max_speed_m_s"])}
    ctx.find(ctx.t("flywheel.finding_rim_too_fast", **params))
    passing = rim.get("passing")
    if passing is None:
        ctx.conclude(ctx.t("flywheel.conclusion_rim_too_fast_no_rim", **params))
        return
    ctx.conclude(
        ctx.t(
            "flywheel.conclusion_rim_too_fast_passing",
            **params,
            diameter=ctx.t.number_g(passing["mean_diameter_m"] * 1e3, 6),
            h=ctx.num(passing["thickness_m"] * 1e3, 3),
            b=ctx.num(passing["width_m"] * 1e3, 3),
            mass=ctx.num(passing["mass_kg"], 3),
        )
    )


#: The engines that carry a flywheel whatever the rated speed's irregularity asks for: a vehicle's,
#: for starting, idling and moving off and for the clutch; an outboard motor's, the magneto's
#: rotor with the starter's ring gear, for starting and idling (the "outboard" texts).
FLYWHEEL_CARRIERS = ("automotive", "tractor", "motorcycle", "outboard")


#: The δ from which the energy method's small-swing assumption no longer holds (the section
#: says the lower speeds' values lie beyond it).
LOWER_SPEED_BEYOND = 0.25


def vehicle_low_speed(scene, r: dict) -> dict | None:
    """The lowest of the lower speeds' rows (``flywheel.lower_speeds``: a quarter of the given
    speed) where a vehicle's flywheel is designed for [δ] at the given speed and δ there exceeds
    [δ]: a vehicle's flywheel is chosen for starting, idling and moving off as well, which the
    section and the conclusions say with that δ; None otherwise."""
    if scene is None or scene.engine.application not in FLYWHEEL_CARRIERS:
        return None
    required = r["required_irregularity"]
    if required is None or r.get("own_inertia_sufficient") or r["flywheel_given"]:
        return None
    rows = r.get("lower_speeds") or []
    if not rows or rows[-1]["irregularity"] <= required:
        return None
    return rows[-1]


def _regime_suffix(application) -> str:
    """The ending of the given speed's caveat: a stationary engine runs at that speed; a
    vehicle's says why its flywheel is chosen at lower speeds in a sentence of its own."""
    if application == "stationary":
        return "_stationary"
    return "_carrier" if application in FLYWHEEL_CARRIERS else ""


def _conclude_not_needed(ctx, r) -> None:
    """The abstract's and the conclusions' words where the engine's own inertia meets [δ]: no
    flywheel is designed, none is reported."""
    t = ctx.t
    ctx.find(t("flywheel.finding_not_needed", delta=ctx.num(r["irregularity"], 3)))
    ctx.conclude(
        t(
            "flywheel.conclusion_not_needed",
            excess=ctx.num(r["excess_work_J"]),
            delta=ctx.num(r["irregularity"], 3),
            required=t.number_g(r["required_irregularity"], 6),
            own=ctx.num(r["own_inertia_kg_m2"]),
            mechanism=ctx.num(r["mechanism_inertia_mean_kg_m2"]),
            shaft=ctx.num(r["engine_inertia_kg_m2"]),
        )
        + " "
        + t(
            "flywheel.rated_regime_only" + _regime_suffix(ctx.scene.engine.application),
            rpm=t.number_g(ctx.scene.engine.rpm, 5),
        )
        + (
            " " + t("flywheel.conclusion_vehicle_flywheel_still")
            if ctx.scene.engine.application in FLYWHEEL_CARRIERS
            else ""
        )
        + (
            " "
            + t(
                "flywheel.conclusion_lower_speeds_reached",
                required=t.number_g(r["required_irregularity"], 6),
                rpm=t.number_g(r["required_irregularity_reached_rpm"], 3),
            )
            if r.get("required_irregularity_reached_rpm")
            else ""
        )
    )


def input_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The [flywheel] table's given data for the report's table of the task's data."""
    opts = options(scene, "flywheel", FlywheelOptions)
    t, num = ctx.t, ctx.t.number_g
    inertia = t("unit.kg_m2")
    rows = []
    if opts.required_irregularity is not None:
        rows.append(
            (t("flywheel.input_irregularity"), "[<i>δ</i>]", num(opts.required_irregularity, 6), "")
        )
    if opts.inertia is not None:
        rows.append(
            (t("flywheel.input_inertia"), "<i>J</i><sub>f</sub>", num(opts.inertia, 4), inertia)
        )
    if "engine_inertia" in opts.model_fields_set:
        rows.append(_engine_inertia_row(opts, t, _cranks(scene)))
    if opts.rim_mean_diameter is not None:
        rows.append(
            (
                t("flywheel.input_rim_diameter"),
                "<i>D</i><sub>m</sub>",
                num(opts.rim_mean_diameter * 1e3, 4),
                t("unit.mm"),
            )
        )
    if opts.rim_width is not None:
        rows.append(
            (t("flywheel.input_rim_width"), "<i>b</i>", num(opts.rim_width * 1e3, 4), t("unit.mm"))
        )
    if "rim_density" in opts.model_fields_set:
        rows.append(_rim_density_row(opts, t))
    if opts.max_rim_speed is not None:
        rows.append(
            (
                t("flywheel.input_rim_speed"),
                "[<i>v</i><sub>o</sub>]",
                num(opts.max_rim_speed, 4),
                t("unit.m_s"),
            )
        )
    return rows


def taken_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The [flywheel] values the scene leaves at their defaults and the calculation takes: the
    shaft's own inertia J_e (zero) and, for a rim, its material's density."""
    opts = options(scene, "flywheel", FlywheelOptions)
    rows = []
    if "engine_inertia" not in opts.model_fields_set:
        rows.append(_engine_inertia_row(opts, ctx.t, _cranks(scene)))
    if "rim_density" not in opts.model_fields_set and opts.rim_mean_diameter is not None:
        rows.append(_rim_density_row(opts, ctx.t))
    return rows


def crank_key(t, key: str, cranks: int | None) -> str:
    """``key``, or its ``_one_crank`` form where the shaft has one crank and the catalog gives it."""
    one = f"{key}_one_crank"
    return one if cranks == 1 and t.has(one) else key


def _engine_inertia_row(opts: FlywheelOptions, t, cranks: int | None) -> tuple[str, str, str, str]:
    return (
        t(crank_key(t, "flywheel.input_engine_inertia", cranks)),
        "<i>J</i><sub>e</sub>",
        t.number_g(opts.engine_inertia, 4),
        t("unit.kg_m2"),
    )


def _rim_density_row(opts: FlywheelOptions, t) -> tuple[str, str, str, str]:
    return (
        t("flywheel.input_rim_density"),
        "<i>ρ</i><sub>mat</sub>",
        t.number_g(opts.rim_density, 4),
        t("unit.kg_m3"),
    )


def rim_material(density_kg_m3: float) -> str | None:
    """The catalog name (``flywheel.material_<name>``) of the material of a rim of this density
    (:data:`RIM_STRENGTHS`), or None for a density neither cast iron nor steel has."""
    for name, low, high, _, _ in RIM_STRENGTHS:
        if low <= density_kg_m3 <= high:
            return name
    return None


def _cranks(scene) -> int | None:
    """The engine's cranks (None for a layout the stages refuse: said there)."""
    try:
        return engine_layout(scene).cranks
    except SceneError:
        return None
