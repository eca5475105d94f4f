"""The plugin module named by the ``crankdyn`` entry point: one mechanism, one stage, catalogs.

Only crankdyn's public API is used: ``crankdyn.plugin.hooks.hookimpl``, the typed objects of
``crankdyn.plugin.types``, the data contracts of ``crankdyn.plugin.contracts``, ``crankdyn.errors.Problem``
and ``crankdyn.scene.options`` (with ``quantity``/``number`` for option models).
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np
import pandas as pd
from pydantic import BaseModel, ConfigDict

from crankdyn.errors import Problem
from crankdyn.plugin.contracts import KINEMATICS, PistonMotion
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import (
    Catalog,
    Guide,
    Mechanism,
    MechanismGeometry,
    Stage,
    StageOutput,
    StagePresentation,
    Symbol,
)
from crankdyn.scene import number, options

from . import physics

HERE = Path(__file__).resolve().parent
MECHANISM = "scotch_yoke"


# ----------------------------------------------------------------------------- mechanism


def check(scene) -> list[Problem]:
    """What the generic validation cannot see: this mechanism has one cylinder and no rod."""
    problems = []
    if scene.engine.cylinders != 1:
        problems.append(
            Problem(
                "engine.cylinders", scene.engine.cylinders, "the Scotch yoke has one cylinder: 1"
            )
        )
    return problems


def geometry(scene, crank_angle_rad) -> MechanismGeometry:
    """Where the members are (drawn by crankdyn's ``drawing`` stage): the crank O-B, the yoke's
    slot (a horizontal bar the crank pin B slides in) and the piston rod from the slot to the piston.

    Frame of ``MechanismGeometry``: crank centre at the origin, y up the cylinder axis, the crank
    at (sin a, cos a). The piston pin is ``H - s`` above the centre, s from ``physics`` (the same
    function as the kinematics table); H = 3.5 R is this drawing's choice of piston-rod length.
    """
    radius = scene.engine.crank_radius_m
    alpha = np.asarray(crank_angle_rad, dtype=float)
    s = physics.piston_displacement_m(alpha, radius)
    top = 3.5 * radius  # piston pin height at TDC
    slot = np.stack([np.zeros_like(s), top - 2.5 * radius - s], axis=-1)  # slot centre, on the axis
    joints = {
        "crank_centre": np.zeros((len(alpha), 2)),
        "crank_pin": np.stack([radius * np.sin(alpha), radius * np.cos(alpha)], axis=-1),
        "yoke_left": slot - [1.3 * radius, 0.0],
        "yoke_right": slot + [1.3 * radius, 0.0],
        "yoke_centre": slot,
        "wrist_pin": np.stack([np.zeros_like(s), top - s], axis=-1),
    }
    return MechanismGeometry(
        joints=joints,
        links=[
            ("crank", "crank_centre", "crank_pin"),
            ("yoke", "yoke_left", "yoke_right"),
            ("piston_rod", "yoke_centre", "wrist_pin"),
        ],
        guides=[
            Guide(
                "wrist_pin", travel_m=(top - 2 * radius, top), bore_m=scene.engine.bore, label="1"
            ),
            Guide(
                "crank_pin",
                moving=("yoke_left", "yoke_right"),
                travel_m=(0.3 * radius, 2.3 * radius),
            ),
        ],
        dimensions={"R": radius, "D": scene.engine.bore},
        travel_m=s,
    )


SCOTCH_YOKE = Mechanism(
    name=MECHANISM,
    summary="Scotch yoke: the crank pin slides in a slotted yoke on the piston rod (harmonic motion, no connecting rod)",
    check=check,
    geometry=geometry,
    needs_rod=False,  # no connecting rod: its scenes give neither rod_length nor rod_ratio
)


# ----------------------------------------------------------------------------- stage


class YokeOptions(BaseModel):
    """The optional [scotch_yoke] table of a scene (validated with crankdyn.scene.options)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    table_step_deg: number(gt=0, le=90) | None = (
        None  # rows of the printed table (default: the scene's)
    )


def applies(scene) -> str | None:
    if scene.engine.mechanism != MECHANISM:
        return f"the scene's mechanism is {scene.engine.mechanism!r}, not the Scotch yoke"
    return None


def _displacement_at_deg(radius_m: float, crank_angle_deg):
    """Piston displacement (m) at any crank angle (deg)."""
    return physics.piston_displacement_m(np.radians(crank_angle_deg), radius_m)


def run(scene, inputs) -> StageOutput:
    """Physics only: arrays in SI on the scene's crank-angle grid; no text."""
    radius, omega = scene.engine.crank_radius_m, scene.engine.angular_velocity_rad_s
    angle_deg = scene.crank_angles_deg
    alpha = np.radians(angle_deg)
    s = physics.piston_displacement_m(alpha, radius)
    v = physics.piston_velocity_m_s(alpha, radius, omega)
    j = physics.piston_acceleration_m_s2(alpha, radius, omega)
    motion = PistonMotion(
        crank_angle_deg=angle_deg,
        piston_displacement_m=s,
        piston_velocity_m_s=v,
        piston_acceleration_m_s2=j,
        rod_angle_rad=None,  # no connecting rod: the force stage passes the piston force along the axis
        crank_radius_m=radius,
        angular_velocity_rad_s=omega,
        method="exact",
        # a module-level function, not a lambda: the output pickles, so a report computes it aside
        displacement_at=functools.partial(_displacement_at_deg, radius),
    )
    results = {
        "crank_radius_m": radius,
        "angular_velocity_rad_s": omega,
        "stroke_m": 2.0 * radius,
        "v_max_m_s": radius * omega,
        "j_max_m_s2": radius * omega**2,
        "mean_piston_speed_m_s": 2.0 * radius * omega / np.pi,
    }
    table = pd.DataFrame(
        {
            "crank_angle_deg": angle_deg,
            "piston_displacement_m": s,
            "piston_velocity_m_s": v,
            "piston_acceleration_m_s2": j,
        }
    )
    return StageOutput(
        data={KINEMATICS: motion},
        results=results,
        tables={"scotch_yoke": table},
        notes=[("scotch_yoke.note", {})],
    )


def render(output: StageOutput, ctx) -> str:
    """Text and figures from what run() produced; never physics."""
    t = ctx.t
    frame = output.tables.arrays("scotch_yoke")
    r = output.results
    opts = (
        options(ctx.scene, "scotch_yoke", YokeOptions) if ctx.scene is not None else YokeOptions()
    )
    step = opts.table_step_deg or ctx.table_step_deg
    angle = frame["crank_angle_deg"]
    one_turn = angle < 360.0
    multiples = angle / step
    shown = one_turn & np.isclose(multiples, np.round(multiples))
    table = ctx.table(
        [
            ("<i>α</i>, °", angle[shown], 0),
            ("<i>s</i>, " + t("unit.mm"), frame["piston_displacement_m"][shown] * 1e3, 2),
            ("<i>v</i>, " + t("unit.m_s"), frame["piston_velocity_m_s"][shown], 2),
            ("<i>j</i>, " + t("unit.m_s2"), frame["piston_acceleration_m_s2"][shown], 0),
        ],
        caption=t("scotch_yoke.table_caption"),
        see="scotch_yoke.see_table",
    )

    # a function that builds the figure, called later by the process that draws it
    figure = ctx.figure(
        functools.partial(_motion_figure, frame, t),
        t("scotch_yoke.figure_caption"),
        "scotch_yoke",
        see="scotch_yoke.see_figure",
    )

    ctx.conclude(
        t("scotch_yoke.conclusion", v_max=ctx.num(r["v_max_m_s"]), j_max=ctx.num(r["j_max_m_s2"]))
    )
    return ctx.render_template("sections/scotch_yoke.html.j2", r=r, table=table, figure=figure)


def _motion_figure(frame, t):
    """The yoke's s, v, j over one turn of the crank."""
    import matplotlib.pyplot as plt

    angle = frame["crank_angle_deg"]
    one_turn = angle < 360.0
    fig, axes = plt.subplots(3, 1, figsize=(16 / 2.54, 14 / 2.54), sharex=True)
    for ax, key, scale, label in (
        (axes[0], "piston_displacement_m", 1e3, "scotch_yoke.axis_s"),
        (axes[1], "piston_velocity_m_s", 1.0, "scotch_yoke.axis_v"),
        (axes[2], "piston_acceleration_m_s2", 1.0, "scotch_yoke.axis_j"),
    ):
        ax.plot(angle[one_turn], frame[key][one_turn] * scale)
        ax.axhline(0, color="0.3", lw=0.6)
        ax.set_ylabel(t(label))
    axes[2].set_xlabel(t("axis.crank_angle"))
    axes[2].set_xlim(0, 360)
    return fig


SCOTCH_YOKE_STAGE = Stage(
    name="scotch_yoke",
    requires=(),
    provides=(KINEMATICS,),
    applies=applies,
    run=run,
    tables=("scotch_yoke",),  # the keys of StageOutput.tables in run(): tables/scotch_yoke.csv
    options_table="scotch_yoke",
    options_model=YokeOptions,
    presentation=StagePresentation(
        title_key="scotch_yoke.title",
        render=render,
        figures=("scotch_yoke",),  # the names given to ctx.figure in render()
        template_dir=HERE / "templates",
        references=("scotch_yoke_uicker",),
        # the letters of the section's equations that crankdyn's symbol table does not have:
        # explained in the list of symbols and under the equation, from [symbol.scotch_yoke] in i18n/
        symbols={
            "displacement": Symbol("s", {}, "unit.mm"),
            "velocity": Symbol("v", {}, "unit.m_s"),
            "acceleration": Symbol("j", {}, "unit.m_s2"),
        },
    ),
)


# ----------------------------------------------------------------------------- hooks


@hookimpl
def crankdyn_mechanisms():
    return [SCOTCH_YOKE]


@hookimpl
def crankdyn_stages():
    return [SCOTCH_YOKE_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
