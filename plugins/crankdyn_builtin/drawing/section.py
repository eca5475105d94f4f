"""The drawing's section: the kinematic scheme, the characteristic positions and (HTML) the
mechanism's motion, drawn by :mod:`crankdyn.report.mechanism_drawing`."""

from __future__ import annotations

import math
import re
from dataclasses import replace

from markupsafe import Markup

from crankdyn.plugin.contracts import COUNTERWEIGHTS
from crankdyn.plugin.scene_inputs import power_take_off
from crankdyn.plugin.types import StageOutput
from crankdyn.report import figure_memo
from crankdyn.report import mechanism_drawing as md

from .compute import POSITIONS


def _labelled(geometry, t):
    """``geometry`` with its cylinders' labels as the report's language prints them (1L → 1Л)."""
    return replace(
        geometry,
        guides=[replace(g, label=t.cylinder(g.label)) if g.label else g for g in geometry.guides],
        cranks=[
            (label, lag, tuple(t.cylinder(c) for c in cylinders))
            for label, lag, cylinders in geometry.cranks
        ],
        firing_order=tuple(t.cylinder(c) for c in geometry.firing_order),
    )


#: The slave rod's length as the scheme writes it (its index as the bays section's symbol).
SLAVE_ROD_LENGTH = {
    "en": r"$l_\mathregular{sr}$",
    "uk": r"$l_\mathregular{п.ш}$",
    "ru": r"$l_\mathregular{п.ш}$",
}


def _labels(geometry, ctx) -> dict[str, str]:
    mm = ctx.t("unit.mm")
    names = {"l_s": SLAVE_ROD_LENGTH.get(ctx.t.language, SLAVE_ROD_LENGTH["en"])}
    return {
        k: f"{names.get(k, k)} = {ctx.t.number_g(value * 1e3, 4)} {mm}"
        for k, value in geometry.dimensions.items()
    }


def position_frames(
    angles: dict[str, float], caption, period_deg: float = 360.0
) -> list[tuple[int, str]]:
    """The positions figure's panels (index into ``angles``' keys, :data:`POSITIONS` and any
    further dead centres after them, caption) in the order the crank reaches them (a supervisor:
    j_min at 158,2° came after v_min at 284,6°), those at one angle merged
    (:func:`_merged_frames`); ``caption(key)`` writes a panel's caption."""
    keys = list(angles)
    order = sorted(range(len(keys)), key=lambda i: angles[keys[i]] % period_deg)
    return _merged_frames([(i, caption(keys[i]), angles[keys[i]]) for i in order], period_deg)


def _merged_frames(
    frames: list[tuple[int, str, float]], period_deg: float = 360.0
) -> list[tuple[int, str]]:
    """One panel per distinct position: of a central crank-slider, TDC is also where the piston's
    acceleration is largest, and two identical panels ("ВМТ" and "j_max", both at 0°) would be
    drawn. Captions are "what\nα = …"; positions within 0.05° share a panel, their names joined."""
    merged: list[tuple[int, list[str], str, float]] = []
    for i, caption, angle in frames:
        name, _, at = caption.partition("\n")
        half = period_deg / 2.0
        same = next(
            (m for m in merged if abs((m[3] - angle + half) % period_deg - half) < 0.05), None
        )
        if same is None:
            merged.append((i, [name], at, angle))
        else:
            same[1].append(name)
    return [(i, ", ".join(names) + "\n" + at) for i, names, at, _ in merged]


def _master_rod_kind(positions) -> str | None:
    """How the scheme's master rod is described: a radial's (``"radial"``), one carrying a single
    slave rod (``"one_slave"``: a V engine's), one carrying several (``"several"``); None
    without articulated rods."""
    if md.is_radial(positions):
        return "radial"
    if not md.master_rod_bodies(positions, 0):
        return None
    return "one_slave" if md.cylinder_axes(positions) == 2 else "several"


def _front_view_kind(positions) -> str:
    """ "row": the scheme shows one cylinder of an in-line row; "rows": one of each bank; "": all."""
    shown = md.front_view(positions).guides
    if len(shown) == len(positions.guides):
        return ""
    return "row" if len(shown) == 1 else "rows"


def scale_text(scale: float, t) -> str:
    """A drawing's scale as written on it: "1:2,5" (a reduction), "1:1", "2:1" (an enlargement)."""
    return f"{t.number_g(scale, 4)}:1" if scale >= 1 else f"1:{t.number_g(1 / scale, 4)}"


def _counterweight_cranks(ctx) -> tuple[int, ...]:
    """The 1-based cranks the run fits a counterweight on, as the balancing and bearing sections
    compute them (none: a crank drawn without one)."""
    fitted = ctx.data(COUNTERWEIGHTS)
    return () if fitted is None else tuple(sorted({int(k) + 1 for k in fitted.crank}))


def _counterweight_angles(ctx) -> tuple[tuple[int, float], ...]:
    """(1-based crank, angle from its pin in the direction of rotation, rad) of every fitted
    counterweight: the ends' counterweights of a crank row sit where the balancing puts them,
    not opposite their pins."""
    fitted = ctx.data(COUNTERWEIGHTS)
    if fitted is None:
        return ()
    return tuple(
        (int(k) + 1, float(a))
        for k, a in zip(fitted.crank, fitted.angle_from_crank_rad, strict=True)
    )


def _counterweight_sentence(t, positions, turned) -> str:
    """What the shaded sector is: the crank's counterweight, opposite its pin or at the angle the
    balancing puts it; "" where none is drawn."""
    if not md.counterweights(positions, 0):
        return ""
    drawn = dict(turned).get(min(positions.counterweight_cranks or (1,)))
    if drawn is None or abs(drawn - math.pi) < 1e-6:
        return t("drawing.counterweight")
    return t("drawing.counterweight_turned", angle=t.fixed(math.degrees(drawn), 1))


def _with_counterweights(output: StageOutput, ctx, turned):
    """(positions, animation) geometries with the counterweights the run fits, where it fits
    them: on the cranks the balancing names, at its angles."""
    chosen = _counterweight_cranks(ctx)
    fitted = {"counterweight_cranks": chosen, "counterweight_angles": turned}
    positions = replace(_labelled(output.artifacts["positions"], ctx.t), **fitted)
    return positions, replace(output.artifacts["animation"], **fitted)


def render(output: StageOutput, ctx) -> str:
    """The scheme (at :data:`SCHEME_ANGLE_DEG`), the positions figure and the animated block (drawing only)."""
    t = ctx.t
    turned = _counterweight_angles(ctx)
    positions, animation = _with_counterweights(output, ctx, turned)
    angles = output.results["crank_angles_deg"]
    order = t.cylinders(positions.firing_order, " – ")
    marks = {
        "alpha": "α",
        "beta": "β",
        "omega": "ω",
        "tdc": t("drawing.mark_tdc"),
        "bdc": t("drawing.mark_bdc"),
    }
    scheme, scale = _scheme(
        ctx,
        positions,
        len(output.results["crank_angles_deg"]),
        _labels(positions, ctx),
        t("drawing.crank_star", cylinder=_first_cylinder(positions)),
        t("drawing.firing_order", order=order) if order else "",
        marks,
    )
    scale = scale_text(scale, t)
    scheme_angle = ctx.angle_text(output.results["scheme_angle_deg"])
    figure_scheme = ctx.figure(
        scheme,
        t(
            _scheme_caption(ctx, positions),
            scale=scale,
            angle=scheme_angle,
        ),
        "scheme",
        see="drawing.see_scheme",
    )
    # none for a whole degree, the step's resolution otherwise: "0°", "75,4°", "180°", "284,6°"
    frames = position_frames(
        angles,
        # a repeated or secondary dead centre (bdc_2, secondary_tdc_1) is named as its kind
        lambda k: t("drawing.position_" + re.sub(r"_\d+$", "", k), angle=ctx.angle_text(angles[k])),
        output.results.get("motion_period_deg", 360.0),
    )
    figure_positions = _positions_figures(ctx, positions, frames)
    svg, payload = md.animation_svg(animation)
    curves = output.artifacts["curves"]
    plot = md.cursor_plot_svg(curves["v"], curves["j"], t("drawing.curve_v"), t("drawing.curve_j"))
    # no conclusion of its own: the kinematics section's states the same angles, computed
    marked, bank_marks = _mark_texts(t, positions)
    return ctx.render_template(
        "sections/drawing.html.j2",
        figure_scheme=figure_scheme,
        scale=scale,
        scheme_angle=scheme_angle,
        marks=marked,
        bank_marks=bank_marks,
        stroke="S" in positions.dimensions,
        front_view=_front_view_kind(positions),
        master_rod=_master_rod_kind(positions),
        counterweight=_counterweight_sentence(t, positions, turned),
        figure_positions=figure_positions,
        svg=Markup(svg),
        plot=Markup(plot),
        payload=Markup(payload.replace("</", "<\\/")),
        step=output.results["animation_step_deg"],
        angles=angles,
        positions=POSITIONS,
    )


def _mark_texts(t, positions) -> tuple[bool, str]:
    """(whether the scheme marks α and β of one cylinder, the sentence naming each bank's or a
    radial's marks, "" otherwise): the text names each mark the scheme draws."""
    front = md.front_view(positions)
    marked = md.angle_mark_parts(front) is not None
    banks = None if marked else md.bank_mark_parts(front)
    own_pins = banks is not None and md.own_crank_pins(banks[1])
    # a bank of one cylinder (a V-twin) has no "first" cylinder to name
    single = banks is not None and len(positions.guides) == len(banks[1])
    bank_marks = (
        t(
            ("drawing.marks_banks_own_pins" if own_pins else "drawing.marks_banks")
            + ("_single" if single else ""),
            banks=", ".join(md.bank_letter(guide.label) for guide, _ in banks[1]),
            first=front.guides[0].label,
        )
        if banks
        else ""
    )
    if not marked and not banks and md.radial_mark_parts(front) is not None:
        bank_marks = t("drawing.marks_radial", first=front.guides[0].label)
    return marked, bank_marks


def _first_cylinder(positions) -> str:
    """Crank 1's first cylinder as printed (1, or 1Л of a V): the star shows the cranks at its
    TDC."""
    for _, _, cylinders in positions.cranks[:1]:
        if cylinders:
            return cylinders[0]
    return "1"


def _scheme_caption(ctx, positions) -> str:
    """The scheme's caption key: a piston engine's says the end it is seen from, the free end of
    a multi-crank shaft; a one-crank shaft has none (a radial is seen from its rear, opposite the
    propeller, or from the end opposite the power take-off)."""
    if not _has_cylinders(positions):
        return "drawing.scheme_caption"
    if len(positions.cranks) > 1:
        return "drawing.scheme_caption_free_end"
    propeller = power_take_off(ctx.scene) == "propeller"
    return "drawing.scheme_caption_rear_" + ("propeller" if propeller else "power")


def _has_cylinders(positions) -> bool:
    """True for a piston engine (its scheme is seen from the crankshaft's free end)."""
    return any(g.bore_m > 0 for g in positions.guides)


def _scheme_drawing(*args):
    """The scheme's figure alone (:func:`md.scheme_figure`)."""
    return md.scheme_figure(*args)[0]


def _scheme(ctx, *args):
    """(the scheme's figure builder, its scale) of :func:`md.scheme_figure` ``(*args)``: the
    figure is built here for its scale, unless this process drew the same scheme before
    (:mod:`crankdyn.report.figure_memo`: a batch's variants with the same dimensions)."""
    build = figure_memo.MemoFigure(_scheme_drawing, *args)
    scale = figure_memo.value(build.digest)
    if scale is None or figure_memo.svg(build.digest, ctx.t, ctx.symbols) is None:
        fig, scale = md.scheme_figure(*args)
        figure_memo.keep_value(build.digest, scale)
        build = figure_memo.MemoFigure(_scheme_drawing, *args, built=fig)
    return build, scale


def _positions_figures(ctx, positions, frames) -> Markup:
    """The positions figure, on as many figures as the page needs (:func:`md.positions_sheets`):
    the middle ones captioned as its continuation, the last one as its end."""
    t = ctx.t
    sheets = md.positions_sheets(positions, frames)
    scale = scale_text(md.positions_scale(positions), t)
    last = len(sheets)
    # several cylinders: the positions are those of the first one's piston (the others' pistons
    # stand elsewhere at the same crank angle)
    several = sum(1 for g in positions.guides if g.bore_m > 0) > 1
    parts = [
        ctx.figure(
            figure_memo.MemoFigure(md.positions_figure, positions, sheets[0]),
            t("drawing.positions_caption", scale=scale),
            "positions",
            see="drawing.see_positions_first" if several else "drawing.see_positions",
            see_params={"first": _first_cylinder(positions)} if several else None,
        )
    ]
    for k, sheet in enumerate(sheets[1:], start=2):
        parts.append(
            ctx.figure(
                figure_memo.MemoFigure(md.positions_figure, positions, sheet),
                t(
                    "drawing.positions_caption_" + ("continued" if k == last else "middle"),
                    scale=scale,
                ),
                f"positions_{k}",
                see="drawing.see_positions_" + ("continued" if k == last else "middle"),
            )
        )
    return Markup("\n").join(parts)
