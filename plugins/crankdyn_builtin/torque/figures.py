"""The torque stage's figures: the output torque over the cycle and the journals' torques."""

from __future__ import annotations

from crankdyn.report.figures import crank_angle_axis, curve_with_mean_figure, new_figure


def _output_figure(angle, torque_Nm, mean_Nm, cycle_deg, t):
    """The engine's output torque over the cycle, with its mean."""
    return curve_with_mean_figure(
        angle,
        torque_Nm,
        mean_Nm,
        cycle_deg,
        t,
        (t("torque.output"), t("torque.mean"), t("torque.axis_torque")),
        height_cm=8.5,
    )


def _journals_figure(f, cranks, cycle_deg, t, newton_metres_per_pascal: float | None = None):
    """The running torque on each main journal over the cycle: the specific tangential force t_k
    (table B.3) and, on the right, the torque it is, t_k·F_p·R (``newton_metres_per_pascal``)."""
    angle = f["crank_angle_deg"]
    fig, ax = new_figure(16, 9)
    for k in range(1, cranks + 1):
        # named as the tables name it: the journal after crank k lies between cranks k and k + 1
        ax.plot(angle, f[f"journal{k}_torque_Pa"] / 1e6, lw=1, label=f"{k}–{k + 1}")
    crank_angle_axis(ax, cycle_deg, t("axis.crank_angle"))
    ax.set_ylabel(
        "t_k, " + t("unit.MPa")
    )  # the running torque as a specific tangential force (table B.3)
    if newton_metres_per_pascal:
        scale = newton_metres_per_pascal * 1e6  # N·m per MPa
        right = ax.secondary_yaxis("right", functions=(lambda v: v * scale, lambda m: m / scale))
        right.set_ylabel("t_k·F_p·R, " + t("unit.Nm"))  # the same quantity, scaled: no new letter
    # short labels under a title: "main journal after crank k" in three columns overran the axes
    ax.legend(loc="upper right", fontsize=8, title=t("torque.journals_legend_title"))
    return fig
