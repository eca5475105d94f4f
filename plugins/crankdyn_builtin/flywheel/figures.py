"""The flywheel's figure: the excess work over the cycle."""

from __future__ import annotations

from crankdyn.physics.extrema import first_argmax, first_argmin
from crankdyn.report.figures import crank_angle_axis, new_figure


def work_figure(f, mean_torque_Nm, cycle_deg, t):
    """The engine torque against its mean, and the cumulative excess work with its swing ΔL."""
    angle = f["crank_angle_deg"]
    work = f["excess_work_J"]
    i_max, i_min = first_argmax(work), first_argmin(work)
    fig, axes = new_figure(16, 13, nrows=2, sharex=True)
    axes[0].plot(angle, f["torque_Nm"], color="C0", label=t("flywheel.torque"))
    axes[0].axhline(mean_torque_Nm, color="C3", ls="--", lw=1, label=t("flywheel.mean_torque"))
    axes[0].fill_between(angle, f["torque_Nm"], mean_torque_Nm, color="C0", alpha=0.15, lw=0)
    axes[0].set_ylabel(t("flywheel.axis_torque"))
    axes[0].legend(loc="upper right", fontsize=8, ncol=2)
    axes[1].plot(angle, work, color="C2", label=t("flywheel.cumulative_work"))
    axes[1].plot([angle[i_max]], [work[i_max]], "o", color="C3")
    axes[1].plot([angle[i_min]], [work[i_min]], "o", color="C3")
    axes[1].annotate(
        "",
        xy=(angle[i_max], work[i_max]),
        xytext=(angle[i_max], work[i_min]),
        arrowprops={"arrowstyle": "<->", "color": "C3"},
    )
    axes[1].axhline(work[i_min], color="C3", lw=0.6, ls=":")
    axes[1].text(angle[i_max], 0.5 * (work[i_max] + work[i_min]), "  ΔL", color="C3", va="center")
    axes[1].set_ylabel(t("flywheel.axis_work"))
    for ax in axes:
        ax.axhline(0, color="0.3", lw=0.6)
    crank_angle_axis(axes[1], cycle_deg, t("axis.crank_angle"))
    return fig
