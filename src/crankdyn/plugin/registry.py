"""Discovering plugins and collecting what they register.

A plugin that cannot be imported, whose hook raises or returns what the hook types do not allow,
is left out and listed in :attr:`Registry.broken` with the reason (``crankdyn plugins`` shows
it); the other plugins work. What the others register is wrapped by :mod:`crankdyn.plugin.guard`,
so that a failure of a third-party stage names its plugin.
"""

from __future__ import annotations

import importlib.metadata
import types
from collections.abc import Iterable
from dataclasses import dataclass, field

import pluggy

from ..errors import CrankdynError, PluginError, PluginFailure, SceneError, shorten
from . import guard as plugin_guard
from . import hooks as hookspecs
from .types import Catalog, ErrorProbe, Mechanism, Stage

ENTRY_POINT_GROUP = hookspecs.PROJECT_NAME
#: the package of the plugins that come with crankdyn: their errors are the program's own
BUILTIN_PACKAGE = "crankdyn_builtin"
#: the attribute of a plugin manager holding the plugins that failed to load (name -> message)
_BROKEN = "crankdyn_broken"


@dataclass
class Registry:
    """Everything the installed plugins registered, keyed by unique name."""

    mechanisms: dict[str, Mechanism] = field(default_factory=dict)
    stages: dict[str, Stage] = field(default_factory=dict)
    catalogs: list[Catalog] = field(default_factory=list)
    error_probes: dict[str, ErrorProbe] = field(default_factory=dict)
    owner: dict[str, str] = field(default_factory=dict)  # "stage:<name>" -> plugin name
    #: plugins left out: plugin name -> why (``plugin 'x' (import): ModuleNotFoundError: ...``)
    broken: dict[str, str] = field(default_factory=dict)

    @property
    def default_mechanism(self) -> str | None:
        """The name of the mechanism declared ``default`` (a scene naming none gets it), or None.

        :func:`collect` allows at most one."""
        return next((m.name for m in self.mechanisms.values() if m.default), None)

    def default_angle_step_deg(self, scene) -> float | None:
        """The smallest crank-angle step [deg] the stages ask for ``scene`` when it gives none
        (``Stage.default_angle_step``), or None when none asks. A stage whose scene table is
        invalid asks nothing here: :func:`crankdyn.engine.orchestrator.check_scene` reports it."""
        wishes = []
        for stage in self.stages.values():
            if stage.default_angle_step is None:
                continue
            try:
                step = stage.default_angle_step(scene)
            except SceneError:
                continue
            if step is not None:
                wishes.append(float(step))
        return min(wishes) if wishes else None


def plugin_manager(
    extra_plugins: Iterable[object] = (), entry_points: bool = True
) -> pluggy.PluginManager:
    """A plugin manager with the crankdyn hooks, the entry-point plugins and ``extra_plugins``.

    An entry point that cannot be imported or registered is not an error here: it is kept as
    broken, and :func:`collect` lists it in :attr:`Registry.broken`."""
    manager = pluggy.PluginManager(hookspecs.PROJECT_NAME)
    manager.add_hookspecs(hookspecs)
    setattr(manager, _BROKEN, {})
    if entry_points:
        _load_entry_points(manager)
    for plugin in extra_plugins:
        _register(manager, plugin, None)
    return manager


def _load_entry_points(manager: pluggy.PluginManager) -> None:
    broken = getattr(manager, _BROKEN)
    for entry_point in importlib.metadata.entry_points(group=ENTRY_POINT_GROUP):
        name = entry_point.name
        if name in broken or manager.get_plugin(name) is not None or manager.is_blocked(name):
            continue
        try:
            plugin = _loading(name, "import", "import", entry_point.load)
        except PluginFailure as exc:
            broken[name] = str(exc)
            continue
        _register(manager, plugin, name)


def _loading(plugin: str, where: str, step: str, fn):
    """``fn()`` of a plugin being loaded: whatever it raises, even a SceneError or an exit, is
    a :class:`PluginFailure` (a scene has not been read yet)."""
    try:
        return plugin_guard.call(plugin, where, step, True, fn)
    except PluginFailure:
        raise
    except (CrankdynError, SystemExit) as exc:  # SystemExit: a module that ends the program
        raise PluginFailure(plugin, where, f"{step} raised {plugin_guard.describe(exc)}") from exc


def _register(manager: pluggy.PluginManager, plugin: object, name: str | None) -> None:
    """Register ``plugin``; one pluggy refuses (a hook function with a wrong signature, one
    registered twice) is kept as broken, with pluggy's reason."""
    try:
        manager.register(plugin, name=name)
    except Exception as exc:  # pluggy's PluginValidationError, ValueError
        label = name or plugin_name(manager, plugin)
        failure = PluginFailure(label, "import", plugin_guard.describe(exc))
        getattr(manager, _BROKEN)[label] = str(failure)


def plugin_name(manager: pluggy.PluginManager, plugin: object) -> str:
    """The name ``plugin`` is known by: its entry point's, its module's, else its class's."""
    name = manager.get_name(plugin)
    if name and name != str(id(plugin)):
        return name
    kind = type(plugin)
    return f"{kind.__module__}.{kind.__qualname__}"


def is_builtin(plugin: object) -> bool:
    """Whether ``plugin`` is one of crankdyn's own (a module or object of
    :data:`BUILTIN_PACKAGE`)."""
    if isinstance(plugin, types.ModuleType):
        module = plugin.__name__
    else:
        module = getattr(plugin, "__module__", "")
    return str(module).split(".")[0] == BUILTIN_PACKAGE


_HOOKS = (
    ("mechanism", "crankdyn_mechanisms", plugin_guard.checked_mechanism),
    ("stage", "crankdyn_stages", plugin_guard.checked_stage),
    ("error probe", "crankdyn_error_probes", plugin_guard.checked_probe),
    ("catalog", "crankdyn_catalogs", plugin_guard.checked_catalog),
)
_GUARDS = {
    "mechanism": plugin_guard.guarded_mechanism,
    "stage": plugin_guard.guarded_stage,
    "error probe": plugin_guard.guarded_probe,
}


def collect(manager: pluggy.PluginManager) -> Registry:
    """Flatten the hooks' results into a :class:`Registry`; duplicate names are an error.

    A third-party plugin whose hook fails is left out whole and listed in ``broken``; a built-in
    plugin's failure is the program's and raises."""
    broken: dict[str, str] = dict(getattr(manager, _BROKEN, {}))
    returned: dict[str, list[tuple[str, bool, list]]] = {kind: [] for kind, _, _ in _HOOKS}
    for kind, hook_name, check in _HOOKS:
        for impl in getattr(manager.hook, hook_name).get_hookimpls():
            name, foreign = plugin_name(manager, impl.plugin), not is_builtin(impl.plugin)
            if name in broken:
                continue
            try:
                items = _hook_items(impl, name, hook_name, check, foreign)
            except PluginFailure as exc:
                if not foreign:
                    raise
                broken[name] = str(exc)
                continue
            returned[kind].append((name, foreign, items))
    registry = Registry(broken=broken)
    targets = {
        "mechanism": registry.mechanisms,
        "stage": registry.stages,
        "error probe": registry.error_probes,
    }
    for kind, target in targets.items():
        for name, foreign, items in returned[kind]:
            if name in broken:
                continue
            for item in items:
                key = f"{kind}:{item.name}"
                if item.name in target:
                    raise PluginError(
                        f"duplicate {kind} name {item.name!r}: registered by "
                        f"{registry.owner[key]!r} and by {name!r}"
                    )
                target[item.name] = _GUARDS[kind](item, name, foreign)
                registry.owner[key] = name
    registry.catalogs = [
        c for name, _, items in returned["catalog"] if name not in broken for c in items
    ]
    _one_default(registry)
    return registry


def _one_default(registry: Registry) -> None:
    """A :class:`PluginError` when more than one mechanism declares itself the default."""
    defaults = [name for name, mechanism in registry.mechanisms.items() if mechanism.default]
    if len(defaults) > 1:
        owners = ", ".join(
            f"{name!r} ({registry.owner['mechanism:' + name]!r})" for name in defaults
        )
        raise PluginError(
            f"more than one mechanism declares itself the default (Mechanism.default): {owners}; "
            "a scene that names no engine.mechanism gets one default"
        )


def _hook_items(impl, name: str, hook_name: str, check, foreign: bool) -> list:
    """What one plugin's hook returned, each item checked (a :class:`PluginFailure` if not)."""
    where = f"hook {hook_name}"
    if foreign:
        returned = _loading(name, where, "the hook", impl.function)
    else:
        returned = plugin_guard.call(name, where, "the hook", foreign, impl.function)
    if returned is None:
        return []
    try:
        items = list(returned)
    except TypeError:
        raise PluginFailure(
            name, f"hook {hook_name}", f"the hook returned {shorten(returned)}; expected a list"
        ) from None
    return [check(item, name, hook_name, foreign) for item in items]


def broken_note(registry: Registry) -> str:
    """A sentence naming the plugins that failed to load (one of them may be what is missing),
    or "" when none did."""
    if not registry.broken:
        return ""
    return "; installed but not loaded: " + "; ".join(registry.broken.values())


def default_registry() -> Registry:
    return collect(plugin_manager())
