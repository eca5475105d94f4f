"""The bays' figure: the forces of a bay on its crank pin over the cycle."""

from __future__ import annotations

from crankdyn.report.figures import crank_angle_axis, new_figure


def bay_figure(f, cycle_deg, t):
    """The bay's summed tangential and radial forces and the master rod's side force over the cycle."""
    angle = f["crank_angle_deg"]
    fig, ax = new_figure(16, 8)
    ax.plot(angle, f["bay_tangential_Pa"] / 1e6, label="$t_\\Sigma$")
    ax.plot(angle, f["bay_radial_Pa"] / 1e6, label="$z_\\Sigma$")
    ax.plot(angle, f["master_side_Pa"] / 1e6, label="$N_\\Sigma$", lw=1)
    ax.axhline(0, color="0.3", lw=0.6)
    crank_angle_axis(ax, cycle_deg, t("axis.crank_angle"))
    ax.set_ylabel(t("unit.MPa"))
    ax.legend(loc="upper right", fontsize=8)
    return fig
