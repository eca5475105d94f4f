"""The ``indicator`` stage's figures, drawn with matplotlib."""

from __future__ import annotations

import numpy as np

from crankdyn.report.figures import crank_angle_axis, new_figure


def _pumping_inset(ax, volume_l, theory_MPa, actual_MPa, t) -> None:
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
    inset.set_title(t("indicator.inset_title"), fontsize=7)


def _pv_figure(volume_l, pressure, theory, points, t):
    """The p–V diagram: the actual (or measured) cycle, the theoretical one and its characteristic points."""
    fig, ax = new_figure(16, 9.5)
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
        )
    for label, volume, p, (dx, dy) in points:
        ax.plot([volume], [p], "o", ms=3, color="k")
        ax.annotate(
            label,
            (volume, p),
            xytext=(dx, dy),
            textcoords="offset points",
            fontsize=8,
            style="italic",
            ha="left" if dx >= 0 else "right",
            va="center" if dy == 0 else "bottom" if dy > 0 else "top",
        )
    ax.set_xlabel(t("indicator.axis_volume"))
    ax.set_ylabel(t("indicator.axis_pressure"))
    ax.legend(loc="upper right", fontsize=8)
    return fig


def _palpha_figure(angle, pressure, theory, cycle_deg, t):
    """The pressure against the crank angle over the cycle (with the theoretical one, if any)."""
    fig, ax = new_figure(16, 8)
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
