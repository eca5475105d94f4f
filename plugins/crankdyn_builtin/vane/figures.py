"""The ``vane`` stage's figures, drawn with matplotlib."""

from __future__ import annotations

from functools import partial

from crankdyn.report.figures import crank_angle_axis, new_figure


def _plot_compared(f, compare, lam, others, t, ax, key, scale=1.0, **style):
    """One column of the vane table over the crank angle, with the same column at each comparison
    rod ratio dashed beside it (``partial`` of the tables gives ``plot(ax, key, scale, **style)``)."""
    angle = f["crank_angle_deg"]
    ax.plot(angle, f[key] * scale, color="C0", label=f"λ = {t.number_g(lam, 4)}", **style)
    for i, other in enumerate(others):
        ax.plot(
            angle,
            compare[f"{key}_lambda_{other:g}"] * scale,
            color=f"C{i + 1}",
            ls="--",
            lw=1,
            label=f"λ = {t.number_g(other, 4)}",
        )
    ax.axhline(0, color="0.3", lw=0.6)


def _two_panels(plot, ctx, keys, axis_labels, caption_key, name, see) -> str:
    """An angle and its rate (or a rate and its derivative) over the crank angle, with the comparison rod ratios."""
    return ctx.figure(
        partial(_two_panels_plot, plot, keys, axis_labels, ctx.t), ctx.t(caption_key), name, see=see
    )


def _two_panels_plot(plot, keys, axis_labels, t):
    """Two columns of the vane table, one above the other, over the crank angle."""
    fig, axes = new_figure(16, 11, nrows=2, sharex=True)
    plot(axes[0], keys[0])
    axes[0].set_ylabel(t(axis_labels[0]))
    axes[0].legend(loc="upper right", fontsize=8)
    plot(axes[1], keys[1])
    axes[1].set_ylabel(t(axis_labels[1]))
    crank_angle_axis(axes[1], 360.0, t("axis.crank_angle"))
    return fig


def _rocker_figure(f, ctx) -> str:
    """The rocker joint's x and y position, velocity and acceleration over the crank angle."""
    return ctx.figure(
        partial(_rocker_plot, f, ctx.t),
        ctx.t("vane.rocker_caption"),
        "vane_rocker",
        see="vane.see_rocker",
    )


def _rocker_plot(f, t):
    """The rocker joint's x and y position, velocity and acceleration, one panel each."""
    mm = 1e3
    angle = f["crank_angle_deg"]
    fig, axes = new_figure(16, 15, nrows=3, sharex=True)
    for ax, (kx, ky), label in (
        (axes[0], ("rocker_x_m", "rocker_y_m"), "vane.axis_rocker_s"),
        (axes[1], ("rocker_vx_m_s", "rocker_vy_m_s"), "vane.axis_rocker_v"),
        (axes[2], ("rocker_jx_m_s2", "rocker_jy_m_s2"), "vane.axis_rocker_j"),
    ):
        scale = mm if kx.endswith("_m") else 1.0
        ax.plot(angle, f[kx] * scale, color="C0", label="x")
        ax.plot(angle, f[ky] * scale, color="C1", ls="--", label="y")
        ax.axhline(0, color="0.3", lw=0.6)
        ax.set_ylabel(t(label))
    axes[0].legend(loc="upper right", fontsize=8)
    crank_angle_axis(axes[2], 360.0, t("axis.crank_angle"))
    return fig


def _three_panels(
    plot, ctx, keys, axis_labels, legend_loc, caption_key, name, see, zeros=()
) -> str:
    """Value, velocity and acceleration of one coordinate over the crank angle, with the
    comparison rod ratios; vertical marks at ``zeros`` on the two derivatives."""
    return ctx.figure(
        partial(_three_panels_plot, plot, keys, axis_labels, legend_loc, zeros, ctx.t),
        ctx.t(caption_key),
        name,
        see=see,
    )


def _three_panels_plot(plot, keys, axis_labels, legend_loc, zeros, t):
    """Three columns of the vane table (the first in mm), one above the other, marks at ``zeros`` below the first."""
    fig, axes = new_figure(16, 15, nrows=3, sharex=True)
    for i, (ax, key, label) in enumerate(zip(axes, keys, axis_labels, strict=True)):
        plot(ax, key, 1e3 if i == 0 else 1.0)
        ax.set_ylabel(t(label))
        if i == 0:
            ax.legend(loc=legend_loc, fontsize=8)
    for zero in zeros:
        for ax in axes[1:]:
            ax.axvline(zero, color="C3", lw=0.7, ls=":")
    crank_angle_axis(axes[2], 360.0, t("axis.crank_angle"))
    return fig


def _lambda_figure(by_lambda, lam, ctx) -> str:
    """How the rod ratio λ sets the largest core angle, the slider's largest travel and the angle where
    its acceleration vanishes; the scene's λ marked."""
    return ctx.figure(
        partial(_lambda_plot, by_lambda, lam, ctx.t),
        ctx.t("vane.lambda_caption"),
        "vane_lambda",
        see="vane.see_lambda",
    )


def _lambda_plot(by_lambda, lam, t):
    """The rod-ratio study's three curves side by side, the scene's λ marked."""
    fig, axes = new_figure(16, 6.5, ncols=3)
    x = by_lambda["rod_ratio"]
    axes[0].plot(x, by_lambda["core_angle_max_deg"], color="C0")
    axes[0].set_ylabel(t("vane.axis_beta_max"))
    axes[1].plot(x, by_lambda["slider_vertical_travel_max_over_tail"], color="C0", label="l = 1")
    axes[1].plot(
        x, by_lambda["slider_vertical_travel_max_over_crank"], color="C1", ls="--", label="r = 1"
    )
    axes[1].set_ylabel(t("vane.axis_y_max"))
    axes[1].legend(loc="upper left", fontsize=8)
    axes[2].plot(x, by_lambda["acceleration_zero_deg"], color="C0")
    axes[2].set_ylabel(t("vane.axis_alpha_zero"))
    for ax in axes:
        ax.axvline(lam, color="C3", lw=0.7, ls=":")
        ax.set_xlabel("λ")
        ax.tick_params(labelsize=7)
    return fig
