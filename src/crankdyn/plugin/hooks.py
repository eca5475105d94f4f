"""Hook specifications: what a crankdyn plugin may implement.

A plugin is any module or object with functions marked ``@crankdyn.plugin.hooks.hookimpl``,
registered through the ``crankdyn`` entry-point group::

    [project.entry-points.crankdyn]
    my_plugin = "my_package.plugin"

The built-in mechanisms and stages register exactly this way. Every hook returns
typed objects from :mod:`crankdyn.plugin.types`; names must be unique across all
plugins (the orchestrator refuses duplicates).
"""

from __future__ import annotations

from collections.abc import Iterable

import pluggy

from .types import Catalog, ErrorProbe, Mechanism, Stage

PROJECT_NAME = "crankdyn"

hookspec = pluggy.HookspecMarker(PROJECT_NAME)
hookimpl = pluggy.HookimplMarker(PROJECT_NAME)


@hookspec
def crankdyn_mechanisms() -> Iterable[Mechanism]:
    """Return the mechanism types this plugin adds.

    A scene chooses one with ``engine.mechanism = "<name>"``. Each :class:`Mechanism`
    gives its name, a one-line summary and a ``check(scene)`` that returns the
    problems the generic validation cannot see (e.g. a linkage that cannot assemble).
    The kinematics of the mechanism come from a stage that provides ``"kinematics"``
    and applies only to scenes naming this mechanism.

    A mechanism that sets ``geometry=`` (``geometry(scene, crank_angle_rad)`` returning a
    :class:`crankdyn.plugin.types.MechanismGeometry`: named joint positions as arrays, the
    rigid links between them, guides, pitch circles) is drawn by the ``drawing`` stage: the
    kinematic scheme, the mechanism at its characteristic positions and the HTML animation.
    """


@hookspec
def crankdyn_stages() -> Iterable[Stage]:
    """Return the analysis stages this plugin adds.

    Each :class:`Stage` declares ``requires`` and ``provides`` (data keys), whether it
    ``applies`` to a scene (and why not), how it ``run``-s (pure computation) and how
    it ``render``-s its report section. The orchestrator orders stages from
    requires/provides, never from registration order.
    """


@hookspec
def crankdyn_catalogs() -> Iterable[Catalog]:
    """Return translation catalogs (one :class:`Catalog` per language file).

    A catalog is a TOML file of ``key = "text"`` entries in a language; a plugin adds
    the texts its templates use, or a whole new report language. Keys already defined
    by another catalog of the same language are an error.
    """


@hookspec
def crankdyn_error_probes() -> Iterable[ErrorProbe]:
    """Return error-against-time studies of solvers (one :class:`ErrorProbe` each).

    The numerics stage runs every probe that ``applies`` to the scene and shows its points
    (error against run time) in its section and in results.json under ``numerics.solvers``.
    Probe names must be unique across plugins.
    """
