"""The ``offset_crank`` stage's section: ``render``, the tables and the conclusions of its text."""

from __future__ import annotations

import functools

from crankdyn.physics import offset_crank as oc
from crankdyn.plugin.types import StageOutput, Symbol
from crankdyn.report.context import sample_rows
from crankdyn.scene import options
from crankdyn_builtin.offset_crank.worked import worked_offset_crank

from .figures import _piston_figure, _rod_figure
from .options import OffsetParams
from .precision import STROKE_DIGITS, angle_text

#: The time ratio K of the two strokes above which the mechanism is a quick-return one: below
#: it the strokes last within 5 % of each other, as in any engine's offset of a few millimetres.
QUICK_RETURN_RATIO = 1.05

#: The table of given data names the scene's stroke as what it is, the crank throw 2R: the
#: offset piston's own stroke S is longer (listed by :func:`input_rows`).
MECHANISM_INPUT_ROWS = {
    "stroke": ("offset_crank.input_throw", "2<i>R</i>"),
    "crank_radius": ("input.crank_radius", "<i>R</i>"),
}


def input_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The offset e (given) and the piston's stroke S it gives (computed in this section), for
    the table of the task's data."""
    t, num = ctx.t, ctx.t.number_g
    engine = scene.engine
    offset = options(scene, "mechanism", OffsetParams).offset
    stroke = oc.dead_centres(engine.crank_radius_m, engine.rod_length_m, offset).stroke_m
    return [
        (t("offset_crank.input_offset"), "<i>e</i>", num(offset * 1e3, 4), t("unit.mm")),
        (
            t("offset_crank.input_stroke"),
            "<i>S</i>",
            num(stroke * 1e3, STROKE_DIGITS),
            t("unit.mm"),
        ),
    ]


def render(output: StageOutput, ctx) -> str:
    t = ctx.t
    f = output.tables.arrays("offset_crank")
    r = output.results
    rows, labels = sample_rows(f["crank_angle_deg"], ctx.table_step_deg, span_deg=360.0)
    g = f.take(rows)
    table = ctx.table(
        [
            ("<i>α</i>, °", labels, 0),
            ("<i>φ</i>, °", g["crank_angle_from_axis_deg"] % 360.0, 2),
            ("<i>s</i><sub>p</sub>, " + t("unit.mm"), g["piston_displacement_m"] * 1e3, 3),
            ("<i>v</i><sub>p</sub>, " + t("unit.m_s"), g["piston_velocity_m_s"], 2),
            ("<i>j</i><sub>p</sub>, " + t("unit.m_s2"), g["piston_acceleration_m_s2"], 0),
            ("<i>β</i>, °", g["rod_angle_deg"], 2),
            ("<i>ω</i><sub>r</sub>, " + t("unit.rad_s"), g["rod_angular_velocity_rad_s"], 1),
            ("<i>ε</i><sub>r</sub>, " + t("unit.rad_s2"), g["rod_angular_acceleration_rad_s2"], 0),
        ],
        caption=t("offset_crank.table_caption"),
        see="offset_crank.see_table",
    ) + worked_offset_crank(ctx, g, labels, r)

    figure_main = ctx.figure(
        functools.partial(_piston_figure, f, r["bdc_crank_angle_deg"], t),
        t("offset_crank.figure_caption"),
        "offset_piston",
        see="offset_crank.see_figure",
    )
    figure_rod = ctx.figure(
        functools.partial(_rod_figure, f, t),
        t("offset_crank.rod_figure_caption"),
        "offset_rod",
        see="offset_crank.see_rod_figure",
    )

    # TDC past the axis in the sense of rotation, or (a negative offset) before it
    before = r["tdc_crank_angle_from_axis_deg"] < 0
    ctx.conclude(
        t(
            "offset_crank.conclusion" + ("_before" if before else ""),
            e=ctx.t.number_g(r["offset_m"] * 1e3, 4),
            tdc=angle_text(t, abs(r["tdc_crank_angle_from_axis_deg"])),
            bdc=angle_text(t, r["bdc_crank_angle_deg"]),
            stroke=t.number_g(r["stroke_m"] * 1e3, STROKE_DIGITS),
            excess=ctx.num(r["stroke_excess_m"] * 1e3, 3),
            ratio=ctx.num(r["stroke_time_ratio"], 5),
        )
    )
    ratio = max(r["stroke_time_ratio"], 1.0 / r["stroke_time_ratio"])
    return ctx.render_template(
        "sections/offset_crank.html.j2",
        r=r,
        indicator_key=_indicator_key(ctx.scene),
        quick_return=ratio > QUICK_RETURN_RATIO,
        quick_return_ratio=QUICK_RETURN_RATIO,
        return_percent=100.0 * (ratio - 1.0),
        table=table,
        figure_main=figure_main,
        figure_rod=figure_rod,
        stroke_digits=STROKE_DIGITS,
        tdc_from_axis=angle_text(t, r["tdc_crank_angle_from_axis_deg"]),
        bdc_from_axis=angle_text(t, r["bdc_crank_angle_from_axis_deg"]),
    )


def _indicator_key(scene) -> str | None:
    """The item saying what the indicator diagram takes from this section (its stroke and BDC),
    when the scene has a cycle to draw one from."""
    if scene is None or scene.cycle is None:
        return None
    if scene.engine.strokes == 4:
        return "offset_crank.replaced_indicator"
    return "offset_crank.replaced_indicator_two"


#: The offset's letters (meanings: symbol.offset_crank.<key> in i18n/).
SYMBOLS = {
    "offset": Symbol("e", {}, "unit.mm"),
    "offset_ratio": Symbol("k", {}, ""),
    # the forces section resolves the rod force at this angle (its t and z formulas)
    "axis_crank_angle": Symbol("φ", {}, "°", sections=("offset_crank", "forces")),
    "tdc_angle": Symbol("φ", {"en": "TDC", "uk": "ВМТ", "ru": "ВМТ"}, "°"),
    "bdc_angle": Symbol("φ", {"en": "BDC", "uk": "НМТ", "ru": "НМТ"}, "°"),
    "time_ratio": Symbol("K", {}, ""),
}
