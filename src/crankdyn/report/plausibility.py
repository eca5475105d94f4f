"""Plausibility of a valid scene: values no real engine has, reported as warnings, never errors.

A student's slip (rpm 10x too high, bore and stroke swapped, rod length in cm) often
still gives a valid scene; these checks name it. Each warning is a catalog key under
``plausibility.`` with its parameters, so the console, ``check`` and the report say the same
thing in the reader's language (the report in the section of the quantity and in the
conclusions, in the engineer's words: :func:`report_key`). Every engine is checked for its mean
piston speed and S/D (:data:`CORE_RULES`); a mechanism or stage declares the rules of its own quantities
(:class:`crankdyn.plugin.types.PlausibilityRule`: ``Mechanism.plausibility``,
``Stage.plausibility``), e.g. the crank-slider's :data:`ROD_RATIO` and :data:`ROD_CENTRE_OF_MASS`
and the indicator's :func:`peak_pressure` offered here. The limits are the ranges of real piston
engines quoted by the course texts (mean piston speed up to 20-25 m/s for the fastest
engines; lambda = R/L 0.15-0.45; S/D 0.5-1.6; peak pressures up to 20-25 MPa in boosted
diesels; the rod's centre of mass between its big end and the rod's middle).
"""

from __future__ import annotations

import re
from typing import Any

from pydantic import BaseModel

from ..plugin.types import PlausibilityRule
from ..scene.model import REGISTRY_DEFAULTS
from .i18n import translator

MAX_MEAN_PISTON_SPEED_M_S = 25.0
ROD_RATIO_RANGE = (0.15, 0.45)
STROKE_BORE_RANGE = (0.5, 1.6)
#: A marine engine's: the low-speed two-stroke crosshead diesels run at S/D = 3…4.7 (the longest
#: strokes of real engines, MAN B&W's G-type about 4.7).
MARINE_STROKE_BORE_RANGE = (0.5, 4.8)
MAX_PEAK_PRESSURE_PA = 25e6
ROD_CM_FRACTION_RANGE = (0.1, 0.5)
#: A real engine at its rated speed loses at least 5 % of its indicated power to friction,
#: pumping and its auxiliaries; the usual mechanical efficiencies are 0.70-0.90 (Kolchin and
#: Demidov, the thermal calculation's choice of eta_m for petrol engines and diesels).
MAX_MECHANICAL_EFFICIENCY = 0.95
#: Below it the friction and pumping would take over 40 % of the indicated power at the rated speed.
MIN_MECHANICAL_EFFICIENCY = 0.60
MECHANICAL_EFFICIENCY_RANGE = (0.70, 0.90)
MECHANICAL_EFFICIENCY_SOURCE = "kolchin2002"


def mean_piston_speed_m_s(stroke_m: float, rpm: float) -> float:
    """Mean piston speed c_m = S*n/30, m/s (S in m, n in rpm)."""
    return stroke_m * rpm / 30.0


def rpm_for_piston_speed(stroke_m: float, speed_m_s: float) -> float:
    """The rpm at which the mean piston speed reaches ``speed_m_s``: n = 30*c_m/S."""
    return 30.0 * speed_m_s / stroke_m


def _piston_speed(scene, results=None) -> list[tuple[str, dict[str, Any]]]:
    engine = scene.engine
    speed = mean_piston_speed_m_s(engine.stroke, engine.rpm)
    if speed <= MAX_MEAN_PISTON_SPEED_M_S:
        return []
    return [
        (
            "plausibility.piston_speed",
            {
                "speed": speed,
                "limit": MAX_MEAN_PISTON_SPEED_M_S,
                "rpm": engine.rpm,
                "rpm_limit": rpm_for_piston_speed(engine.stroke, MAX_MEAN_PISTON_SPEED_M_S),
            },
        )
    ]


def _stroke_bore(scene, results=None) -> list[tuple[str, dict[str, Any]]]:
    ratio = scene.engine.stroke / scene.engine.bore
    low, high = (
        MARINE_STROKE_BORE_RANGE if scene.engine.application == "marine" else STROKE_BORE_RANGE
    )
    if low <= ratio <= high:
        return []
    return [("plausibility.stroke_bore", {"ratio": ratio, "low": low, "high": high})]


def _rod_ratio(scene, results=None) -> list[tuple[str, dict[str, Any]]]:
    if not scene.engine.has_rod:
        return []
    ratio = scene.engine.rod_ratio_value
    if ROD_RATIO_RANGE[0] <= ratio <= ROD_RATIO_RANGE[1]:
        return []
    return [
        (
            "plausibility.rod_ratio",
            {"ratio": ratio, "low": ROD_RATIO_RANGE[0], "high": ROD_RATIO_RANGE[1]},
        )
    ]


def _rod_cm(scene, results=None) -> list[tuple[str, dict[str, Any]]]:
    if scene.masses is None or not scene.engine.has_rod:
        return []
    fraction = scene.rod_cm_from_big_end_m / scene.engine.rod_length_m
    if ROD_CM_FRACTION_RANGE[0] <= fraction <= ROD_CM_FRACTION_RANGE[1]:
        return []
    return [
        (
            "plausibility.rod_cm",
            {
                "fraction": fraction,
                "low": ROD_CM_FRACTION_RANGE[0],
                "high": ROD_CM_FRACTION_RANGE[1],
            },
        )
    ]


#: What every engine is checked for, whatever its mechanism: the mean piston speed and S/D.
CORE_RULES = (
    PlausibilityRule("piston_speed", _piston_speed),
    PlausibilityRule("stroke_bore", _stroke_bore),
)
#: λ = R/L of a connecting rod from a crank pin to a piston pin, for a mechanism to declare
#: (``Mechanism.plausibility``) whose λ is the crank-slider's ratio.
ROD_RATIO = PlausibilityRule("rod_ratio", _rod_ratio)
#: The rod's centre of mass between its big end and the rod's middle, for a mechanism with a
#: crank-slider's connecting rod to declare.
ROD_CENTRE_OF_MASS = PlausibilityRule("rod_cm", _rod_cm)


def peak_pressure(result_key: str) -> PlausibilityRule:
    """The peak cylinder pressure against the boosted diesels' 25 MPa, for a stage to declare:
    its result ``result_key`` (Pa) when it ran, else the scene's ``cycle.max_pressure``."""

    def check(scene, results=None) -> list[tuple[str, dict[str, Any]]]:
        peak = _peak_pressure_Pa(scene, results, result_key)
        if peak is None or peak <= MAX_PEAK_PRESSURE_PA:
            return []
        return [
            (
                "plausibility.peak_pressure",
                {"pressure": peak / 1e6, "limit": MAX_PEAK_PRESSURE_PA / 1e6},
            )
        ]

    return PlausibilityRule("peak_pressure", check)


def mechanical_efficiency(result_key: str) -> PlausibilityRule:
    """The mechanical efficiency N_e/N_i a stage computed (its result ``result_key``) against the
    0.95 no real engine reaches and the 0.60 below which the given powers do not belong together,
    for the stages that compute it to declare."""

    def check(scene, results=None) -> list[tuple[str, dict[str, Any]]]:
        eta = (results or {}).get(result_key)
        if (
            not isinstance(eta, (int, float))
            or MIN_MECHANICAL_EFFICIENCY <= eta <= MAX_MECHANICAL_EFFICIENCY
        ):
            return []
        low, high = MECHANICAL_EFFICIENCY_RANGE
        above = eta > MAX_MECHANICAL_EFFICIENCY
        # at 1 or more the given effective power exceeds the diagram's indicated power: no engine
        # of any kind, so the data contradict each other (not merely an unusual engine)
        kind = "_impossible" if eta >= 1.0 else "" if above else "_low"
        return [
            (
                "plausibility.mechanical_efficiency" + kind,
                {
                    "eta": float(eta),
                    "limit": MAX_MECHANICAL_EFFICIENCY if above else MIN_MECHANICAL_EFFICIENCY,
                    "low": low,
                    "high": high,
                    "source": MECHANICAL_EFFICIENCY_SOURCE,
                },
            )
        ]

    return PlausibilityRule("mechanical_efficiency", check)


def _peak_pressure_Pa(scene, results, result_key: str) -> float | None:
    value = (results or {}).get(result_key)
    if isinstance(value, (int, float)):
        return float(value)
    if scene.cycle is not None and scene.cycle.max_pressure is not None:
        return scene.cycle.max_pressure
    return None


def warnings(scene, registry, result=None) -> list[tuple[str, dict[str, Any]]]:
    """``(catalog key, parameters)`` of every implausible value of ``scene`` (and of its computed
    ``result``, when given: the peak pressure of a pressure trace is known only after reading it):
    the core's rules, the rules of the scene's mechanism, then those of the registry's stages
    (each given its stage's results when the stage ran)."""
    found = scene_warnings(scene, registry)
    outputs = result.outputs if result is not None else {}
    for name, stage in registry.stages.items():
        results = outputs[name].results if name in outputs else None
        for rule in stage.plausibility:
            found += rule.check(scene, results)
    return found


def scene_warnings(scene, registry) -> list[tuple[str, dict[str, Any]]]:
    """The core's rules and the scene's mechanism's: what the report says of its given data."""
    found: list[tuple[str, dict[str, Any]]] = []
    for rule in CORE_RULES:
        found += rule.check(scene, None)
    mechanism = registry.mechanisms.get(scene.with_plugin_defaults(registry).engine.mechanism)
    for rule in mechanism.plausibility if mechanism is not None else ():
        found += rule.check(scene, None)
    return found


def stage_warnings(stage, scene, results) -> list[tuple[str, dict[str, Any]]]:
    """The rules ``stage`` declares, given its results (None when it did not run)."""
    found: list[tuple[str, dict[str, Any]]] = []
    for rule in stage.plausibility:
        found += rule.check(scene, results)
    return found


def report_key(t, key: str, kind: str) -> str:
    """The catalog key of a warning as a report words it: ``<key>_section`` (the sentence in the
    section, in the engineer's words, naming no input key) or ``<key>_conclusion`` (the
    conclusions' sentence, no limits repeated), else the warning's own text."""
    return f"{key}_{kind}" if t.has(f"{key}_{kind}") else key


_LATIN = re.compile(r"[A-Za-z]")
_CYRILLIC = re.compile(r"[\u0400-\u04FF]")
#: The scene's own texts that a report prints as they are (title page, assignment, abstract).
_PRINTED_TEXTS = (
    "report.title",
    "report.subtitle",
    "report.ministry",
    "report.university",
    "report.department",
    "report.discipline",
    "report.student",
    "report.supervisor",
    "report.city",
    "engine.name",
)


def language_warnings(scene) -> list[tuple[str, dict[str, Any]]]:
    """A Ukrainian or Russian report whose scene gives its title page's texts in Latin letters
    only (an English example run with ``--lang uk``): the report prints them as written. For the
    terminal only; the report itself says nothing of it."""
    language = scene.report.language
    if language not in ("uk", "ru"):
        return []
    latin = []
    for name in _PRINTED_TEXTS:
        table, field = name.split(".")
        owner = getattr(scene, table)
        value = getattr(owner, field, None)
        if (
            field in owner.model_fields_set
            and isinstance(value, str)
            and _LATIN.search(value)
            and not _CYRILLIC.search(value)
        ):
            latin.append(name)
    return (
        [("plausibility.latin_texts", {"fields": ", ".join(latin), "language": language})]
        if latin
        else []
    )


def defaults_applied(scene) -> list[tuple[str, Any]]:
    """``(dotted field, default as declared)`` of every core scene value the scene did not give.

    Optional values without a default (None) and empty texts are not listed: nothing was assumed;
    nor are the values the scene's engine and cycle do not use (``Scene.fields_not_used``: a
    two-stroke's valve timing).
    A value whose default the plugins declare (:data:`crankdyn.scene.model.REGISTRY_DEFAULTS`,
    the default mechanism) is listed as the scene holds it once read with a registry.
    """
    out: list[tuple[str, Any]] = []
    unused = scene.fields_not_used()

    def walk(model: BaseModel, prefix: str) -> None:
        for name, info in type(model).model_fields.items():
            if not prefix and name in ("base_dir", "data_dirs", "mechanism"):
                continue
            value = getattr(model, name)
            if isinstance(value, BaseModel):
                walk(value, f"{prefix}{name}.")
            elif (
                name not in model.model_fields_set
                and not info.is_required()
                and prefix + name not in unused
            ):
                default = value if prefix + name in REGISTRY_DEFAULTS else info.default
                if default not in (None, ""):
                    out.append((prefix + name, default))

    walk(scene, "")
    return out


def format_params(params: dict[str, Any], decimal_separator: str = ".") -> dict[str, Any]:
    """Numbers to 3 significant digits without exponents (``4690``, ``0.15``, ``149``)."""

    def shown(value: Any) -> Any:
        if not isinstance(value, float):
            return value
        text = f"{value:.0f}" if abs(value) >= 1000 else f"{value:.3g}"
        return text.replace(".", decimal_separator)

    return {k: shown(v) for k, v in params.items()}


def console_lines(found: list[tuple[str, dict[str, Any]]], registry) -> list[str]:
    """The warnings as English sentences for the terminal."""
    if not found:  # the usual case: no catalog to read
        return []
    t = translator("en", registry.catalogs)
    return [t(key, **format_params(params)) for key, params in found]
