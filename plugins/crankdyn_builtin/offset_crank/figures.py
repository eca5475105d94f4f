"""The ``offset_crank`` stage's figures, drawn with matplotlib."""

from __future__ import annotations

from crankdyn.report.figures import crank_angle_axis, new_figure


def _piston_figure(f, bdc_crank_angle_deg, t):
    """The piston's s, v, j over one revolution against the central crank-slider's, BDC marked."""
    angle = f["crank_angle_deg"]
    one = angle < 360.0
    fig, axes = new_figure(16, 16, nrows=3, sharex=True)
    for ax, key, label in (
        (axes[0], "piston_displacement", "offset_crank.axis_s"),
        (axes[1], "piston_velocity", "offset_crank.axis_v"),
        (axes[2], "piston_acceleration", "offset_crank.axis_j"),
    ):
        scale = 1e3 if key == "piston_displacement" else 1.0
        unit = (
            "_m"
            if key == "piston_displacement"
            else ("_m_s" if key == "piston_velocity" else "_m_s2")
        )
        ax.plot(
            angle[one], f[key + unit][one] * scale, color="C0", label=t("offset_crank.offset_label")
        )
        ax.plot(
            angle[one],
            f["central_" + key + unit][one] * scale,
            color="0.45",
            ls="--",
            lw=1,
            label=t("offset_crank.central_label"),
        )
        ax.axhline(0, color="0.3", lw=0.6)
        ax.set_ylabel(t(label))
    axes[0].axvline(bdc_crank_angle_deg, color="C3", lw=0.8, ls=":")
    axes[0].legend(loc="upper right", fontsize=8)
    crank_angle_axis(axes[2], 360.0, t("axis.crank_angle"))
    return fig


def _rod_figure(f, t):
    """The rod's angle over one revolution."""
    angle = f["crank_angle_deg"]
    one = angle < 360.0
    fig, ax = new_figure(16, 7)
    ax.plot(angle[one], f["rod_angle_deg"][one], color="C4")
    ax.axhline(0, color="0.3", lw=0.6)
    ax.set_ylabel(t("offset_crank.axis_beta"))
    crank_angle_axis(ax, 360.0, t("axis.crank_angle"))
    return fig
