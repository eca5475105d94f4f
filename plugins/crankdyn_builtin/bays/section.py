"""The bays' section: the firing of the cylinders, the phase and stroke tables, the slave rods'
table, and the articulated rods' own letters."""

from __future__ import annotations

import math
from functools import partial

import numpy as np
from markupsafe import Markup, escape

from crankdyn.errors import SceneError
from crankdyn.physics.extrema import first_argmax, first_extremum_index
from crankdyn.plugin.contracts import ArticulatedOptions
from crankdyn.plugin.scene_inputs import engine_layout, power_take_off, slave_geometries
from crankdyn.plugin.types import StageOutput, Symbol
from crankdyn.report.context import add_extreme_rows, exact_decimals, sample_rows
from crankdyn.scene import options

from .compute import ARTICULATED, largest_tdc_shift
from .figures import bay_figure
from .plan import PlanTexts, plan_figure


def one_crank_key(key: str, r: dict, t) -> str:
    """``key``'s wording for an engine of one crank (a radial, a V-twin), which has no crank
    arrangement and no bays to tell apart, where the catalog gives one."""
    variant = key + "_one_crank"
    return variant if r["cranks"] == 1 and t.has(variant) else key


def _phase_table(r: dict, ctx):
    """Table of :func:`cylinder_phases` in firing order (the cycle delays then rise); one crank's
    has no columns of the crank and its lag (1 and 0 in every row)."""
    t = ctx.t
    phases = sorted(r["cylinder_phases"], key=lambda p: p["cycle_delay_deg"])
    columns: list[tuple[Markup, list, int | None]] = [
        (escape(t("bays.cylinder")), [t.cylinder(p["cylinder"]) for p in phases], None)
    ]
    if r["cranks"] > 1:
        columns += [
            (escape(t("bays.crank")), [str(p["crank"]) for p in phases], None),
            (escape(t("bays.crank_lag")), *_angles([p["crank_lag_deg"] for p in phases])),
        ]
    if any(p["axis_deg"] for p in phases):
        first = t.cylinder(phases[0]["cylinder"])  # the cylinder the delays count from
        columns.append(
            (escape(t("bays.axis_angle", first=first)), *_angles([p["axis_deg"] for p in phases]))
        )
    columns.append(
        (
            escape(t("bays.cycle_delay")) + Markup(" Δ<i>α</i><sub>0<i>i</i></sub>, °"),
            *_angles([p["cycle_delay_deg"] for p in phases]),
        )
    )
    return ctx.table(
        columns,
        caption=t(one_crank_key("bays.phases_caption", r, t)),
        see=one_crank_key("bays.see_phases", r, t),
    )


def _angles(values: list[float]) -> tuple[list[float], int]:
    """A column of angles and the decimals that print each as it is (a 22.5° crank, not 22)."""
    return values, exact_decimals(values)


def _stroke_table(r: dict, ctx):
    """The strokes of every cylinder over cylinder 1's crank angle (none without the data)."""
    sequence, phases = r.get("stroke_sequence"), r["cylinder_phases"]
    if not sequence:
        return None
    step, rows = sequence["step_deg"], sequence["rows"]
    t = ctx.t
    headers = [t("bays.cylinder")] + [
        f"{t.number_g(c * step, 4)}–{t.number_g((c + 1) * step, 4)}"
        for c in range(int(720 // step))
    ]
    body = [
        [t.cylinder(p["cylinder"])] + [(t(f"bays.stroke_{stroke}"), span) for stroke, span in runs]
        for p, runs in zip(phases, rows, strict=True)
    ]
    return ctx.table_html(
        headers,
        body,
        caption=t("bays.strokes_caption"),
        text_columns=range(1, 13),
        see="bays.see_strokes",
    )


def _digits(t, value: float, decimals: int) -> str:
    """``value`` rounded to ``decimals`` places, without trailing zeros (60° not 60,00°)."""
    return t.number_g(round(value, decimals), 12)


def _slave_table(r: dict, ctx):
    """Table of the articulated (slave) rods' geometry."""
    t = ctx.t
    return ctx.table(
        [
            (t("bays.cylinder"), [t.cylinder(s["cylinder"]) for s in r["slaves"]], None),
            # angles and lengths to the digits a drawing gives (0,1°, 0,01 mm), no padding zeros
            ("<i>γ</i>, °", [_digits(t, s["bank_angle_deg"], 1) for s in r["slaves"]], None),
            (
                "<i>γ</i><sub>1</sub>, °",
                [_digits(t, s["pin_angle_deg"], 1) for s in r["slaves"]],
                None,
            ),
            (
                "<i>l</i><sub>sr</sub>, " + t("unit.mm"),
                [_digits(t, s["slave_rod_length_m"] * 1e3, 2) for s in r["slaves"]],
                None,
            ),
            (
                "<i>l</i><sub>sr</sub> " + t("bays.by_source") + ", " + t("unit.mm"),
                [_digits(t, s["slave_rod_length_textbook_m"] * 1e3, 2) for s in r["slaves"]],
                None,
            ),
            ("<i>S</i><sub><i>l</i></sub>/<i>S</i>", [s["stroke_ratio"] for s in r["slaves"]], 4),
            # the true dead centres' shifts from the cylinder's axis (BDC's about twice TDC's)
            (
                t("bays.tdc_shift") + ", °",
                [t.fixed(s["tdc_shift_deg"], 2) for s in r["slaves"]],
                None,
            ),
            (
                t("bays.bdc_shift") + ", °",
                [t.fixed(s["bdc_shift_deg"], 2) for s in r["slaves"]],
                None,
            ),
        ],
        caption=t("bays.slave_caption"),
        see="bays.see_slaves",
    )


def _true_firing_text(r: dict, ctx) -> dict | None:
    """The arguments of the firing sentence of an articulated bay whose slave cylinders' true dead
    centres lie off their bank angles (None when the intervals are the nominal ones)."""
    nominal = r.get("firing_intervals_nominal_deg")
    if nominal is None or nominal == r["firing_intervals_deg"]:
        return None
    steps = sorted({round(x, 6) for x in nominal})
    return {
        "nominal": "; ".join(ctx.t.number_g(x, 4) for x in steps),
        "shift": ctx.t.number_g(largest_tdc_shift(r["slaves"]), 4),
    }


def _bank_letters_text(r: dict, t) -> str:
    """What the bank letters of the cylinders' labels stand for ("Л – лівий ряд, П – правий
    ряд"); "" for labels without letters or with letters of no named bank."""
    letters = []
    for label in r["firing_order"]:
        letter = str(label).lstrip("0123456789")
        if letter and letter not in letters:
            letters.append(letter)
    if not letters or not all(t.has("bays.bank_" + x) for x in letters):
        return ""
    ordered = sorted(letters, key="LCR".index)
    # a one-crank shaft has no "free end": its ends are named by what is there
    key = "bays.bank_letters" + ("_one_crank" if r["cranks"] == 1 else "")
    return t(key, letters=", ".join(t("bays.bank_" + x) for x in ordered))


def _master_cylinder_text(r: dict, t) -> str:
    """Which cylinder of a radial has the master rod ("Главный шатун работает в цилиндре 1"):
    the tables name the slave cylinders by number, and the master's is the one left; "" for
    other engines."""
    if r["layout"] != "radial" or r["rod_type"] != "articulated":
        return ""
    slaves = {str(s["cylinder"]) for s in r.get("slaves", ())}
    masters = [label for label in r["firing_order"] if str(label) not in slaves]
    if len(masters) != 1:
        return ""
    return t("bays.master_cylinder", master=t.cylinder(str(masters[0])))


def _bay_parts(output: StageOutput, ctx) -> dict:
    """The bay table of an engine with several cylinders per crank (textbook B.2), the slaves'
    table, the bay's figure, the pin's masses and the conclusion on the crank pin's largest load;
    all None for an engine with a crank pin per cylinder."""
    r, t = output.results, ctx.t
    parts: dict = {"bay_table": None, "slave_table": None, "figure": None, "masses": None}
    if "bay" not in output.tables:
        return parts
    f = output.tables.arrays("bay")
    angle = f["crank_angle_deg"]
    rows, labels = sample_rows(angle, ctx.table_step_deg)
    # the crank pin's largest load, which the conclusions cite, is a row of the table too
    rows, labels, extremes = add_extreme_rows(
        angle,
        rows,
        labels,
        [
            (f["pin_load_Pa"], "max", t("bays.extreme_max")),
            (f["master_side_Pa"], _side_kind(f["master_side_Pa"]), t("bays.extreme_side")),
        ],
        resolution=0.0,  # the conclusion quotes the peak itself, not a row near it
    )
    first_key = [k for k in output.tables if k.startswith("slave_")][0]
    first = output.tables.arrays(first_key)
    parts["slave_table"] = _slave_table(r, ctx)
    parts["bay_table"] = ctx.table(
        [
            ("<i>α</i>, °", ctx.angle_labels(labels), None),
            ("<i>N</i><sub>Σ</sub>", f["master_side_Pa"][rows] / 1e6, 3),
            ("<i>p</i><sub>1<i>l</i></sub>", first["slave_total_Pa"][rows] / 1e6, 3),
            ("<i>β</i><sub><i>l</i></sub>, °", first["slave_rod_angle_deg"][rows], 2),
            ("<i>z</i><sub>Σ</sub>", f["bay_radial_Pa"][rows] / 1e6, 3),
            ("<i>t</i><sub>Σ</sub>", f["bay_tangential_Pa"][rows] / 1e6, 3),
            ("<i>q</i><sub>pin</sub>", f["pin_load_Pa"][rows] / 1e6, 3),
        ],
        caption=t(
            one_crank_key("bays.table_b2_caption", r, t),
            cylinder=t.cylinder(first_key.removeprefix("slave_")),
        ),
        see=one_crank_key("bays.see_table_b2", r, t),
        extremes=extremes,
    )
    bay_table_number = ctx.last_table_number
    parts["masses"] = _pin_masses(r, ctx.scene)
    parts["figure"] = ctx.figure(
        partial(bay_figure, f, ctx.cycle_deg, t),
        t(one_crank_key("bays.figure_caption", r, t)),
        "bay",
        see=one_crank_key("bays.see_figure", r, t),
    )
    peak = first_argmax(f["pin_load_Pa"])  # the crank pin's load of all its cylinders
    ctx.conclude(
        t(
            "bays.conclusion_bay_load",
            q_max=ctx.num(f["pin_load_Pa"][peak] / 1e6),
            force=ctx.t.fixed(f["pin_load_Pa"][peak] * r["piston_area_m2"] / 1e3, 2),
            q_angle=ctx.angle_text(float(angle[peak])),
            table=bay_table_number,
        )
    )
    # the slave rods' thrust included; the row the table adds for it (the first such extreme)
    side = first_extremum_index(f["master_side_Pa"], _side_kind(f["master_side_Pa"]))
    ctx.conclude(
        t(
            "bays.conclusion_master_side",
            n_max=ctx.num(f["master_side_Pa"][side] / 1e6, 3),
            n_angle=ctx.angle_text(float(angle[side])),
            table=bay_table_number,
        )
    )
    return parts


def _side_kind(side_Pa) -> str:
    """Whether the side force is largest in magnitude as its maximum or as its minimum."""
    return "max" if np.max(side_Pa) >= -np.min(side_Pa) else "min"


def render(output: StageOutput, ctx) -> str | None:
    r = output.results
    if r["cylinders"] == 1:
        return None
    t = ctx.t
    # tables are numbered as made: the cylinders' phases first, as the template shows them
    phase_table = _phase_table(r, ctx)
    phase_table_number = ctx.last_table_number
    stroke_table = _stroke_table(r, ctx)
    plan = _plan_parts(r, ctx)
    parts = _bay_parts(output, ctx)
    own_pins = (
        r["cranks"] == r["cylinders"]
    )  # an in-line engine: a crank pin per cylinder, no bays to sum
    if own_pins or parts["bay_table"] is None:
        # no table of a pin's summed forces (central or fork rods: the crank section sums them)
        ctx.title = t("bays.title_own_pins")
    elif r["cranks"] == 1:  # a radial's one crank pin carries every cylinder
        ctx.title = t("bays.title_one_crank")
    return ctx.render_template(
        "sections/bays.html.j2",
        r=r,
        **parts,
        phase_table=phase_table,
        phase_table_number=phase_table_number,
        true_firing=_true_firing_text(r, ctx),
        uneven=_uneven_text(r, ctx),
        slave_length_given=_slave_length_given(ctx.scene),
        bank_letters=_bank_letters_text(r, t),
        master_cylinder=_master_cylinder_text(r, t),
        stroke_table=stroke_table,
        own_pins=own_pins,
        scheme_figure=ctx.figure_number("scheme"),
        one_crank=partial(one_crank_key, r=r, t=t),
        second_order=_second_order_text(r, t),
        plan=plan,
    )


#: What the plan names at the power take-off end (:func:`power_take_off`).
TAKE_OFF_ENDS = {
    "propeller": "bays.plan_propeller",
    "drive": "bays.plan_power_take_off",
    "flywheel": "bays.plan_flywheel",
}


def _take_off_end(ctx) -> str:
    """The catalog key of the plan's power take-off end."""
    return TAKE_OFF_ENDS[power_take_off(ctx.scene)]


def plan_texts(plan: dict, t, take_off_end: str = "bays.plan_flywheel") -> PlanTexts:
    """The plan's words in the report's language: the cylinders' labels as printed, the ends,
    the banks' rows, a's and the rods' offset's dimension texts."""
    mm = t("unit.mm")
    spacing = plan["spacing_m"]
    letters = [
        next(str(c["label"]).lstrip("0123456789") for c in plan["cylinders"] if c["bank"] == b)
        for b in sorted({c["bank"] for c in plan["cylinders"]})
    ]
    named = all(x and t.has("bays.bank_" + x) for x in letters) and plan["layout"] != "boxer"
    return PlanTexts(
        crank=t("bays.plan_crank"),
        free_end=t("bays.plan_free_end"),
        take_off_end=t(take_off_end),
        rotation=t("bays.plan_rotation"),
        banks=tuple(t("bays.bank_" + x) for x in letters) if named else (),
        spacing=f"a = {t.number_g(spacing * 1e3, 4)} {mm}" if spacing else "a",
        offset=(
            f"{t.number_g(plan['rod_offset_m'] * 1e3, 3)} {mm}" if plan["rod_offset_m"] else ""
        ),
    )


def _plan_parts(r: dict, ctx) -> dict | None:
    """The engine's plan figure (several cranks only), and the sentences on the rods' offset
    along the shaft and on a crank spacing the scene does not give."""
    plan = r.get("plan")
    if not plan:
        return None
    t = ctx.t
    printed = dict(
        plan, cylinders=[dict(c, label=t.cylinder(c["label"])) for c in plan["cylinders"]]
    )
    figure = ctx.figure(
        partial(plan_figure, printed, plan_texts(plan, t, _take_off_end(ctx))),
        t("bays.plan_caption"),
        "plan",
        see="bays.see_plan",
    )
    offset = ""
    if plan["rod_offset_m"]:
        two_banks = len(plan["bank_axes_deg"]) == 2  # "the right bank's", not "each next bank's"
        key = "bays.plan_offset" + ("_two_banks" if two_banks else "")
        offset = t(  # an aircraft engine's: towards the propeller (its texts' variant)
            key,
            offset=t.number_g(plan["rod_offset_m"] * 1e3, 3),
            taken=_rod_offset_taken(t, plan.get("rod_offset_source")),
        )
    spacing = "" if plan["spacing_m"] else t("bays.plan_spacing_assumed")
    return {"figure": figure, "offset": offset, "spacing": spacing}


def _rod_offset_taken(t, source: str | None) -> str:
    """Where the rods' offset comes from, as the sentence adds it: nothing for a given offset,
    the given crank pin's length shared by its rods, or the typical proportions."""
    return {"given": "", "pin_width": t("bays.plan_offset_pin_width")}.get(
        source or "", t("bays.plan_offset_taken")
    )


def _second_order_text(r: dict, t) -> str:
    """Where the chosen crank arrangement's second-order moment is the largest of all the
    even-firing orders (and some have a smaller one): the sentence saying so, its coefficient
    as the balancing tables print it, and its cure; "" otherwise."""
    rank = r.get("second_order_rank")
    if not rank or rank["coefficient"] <= 0 or rank["larger"] or not rank["smaller"]:
        return ""
    tied = rank["orders"] - rank["smaller"]
    return t(
        "bays.second_order_largest",
        coefficient=t.fixed(rank["coefficient"], 4),
        orders=rank["orders"],
        shared=t("bays.second_order_shared", tied=tied) if tied > 1 else "",
    )


def _pin_masses(r: dict, scene) -> dict:
    """The rotating masses behind the bay's centrifugal forces, kg: the rods' part on the crank pin
    (c_r) and one cylinder's of the forces section (c), each m = −c F_p / (R ω²)."""
    e = scene.engine
    per_pa = r["piston_area_m2"] / (e.crank_radius_m * e.angular_velocity_rad_s**2)
    return {
        "rods_kg": -r["centrifugal_rod_Pa"] * per_pa,
        "forces_kg": -r["forces_centrifugal_Pa"] * per_pa,
    }


def _slave_length_given(scene) -> bool:
    """True when the assignment gives the slave rods' length (else it is chosen for equal
    compression ratios)."""
    if scene is None or scene.engine.rod_type != "articulated":
        return False
    return options(scene, ARTICULATED, ArticulatedOptions).slave_rod_length is not None


def _uneven_text(r, ctx) -> str | None:
    """Why the firing is uneven, as a fact of the engine: each cylinder fires once a cycle, and the
    crank arrangement (with the bank angle of a V) spaces the firings by the intervals given, not
    by the cycle's equal shares (a 180° crank in a four-stroke twin: 180° and 540°)."""
    if r["even_firing"]:
        return None
    t = ctx.t
    intervals = r["firing_intervals_deg"]
    cycle = sum(intervals)
    bank = ctx.scene.engine.bank_angle_deg if ctx.scene is not None else None
    even = cycle / len(intervals)
    text = t(
        one_crank_key("bays.uneven_bank" if bank else "bays.uneven", r, t),
        cycle=t.number_g(cycle, 4),
        cranks="; ".join(t.number_g(x, 4) for x in r["crank_angles_deg"]),
        bank=t.number_g(bank, 4) if bank else "",
        intervals=t.degrees_and(intervals),
        even=t.number_g(even, 4),
    )
    split = split_pin_offset_deg(len(intervals), len(r["crank_angles_deg"]), bank, even)
    if ctx.scene is not None and ctx.scene.engine.layout == "V" and split:
        text += " " + t("bays.split_pins", even=t.number_g(even, 4), offset=t.number_g(split, 4))
    return text


def split_pin_offset_deg(cylinders: int, cranks: int, bank_deg, even_deg: float) -> float | None:
    """The offset between the two banks' pins of a crank that would space a V engine's firings
    evenly (a 60° V6: 120° − 60° = 60°; a 90° V6: 30°; a 90° V10: 18°), where its rods share the
    pins (two cylinders a crank) and there are at least three cranks; None otherwise."""
    if not bank_deg or cylinders < 6 or cylinders != 2 * cranks:
        return None
    offset = abs(even_deg - bank_deg) % 180.0
    offset = min(offset, 180.0 - offset)
    return offset if 1e-6 < offset < 90.0 else None


#: The articulated rods' letters (textbook §3.3, eq. (27)-(33); meanings: symbol.bays.<key> in
#: i18n/): l numbers the slave (side) cylinders.
_L = {"en": "l"}


SYMBOLS = {
    "slave_rod_angle": Symbol("β", _L, "°", html="<i>β</i><sub><i>l</i></sub>"),
    "slave_crank_angle": Symbol("α", _L, "°", html="<i>α</i><sub><i>l</i></sub>"),
    # its own subscript: the bare l numbers the slave cylinders
    "slave_rod_length": Symbol("l", {"en": "sr", "uk": "п.ш", "ru": "п.ш"}, "unit.mm"),
    "pin_radius": Symbol("r", {}, "unit.mm"),
    "bank_angle": Symbol("γ", {}, "°"),
    "pin_angle": Symbol("γ", {"en": "1"}, "°"),
    "pin_angle_difference": Symbol("φ", {}, "°"),
    "slave_total_force": Symbol("p", _L, "unit.MPa", html="<i>p</i><sub>1<i>l</i></sub>"),
    "slave_rod_force": Symbol("k", _L, "unit.MPa", html="<i>k</i><sub><i>l</i></sub>"),
    "slave_side_force": Symbol("N", _L, "unit.MPa", html="<i>N</i>′<sub><i>l</i></sub>"),
    "master_side_force_total": Symbol("N", {"en": "Σ"}, "unit.MPa"),
    "slave_tangential_force": Symbol("t", _L, "unit.MPa", html="<i>t</i><sub><i>l</i></sub>"),
    "slave_radial_force": Symbol("z", _L, "unit.MPa", html="<i>z</i><sub><i>l</i></sub>"),
    "slave_stroke": Symbol("S", _L, "unit.mm", html="<i>S</i><sub><i>l</i></sub>"),
    # the load on the crank pin, where the forces section's q is one cylinder's load on the throw
    "pin_load": Symbol("q", {"en": "pin", "uk": "ш.ш", "ru": "ш.ш"}, "unit.MPa"),
    "slave_rod_mass": Symbol("m", {"en": "sr", "uk": "п.ш", "ru": "п.ш"}, "unit.kg"),
    "slave_rod_cm_fraction": Symbol("κ", {"en": "s", "uk": "п", "ru": "п"}, ""),
    "slave_pin_mass": Symbol("m", {"en": "sp", "uk": "п.п", "ru": "п.п"}, "unit.kg"),
    # defined here, used in the main journals' loads too
    "throw_centrifugal": Symbol("c", {"en": "Σ"}, "unit.MPa", sections=("bays", "bearings")),
}


def input_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The cranks' angles the scene gives and the [articulated] table's given data for the
    report's table of the task's data: what the scene gives (a default it leaves is no datum of
    the task)."""
    rows = _crank_angle_rows(scene, ctx)
    if scene.engine.rod_type != "articulated":
        return rows
    return rows + _articulated_rows(scene, ctx)


def _crank_angle_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The angles of the cranks of the cylinders, when the scene gives them (the engine's layout
    otherwise chooses them) and the shaft has more than one crank (one crank lags none)."""
    engine = scene.engine
    if (
        engine.cylinders < 2
        or "crank_angles_deg" not in engine.model_fields_set
        or len(engine.crank_angles_deg) < 2
    ):
        return []
    angles = "; ".join(ctx.t.number_g(float(a), 4) for a in engine.crank_angles_deg)
    return [(ctx.t("bays.input_crank_angles"), "", angles, "°")]


def _articulated_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The [articulated] table's given data."""
    opts = options(scene, ARTICULATED, ArticulatedOptions)
    given = opts.model_fields_set
    t, num = ctx.t, ctx.t.number_g
    mm, kg = t("unit.mm"), t("unit.kg")
    rows = [(t("bays.input_pin_radius"), "<i>r</i>", num(opts.pin_radius * 1e3, 4), mm)]
    if opts.pin_angle_deg is not None:
        rows.append(
            (t("bays.input_pin_angle"), "<i>γ</i><sub>1</sub>", num(opts.pin_angle_deg, 4), "°")
        )
    if opts.slave_rod_length is not None:
        rows.append(
            (
                t("bays.input_slave_rod_length"),
                "<i>l</i><sub>sr</sub>",
                num(opts.slave_rod_length * 1e3, 4),
                mm,
            )
        )
    if opts.slave_rod is not None:
        rows.append(
            (t("bays.input_slave_rod"), "<i>m</i><sub>sr</sub>", num(opts.slave_rod, 4), kg)
        )
    if "slave_rod_cm_fraction" in given:
        rows.append(
            (
                t("bays.input_slave_rod_cm"),
                "<i>κ</i><sub>s</sub>",
                num(opts.slave_rod_cm_fraction, 4),
                "",
            )
        )
    if "slave_pin" in given:
        rows.append(
            (t("bays.input_slave_pin"), "<i>m</i><sub>sp</sub>", num(opts.slave_pin, 4), kg)
        )
    return rows


def taken_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The values the calculation takes where the scene gives none, for the table of the values
    taken: a shaft of several cranks has a main support between neighbouring cranks and at both
    ends; articulated rods' knuckle pins' angles γ_1 (each slave cylinder's axis angle), the
    slave rods' lengths (for equal compression ratios, or the textbook's L − r), the slave rod's
    centre of mass and a knuckle pin of no mass (it enters m_R)."""
    try:
        layout = engine_layout(scene)
    except SceneError:  # refused where the stages run, with its own message
        return []
    t, num = ctx.t, ctx.t.number_g
    supports = (
        [(t("bays.input_main_supports"), "", str(layout.cranks + 1), "")]
        if layout.cranks > 1
        else []
    )
    if scene.engine.rod_type != "articulated":
        return supports
    opts = options(scene, ARTICULATED, ArticulatedOptions)
    given = opts.model_fields_set
    try:
        slaves = slave_geometries(scene, layout, opts, ARTICULATED)
    except SceneError:  # refused where the stages run, with its own message
        return supports
    rows = supports
    if opts.pin_angle_deg is None and opts.pin_angles_deg is None:
        angles = "; ".join(num(math.degrees(g.pin_angle_rad), 4) for _, g in slaves)
        rows.append((t("bays.input_pin_angle"), "<i>γ</i><sub>1</sub>", angles, "°"))
    if opts.slave_rod_length is None:
        lengths = "; ".join(num(g.slave_rod_length_m * 1e3, 5) for _, g in slaves)
        rows.append(
            (t("bays.input_slave_rod_length"), "<i>l</i><sub>sr</sub>", lengths, t("unit.mm"))
        )
    if "slave_rod_cm_fraction" not in given:
        fraction = num(opts.slave_rod_cm_fraction, 4)
        rows.append((t("bays.input_slave_rod_cm"), "<i>κ</i><sub>s</sub>", fraction, ""))
    if "slave_pin" not in given:
        rows.append((t("bays.input_slave_pin"), "<i>m</i><sub>sp</sub>", num(0.0), t("unit.kg")))
    return rows
