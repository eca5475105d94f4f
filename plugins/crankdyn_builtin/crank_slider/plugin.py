"""The ``crank_slider`` mechanism: the central crank-slider, alone or as the banks of a
multi-cylinder engine (layouts in-line, V, W, Y, X, boxer, radial; see the ``bays`` plugin)."""

from crankdyn.errors import Problem, SceneError
from crankdyn.physics import layout as lay
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.scene_inputs import engine_layout
from crankdyn.plugin.types import Mechanism
from crankdyn.report.plausibility import ROD_CENTRE_OF_MASS, ROD_RATIO

from .geometry import ARTICULATED, engine_geometry


def _check_crank_slider(scene):
    """Multi-cylinder engines are banks of crank-slider mechanisms: their layout is checked here
    (every firing delay and cylinder axis on the angle grid; articulated rods need their table)."""
    try:
        layout = engine_layout(scene)
        step = scene.analysis.angle_step_deg
        grid = lay.layout_grid_deg(layout)
        for c in layout.cylinders:
            lay.grid_shift(c.firing_delay_deg, step, grid)
            lay.grid_shift(c.axis_deg, step, grid)
    except SceneError as exc:
        return exc.problems
    except lay.LayoutError as exc:
        return [Problem(exc.field, exc.value, str(exc))]
    if scene.engine.rod_type == "articulated" and ARTICULATED not in scene.plugin_tables():
        return [
            Problem(
                ARTICULATED,
                "(missing)",
                "articulated rods need an [articulated] table with "
                "pin_radius (distance from the big-end centre to the slave pins)",
            )
        ]
    return []


@hookimpl
def crankdyn_mechanisms():
    return [
        Mechanism(
            name="crank_slider",
            summary="central (axial) crank-slider mechanism: the cylinder axis passes through the crankshaft axis",
            check=_check_crank_slider,
            geometry=engine_geometry,
            plausibility=(ROD_RATIO, ROD_CENTRE_OF_MASS),
            default=True,  # the mechanism of a scene that names none
        ),
    ]
