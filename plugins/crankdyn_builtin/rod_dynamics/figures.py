"""The ``rod_dynamics`` stage's figures, drawn with matplotlib."""

from __future__ import annotations

from crankdyn.report.figures import crank_angle_axis, new_figure


def _motion_figure(f, period, t):
    """The rod's angular velocity, angular acceleration and its centre of mass's acceleration over the period."""
    angle = f["crank_angle_deg"]
    inside = angle < period
    fig, axes = new_figure(16, 14, nrows=3, sharex=True)
    axes[0].plot(angle[inside], f["rod_angular_velocity_rad_s"][inside], color="C0")
    axes[0].set_ylabel(t("rod_dynamics.axis_omega"))
    axes[1].plot(angle[inside], f["rod_angular_acceleration_rad_s2"][inside], color="C1")
    axes[1].set_ylabel(t("rod_dynamics.axis_epsilon"))
    axes[2].plot(angle[inside], f["cm_acceleration_x_m_s2"][inside], color="C2", label=r"$a_{Gx}$")
    axes[2].plot(
        angle[inside], f["cm_acceleration_z_m_s2"][inside], color="C3", ls="--", label=r"$a_{Gz}$"
    )
    axes[2].set_ylabel(t("rod_dynamics.axis_cm"))
    axes[2].legend(loc="upper right", fontsize=8)
    for ax in axes:
        ax.axhline(0, color="0.3", lw=0.6)
    crank_angle_axis(axes[2], period, t("axis.crank_angle"))
    return fig


def _torque_figure(f, period, exact, t):
    """The rod's torque in the two-mass split and, when exact, the exact one, their difference and the couple."""
    angle = f["crank_angle_deg"]
    inside = angle < period
    fig, axes = new_figure(16, 11 if exact else 6, nrows=2 if exact else 1, sharex=True)
    top = axes[0] if exact else axes
    top.plot(
        angle[inside],
        f["torque_two_mass_Nm"][inside],
        color="0.45" if exact else "C0",
        ls="--" if exact else "-",
        label=t("rod_dynamics.two_mass"),
    )
    if exact:
        top.plot(
            angle[inside], f["torque_exact_Nm"][inside], color="C0", label=t("rod_dynamics.exact")
        )
        axes[1].plot(
            angle[inside],
            f["torque_difference_Nm"][inside],
            color="C3",
            label=t("rod_dynamics.difference"),
        )
        axes[1].plot(
            angle[inside],
            f["inertia_couple_Nm"][inside],
            color="C4",
            ls=":",
            label=t("rod_dynamics.couple"),
        )
        axes[1].set_ylabel(t("rod_dynamics.axis_torque"))
        axes[1].legend(loc="upper right", fontsize=8)
    top.set_ylabel(t("rod_dynamics.axis_torque"))
    top.legend(loc="upper right", fontsize=8)
    for ax in axes if exact else [axes]:
        ax.axhline(0, color="0.3", lw=0.6)
    crank_angle_axis(axes[1] if exact else axes, period, t("axis.crank_angle"))
    return fig
