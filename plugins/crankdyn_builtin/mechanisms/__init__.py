"""Built-in mechanism types."""

from crankdyn.hookspecs import hookimpl
from crankdyn.plugin_types import Mechanism
from crankdyn_builtin.stages.offset_crank import OFFSET_CRANK_MECHANISM
from crankdyn_builtin.stages.planetary import PLANETARY_MECHANISM
from crankdyn_builtin.stages.vane import VANE_MECHANISM


def _check_crank_slider(scene):
    # Multi-cylinder engines are banks of crank-slider mechanisms; their layout is checked here.
    from crankdyn_builtin.stages.bays import check_layout

    return check_layout(scene)


@hookimpl
def crankdyn_mechanisms():
    return [
        Mechanism(
            name="crank_slider",
            summary="central (axial) crank-slider mechanism: the cylinder axis passes through the crankshaft axis",
            check=_check_crank_slider,
        ),
        OFFSET_CRANK_MECHANISM,
        PLANETARY_MECHANISM,
        VANE_MECHANISM,
    ]
