"""Unit strings at the input boundary ("82 mm", "0.085 MPa") turned into SI floats.

The text is split by our own grammar (:mod:`crankdyn.quantity`: one number, one unit
expression, nothing evaluated); pint supplies the unit names and the dimensional check
that catches "82 kg" given for a bore.
"""

from __future__ import annotations

import math
import sys
from functools import lru_cache

from .quick_units import quick_quantity
from .unit_grammar import QuantityError, parse

# Display units and the SI unit each physical kind converts to.
SI_UNIT = {
    "length": "m",
    "mass": "kg",
    "pressure": "Pa",
    "time": "s",
    "volume": "m**3",
    "moment_of_inertia": "kg*m**2",
    "torsional_stiffness": "N*m/rad",
    "density": "kg/m**3",
    "velocity": "m/s",
    "power": "W",
}


@lru_cache(maxsize=1)
def _registry():
    import pint  # lazy: heavy optional import

    return pint.UnitRegistry(autoconvert_offset_to_baseunit=True)


def parse_quantity(text: object, kind: str) -> float:
    """Return ``text`` (e.g. ``"82 mm"``) as a float in the SI unit of ``kind``.

    Raises ValueError with a message saying what is expected; a bare number is
    refused because a unit-less size is the commonest source of 1000x errors.
    """
    si = SI_UNIT[kind]
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise ValueError(f"expected a {kind} with a unit, e.g. {_example(kind)!r}")
    if isinstance(text, (int, float)):
        raise ValueError(f"a bare number has no unit; write the {kind} with its unit, e.g. {_example(kind)!r}")
    quick = quick_quantity(text, kind)  # the common spellings without importing pint (same values)
    if quick is not None:
        return quick
    import pint  # lazy: heavy optional import


    registry = _registry()
    example = _example(kind)
    try:
        number, units = parse(text, registry)
    except QuantityError as exc:
        raise ValueError(f"cannot read {_shown(text)} as a {kind}: {exc}; write one number and one unit, "
                         f"e.g. {example!r}") from None
    unit = registry.Unit("")
    for name, exponent in units.items():
        unit = unit * registry.Unit(name) ** exponent
    if unit.dimensionless:
        raise ValueError(f"{_shown(text)} has no unit; write the {kind} with its unit, e.g. {example!r}")
    try:
        value = float(registry.Quantity(number, unit).to(si).magnitude)
    except pint.errors.DimensionalityError:
        raise ValueError(f"{_shown(text)} is not a {kind} (its unit is {unit:~}); e.g. {example!r}") from None
    except (OverflowError, ZeroDivisionError, ValueError):
        value = math.inf
    if not math.isfinite(value):
        raise ValueError(f"{_shown(text)} is not a finite {kind}; e.g. {example!r}")
    if number != 0 and abs(value) < sys.float_info.min:
        raise ValueError(f"{_shown(text)} is too close to zero to compute with (below "
                         f"{sys.float_info.min:.3g} {si}); give 0 or a {kind} of a physical size")
    return value


def _shown(text: str) -> str:
    """``text`` quoted and escaped for a message, cut to 40 characters."""
    return repr(text if len(text) <= 40 else text[:37] + "...")


def _example(kind: str) -> str:
    return {"length": "82 mm", "mass": "0.45 kg", "pressure": "0.085 MPa", "time": "1.5 ms",
            "volume": "0.5 L", "moment_of_inertia": "0.12 kg*m^2", "torsional_stiffness": "1.2e5 N*m/rad",
            "density": "7200 kg/m^3", "velocity": "50 m/s", "power": "55 kW"}[kind]


def format_si(value: float, kind: str, unit: str) -> str:
    """Express an SI value in ``unit`` (used for messages and the input table)."""
    registry = _registry()
    return f"{registry.Quantity(value, SI_UNIT[kind]).to(unit).magnitude:g} {unit}"
