"""The ``indicator`` stage's figures, drawn with matplotlib."""

from __future__ import annotations

import numpy as np

from crankdyn.report.figures import crank_angle_axis, new_figure


def _pumping_inset(ax, volume_l, theory_MPa, actual_MPa, t, two_stroke=False) -> None:
    """The exhaust and intake strokes enlarged in a corner of the p–V diagram: at the scale of the
    combustion peak the pumping loop (0,1 MPa against 5 MPa) is one line."""
    low = 0.45 * float(np.max(actual_MPa)) / 5.0 + 0.1  # about 0.55 MPa for a 5 MPa peak
    inset = ax.inset_axes([0.45, 0.32, 0.5, 0.42])
    inset.plot(volume_l, theory_MPa, color="0.45", lw=0.8, ls="--")
    inset.plot(volume_l, actual_MPa, color="C3", lw=1.0)
    inset.set_ylim(0.0, low)
    inset.set_xlim(float(np.min(volume_l)), float(np.max(volume_l)))
    inset.tick_params(labelsize=7)
    inset.set_xlabel(t("indicator.axis_volume"), fontsize=7, labelpad=1)
    inset.set_ylabel(t("indicator.axis_pressure"), fontsize=7, labelpad=1)
    # a two-stroke has no pumping strokes: its low-pressure part is the scavenging near BDC
    inset.set_title(
        t("indicator.inset_title_two" if two_stroke else "indicator.inset_title"), fontsize=7
    )


#: The least vertical distance between the centres of two labels on one side of their points, pt
#: (8-pt type), and the distance from a point to the centre of a label above or under it.
LABEL_GAP_PT = 9.0
LABEL_HALF_HEIGHT_PT = 4.0
#: Points closer than this fraction of the volume range have their labels kept apart.
NEAR_FRACTION = 0.08


def separated_labels(points, pressures, axes_height_pt: float, gap_pt: float = LABEL_GAP_PT):
    """``points`` (label, volume, pressure, (dx, dy) in points, dy to the label's near edge: up,
    down or 0 for beside) as (label, volume, pressure, (dx, dy to the label's centre)), with the
    labels that stand on the same side of their points moved apart to at least ``gap_pt``
    between centres: near TDC a diesel's c, f and c″ lie within a few tenths of a megapascal and
    their labels would print over one another. The height scale is the axes'
    (``axes_height_pt`` over the range of ``pressures``)."""
    span = float(np.ptp(pressures)) or 1.0
    low = float(np.min(pressures))
    out = [
        (label, volume, p, (dx, dy + float(np.sign(dy)) * LABEL_HALF_HEIGHT_PT))
        for label, volume, p, (dx, dy) in points
    ]
    if not out:  # a measured trace has no characteristic points
        return out
    volumes = [volume for _, volume, _, _ in out]
    near = NEAR_FRACTION * (max(volumes) - min(volumes) or 1.0)
    for side in (True, False):  # labels right of their points, then left of them
        placed: list[tuple[float, float]] = []  # (centre, volume) of the labels placed so far
        for y, k in sorted(
            (axes_height_pt * (p - low) / span + dy, k)
            for k, (_, _, p, (dx, dy)) in enumerate(out)
            if (dx >= 0) == side
        ):
            label, volume, p, (dx, dy) = out[k]
            below = [c for c, v in placed if abs(v - volume) < near and y - c < gap_pt]
            if below:  # over a label of a point nearby: moved up to stand clear of it
                shift = max(below) + gap_pt - y
                out[k] = (label, volume, p, (dx, dy + shift))
                y += shift
            placed.append((y, volume))
    return out


def _pv_figure(volume_l, pressure, theory, points, t, two_stroke=False, ports=None):
    """The p–V diagram: the actual (or measured) cycle, the theoretical one and its characteristic
    points; with ``ports`` (:func:`section._port_marks`) the volume V_a′ of the exhaust ports'
    edge, where they open (b) and close (a′)."""
    fig, ax = new_figure(16, 9.5)
    if ports is not None:
        ax.axvline(ports["volume_l"], color="0.6", lw=0.7, ls=":")
        ax.annotate(
            # the prime as a text character: mathtext's \prime is a symbol font's "0" to a reader
            r"$V_{\mathrm{a}}$′",
            (ports["volume_l"], 1.0),
            xycoords=("data", "axes fraction"),
            xytext=(-3, -10),
            textcoords="offset points",
            fontsize=8,
            style="italic",
            ha="right",
        )
    if theory is not None:
        ax.plot(
            np.append(volume_l, volume_l[0]),
            np.append(theory, theory[0]),
            color="0.45",
            lw=1,
            ls="--",
            label=t("indicator.theoretical"),
        )
    ax.plot(
        np.append(volume_l, volume_l[0]),
        np.append(pressure, pressure[0]),
        color="C3",
        label=t("indicator.actual") if theory is not None else t("indicator.trace"),
    )
    if theory is not None:
        _pumping_inset(
            ax,
            np.append(volume_l, volume_l[0]),
            np.append(theory, theory[0]),
            np.append(pressure, pressure[0]),
            t,
            two_stroke,
        )
    pressures = np.append(pressure, theory if theory is not None else pressure)
    for label, volume, p, (dx, dy) in separated_labels(points, pressures, 9.5 * 0.8 * 72 / 2.54):
        ax.plot([volume], [p], "o", ms=3, color="k")
        ax.annotate(
            label,
            (volume, p),
            xytext=(dx, dy),
            textcoords="offset points",
            fontsize=8,
            style="italic",
            ha="left" if dx >= 0 else "right",
            va="center",
        )
    ax.set_xlabel(t("indicator.axis_volume"))
    ax.set_ylabel(t("indicator.axis_pressure"))
    ax.legend(loc="upper right", fontsize=8)
    return fig


def _palpha_figure(angle, pressure, theory, cycle_deg, t, ports=None):
    """The pressure against the crank angle over the cycle (with the theoretical one, if any);
    with ``ports`` the exhaust ports' opening b and closing a′ marked."""
    fig, ax = new_figure(16, 8)
    if ports is not None:
        for label, at, name in ports["angles"]:
            ax.axvline(at, color="0.6", lw=0.7, ls=":")
            ax.annotate(
                f"{label} – {name}",
                (at, 0.97),
                xycoords=("data", "axes fraction"),
                xytext=(3, 0),
                textcoords="offset points",
                fontsize=7,
                rotation=90,
                ha="left",
                va="top",
            )
    if theory is not None:
        ax.plot(angle, theory, color="0.45", lw=1, ls="--", label=t("indicator.theoretical"))
    ax.plot(
        angle,
        pressure,
        color="C3",
        label=t("indicator.actual") if theory is not None else t("indicator.trace"),
    )
    crank_angle_axis(ax, cycle_deg, t("axis.crank_angle"))
    ax.set_ylabel(t("indicator.axis_pressure"))
    ax.legend(loc="upper right", fontsize=8)
    return fig
