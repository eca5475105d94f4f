"""The balancing figures: the crank stars and the engine's dynamic models."""

from __future__ import annotations

import math

import numpy as np

from crankdyn.report import figure_memo
from crankdyn.report.figures import hide_axes, new_figure

from .vectors import NEGLIGIBLE


def _arrow(ax, x0, y0, x1, y1, **kw):
    """A vector from (x0, y0) to (x1, y1), its head's tip on the end point: drawn to the scale
    the caption gives (matplotlib would stop it 2 pt short at each end)."""
    ax.annotate(
        "",
        xy=(x1, y1),
        xytext=(x0, y0),
        arrowprops=dict(arrowstyle="-|>", lw=kw.pop("lw", 1.2), shrinkA=0, shrinkB=0, **kw),
    )


def star_figure(ctx, r):
    """Crank diagrams seen from the free end: cranks (first order) and doubled angles (second order)."""
    single = (
        len(r["cylinder_labels"]) == 1
    )  # one crank and one cylinder: a vector of each order, not a "star"
    plane = not single and len(set(r["cylinder_bays"])) == 1  # several cylinders on one crank
    caption = ctx.t(
        "balancing.star_caption_single"
        if single
        else ("balancing.star_caption_plane" if plane else "balancing.star_caption")
    )
    return ctx.figure(
        figure_memo.MemoFigure(
            _star_drawing,
            (ctx.t("balancing.star_first"), ctx.t("balancing.star_second")),
            [ctx.t.cylinder(label) for label in r["cylinder_labels"]],
            r["crank_directions_deg"],
            r["cylinder_phases_deg"],
            r["cylinder_axes_deg"],
        ),
        caption,
        "crank_diagrams",
        see="balancing.see_star_single" if single or plane else "balancing.see_star",
    )


def _star_drawing(titles, labels, crank_directions_deg, phases_deg, axes_deg):
    """The crank diagrams' figure (:func:`star_figure`): the orders' ``titles``, the cylinders'
    ``labels`` as printed, and the geometry alone (the same for a batch's variants of one
    engine, built by a ``figure_memo.MemoFigure``)."""
    from matplotlib.patches import Circle  # lazy: heavy optional import

    fig, axes = new_figure(16, 8.2, ncols=2)
    crank_dirs = np.radians(crank_directions_deg)
    phases = np.radians(phases_deg)
    axes_rad = np.radians(axes_deg)
    for ax, order in zip(axes, (1, 2), strict=True):
        ax.set_aspect("equal")
        hide_axes(ax)
        ax.add_patch(Circle((0, 0), 1.0, fill=False, lw=0.5, ls=":", color="0.5"))
        for axis in sorted(set(np.round(axes_rad, 9))):
            ax.plot(
                [0, 1.25 * math.sin(axis)], [0, 1.25 * math.cos(axis)], color="0.6", lw=0.8, ls="--"
            )
        single = len(labels) == 1  # one crank: its vectors are named, not numbered
        if order == 1:  # cranks, numbered from the free end
            vectors = [
                (d, r"$C$, $C_{\mathrm{I}}$" if single else str(k + 1))
                for k, d in enumerate(crank_dirs)
            ]
            color, title = "C0", titles[0]
        else:  # one C_II vector per cylinder, at twice the angle between its crank and its axis
            # an offset crank-slider's crank stands off the axis at TDC (crank 1 carries the
            # first cylinder, at its own TDC when θ = 0): that angle doubles too
            tdc = crank_dirs[0] - (axes_rad[0] - phases[0])
            vectors = [
                (axes_rad[i] - 2 * phases[i] + 2 * tdc, r"$C_{\mathrm{II}}$" if single else label)
                for i, label in enumerate(labels)
            ]
            color, title = "C1", titles[1]
        groups: dict[int, list[str]] = {}
        for d, label in vectors:
            groups.setdefault(int(round(math.degrees(d) * 100)) % 36000, []).append(label)
        for key, members in groups.items():
            d = math.radians(key / 100)
            _arrow(ax, 0, 0, math.sin(d), math.cos(d), color=color)
            # on a white ground: the dashed cylinder axis behind a label along it does not cut it
            ax.text(
                1.17 * math.sin(d),
                1.17 * math.cos(d),
                ", ".join(members),
                ha="center",
                va="center",
                fontsize=7,
                zorder=5,
                bbox={"facecolor": "white", "edgecolor": "none", "pad": 0.6},
            )
        # the title inside the axes' limits: above them, an equal-aspect panel's title is cut
        ax.text(0, 1.62, title, ha="center", va="center", fontsize=8)
        ax.set_xlim(-1.4, 1.4)
        ax.set_ylim(-1.4, 1.75)
    return fig


#: The most panels a row of the vector models' figure holds and stays readable on a page's width.
MAX_MODEL_PANELS = 6


def _higher_unbalanced(r) -> list:
    """The orders above the second whose force or moment the engine leaves unbalanced (an offset
    crank-slider's odd orders among them), in the order of the table."""
    return [
        o
        for o in r["orders"]
        if o["order"] >= 3
        and (o["force_coefficient"] > NEGLIGIBLE or o["moment_coefficient"] > NEGLIGIBLE)
    ]


def models_left_out(r) -> list[int]:
    """The unbalanced orders the vector models' figure has no room for."""
    shown = {o["order"] for o in _models_shown(r)[0]}
    return [o["order"] for o in _higher_unbalanced(r) if o["order"] not in shown]


def _models_shown(r) -> tuple[list, bool]:
    """The orders the vector models show, and whether a row of moments is drawn: the orders up
    to the second and every unbalanced higher one, as many as the figure holds."""
    low = [o for o in r["orders"] if o["order"] in (0, 1, 2)]
    shown = low + _higher_unbalanced(r)[: MAX_MODEL_PANELS - len(low)]
    moments = r["cylinder_spacing_m"] is not None or any(
        o["moment_coefficient"] > NEGLIGIBLE for o in shown
    )
    return shown, moments


#: How far a vector's name stands off its arrow, pt; an arrow shorter than SHORT_ARROW of the
#: panel's half-width is mostly its head, and its name stands further off, clear of the head.
NAME_OFFSET_PT, SHORT_NAME_OFFSET_PT, SHORT_ARROW = 5.0, 9.0, 0.3


def _name_arrow(
    ax, name: str, start: complex, vector: complex, side: float, half_width: float = 1.0
) -> None:
    """``name`` in italics beside the middle of the arrow ``start`` → ``start + vector`` (complex
    numbers: imag along x, real along y, as the panels draw them), off it on ``side`` (+1 left)
    by :data:`NAME_OFFSET_PT` (a short arrow's by :data:`SHORT_NAME_OFFSET_PT`)."""
    length = abs(vector)
    normal = (-vector.real / length * side, vector.imag / length * side)  # the arrow turned by 90°
    middle = start + 0.5 * vector
    offset = SHORT_NAME_OFFSET_PT if length < SHORT_ARROW * half_width else NAME_OFFSET_PT
    ax.annotate(
        name,
        (middle.imag, middle.real),
        xytext=(offset * normal[0], offset * normal[1]),
        textcoords="offset points",
        fontsize=7,
        style="italic",
        ha="center",
        va="center",
    )


def _models_figure(ctx, r):
    """Vector models and hodographs (textbook figs. 26-33): forces (top row) and moments (bottom row)."""
    moments = _models_shown(r)[1]
    return ctx.figure(
        figure_memo.MemoFigure(
            _models_drawing,
            _model_panels(r),
            moments,
            len(r["cylinder_labels"]),
            ctx.t("balancing.balanced_label"),
        ),
        ctx.t("balancing.models_caption" if moments else "balancing.models_caption_forces"),
        "vector_models",
        see="balancing.see_models",
    )


def _model_panels(r) -> list[tuple]:
    """What the vector models' figure draws of each order shown: (order, name, speed, a row per
    kind: (kind, forward, backward, coefficient)), the vectors as complex numbers over one
    amplitude C_n (C_n * a for moments), the panel's scale: the same for a batch's variants of
    one engine at any speed (the figure is built by a ``figure_memo.MemoFigure``)."""
    shown, moments = _models_shown(r)
    panels = []
    for o in shown:
        rows = []
        for kind in ("force", "moment")[: 2 if moments else 1]:
            norm = o["amplitude_N"] * (
                (r["cylinder_spacing_m"] or 1.0) if kind == "moment" else 1.0
            )
            fwd, bwd = o[f"{kind}_forward"], o[f"{kind}_backward"]
            f = complex(fwd["y"], fwd["x"]) / norm if norm else 0j
            b = complex(bwd["y"], bwd["x"]) / norm if norm else 0j
            rows.append((kind, f, b, o[f"{kind}_coefficient"]))
        panels.append((o["order"], o["name"], o["speed"], rows))
    return panels


def _models_drawing(panels, moments: bool, cylinders: int, balanced_label: str):
    """The vector models' figure (:func:`_models_figure`) of :func:`_model_panels`."""
    from matplotlib.patches import Circle  # lazy: heavy optional import

    rows = 2 if moments else 1
    fig, axes = new_figure(
        16, rows * (16.0 / len(panels) + 0.9), nrows=rows, ncols=len(panels), squeeze=False
    )
    for col, (order, name, speed, kinds) in enumerate(panels):
        for row, (kind, f, b, coefficient) in enumerate(kinds):
            ax = axes[row][col]
            ax.set_aspect("equal")
            ax.set_xticks([])
            ax.set_yticks([])
            for side in ("left", "bottom"):
                ax.spines[side].set_visible(False)
            # the dotted circle is one amplitude C_n (one C_n * a for moments): the scale of the panel
            ax.add_patch(Circle((0, 0), 1.0, fill=False, lw=0.5, ls=":", color="0.55"))
            th = np.linspace(0, 2 * np.pi / speed, 241)
            wv = f * np.exp(1j * speed * th) + b * np.exp(-1j * speed * th)
            ax.plot(wv.imag, wv.real, color="C2", lw=1.8, zorder=3, solid_capstyle="round")
            # the vectors named beside their middles (a black-and-white print still tells them apart),
            # f on the left of its arrow, b on the right, 5 pt off the line (not on the arrows)
            lim = max(abs(f) + abs(b), 1.0) * 1.25
            if abs(f) > 1e-9:
                _arrow(ax, 0, 0, f.imag, f.real, color="C0")
                _name_arrow(ax, "f", 0j, f, side=1.0, half_width=lim)
            if abs(b) > 1e-9:
                _arrow(ax, f.imag, f.real, f.imag + b.imag, f.real + b.real, color="C3")
                # b turned back over f (an offset single's odd orders): its right is f's left,
                # where f is named, so b is named on its left
                back = (f.conjugate() * b).real < 0
                _name_arrow(ax, "b", f, b, side=1.0 if back else -1.0, half_width=lim)
            ax.set_xlim(-lim, lim)
            ax.set_ylim(-lim, lim)
            ax.axhline(0, color="0.75", lw=0.5, zorder=1)
            ax.axvline(0, color="0.75", lw=0.5, zorder=1)
            if coefficient <= NEGLIGIBLE * cylinders:
                # under the panel, clear of its dotted circle (over it the label is unreadable)
                ax.text(
                    0.5,
                    0.0,
                    balanced_label,
                    ha="center",
                    va="top",
                    fontsize=7,
                    color="C2",
                    transform=ax.transAxes,
                )
            # the order's Roman numeral upright, as in the text and tables (P_II, not P_{II} in italics)
            sub = "C" if order == 0 else f"\\mathrm{{{name[1:]}}}"
            # the dotted circle's radius C_ν = |A_ν| C_I, which the force is divided by (C_II is the
            # textbook's λC_I, not the exact second-order amplitude)
            amp = (
                "C"
                if order == 0
                else "C_{\\mathrm{I}}"
                if order == 1
                else f"|A_{{{order}}}|C_{{\\mathrm{{I}}}}"
            )
            # one cylinder's own force, without the sum sign, as its tables and text write it
            sigma = "" if cylinders == 1 else "\\Sigma "
            # a product divides in brackets: ΣP_II/(|A_2|C_I), as the tables' headers write it
            scale = f"({amp})" if order > 1 else amp
            title = (
                (f"${sigma}P_{{{sub}}}/{scale}$" if order else f"${sigma}C/C$")
                if kind == "force"
                else f"${sigma}M_{{{sub}}}/({amp}a)$"
            )
            ax.set_title(title, fontsize=8)
    return fig
