"""The ``planetary`` stage's section: ``render``, the tables and the conclusions of its text."""

from __future__ import annotations

from crankdyn.plugin.types import StageOutput, Symbol
from crankdyn.report.context import sample_rows
from crankdyn_builtin.planetary.worked import worked_planetary

from .figures import _arms_figure, _family_figure, _motion_figure, _path_figure


def _sampled_table(f, r, span, ctx) -> str:
    """The sampled table of the linkage's motion and force ratios, with its worked substitutions."""
    t = ctx.t
    mm = 1e3
    angle = f["crank_angle_deg"]
    rows, labels = sample_rows(angle, ctx.table_step_deg, span_deg=span)
    g = f.take(rows)
    table = ctx.table(
        [
            ("<i>α</i>, °", labels, 0),
            ("<i>x</i><sub>B</sub>, " + t("unit.mm"), g["big_end_x_m"] * mm, 3),
            ("<i>z</i><sub>B</sub>, " + t("unit.mm"), g["big_end_z_m"] * mm, 3),
            ("<i>s</i><sub>p</sub>, " + t("unit.mm"), g["piston_displacement_m"] * mm, 3),
            ("<i>v</i><sub>p</sub>, " + t("unit.m_s"), g["piston_velocity_m_s"], 2),
            ("<i>j</i><sub>p</sub>, " + t("unit.m_s2"), g["piston_acceleration_m_s2"], 0),
            ("<i>β</i>, °", g["rod_angle_deg"], 2),
            ("<i>h</i>, " + t("unit.mm"), g["carrier_torque_arm_m"] * mm, 3),
            ("<i>MN</i>, " + t("unit.mm"), g["rod_line_arm_m"] * mm, 3),
            ("<i>F</i><sub>t</sub>/<i>F</i>", g["tooth_tangential_per_piston_force"], 3),
        ]
        + (
            [("<i>P</i><sub>j</sub>, " + t("unit.kN"), g["inertia_force_N"] / 1e3, 3)]
            if "inertia_force_N" in g
            else []
        ),
        caption=t("planetary.table_caption"),
        see="planetary.see_table",
    )
    return table + worked_planetary(ctx, g, labels, r)


def render(output: StageOutput, ctx) -> str:
    """The section: the sampled table, the four figures (path, family, motion, arms) and the conclusion."""
    t = ctx.t
    f = output.tables.arrays("planetary")
    r = output.results
    span = 360.0 * r["period_revolutions"]
    angle = f["crank_angle_deg"]
    inside = angle < span
    mm = 1e3

    table = _sampled_table(f, r, span, ctx)
    figure_path = _path_figure(f, r, inside, ctx)
    figure_family = _family_figure(output.tables.arrays("family"), r, ctx)
    figure_motion = _motion_figure(f, angle, inside, span, ctx)
    figure_arms = _arms_figure(f, angle, inside, span, ctx)

    ctx.conclude(
        t(
            "planetary.conclusion",
            gear=t("planetary.gear_" + r["gear"]),
            ratio=ctx.num(r["gear_ratio"], 4),
            stroke=ctx.num(r["stroke_m"] * mm, 5),
            arm=ctx.num(r["torque_arm_tdc_m"] * mm, 4),
            arm_max=ctx.num(r["carrier_torque_arm_max_m"] * mm, 4),
            conventional=ctx.num(r["conventional_torque_arm_max_m"] * mm, 4),
        )
    )
    # The effective arm at TDC is zero; show round-off (~1e-17 m) as 0.
    effective_tdc = (
        r["effective_torque_arm_tdc_m"]
        if abs(r["effective_torque_arm_tdc_m"]) > 1e-9 * r["stroke_m"]
        else 0.0
    )
    return ctx.render_template(
        "sections/planetary.html.j2",
        r=r,
        effective_tdc=effective_tdc,
        table=table,
        figure_path=figure_path,
        figure_family=figure_family,
        figure_motion=figure_motion,
        figure_arms=figure_arms,
    )


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
    # the inertia force of the reciprocating masses, given the masses
    "inertia_force": Symbol("P", {"en": "j"}, "unit.N"),
    "reciprocating_mass": Symbol("m", {"en": "j"}, "unit.kg"),
    # the points of the rod line's arm MN (the table's column and the text at TDC)
    "shaft_axis_point": Symbol("M", {}, ""),
    "arm_foot_point": Symbol("N", {}, ""),
}
