"""The ``kinematics`` stage's figures, drawn with matplotlib."""

from __future__ import annotations

from crankdyn.report.figures import crank_angle_axis, new_figure, twin_axes


def _piston_figure(frame, t):
    """The piston's s, v, j over one revolution, and the two-term j's difference from the exact."""
    angle = frame["crank_angle_deg"]
    fig, axes = new_figure(
        16, 19, nrows=4, sharex=True, gridspec_kw={"height_ratios": [1, 1, 1, 0.6]}
    )
    # one colour for the report's curves in every panel, the two-term acceleration dashed; one
    # legend above the top panel for all; the bottom panel shows the two-term acceleration's
    # difference from the exact one (on the scale of j itself the two curves cannot be told apart)
    axes[0].plot(angle, frame["piston_displacement_m"] * 1e3, color="C0")
    axes[0].set_ylabel(t("kinematics.axis_s"))
    axes[1].plot(angle, frame["piston_velocity_m_s"], color="C0")
    axes[1].set_ylabel(t("kinematics.axis_v"))
    exact = axes[2].plot(angle, frame["piston_acceleration_m_s2"], color="C0")[0]
    two_term = axes[2].plot(
        angle, frame["piston_acceleration_two_term_m_s2"], color="C3", ls="--", lw=1
    )[0]
    axes[2].set_ylabel(t("kinematics.axis_j"))
    axes[3].plot(
        angle,
        frame["piston_acceleration_two_term_m_s2"] - frame["piston_acceleration_m_s2"],
        color="C3",
        ls="--",
        lw=1,
    )
    axes[3].set_ylabel(t("kinematics.axis_dj"))
    axes[0].legend(
        [exact, two_term],
        [t("kinematics.exact"), t("kinematics.two_term_j")],
        loc="lower right",
        bbox_to_anchor=(1.0, 1.0),
        ncol=2,
        frameon=False,
        fontsize=8,
        borderaxespad=0.2,
    )
    # The motion repeats every revolution; one revolution is the textbook's fig. 3.
    crank_angle_axis(axes[3], 360.0, t("axis.crank_angle"))
    for ax in axes:
        ax.axhline(0, color="0.3", lw=0.6)
    return fig


def _rod_figure(frame, t):
    """The rod's angle, angular velocity and angular acceleration over one revolution."""
    angle = frame["crank_angle_deg"]
    fig, axes = new_figure(16, 10, nrows=2, sharex=True)
    axes[0].plot(angle, frame["rod_angle_deg"], color="C4")
    axes[0].set_ylabel(t("kinematics.axis_beta"))
    axes[1].plot(angle, frame["rod_angular_velocity_rad_s"], color="C5", label="ω")
    ax2 = twin_axes(axes[1])
    ax2.plot(angle, frame["rod_angular_acceleration_rad_s2"], color="C6", ls="--", label="ε")
    axes[1].set_ylabel(t("kinematics.axis_rod_omega"))
    ax2.set_ylabel(t("kinematics.axis_rod_epsilon"))
    crank_angle_axis(axes[1], 360.0, t("axis.crank_angle"))
    return fig


def _rod_cm_figure(x_m, z_m, label_x: str, label_z: str):
    """The path (``x_m``, ``z_m``) of the rod's centre of mass: of the geometry alone, the same
    for a batch's variants of one mechanism (built by a ``figure_memo.MemoFigure``)."""
    fig, ax = new_figure(9, 9)
    ax.plot(x_m * 1e3, z_m * 1e3, color="C0")
    ax.set_aspect("equal")
    ax.set_xlabel(label_x)
    ax.set_ylabel(label_z)
    return fig
