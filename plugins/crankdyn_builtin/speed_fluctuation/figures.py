"""The ``speed_fluctuation`` stage's figures, drawn with matplotlib."""

from __future__ import annotations

from functools import partial

import numpy as np

from crankdyn.report.figures import crank_angle_axis, new_figure

from .solver_text import _power_of_ten
from .solvers import METHODS
from .torsion import CRITICAL_BAND, MAIN_ORDER_FRACTION


def _error_figure(ctx, records, caption, name, see, key="error_relative"):
    return ctx.figure(partial(_error_plot, records, key, ctx.t), caption, name, see=see)


def _error_plot(records, key, t):
    """The error of each solver's runs against their time, the tolerances marked, the run quoted ringed."""
    fig, ax = new_figure(16, 9)
    for i, method in enumerate(METHODS):
        rows = [
            r
            for r in records
            if r["method"] == method
            and not r.get("reference")
            and r[key] is not None
            and r[key] > 0
        ]
        if rows:
            # milliseconds, as the table of the runs beside it
            ax.loglog(
                [r["time_s"] * 1e3 for r in rows],
                [r[key] for r in rows],
                "o-",
                color=f"C{i}",
                label=method,
            )
            for r in rows:
                ax.annotate(
                    _power_of_ten(r["rtol"], t),
                    (r["time_s"] * 1e3, r[key]),
                    fontsize=7,
                    xytext=(3, 3),
                    textcoords="offset points",
                )
    used = [r for r in records if r.get("used") and r[key] is not None and r[key] > 0]
    if used:  # the run the section quotes, ringed (a shape, not a colour: black-and-white print)
        ax.loglog(
            [r["time_s"] * 1e3 for r in used],
            [r[key] for r in used],
            "o",
            ms=11,
            mfc="none",
            mec="black",
            mew=0.9,
            label=t("speed_fluctuation.used_run"),
        )
    ax.set_xlabel(t("speed_fluctuation.axis_time"))
    ax.set_ylabel(t("speed_fluctuation.axis_error"))
    ax.legend(loc="best", fontsize=8)
    return fig


def _speed_figure(f, r, ctx) -> str:
    """The crankshaft speed over the cycle (exact, the solver's, the energy method's) above the variable inertia."""
    # a course note names no solver, and its section describes the exact solution and the energy
    # method only: the solver's curve (the same as the exact one to the error study's accuracy,
    # checked in the appendix) is left out of its figure
    course = ctx.scene is not None and ctx.scene.report.detail == "course"
    return ctx.figure(
        partial(_speed_plot, f, None if course else r["solver"]["method"], ctx.cycle_deg, ctx.t),
        ctx.t("speed_fluctuation.speed_caption"),
        "speed",
        see="speed_fluctuation.see_speed",
    )


def _speed_plot(f, method, cycle_deg, t):
    """The speed over the cycle (exact, the solver's where ``method`` names it, the energy
    method's) above the variable inertia."""
    angle = f["crank_angle_deg"]
    fig, axes = new_figure(16, 13, nrows=2, sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    axes[0].plot(angle, f["omega_rad_s"], color="C0", label=t("speed_fluctuation.exact"))
    if method:
        axes[0].plot(
            angle,
            f["omega_solver_rad_s"],
            color="C1",
            ls="--",
            lw=1,
            label=t("speed_fluctuation.solver_curve", method=method),
        )
    axes[0].plot(
        angle,
        f["omega_energy_method_rad_s"],
        color="C2",
        ls=":",
        label=t("speed_fluctuation.energy_curve"),
    )
    axes[0].set_ylabel(t("speed_fluctuation.axis_omega"))
    axes[0].legend(loc="upper right", fontsize=8)
    inertia = np.asarray(f["inertia_kg_m2"], dtype=float)
    axes[1].plot(angle, inertia, color="C4")
    mean = float(inertia.mean())
    # an even V16's (constant but for rounding) or a V12's (0.001 %): drawn flat within ±2 %,
    # not stretched over the axis's height as if J swung, nor one tick value over and over
    if np.ptp(inertia) <= 1e-3 * abs(mean):
        axes[1].set_ylim(0.98 * mean, 1.02 * mean)
    axes[1].set_ylabel(t("speed_fluctuation.axis_inertia"))
    crank_angle_axis(axes[1], cycle_deg, t("axis.crank_angle"))
    return fig


def _modes_figure(ctx, torsion, parts) -> None:
    """The shapes of the first (at most three) elastic modes along the shaft."""
    t = ctx.t
    modes = torsion["modes"]
    labels = [
        t("speed_fluctuation.mode_label", mode=m["mode"], f=ctx.num(m["natural_frequency_Hz"], 4))
        for m in modes[: min(3, len(modes))]
    ]
    parts["figure_modes"] = ctx.figure(
        partial(_modes_plot, len(torsion["nodes"]), modes, labels, t),
        t("speed_fluctuation.modes_figure_caption"),
        "modes",
        see="speed_fluctuation.see_modes_figure",
    )


def _modes_plot(node_count, modes, labels, t):
    """The shapes of the first modes (one curve per label) along the shaft's nodes."""
    fig, ax = new_figure(16, 7)
    for m, label in zip(modes, labels, strict=False):
        ax.plot(range(1, node_count + 1), m["shape"], "o-", label=label)
    ax.axhline(0, color="0.3", lw=0.6)
    ax.set_xticks(range(1, node_count + 1))
    ax.set_xlabel(t("speed_fluctuation.axis_node"))
    ax.set_ylabel(t("speed_fluctuation.axis_amplitude"))
    ax.legend(loc="best", fontsize=8)
    return fig


def _torsion_figure(ctx, tf, torsion, node_names, parts) -> None:
    """The periodic state: the flywheel's and the first crank's speed against the rigid shaft's, and the
    torque in every span, over the shaft angle."""
    # a run that did not settle shows its last cycle: said so, not called the steady state
    last = "" if torsion["steady_state"]["converged"] else "_last"
    bare = no_flywheel(torsion)
    parts["figure_torsion"] = ctx.figure(
        partial(_torsion_plot, tf, torsion, node_names, ctx.cycle_deg, ctx.t),
        ctx.t("speed_fluctuation.torsion_caption" + last + bare, last=last_crank(torsion)),
        "torsion",
        see="speed_fluctuation.see_torsion" + last + bare,
        see_params={"last": last_crank(torsion)},
    )


def no_flywheel(torsion) -> str:
    """The catalog keys' ending of a torsional model without a flywheel disc (the flywheel stage
    found none needed): "_no_flywheel", its reference disc the last crank; "" with one."""
    return "" if any(node["name"] == "flywheel" for node in torsion["nodes"]) else "_no_flywheel"


def last_crank(torsion) -> int:
    """The number of the last crank of the torsional model's chain."""
    return sum(node["name"].startswith("crank ") for node in torsion["nodes"])


def _torsion_plot(tf, torsion, node_names, cycle_deg, t):
    """The speeds of the reference node and the first crank against the rigid shaft's, and the span torques."""
    nodes = torsion["nodes"]
    fig, axes = new_figure(16, 13, nrows=2, sharex=True)
    shaft = tf["shaft_angle_deg"]
    speed_columns = [c for c in tf.columns if c.startswith("speed_")]
    reference = torsion["reference_node"]
    axes[0].plot(shaft, tf[speed_columns[reference]], color="C0", label=node_names[reference])
    axes[0].plot(
        shaft,
        tf["rigid_speed_rad_s"],
        color="C3",
        ls="--",
        lw=1,
        label=t("speed_fluctuation.rigid_speed"),
    )
    first_crank = next(i for i, node in enumerate(nodes) if node["name"].startswith("crank "))
    axes[0].plot(
        shaft, tf[speed_columns[first_crank]], color="C1", lw=0.8, label=node_names[first_crank]
    )
    axes[0].set_ylabel(t("speed_fluctuation.axis_omega"))
    axes[0].legend(loc="upper right", fontsize=8)
    spans = [c for c in tf.columns if c.startswith("span_torque_")]
    for j, column in enumerate(spans):
        axes[1].plot(
            shaft,
            tf[column],
            lw=0.9,
            label=t("speed_fluctuation.span_label", first=j + 1, second=j + 2),
        )
    axes[1].set_ylabel(t("speed_fluctuation.axis_span_torque"))
    axes[1].legend(loc="upper right", fontsize=8, ncol=3)
    crank_angle_axis(
        axes[1],
        cycle_deg,
        t("speed_fluctuation.axis_shaft_angle" + no_flywheel(torsion), last=last_crank(torsion)),
    )
    return fig


def _campbell_plot(torsion, t):
    """The natural frequencies and the significant orders against engine speed, the operating band shaded."""
    rpm = torsion["operating_rpm"]
    harmonics = torsion["harmonics"]
    largest = max((h["amplitude_Nm"] for h in harmonics), default=0.0)
    main = [h for h in harmonics if h["amplitude_Nm"] >= MAIN_ORDER_FRACTION * largest]
    speeds = np.linspace(0.0, 1.3 * rpm, 200)
    fig, ax = new_figure(16, 10)
    top = max(m["natural_frequency_Hz"] for m in torsion["modes"][:2]) * 1.25
    for h in main:
        ax.plot(speeds, h["order"] * speeds / 60.0, color="0.6", lw=0.6)
        end = min(1.3 * rpm, top * 60.0 / h["order"])
        ax.text(end, h["order"] * end / 60.0, t.number_g(h["order"]), fontsize=7, color="0.35")
    for m in torsion["modes"][:2]:
        ax.axhline(m["natural_frequency_Hz"], color="C0", lw=1.0)
    ax.axvspan((1 - CRITICAL_BAND) * rpm, (1 + CRITICAL_BAND) * rpm, color="C3", alpha=0.12, lw=0)
    ax.axvline(rpm, color="C3", lw=0.8, ls="--")
    for c in torsion["critical_speeds_near_operating"]:
        f = next(m["natural_frequency_Hz"] for m in torsion["modes"] if m["mode"] == c["mode"])
        ax.plot([c["critical_rpm"]], [f], "o", color="C3", ms=3)
    ax.set_xlim(0, 1.3 * rpm)
    ax.set_ylim(0, top)
    ax.set_xlabel(t("speed_fluctuation.axis_campbell_rpm"))
    ax.set_ylabel(t("speed_fluctuation.axis_campbell_hz"))
    return fig
