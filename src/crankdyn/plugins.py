"""Discovering plugins and collecting what they register."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterable

import pluggy

from . import hookspecs
from .errors import PluginError
from .plugin_types import Catalog, ErrorProbe, Mechanism, Stage

ENTRY_POINT_GROUP = hookspecs.PROJECT_NAME


@dataclass
class Registry:
    """Everything the installed plugins registered, keyed by unique name."""

    mechanisms: dict[str, Mechanism] = field(default_factory=dict)
    stages: dict[str, Stage] = field(default_factory=dict)
    catalogs: list[Catalog] = field(default_factory=list)
    error_probes: dict[str, ErrorProbe] = field(default_factory=dict)
    owner: dict[str, str] = field(default_factory=dict)  # "stage:<name>" -> plugin name


def plugin_manager(extra_plugins: Iterable[object] = (), entry_points: bool = True) -> pluggy.PluginManager:
    """A plugin manager with the crankdyn hooks, the entry-point plugins and ``extra_plugins``."""
    manager = pluggy.PluginManager(hookspecs.PROJECT_NAME)
    manager.add_hookspecs(hookspecs)
    if entry_points:
        manager.load_setuptools_entrypoints(ENTRY_POINT_GROUP)
    for plugin in extra_plugins:
        manager.register(plugin)
    return manager


def collect(manager: pluggy.PluginManager) -> Registry:
    """Flatten the hooks' results into a :class:`Registry`; duplicate names are an error."""
    registry = Registry()
    for kind, hook, target in (("mechanism", manager.hook.crankdyn_mechanisms, registry.mechanisms),
                               ("stage", manager.hook.crankdyn_stages, registry.stages),
                               ("error probe", manager.hook.crankdyn_error_probes, registry.error_probes)):
        for impl in hook.get_hookimpls():
            plugin_name = manager.get_name(impl.plugin) or repr(impl.plugin)
            for item in impl.function() or ():
                expected = {"mechanism": Mechanism, "stage": Stage, "error probe": ErrorProbe}[kind]
                if not isinstance(item, expected):
                    raise PluginError(f"plugin {plugin_name!r} returned {item!r} from its {kind} hook; "
                                      f"expected {expected.__name__}")
                key = f"{kind}:{item.name}"
                if item.name in target:
                    raise PluginError(f"duplicate {kind} name {item.name!r}: registered by "
                                      f"{registry.owner[key]!r} and by {plugin_name!r}")
                target[item.name] = item
                registry.owner[key] = plugin_name
    for impl in manager.hook.crankdyn_catalogs.get_hookimpls():
        for catalog in impl.function() or ():
            if not isinstance(catalog, Catalog):
                raise PluginError(f"plugin {manager.get_name(impl.plugin)!r} returned {catalog!r} "
                                  f"from crankdyn_catalogs; expected Catalog")
            registry.catalogs.append(catalog)
    return registry


def default_registry() -> Registry:
    return collect(plugin_manager())
