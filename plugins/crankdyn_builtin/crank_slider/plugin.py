"""The ``crank_slider`` mechanism: the central crank-slider, alone or as the banks of a
multi-cylinder engine (layouts in-line, V, W, Y, X, boxer, radial; see the ``bays`` plugin)."""

from crankdyn.hookspecs import hookimpl
from crankdyn.plugin_types import Mechanism
from crankdyn_builtin.bays.stage import check_layout

from .geometry import engine_geometry


def _check_crank_slider(scene):
    # Multi-cylinder engines are banks of crank-slider mechanisms; their layout is checked here.
    return check_layout(scene)


@hookimpl
def crankdyn_mechanisms():
    return [
        Mechanism(
            name="crank_slider",
            summary="central (axial) crank-slider mechanism: the cylinder axis passes through the crankshaft axis",
            check=_check_crank_slider,
            geometry=engine_geometry,
        ),
    ]
