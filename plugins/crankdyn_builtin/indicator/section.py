"""The ``indicator`` stage's section: ``render``, the tables and the conclusions of its text."""

from __future__ import annotations

from functools import partial

import numpy as np

from crankdyn.plugin.contracts import FLYWHEEL
from crankdyn.plugin.types import StageOutput, Symbol
from crankdyn.report.context import add_extreme_rows, sample_rows
from crankdyn_builtin.indicator.worked import worked_indicator

from .compute import MEAN_PRESSURE_CHECK_PERCENT
from .figures import _palpha_figure, _pv_figure

#: The textbook's characteristic points of a four-stroke diagram: (label, crank angle of cylinder 1 in
#: degrees or an event's name, which curve, label offset in points). 0° is the TDC at
#: the start of intake; "advance" is the ignition (injection), "visible" the start of visible
#: combustion, "peak" the actual cycle's largest pressure, "exhaust" the exhaust valve's opening;
#: the curve is the theoretical or the actual (rounded) one, or p_c for the end of compression.
#: A vertical offset of 0 centres the label on its point's height: b″ stands between b and a at
#: BDC, and a label under it would read as a's. At TDC the labels keep the points' order from the
#: top: c″ (the actual pressure at TDC) above and right, c beside on the left, f under it.
_POINTS = (
    ("r", 0.0, "actual", (4, 3)),
    ("a", "bdc", "actual", (-4, -3)),
    ("c", 360.0, "compression_end", (-4, 0)),
    ("c′", "advance", "actual", (4, -3)),
    ("f", "visible", "actual", (-5, -3)),
    ("c″", 360.0, "actual", (4, 2)),
    ("z", "theory_peak", "theory", (4, 2)),
    ("z′", "peak", "actual", (4, 2)),
    ("b′", "exhaust", "actual", (3, 3)),
    ("b", "expansion_bdc", "theory", (4, 3)),
    ("b″", "expansion_bdc", "actual", (5, 0)),
)


#: The characteristic points of a port-scavenged two-stroke diagram (0° is firing TDC): b the
#: exhaust port opening (the theoretical expansion's end), a′ their closing (the start of
#: compression), and the points of combustion as in a four-stroke diagram.
_PORT_POINTS = (
    ("b", "ports_open", "theory", (4, 3)),
    ("a′", "ports_close", "actual", (-4, -3)),
    ("c", 0.0, "compression_end", (-4, 0)),
    ("c′", "advance", "actual", (4, -3)),
    ("f", "visible", "actual", (-5, -3)),
    ("c″", 0.0, "actual", (4, 2)),
    ("z", "theory_peak", "theory", (4, 2)),
    ("z′", "peak", "actual", (4, 2)),
)


def _combustion_angles(r, angle, theory) -> dict[str, float]:
    """The crank angles of cylinder 1 (deg, from the TDC before firing's cycle start) of the
    rounding's events as run() used them (its results): the ignition (injection), the start of
    visible combustion, the actual peak and the end of heat addition of the theoretical cycle (at
    ρV_c in a diesel's: the last point at p_z)."""
    return {
        "advance": 360.0 - r["ignition_advance_deg"],
        "visible": 360.0 - r["ignition_advance_deg"] + r["combustion_delay_deg"],
        "peak": r["max_pressure_crank_angle_deg"],
        "theory_peak": float(angle[int(np.flatnonzero(theory >= theory.max() * (1 - 1e-12))[-1])]),
    }


def _curve_pressure(curve: str, i: int, r, theory, actual) -> float:
    """A characteristic point's pressure (MPa) on its curve at grid index ``i``; c is the end of
    the compression line, p_c: at TDC itself the theoretical spark-ignition cycle is already at
    p_z (heat added at constant volume)."""
    if curve == "compression_end":
        return r["compression_end_pressure_Pa"] / 1e6
    return float(theory[i] if curve == "theory" else actual[i])


def _port_points(frame, r) -> list[tuple[str, float, float, tuple[int, int]]]:
    """The characteristic points of a two-stroke diagram with exhaust ports (as
    :func:`_characteristic_points`)."""
    angle = frame["crank_angle_deg"]
    theory, actual = frame["pressure_theoretical_Pa"] / 1e6, frame["pressure_Pa"] / 1e6
    where = _combustion_angles(r, angle, theory)
    points = []
    volume_l = frame["cylinder_volume_m3"] * 1e3
    for label, at, curve, offset in _PORT_POINTS:
        if at == "ports_open":  # the end of the expansion polytrope, at V_a′
            points.append(
                (
                    label,
                    r["port_closing_volume_m3"] * 1e3,
                    r["expansion_end_pressure_Pa"] / 1e6,
                    offset,
                )
            )
            continue
        if at == "ports_close":  # the start of compression: p_a at V_a′
            points.append((label, r["port_closing_volume_m3"] * 1e3, float(theory.min()), offset))
            continue
        i = int(np.argmin(np.abs((angle - where.get(at, at) + 180.0) % 360.0 - 180.0)))
        p = _curve_pressure(curve, i, r, theory, actual)
        points.append((label, float(volume_l[i]), p, offset))
    return points


def _characteristic_points(ctx, frame, r) -> list[tuple[str, float, float, tuple[int, int]]]:
    """(label, volume in l, pressure in MPa, label offset) of each characteristic point of a
    four-stroke diagram, or a two-stroke one with exhaust ports, computed from cycle data; none
    for other cycles."""
    if ctx.scene is None or getattr(ctx.scene, "cycle", None) is None:
        return []
    if ctx.scene.engine.strokes == 2 and "lost_stroke_fraction" in r:
        return _port_points(frame, r)
    if ctx.scene.engine.strokes != 4:
        return []
    angle = frame["crank_angle_deg"]
    theory, actual = frame["pressure_theoretical_Pa"] / 1e6, frame["pressure_Pa"] / 1e6
    bdc = r.get("bdc_crank_angle_deg", 180.0)  # the mechanism's BDC (points a and b)
    # the rounding's angles as run() used them (its results), the valve timing as the scene gives it
    where = {
        **_combustion_angles(r, angle, theory),
        "exhaust": 360.0 + bdc - ctx.scene.cycle.rounding.exhaust_opens_before_bdc_deg,
        "bdc": bdc,
        "expansion_bdc": 360.0 + bdc,
    }
    step = float(angle[1] - angle[0])
    points = []
    for label, at, curve, offset in _POINTS:
        i = int(round(where.get(at, at) / step)) % len(
            angle
        )  # a named event's angle, or the angle given
        p = _curve_pressure(curve, i, r, theory, actual)
        points.append((label, float(frame["cylinder_volume_m3"][i] * 1e3), p, offset))
    return points


def _pressure_table(ctx, frame, theory):
    """Table of V, p (and p_theor) at the table step with the peak pressure's row; its rows."""
    t = ctx.t
    angle = frame["crank_angle_deg"]
    volume_l = frame["cylinder_volume_m3"] * 1e3
    pressure = frame["pressure_Pa"] / 1e6
    has_theory = theory is not None
    rows, labels = sample_rows(angle, ctx.table_step_deg)
    rows, labels, extremes = add_extreme_rows(
        angle, rows, labels, [(pressure, "max", t("indicator.extreme_p_max"))]
    )
    columns = [
        ("<i>α</i>, °", ctx.angle_labels(labels), None),
        ("<i>V</i>, " + t("unit.l"), volume_l[rows], 4),
    ]
    if has_theory:
        columns.append(
            (
                "<i>p</i><sub>theor</sub>, " + t("unit.MPa"),
                _closing_row_theory(theory, rows, labels, ctx.cycle_deg),
                4,
            )
        )
    columns.append(("<i>p</i>, " + t("unit.MPa"), pressure[rows], 4))
    table = ctx.table(
        columns, caption=t("indicator.table_caption"), extremes=extremes, see="indicator.see_table"
    )
    return table, rows, labels


def _conclude(ctx, r: dict, two_stroke: bool = False):
    """The abstract's finding and the conclusions on the peak pressure and the indicated work;
    returns the mean indicated pressure's deviation from the given one (percent) or None. A
    two-stroke cycle has no pumping strokes to leave out of the diagram's mean pressure."""
    t = ctx.t
    ctx.find(
        t(
            "indicator.finding",
            p_max=ctx.num(r["max_pressure_Pa"] / 1e6),
            angle=ctx.angle_text(r["max_pressure_crank_angle_deg"]),
        )
    )
    deviation = r.get("mean_indicated_pressure_deviation_percent")
    ctx.conclude(
        t(
            "indicator.conclusion",
            p_max=ctx.num(r["max_pressure_Pa"] / 1e6),
            angle=ctx.angle_text(r["max_pressure_crank_angle_deg"]),
            p_i=ctx.num(r["mean_indicated_pressure_Pa"] / 1e6),
            work=ctx.num(r["indicated_work_J"]),
        )
    )
    if deviation is not None:
        key = (
            "indicator.check_ok"
            if abs(deviation) <= MEAN_PRESSURE_CHECK_PERCENT
            else "indicator.check_bad"
        )
        ctx.conclude(t(key + ("_two" if two_stroke else ""), deviation=ctx.num(deviation, 2)))
    return deviation


def render(output: StageOutput, ctx) -> str:
    t = ctx.t
    frame = output.tables.arrays("indicator")
    r = output.results
    angle = frame["crank_angle_deg"]
    volume_l = frame["cylinder_volume_m3"] * 1e3
    pressure = frame["pressure_Pa"] / 1e6
    has_theory = "pressure_theoretical_Pa" in frame

    theory = frame["pressure_theoretical_Pa"] / 1e6 if has_theory else None
    points = _characteristic_points(ctx, frame, r) if has_theory else []
    two_stroke = ctx.scene is not None and ctx.scene.engine.strokes == 2
    ports = _port_marks(r, t)
    figure_pv = ctx.figure(
        partial(
            _pv_figure, volume_l, pressure, theory, points, t, two_stroke=two_stroke, ports=ports
        ),
        t("indicator.pv_caption_points" if points else "indicator.pv_caption"),
        "pV",
        see="indicator.see_pv",
    )
    pv_number = ctx.last_figure_number
    figure_pa = ctx.figure(
        partial(_palpha_figure, angle, pressure, theory, ctx.cycle_deg, t, ports=ports),
        t("indicator.palpha_caption"),
        "p_alpha",
        see="indicator.see_palpha",
    )

    table, rows, labels = _pressure_table(ctx, frame, theory)
    table += worked_indicator(ctx, frame, rows, labels, r)

    deviation = _conclude(ctx, r, two_stroke)
    diesel = getattr(getattr(ctx.scene, "cycle", None), "ignition", None) == "diesel"
    return ctx.render_template(
        "sections/indicator.html.j2",
        r=r,
        # the excess work is the flywheel section's: named only where there is one
        excess_work=ctx.data(FLYWHEEL) is not None,
        figure_pv=figure_pv,
        figure_pa=figure_pa,
        diesel=diesel,
        points=bool(points),
        pv_number=pv_number,
        table=table,
        deviation=deviation,
        has_theory=has_theory,
        two_stroke=two_stroke,
        rho_case=_pre_expansion_case(ctx.scene) if diesel else "",
    )


def _port_marks(r: dict, t) -> dict | None:
    """A port-scavenged two-stroke's marks on the figures: the volume V_a′ (l) and the crank
    angles (deg) of the exhaust port opening b and closing a′ with their names; None otherwise."""
    if "lost_stroke_fraction" not in r:
        return None
    return {
        "volume_l": r["port_closing_volume_m3"] * 1e3,
        "angles": (
            ("b", r["exhaust_ports_open_deg"], t("indicator.ports_open_label")),
            ("a′", r["exhaust_ports_close_deg"], t("indicator.ports_close_label")),
        ),
    }


def _pre_expansion_case(scene) -> str:
    """The suffix of a diesel's intro: "" with constant-pressure heat addition (ρ > 1),
    "_isochoric" with ρ = 1 given, "_taken" with ρ = 1 taken for want of one in the scene (then
    all the heat is added at constant volume and the diagram reaches p_z at TDC)."""
    cycle = scene.cycle
    if cycle.pre_expansion_ratio > 1.0:
        return ""
    return "_isochoric" if "pre_expansion_ratio" in cycle.model_fields_set else "_taken"


def _closing_row_theory(theory, rows, labels, cycle_deg: float):
    """The theoretical pressure at the table's rows, the closing row (720°) given the value the
    diagram ends the cycle with: where it ends on a flat line (the exhaust line at p_r, point r),
    that line's value, not the intake's p_a that the periodic grid has at 0° (the theoretical
    diagram steps from p_r to p_a at TDC; a table with p_a at 720° contradicts point r)."""
    shown = np.array(theory[rows], dtype=float)
    if (
        len(labels)
        and abs(float(labels[-1]) - cycle_deg) < 1e-9
        and len(theory) > 2
        and theory[-1] == theory[-2]
    ):
        shown[-1] = theory[-1]
    return shown


#: The indicator's own letters (Stage.symbols): the theoretical (unrounded) diagram's pressure of its table.
SYMBOLS = {
    "theoretical_pressure": Symbol("p", {"en": "theor", "uk": "теор", "ru": "теор"}, "unit.MPa"),
    # the textbook's φ_п, not the crank angle φ of an offset crank-slider
    "fullness": Symbol("φ", {"en": "f", "uk": "п", "ru": "п"}, ""),
    # a port-scavenged two-stroke's exhaust ports (Kolchin and Demidov)
    "lost_stroke_fraction": Symbol("ψ", {}, ""),
    "port_travel": Symbol("s", {"en": "b"}, "unit.mm"),
    "port_volume": Symbol("V", {"en": "a′"}, "unit.l"),
    "actual_compression_ratio": Symbol("ε", {"en": "t", "uk": "д", "ru": "д"}, ""),
}
