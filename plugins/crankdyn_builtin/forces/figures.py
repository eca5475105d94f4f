"""The ``forces`` stage's figures, drawn with matplotlib."""

from __future__ import annotations

from crankdyn.report.figures import crank_angle_axis, curve_with_mean_figure, new_figure
from crankdyn.report.typeset import symbol_mathtext


def _forces_figure(t, cycle_deg, angle, mpa):
    """The specific gas, inertia and total forces, n and k, z and t over the cycle (MPa)."""
    fig, axes = new_figure(16, 13.5, nrows=3, sharex=True)
    panels = (
        [
            ("gas_Pa", symbol_mathtext("gas_pressure", t.language)),  # p_г in uk/ru, as in the text
            ("inertia_Pa", symbol_mathtext("inertia_pressure", t.language)),
            ("total_Pa", symbol_mathtext("total_pressure", t.language)),
        ],
        [("side_Pa", "$N$"), ("rod_Pa", "$k$")],
        [("radial_Pa", "$z$"), ("tangential_Pa", "$t$")],
    )
    for ax, curves in zip(axes, panels, strict=True):
        # solid, dashed, dash-dotted: the curves stay apart in a black-and-white print too
        for (key, label), style in zip(curves, ("-", "--", "-."), strict=False):
            ax.plot(angle, mpa[key], ls=style, label=label)
        ax.axhline(0, color="0.3", lw=0.6)
        ax.set_ylabel(", ".join(label for _, label in curves) + ", " + t("forces.axis_specific"))
        ax.legend(loc="upper right", fontsize=8, ncol=3)
    crank_angle_axis(axes[2], cycle_deg, t("axis.crank_angle"))
    return fig


def _torque_figure(t, cycle_deg, angle, torque_Nm, mean_torque_Nm, whose=""):
    """One cylinder's torque over the cycle, with its mean."""
    labels = (t("forces.torque" + whose), t("forces.mean_torque"), t("forces.axis_torque"))
    return curve_with_mean_figure(angle, torque_Nm, mean_torque_Nm, cycle_deg, t, labels)
