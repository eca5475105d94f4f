"""crankdyn: the dynamic calculation of crank mechanisms and piston engines.

The public entry points are :func:`crankdyn.scene.load_scene`,
:func:`crankdyn.orchestrator.run_scene` and the ``crankdyn`` command line.
Mechanisms and analysis stages are pluggy plugins; see :mod:`crankdyn.hookspecs`.
"""

__version__ = "0.1.0"
