"""The ``rod_dynamics`` stage's section: ``render``, the tables and the conclusions of its text."""

from __future__ import annotations

from functools import partial

from crankdyn.plugin.contracts import FORCES
from crankdyn.plugin.types import StageOutput, Symbol
from crankdyn.report.context import sample_rows
from crankdyn.report.typeset import symbol_html
from crankdyn_builtin.rod_dynamics.worked import rod_table_decimals, worked_rod_dynamics

from .figures import _motion_figure, _torque_figure


def _columns(t, g, labels, exact: bool) -> list:
    """The table's columns: the rod's motion, its inertia couple and the torques."""
    omega_dec, eps_dec, ax_dec, az_dec = rod_table_decimals(g)
    columns = [
        ("<i>α</i>, °", labels, 0),
        ("<i>β</i>, °", g["rod_angle_deg"], 2),
        ("<i>ω</i><sub>r</sub>, " + t("unit.rad_s"), g["rod_angular_velocity_rad_s"], omega_dec),
        (
            "<i>ε</i><sub>r</sub>, " + t("unit.rad_s2"),
            g["rod_angular_acceleration_rad_s2"],
            eps_dec,
        ),
        ("<i>a</i><sub>Gx</sub>, " + t("unit.m_s2"), g["cm_acceleration_x_m_s2"], ax_dec),
        ("<i>a</i><sub>Gz</sub>, " + t("unit.m_s2"), g["cm_acceleration_z_m_s2"], az_dec),
        ("<i>M</i><sub>2</sub>, " + t("unit.Nm"), g["torque_two_mass_Nm"], 2),
    ]
    if exact:
        columns[6:6] = [("<i>M</i><sub>G</sub>, " + t("unit.Nm"), g["inertia_couple_Nm"], 2)]
        columns += [
            ("<i>M</i><sub>exact</sub>, " + t("unit.Nm"), g["torque_exact_Nm"], 2),
            (
                "<i>M</i><sub>exact</sub> − <i>M</i><sub>2</sub>, " + t("unit.Nm"),
                g["torque_difference_Nm"],
                3,
            ),
        ]
    return columns


def _conclusion(ctx, r) -> str:
    """The conclusion on the rod's inertia couple and on the two-mass split's error; a model
    other than the two-mass one is this section's alone: the forces and the torque, where the
    run computed them, keep the two-mass split."""
    t = ctx.t
    numbers = {
        "couple": ctx.num(r["inertia_couple_max_Nm"]),
        "difference": ctx.num(r["torque_difference_max_abs_Nm"]),
        "relative": ctx.num(r["torque_difference_relative"] * 100.0, 3),
    }
    if r["model"] == "two_mass":
        return t("rod_dynamics.conclusion", model=t("rod_dynamics.model_two_mass"), **numbers)
    text = t(
        "rod_dynamics.conclusion_apart",
        number=ctx.section_number,
        by_model=t("rod_dynamics.model_by_" + r["model"]),
        **numbers,
    )
    if ctx.data(FORCES) is None:
        return text
    single = getattr(ctx.scene.engine, "cylinders", 1) == 1
    return text + " " + t("rod_dynamics.conclusion_apart_forces" + ("_single" if single else ""))


def render(output: StageOutput, ctx) -> str:
    t = ctx.t
    f = output.tables.arrays("rod_dynamics")
    r = output.results
    exact = "torque_exact_Nm" in f  # the rod's moment of inertia was given
    angle = f["crank_angle_deg"]
    # the motion's own period: one turn, or the turns after which a planetary mechanism repeats
    period = r.get("period_deg", 360.0)
    rows, labels = sample_rows(angle, ctx.table_step_deg, span_deg=period)
    g = f.take(rows)
    columns = _columns(t, g, labels, exact)
    table = ctx.table(
        columns,
        caption=t("rod_dynamics.table_caption" if exact else "rod_dynamics.table_caption_two"),
        css_class="data wide",
        see="rod_dynamics.see_table" if exact else "rod_dynamics.see_table_two",
    ) + worked_rod_dynamics(ctx, g, labels, r)

    figure_motion = ctx.figure(
        partial(_motion_figure, f, period, t),
        t("rod_dynamics.motion_caption"),
        "rod_motion",
        see="rod_dynamics.see_motion",
    )
    figure_torque = ctx.figure(
        partial(_torque_figure, f, period, exact, t),
        t("rod_dynamics.torque_caption" if exact else "rod_dynamics.torque_caption_two"),
        "rod_torque",
        see="rod_dynamics.see_torque" if exact else "rod_dynamics.see_torque_two",
    )

    if exact:
        ctx.conclude(_conclusion(ctx, r))
    else:
        ctx.conclude(
            t(
                "rod_dynamics.conclusion_two",
                cm=ctx.num(r["cm_acceleration_max_m_s2"]),
                torque=ctx.num(r["torque_two_mass_max_abs_Nm"]),
            )
        )
    return ctx.render_template(
        "sections/rod_dynamics.html.j2",
        r=r,
        exact=exact,
        table=table,
        figure_motion=figure_motion,
        figure_torque=figure_torque,
    )


#: The letters of this section's equations (meanings: symbol.rod_dynamics.<key> in i18n/).
_G, _A, _B = {"en": "G"}, {"en": "A"}, {"en": "B"}

SYMBOLS = {
    "moment_of_inertia_G": Symbol("I", _G, "unit.kg_m2"),
    "two_mass_moment_of_inertia": Symbol("I", {"en": "2"}, "unit.kg_m2"),
    "model_moment_of_inertia": Symbol("I", {}, "unit.kg_m2"),
    "two_mass_A": Symbol("m", _A, "unit.kg"),
    "two_mass_B": Symbol("m", _B, "unit.kg"),
    "three_mass_A": Symbol("m", _A, "unit.kg", html="<i>m</i>′<sub>{sub}</sub>"),
    "three_mass_B": Symbol("m", _B, "unit.kg", html="<i>m</i>′<sub>{sub}</sub>"),
    "three_mass_G": Symbol("m", _G, "unit.kg"),
    "acceleration_G": Symbol("a", _G, "unit.m_s2", html="<b>a</b><sub>{sub}</sub>"),
    "velocity_G": Symbol("v", _G, "unit.m_s", html="<b>v</b><sub>{sub}</sub>"),
    "cm_acceleration_x": Symbol("a", {"en": "Gx"}, "unit.m_s2"),
    "cm_acceleration_z": Symbol("a", {"en": "Gz"}, "unit.m_s2"),
    "acceleration_A": Symbol("a", _A, "unit.m_s2", html="<b>a</b><sub>{sub}</sub>"),
    "velocity_A": Symbol("v", _A, "unit.m_s", html="<b>v</b><sub>{sub}</sub>"),
    "acceleration_B": Symbol("a", _B, "unit.m_s2", html="<b>a</b><sub>{sub}</sub>"),
    "velocity_B": Symbol("v", _B, "unit.m_s", html="<b>v</b><sub>{sub}</sub>"),
    "cylinder_axis_vector": Symbol("e", {"en": "z"}, "", html="<b>e</b><sub><i>{sub}</i></sub>"),
    "small_end_acceleration": Symbol("z\u0308", _A, "unit.m_s2"),
    "inertia_couple": Symbol("M", _G, "unit.Nm"),
    "correction_couple": Symbol("M", _G, "unit.Nm", html="Δ<i>M</i><sub>{sub}</sub>"),
    "rod_inertia_torque": Symbol("M", {}, "unit.Nm"),
    "rod_inertia_torque_exact": Symbol("M", {"en": "exact", "uk": "точн", "ru": "точн"}, "unit.Nm"),
    "rod_inertia_torque_two_mass": Symbol("M", {"en": "2"}, "unit.Nm"),
}


def input_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The rod's moment of inertia about its centre of mass, where the assignment gives it: a
    row of the table of the task's data (the section's dynamics start from it)."""
    inertia = getattr(getattr(scene, "masses", None), "rod_moment_of_inertia", None)
    if inertia is None:
        return []
    t = ctx.t
    return [
        (
            t("rod_dynamics.input_moment_of_inertia"),
            symbol_html("rod_dynamics.moment_of_inertia_G", t.language, ctx.symbols),
            t.number_g(inertia, 4),
            t("unit.kg_m2"),
        )
    ]
