"""The ``planetary`` stage's section: ``render``, the tables and the conclusions of its text."""

from __future__ import annotations

import numpy as np

from crankdyn.plugin.types import ColumnTable, StageOutput, Symbol
from crankdyn.report.context import TableExtreme, sample_rows
from crankdyn.scene import options
from crankdyn_builtin.planetary.worked import worked_planetary

from .figures import _arms_figure, _family_figure, _motion_figure, _path_figure
from .options import PlanetaryParams

#: A displacement within this share of the stroke of its dead centre's is that dead centre (ties).
TIE = 1e-9


def _with_reversal_rows(f, reversals, rows, labels):
    """The sampled rows with a row at each reversal of the piston the table step misses: the columns
    (name -> values) in angle order and the positions of the added rows."""
    shown = {round(float(a), 6) for a in labels}
    extra = [
        i for i, a in enumerate(reversals["crank_angle_deg"]) if round(float(a), 6) not in shown
    ]
    angles = np.concatenate([np.asarray(labels, dtype=float), reversals["crank_angle_deg"][extra]])
    order = np.argsort(angles, kind="stable")
    columns = {}
    for name in f.columns:
        if name in reversals:
            merged = np.concatenate([f[name][rows], reversals[name][extra]])
            columns[name] = merged[order]
    added = [int(k) for k in np.flatnonzero(order >= len(labels))]
    return ColumnTable(columns), angles[order], added


def _sampled_table(f, r, span, ctx, reversals) -> str:
    """The sampled table of the linkage's motion and force ratios, with a row at each reversal of
    the piston, and its worked substitutions."""
    t = ctx.t
    mm = 1e3
    angle = f["crank_angle_deg"]
    rows, labels = sample_rows(angle, ctx.table_step_deg, span_deg=span)
    g, labels, added = _with_reversal_rows(f, reversals, rows, labels)
    marks = [
        TableExtreme(position=i, crank_angle_deg=float(labels[i]), what=t("planetary.reversal_row"))
        for i in added
    ]
    table = ctx.table(
        [
            ("<i>α</i>, °", ctx.angle_labels(labels), None),
            ("<i>x</i><sub>B</sub>, " + t("unit.mm"), g["big_end_x_m"] * mm, 2),
            ("<i>z</i><sub>B</sub>, " + t("unit.mm"), g["big_end_z_m"] * mm, 2),
            ("<i>s</i><sub>p</sub>, " + t("unit.mm"), g["piston_displacement_m"] * mm, 2),
            ("<i>v</i><sub>p</sub>, " + t("unit.m_s"), g["piston_velocity_m_s"], 2),
            ("<i>j</i><sub>p</sub>, " + t("unit.m_s2"), g["piston_acceleration_m_s2"], 0),
            ("<i>β</i>, °", g["rod_angle_deg"], 2),
            ("<i>h</i>, " + t("unit.mm"), g["carrier_torque_arm_m"] * mm, 2),
            ("<i>MN</i>, " + t("unit.mm"), g["rod_line_arm_m"] * mm, 2),
            ("<i>F</i><sub>t</sub>/<i>F</i>", g["tooth_tangential_per_piston_force"], 3),
        ]
        + (
            [("<i>P</i><sub>j</sub>, " + t("unit.kN"), g["inertia_force_N"] / 1e3, 3)]
            if "inertia_force_N" in g
            else []
        ),
        caption=t("planetary.table_caption"),
        extremes=marks,
        see="planetary.see_table",
    )
    kept = [i for i in range(len(labels)) if i not in added]
    return table + worked_planetary(ctx, g.take(kept), labels[kept], r)


def _angles(ctx, angles) -> str:
    """Crank angles as a list in the report's language: "136,4 і 223,6" (the text adds the °)."""
    texts = [ctx.angle_text(float(a)) for a in angles]
    if len(texts) == 1:
        return texts[0]
    return ", ".join(texts[:-1]) + " " + ctx.t("planetary.and") + " " + texts[-1]


def _mm(ctx, metres) -> str:
    """A length in mm to four significant digits without padding zeros (60, 2,303)."""
    return ctx.t.number_g(metres * 1e3, 4)


def _curve_sentence(r, ctx) -> str:
    t = ctx.t
    e, r_p = r["pin_radius_m"], r["planet_pitch_diameter_m"] / 2
    where = "on" if r["curve"].endswith("cycloid") else ("inside" if e < r_p else "outside")
    return t(
        "planetary.curve_" + where,
        e=t.number_g(e * 1e3, 6),
        r_p=t.number_g(r_p * 1e3, 6),
        curve=t("planetary.curve_" + r["curve"]),
    )


def _conventional(r) -> dict:
    """What a conventional crank-slider does over the planetary's period of ``turns`` carrier
    revolutions: ``ordinary`` reversals (two a revolution) and a path of ``strokes`` × S, with
    which the planetary's reversals and path are compared (not with one revolution's)."""
    turns = int(r["period_revolutions"])
    return {"turns": turns, "ordinary": r["conventional_reversals"], "strokes_n": 2 * turns}


def _dead_centre_paragraphs(r, ctx) -> list[str]:
    """The dead centres and the stroke; with more than two reversals of the piston per period, every
    reversal, the secondary strokes and what they mean for the working cycle."""
    t = ctx.t
    common = {
        "tdc": ctx.angle_text(r["tdc_carrier_angle_deg"]),
        "stroke": t.fixed(r["stroke_m"] * 1e3, 3),
        "period": r["period_revolutions"],
        "reach": t.fixed(r["path_lateral_max_m"] * 1e3, 2),
        "beta": t.number_g(r["rod_angle_max_deg"], 4),
    }
    bdcs = r["bdc_crank_angles_deg"]
    if len(bdcs) == 1:
        first = t("planetary.dead_centres", bdc=ctx.angle_text(bdcs[0]), **common)
    else:
        first = t(
            "planetary.dead_centres_repeated", bdcs=_angles(ctx, bdcs), count=len(bdcs), **common
        )
    if r["reversal_count"] <= 2:
        return [first]
    items = []
    for item in r["reversals"]:
        kind = ("main_" if item["main"] else "") + item["kind"]
        items.append(
            t(
                "planetary.reversal_" + kind,
                angle=ctx.angle_text(item["crank_angle_deg"]),
                s=_mm(ctx, item["displacement_m"]),
            )
        )
    paragraphs = [
        first,
        t(
            "planetary.reversals",
            count=r["reversal_count"],
            items="; ".join(items),
            **_conventional(r),
        ),
    ]
    strokes = r["secondary_strokes"]
    paragraphs.append(
        t(
            "planetary.secondary_intro",
            count=len(strokes),
            items="; ".join(
                t(
                    "planetary.secondary_" + s["direction"],
                    start=ctx.angle_text(s["from_deg"]),
                    end=ctx.angle_text(s["to_deg"]),
                    depth=_mm(ctx, s["depth_m"]),
                )
                for s in strokes
            ),
            path=t.fixed(r["piston_path_m"] * 1e3, 2),
            two_s=t.fixed(r["conventional_path_m"] * 1e3, 2),
            **_conventional(r),
        )
    )
    meaning = t(f"planetary.meaning_{ctx.scene.engine.strokes}")
    dwell = _bdc_dwell(r)
    if dwell is not None:
        meaning += " " + t(
            "planetary.meaning_dwell",
            start=ctx.angle_text(dwell[0]),
            end=ctx.angle_text(dwell[1]),
            span=ctx.angle_text(dwell[1] - dwell[0]),
            depth=_mm(ctx, dwell[2]),
        )
    paragraphs.append(meaning)
    return paragraphs


def _bdc_dwell(r):
    """(first BDC, last BDC, largest distance from BDC between them) when two BDCs enclose only
    secondary reversals near BDC, the piston's dwell there; None otherwise."""
    bdcs = r["bdc_crank_angles_deg"]
    if len(bdcs) != 2:
        return None
    between = [item for item in r["reversals"] if bdcs[0] < item["crank_angle_deg"] < bdcs[1]]
    if not between or any(item["main"] for item in between):
        return None
    depth = max(r["stroke_m"] - item["displacement_m"] for item in between)
    if depth > 0.25 * r["stroke_m"]:
        return None
    return bdcs[0], bdcs[1], depth


def _tdc_arm(r, ctx) -> str:
    t = ctx.t
    mm = 1e3
    common = {
        "arm_max": ctx.num(r["carrier_torque_arm_max_m"] * mm, 4),
        "conventional": ctx.num(r["conventional_torque_arm_max_m"] * mm, 4),
    }
    if abs(r["torque_arm_tdc_m"]) <= TIE * r["stroke_m"]:
        return t("planetary.tdc_arm_zero", **common)
    return t(
        "planetary.tdc_arm",
        arm=ctx.num(r["torque_arm_tdc_m"] * mm, 4),
        tooth=ctx.num(r["tooth_force_tdc"], 4),
        **common,
    )


def _flank_sentence(r, ctx) -> str:
    changes = r["tooth_force_sign_changes_deg"]
    if not changes:
        return ""
    return ctx.t(
        "planetary.flanks",
        count=len(changes),
        angles=_angles(ctx, changes),
        figure=ctx.figure_number("planetary_arms") or "",
    )


def _speed_sentence(r, ctx) -> str:
    t = ctx.t
    mean = t.fixed(r["mean_piston_speed_m_s"], 2)
    if r["reversal_count"] <= 2:
        return t("planetary.mean_speed", mean=mean)
    return t(
        "planetary.mean_speed_path",
        mean=mean,
        path=t.fixed(r["piston_path_m"] * 1e3, 2),
        path_mean=t.fixed(r["mean_piston_speed_path_m_s"], 2),
    )


def _conclusion_stroke(r, ctx) -> str:
    """The stroke, where the piston reverses and, with more reversals, its path."""
    t = ctx.t
    mm = 1e3
    common = {
        "gear": t("planetary.gear_" + r["gear"]),
        "ratio": t.number_g(r["gear_ratio"], 5),
        "e": t.number_g(r["pin_radius_m"] * mm, 6),
        # the curve's name alone: its synonym in brackets would nest brackets in the sentence
        "curve": t("planetary.curve_" + r["curve"]).split(" (")[0],
        "stroke": t.fixed(r["stroke_m"] * mm, 3),
    }
    if r["reversal_count"] <= 2:
        return t(
            "planetary.conclusion_stroke",
            tdc=ctx.angle_text(0.0),
            bdc=ctx.angle_text(r["bdc_crank_angles_deg"][0]),
            **common,
        )
    return t(
        "planetary.conclusion_stroke_reversals",
        count=r["reversal_count"],
        bdcs=_angles(ctx, r["bdc_crank_angles_deg"]),
        secondary=_mm(ctx, r["secondary_stroke_max_m"]),
        path=t.fixed(r["piston_path_m"] * mm, 2),
        two_s=t.fixed(r["conventional_path_m"] * mm, 2),
        **_conventional(r),
        **common,
    )


def _conclusion_speed(r, ctx) -> str:
    """|v|max where it is reached, and the mean speeds."""
    t = ctx.t
    fastest = max(abs(r["v_max_m_s"]), abs(r["v_min_m_s"]))
    at = [
        r[k + "_crank_angle_deg"]
        for k in ("v_max", "v_min")
        if abs(abs(r[k + "_m_s"]) - fastest) <= 1e-6 * fastest
    ]
    speed = {
        "v": t.fixed(fastest, 2),
        "angles": _angles(ctx, sorted(at)),
        "mean": t.fixed(r["mean_piston_speed_m_s"], 2),
    }
    if r["reversal_count"] <= 2:
        return t("planetary.conclusion_speed", **speed)
    return t(
        "planetary.conclusion_speed_path",
        path_mean=t.fixed(r["mean_piston_speed_path_m_s"], 2),
        **speed,
    )


def _conclusion_acceleration(r, ctx) -> str:
    """The acceleration at TDC against the central crank-slider's R ω² (1 + λ)."""
    t = ctx.t
    excess = r["j_tdc_excess"]
    return t(
        "planetary.conclusion_tdc_acceleration",
        j=t.fixed(r["j_tdc_m_s2"], 0),
        compare=t(
            "planetary.compare_" + ("more" if excess >= 0 else "less"),
            percent=t.fixed(abs(excess) * 100, 1),
        ),
        conventional=t.fixed(r["conventional_j_tdc_m_s2"], 0),
        radius=t.number_g(r["conventional_crank_radius_m"] * 1e3, 5),
        lam=t.fixed(r["conventional_rod_ratio"], 4),
    )


def _conclusions(r, ctx) -> list[str]:
    """The section's conclusions, from its numbers."""
    t = ctx.t
    mm = 1e3
    out = [
        _conclusion_stroke(r, ctx),
        _conclusion_speed(r, ctx),
        _conclusion_acceleration(r, ctx),
        t(
            "planetary.conclusion_rod",
            beta=t.number_g(r["rod_angle_max_deg"], 4),
            reach=t.fixed(r["path_lateral_max_m"] * mm, 2),
        ),
    ]
    if r["tooth_force_sign_changes_deg"]:
        out.append(t("planetary.conclusion_flanks", count=len(r["tooth_force_sign_changes_deg"])))
    arm = {
        "arm_max": ctx.num(r["carrier_torque_arm_max_m"] * mm, 4),
        "conventional": ctx.num(r["conventional_torque_arm_max_m"] * mm, 4),
    }
    if abs(r["torque_arm_tdc_m"]) <= TIE * r["stroke_m"]:
        out.append(t("planetary.conclusion_arm", **arm))
    else:
        out.append(
            t("planetary.conclusion_arm_offset", arm=ctx.num(r["torque_arm_tdc_m"] * mm, 4), **arm)
        )
    return out


def _findings(r, ctx) -> None:
    """The main results for the abstract."""
    t = ctx.t
    ctx.find(t("planetary.finding_stroke", stroke=t.fixed(r["stroke_m"] * 1e3, 3)))
    if r["reversal_count"] > 2:
        ctx.find(
            t(
                "planetary.finding_reversals",
                count=r["reversal_count"],
                secondary=_mm(ctx, r["secondary_stroke_max_m"]),
                **_conventional(r),
            )
        )
    fastest = max(abs(r["v_max_m_s"]), abs(r["v_min_m_s"]))
    ctx.find(t("planetary.finding_speed", v=t.fixed(fastest, 2)))
    ctx.find(t("planetary.finding_acceleration", j=t.fixed(r["j_tdc_m_s2"], 0)))


def render(output: StageOutput, ctx) -> str:
    """The section: the sampled table, the four figures (path, family, motion, arms) and the
    conclusions."""
    f = output.tables.arrays("planetary")
    r = output.results
    span = 360.0 * r["period_revolutions"]
    angle = f["crank_angle_deg"]
    inside = angle < span

    reversals = output.tables.arrays("reversals")
    figure_path = _path_figure(f, r, inside, ctx)
    figure_family = _family_figure(output.tables.arrays("family"), r, ctx)
    figure_motion = _motion_figure(f, angle, inside, span, r, ctx)
    figure_arms = _arms_figure(f, angle, inside, span, ctx)
    table = _sampled_table(f, r, span, ctx, reversals)

    for sentence in _conclusions(r, ctx):
        ctx.conclude(sentence)
    _findings(r, ctx)
    return ctx.render_template(
        "sections/planetary.html.j2",
        r=r,
        curve_sentence=_curve_sentence(r, ctx),
        dead_centre_paragraphs=_dead_centre_paragraphs(r, ctx),
        tdc_arm=_tdc_arm(r, ctx),
        flank_sentence=_flank_sentence(r, ctx),
        speed_sentence=_speed_sentence(r, ctx),
        table=table,
        figure_path=figure_path,
        figure_family=figure_family,
        figure_motion=figure_motion,
        figure_arms=figure_arms,
    )


def input_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The [mechanism] table's given data for the report's table of the task's data, as given."""
    params = options(scene, "mechanism", PlanetaryParams)
    t, num = ctx.t, ctx.t.number_g
    mm = t("unit.mm")
    rows = [(t("planetary.input_gear"), "", t("planetary.input_gear_" + params.gear), "")]
    if params.module is not None:
        rows += [
            (
                t("planetary.input_fixed_teeth"),
                "<i>z</i><sub>f</sub>",
                str(params.fixed_gear_teeth),
                "",
            ),
            (
                t("planetary.input_planet_teeth"),
                "<i>z</i><sub>p</sub>",
                str(params.planet_teeth),
                "",
            ),
            (t("planetary.input_module"), "<i>m</i>", num(params.module * 1e3, 6), mm),
        ]
    else:
        rows += [
            (
                t("planetary.input_fixed_diameter"),
                "<i>d</i><sub>f</sub>",
                num(params.fixed_gear_pitch_diameter * 1e3, 6),
                mm,
            ),
            (
                t("planetary.input_planet_diameter"),
                "<i>d</i><sub>p</sub>",
                num(params.planet_pitch_diameter * 1e3, 6),
                mm,
            ),
        ]
    rows += [
        (t("planetary.input_pin_radius"), "<i>e</i>", num(params.pin_radius * 1e3, 6), mm),
        (t("planetary.input_pin_phase"), "<i>ψ</i><sub>0</sub>", num(params.pin_phase_deg, 6), "°"),
        (
            t("planetary.input_pressure_angle"),
            "<i>α</i><sub>w</sub>",
            num(params.pressure_angle_deg, 6),
            "°",
        ),
    ]
    return rows


#: The letters of the section's equations (meanings: symbol.planetary.<key> in i18n/); the crank angle,
#: the crankshaft's speed, the rod's angle and length and the piston's motion are the core's. The
#: subscripts are Latin in every language (f: the fixed gear, p: the planet, B: the big end, A: the
#: piston pin), but the carrier torque's, whose Latin c is the resistance torque's M_оп in uk/ru.
#: P, C and K in the prose are points; in the equations they are the points' position vectors.
_CARRIER = {"en": "c", "uk": "в", "ru": "в"}

SYMBOLS = {
    "fixed_teeth": Symbol("z", {"en": "f"}, ""),
    "planet_teeth": Symbol("z", {"en": "p"}, ""),
    "module": Symbol("m", {}, "unit.mm"),
    "fixed_diameter": Symbol("d", {"en": "f"}, "unit.mm"),
    "planet_diameter": Symbol("d", {"en": "p"}, "unit.mm"),
    "gear_ratio": Symbol("i", {}, ""),
    "carrier_radius": Symbol("a", {}, "unit.mm"),
    "speed_ratio": Symbol("k", {}, ""),
    "planet_angular_velocity": Symbol("ω", {"en": "p"}, "unit.rad_s"),
    "big_end_x": Symbol("x", {"en": "B"}, "unit.mm"),
    "big_end_z": Symbol("z", {"en": "B"}, "unit.mm"),
    "carrier_angle": Symbol("φ", {}, "°"),
    "pin_radius": Symbol("e", {}, "unit.mm"),
    "pin_angle": Symbol("θ", {}, "°"),
    "pin_phase": Symbol("ψ", {"en": "0"}, "°"),
    "piston_pin_z": Symbol("z", {"en": "A"}, "unit.mm"),
    "piston_pin_z_tdc": Symbol("z", {"en": "A,TDC", "uk": "A,ВМТ", "ru": "A,ВМТ"}, "unit.mm"),
    "big_end_x_derivative": Symbol(
        "x", {"en": "B"}, "unit.m_rad", html="<i>x</i>′<sub>{sub}</sub>"
    ),
    "big_end_z_derivative": Symbol(
        "z", {"en": "B"}, "unit.m_rad", html="<i>z</i>′<sub>{sub}</sub>"
    ),
    "rod_force_vector": Symbol("F", {"en": "P"}, "unit.N", html="<b>F</b><sub>{sub}</sub>"),
    "piston_force": Symbol("F", {}, "unit.N"),
    "tooth_tangential": Symbol("F", {"en": "t"}, "unit.N"),
    "pin_vector": Symbol("P", {}, "unit.mm", html="<b>P</b>"),
    "planet_centre_vector": Symbol("C", {}, "unit.mm", html="<b>C</b>"),
    "mesh_sign": Symbol("s", {}, ""),
    "planet_radius": Symbol("r", {"en": "p"}, "unit.mm"),
    "tooth_radial": Symbol("F", {"en": "r"}, "unit.N"),
    "pressure_angle": Symbol("α", {"en": "w"}, "°"),
    "carrier_torque": Symbol("M", _CARRIER, "unit.Nm"),
    "tooth_force_vector": Symbol("F", {"en": "K"}, "unit.N", html="<b>F</b><sub>{sub}</sub>"),
    "rotation_direction": Symbol("t", {}, "", html="<b>t</b>"),
    "torque_arm": Symbol("h", {}, "unit.mm"),
    # the carrier is the crank: ω and α are the carrier's, not a crankshaft's
    "carrier_angular_velocity": Symbol("ω", {}, "unit.rad_s"),
    "carrier_crank_angle": Symbol("α", {}, "°"),
    # the inertia force of the reciprocating masses, given the masses
    "inertia_force": Symbol("P", {"en": "j"}, "unit.N"),
    "reciprocating_mass": Symbol("m", {"en": "j"}, "unit.kg"),
    # the points of the rod line's arm MN (the table's column and the text at TDC)
    "shaft_axis_point": Symbol("M", {}, ""),
    "arm_foot_point": Symbol("N", {}, ""),
}
