"""The worked substitution of the indicator stage: the polytrope's pressure at one table row.

The scene's worked angle is moved by whole strokes (180°) until it lies on the compression or
the expansion polytrope of the theoretical diagram (at 30° a four-stroke engine is still
drawing in at constant pressure), so the example shows the formula a supervisor checks.
"""

from __future__ import annotations

from markupsafe import Markup

from crankdyn.report.worked import (
    WorkedBlock,
    WorkedStep,
    printed,
    printed_g,
    worked_markup,
    worked_row,
)


def polytrope_of(crank_angle_deg: float, strokes: int) -> str | None:
    """ "compression", "expansion" or None (gas exchange), as the theoretical diagram has it."""
    cycle = 180.0 * strokes
    a = crank_angle_deg % cycle
    if strokes == 4:
        return "compression" if 180.0 < a < 360.0 else "expansion" if 360.0 < a < 540.0 else None
    return "expansion" if 0.0 < a < 180.0 else "compression" if 180.0 < a < 360.0 else None


def _worked_row(frame, rows, labels, r, scene, wanted_deg):
    """The printed row nearest the worked angle (moved by whole strokes) on a polytrope, or None."""
    volume = frame["cylinder_volume_m3"][rows]
    v_z = scene.cycle.pre_expansion_ratio * r["clearance_volume_m3"]
    v_a = _start_volume_m3(r, scene)
    for shift in (0.0, 360.0, 180.0, 540.0):
        i = worked_row(labels, (wanted_deg + shift) % (180.0 * scene.engine.strokes))
        line = polytrope_of(float(labels[i]), scene.engine.strokes)
        if line is not None and v_z < volume[i] < v_a:
            return i, line
    return None


def _start_volume_m3(r, scene) -> float:
    """The volume the polytropes start from, m³: V_a′ at a two-stroke's exhaust port closing and
    opening, else V_a = ε·V_c."""
    if "port_closing_volume_m3" in r:
        return r["port_closing_volume_m3"]
    return scene.cycle.compression_ratio * r["clearance_volume_m3"]


def worked_indicator(ctx, frame, rows, labels, r) -> Markup:
    """``p = p_a (V_a/V)^n1`` or ``p = p_b (V_a/V)^n2`` with the numbers of one row of the table."""
    scene = ctx.scene
    if "pressure_theoretical_Pa" not in frame:
        return Markup("")  # a measured trace: no formula to substitute
    found = _worked_row(frame, rows, labels, r, scene, ctx.worked_angle_deg)
    if found is None:
        return Markup("")
    i, line = found
    t, c = ctx.t, scene.cycle
    alpha = float(labels[i])
    volume_l = float(frame["cylinder_volume_m3"][rows][i]) * 1e3
    v_a_l = _start_volume_m3(r, scene) * 1e3
    v_a_html = "<i>V</i><sub>a′</sub>" if "port_closing_volume_m3" in r else "<i>V</i><sub>a</sub>"
    if line == "compression":
        start, start_html, index, index_html = (
            c.intake_pressure / 1e6,
            "<i>p</i><sub>a</sub>",
            c.compression_index,
            "<i>n</i><sub>1</sub>",
        )
    else:
        start, start_html, index, index_html = (
            r["expansion_end_pressure_Pa"] / 1e6,
            "<i>p</i><sub>b</sub>",
            c.expansion_index,
            "<i>n</i><sub>2</sub>",
        )
    p_txt, p0 = printed(t, start, 5) if line == "expansion" else printed_g(t, start)
    n_txt, n = printed_g(t, index)
    va_txt, v_a = printed(t, v_a_l, 5)
    v_txt, v = printed(
        t, volume_l, 5
    )  # one digit more than the table: the power magnifies round-off
    inputs = {"p0": p0, "n": n, "V_a": v_a, "V": v, "alpha_deg": alpha}
    exact = {"p0": start, "n": index, "V_a": v_a_l, "V": volume_l, "alpha_deg": alpha}
    step = WorkedStep(
        "polytrope_pressure",
        "<i>p</i><sub>theor</sub>",
        f"{start_html}({v_a_html}/<i>V</i>)<sup>{index_html}</sup>",
        f"{p_txt}·({va_txt}/{v_txt})<sup>{n_txt}</sup>",
        float(frame["pressure_theoretical_Pa"][rows][i]) / 1e6,
        4,
        t("unit.MPa"),
        inputs,
        exact=exact,
    )
    note = t(f"indicator.worked_{line}", angle=ctx.angle_text(alpha))
    return worked_markup(
        ctx, WorkedBlock("indicator", ctx.last_table_number, alpha, [step], note=note)
    )
