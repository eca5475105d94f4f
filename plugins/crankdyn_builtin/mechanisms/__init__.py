"""Built-in mechanism types."""

from crankdyn.hookspecs import hookimpl
from crankdyn.plugin_types import Mechanism


@hookimpl
def crankdyn_mechanisms():
    return [
        Mechanism(
            name="crank_slider",
            summary="central (axial) crank-slider mechanism: the cylinder axis passes through the crankshaft axis",
        ),
    ]
