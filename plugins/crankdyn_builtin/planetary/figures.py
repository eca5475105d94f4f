"""The ``planetary`` stage's figures, drawn with matplotlib."""

from __future__ import annotations

import functools

import numpy as np

from crankdyn.report.figures import crank_angle_axis, new_figure

from .compute import FAMILY_RATIOS


def _circle(ax, centre, radius, **style):
    theta = np.linspace(0.0, 2.0 * np.pi, 361)
    ax.plot(centre[0] + radius * np.sin(theta), centre[1] + radius * np.cos(theta), **style)


def _path_figure(f, r, inside, ctx) -> str:
    """The big end's trajectory and the mechanism at TDC with the torque arm MN (source, figs. 1 and 3b)."""
    return ctx.figure(
        functools.partial(_path_plot, f, r, inside, ctx.t),
        ctx.t("planetary.path_caption"),
        "planetary_path",
        see="planetary.see_path",
    )


def _path_plot(f, r, inside, t):
    """The gears' pitch circles, the big end's path and the mechanism at TDC with its arm MN."""
    mm = 1e3
    snap = r["tdc_snapshot_m"]
    fig, ax = new_figure(16, 10)
    _circle(
        ax,
        (0.0, 0.0),
        r["fixed_pitch_diameter_m"] / 2 * mm,
        color="0.5",
        ls="--",
        lw=0.9,
        label=t("planetary.fixed_gear"),
    )
    _circle(
        ax,
        (0.0, 0.0),
        r["carrier_radius_m"] * mm,
        color="0.7",
        ls=":",
        lw=0.9,
        label=t("planetary.carrier_path"),
    )
    ax.plot(
        f["big_end_x_m"][inside] * mm,
        f["big_end_z_m"][inside] * mm,
        color="C0",
        label=t("planetary.big_end_path"),
    )
    centre = np.array(snap["planet_centre"]) * mm
    _circle(
        ax,
        centre,
        r["planet_pitch_diameter_m"] / 2 * mm,
        color="C2",
        lw=0.9,
        label=t("planetary.planet_at_tdc"),
    )
    pin, piston, pitch, foot = (
        np.array(snap[k]) * mm for k in ("pin", "piston_pin", "pitch_point", "arm_foot")
    )
    # the frame holds the ring's or sun's pitch circle, the planet and the path with a margin
    reach = max(
        r["fixed_pitch_diameter_m"] / 2,
        r["carrier_radius_m"] + r["planet_pitch_diameter_m"] / 2,
        r["carrier_radius_m"] + r["pin_radius_m"],
    )
    extent = reach * mm * 1.12
    top = extent + 0.3 * r["rod_length_m"] * mm  # room for a part of the rod above the path
    ax.plot([0, centre[0]], [0, centre[1]], color="C2", lw=2)
    ax.plot([centre[0], pin[0]], [centre[1], pin[1]], color="C2", lw=1.2)
    # The rod towards the piston pin (cut at the frame's top), and its line of action down to the
    # foot N of the perpendicular from the shaft axis, the source's arm MN when it is not zero.
    ax.plot(
        [pin[0], piston[0]],
        [pin[1], piston[1]],
        color="C3",
        lw=1.6,
        label=t("planetary.rod_at_tdc"),
    )
    ax.plot([pin[0], foot[0]], [pin[1], foot[1]], color="C3", lw=0.7, ls="--")
    arm = float(np.hypot(*foot))
    if arm > 1e-6 * r["stroke_m"] * mm:
        ax.plot([0, foot[0]], [0, foot[1]], color="k", lw=1.0, label="MN")
    ax.plot([0], [0], "k+", ms=8)
    ax.plot([pitch[0]], [pitch[1]], "ko", ms=3)
    _point_letters(ax, centre, pin, pitch)
    ax.axvline(0, color="0.3", lw=0.5)
    ax.set_xlim(-extent, extent)
    ax.set_ylim(-extent, top)
    ax.set_aspect("equal")
    ax.set_xlabel(t("planetary.axis_x"))
    ax.set_ylabel(t("planetary.axis_z"))
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8)
    return fig


def _point_letters(ax, centre, pin, pitch) -> None:
    """The letters of the shaft axis O, the planet centre C, its pin B and the pitch point K."""
    for point, text, offset in (
        ((0.0, 0.0), "O", (4, -10)),
        (centre, "C", (4, -4)),
        (pin, "B", (4, -4)),
        (pitch, "K", (-10, 3)),
    ):
        ax.annotate(
            text, point, xytext=offset, textcoords="offset points", fontsize=9, fontstyle="italic"
        )


def _family_figure(family, r, ctx) -> str:
    """The big-end paths of the source's fig. 2 family of gear ratios."""
    return ctx.figure(
        functools.partial(_family_plot, family, r["fixed_pitch_diameter_m"], ctx.t),
        ctx.t("planetary.family_caption_" + r["gear"]),
        "planetary_family",
        see="planetary.see_family_" + r["gear"],
    )


def _family_plot(family, fixed_pitch_diameter_m, t):
    """One big-end path per gear ratio of the family, side by side, in the fixed gear's pitch circle."""
    mm = 1e3
    fig, axes = new_figure(16, 6.5, ncols=3)
    for ax, ratio in zip(axes, FAMILY_RATIOS, strict=True):
        d_fixed = fixed_pitch_diameter_m * mm
        _circle(ax, (0.0, 0.0), d_fixed / 2, color="0.5", ls="--", lw=0.8)
        ax.plot(
            family[f"ratio_{ratio:g}_x_m"] * mm, family[f"ratio_{ratio:g}_z_m"] * mm, color="C0"
        )
        ax.set_aspect("equal")
        # numbers in the report's locale; a semicolon parts the two (a decimal comma would not)
        ax.set_title(
            f"d_p = {t.number_g(d_fixed / ratio, 4)}; d_f = {t.number_g(d_fixed, 4)} "
            + t("unit.mm"),
            fontsize=8,
        )
        ax.tick_params(labelsize=7)
    return fig


def _motion_figure(f, angle, inside, span, r, ctx) -> str:
    """Piston displacement, velocity and acceleration against the equivalent crank-slider's (source, fig. 3a)."""
    return ctx.figure(
        functools.partial(_motion_plot, f, angle, inside, span, r["reversals"], ctx.t),
        ctx.t("planetary.motion_caption"),
        "planetary_motion",
        see="planetary.see_motion",
    )


def _motion_plot(f, angle, inside, span, reversals, t):
    """The piston's s, v, j over the period, the equivalent crank-slider's dashed beside them; the
    piston's reversals marked on its displacement."""
    mm = 1e3
    fig, axes = new_figure(16, 16, nrows=3, sharex=True)
    for ax, key, unit, scale, label in (
        (axes[0], "piston_displacement", "_m", mm, "planetary.axis_s"),
        (axes[1], "piston_velocity", "_m_s", 1.0, "planetary.axis_v"),
        (axes[2], "piston_acceleration", "_m_s2", 1.0, "planetary.axis_j"),
    ):
        ax.plot(
            angle[inside], f[key + unit][inside] * scale, color="C0", label=t("planetary.planetary")
        )
        ax.plot(
            angle[inside],
            f["conventional_" + key + unit][inside] * scale,
            color="0.45",
            ls="--",
            lw=1,
            label=t("planetary.conventional"),
        )
        ax.axhline(0, color="0.3", lw=0.6)
        ax.set_ylabel(t(label))
    for item in reversals:
        axes[0].plot(
            [item["crank_angle_deg"]],
            [item["displacement_m"] * mm],
            "o",
            color="C3" if item["main"] else "C1",
            ms=4,
            zorder=5,
        )
        axes[0].annotate(
            t.number_g(round(item["crank_angle_deg"], 1), 4) + "°",
            (item["crank_angle_deg"], item["displacement_m"] * mm),
            # s grows towards BDC: a BDC is a peak of the curve, a TDC a dip
            xytext=(0, 5 if item["kind"] == "bdc" else -12),
            textcoords="offset points",
            ha="center",
            fontsize=7,
        )
    low, high = axes[0].get_ylim()
    axes[0].set_ylim(low, high + 0.12 * (high - low))  # room for the labels above the BDCs
    axes[0].legend(loc="lower center", fontsize=8)
    crank_angle_axis(axes[2], span, t("planetary.axis_carrier_angle"))
    return fig


def _arms_figure(f, angle, inside, span, ctx) -> str:
    """How a piston force reaches the carrier: the torque arms and the tooth and carrier force ratios."""
    return ctx.figure(
        functools.partial(_arms_plot, f, angle, inside, span, ctx.t),
        ctx.t("planetary.arms_caption"),
        "planetary_arms",
        see="planetary.see_arms",
    )


def _arms_plot(f, angle, inside, span, t):
    """The torque arms above the tooth and carrier force ratios over the period."""
    mm = 1e3
    fig, axes = new_figure(16, 12, nrows=2, sharex=True)
    axes[0].plot(
        angle[inside],
        f["carrier_torque_arm_m"][inside] * mm,
        color="C0",
        label=t("planetary.arm_effective"),
    )
    axes[0].plot(
        angle[inside],
        f["rod_line_arm_m"][inside] * mm,
        color="C3",
        ls=":",
        label=t("planetary.arm_rod_line"),
    )
    axes[0].plot(
        angle[inside],
        f["conventional_torque_arm_m"][inside] * mm,
        color="0.45",
        ls="--",
        lw=1,
        label=t("planetary.arm_conventional"),
    )
    axes[0].set_ylabel(t("planetary.axis_arm"))
    axes[0].legend(loc="upper right", fontsize=8)
    axes[1].plot(
        angle[inside],
        f["tooth_tangential_per_piston_force"][inside],
        color="C2",
        label=t("planetary.tooth_force"),
    )
    axes[1].plot(
        angle[inside],
        f["carrier_radial_per_piston_force"][inside],
        color="C4",
        ls="--",
        label=t("planetary.carrier_radial"),
    )
    axes[1].set_ylabel(t("planetary.axis_force_ratio"))
    axes[1].legend(loc="upper right", fontsize=8)
    for ax in axes:
        ax.axhline(0, color="0.3", lw=0.6)
    crank_angle_axis(axes[1], span, t("planetary.axis_carrier_angle"))
    return fig
