"""Unit strings at the input boundary ("82 mm", "0.085 MPa") turned into SI floats: the one
parser of a value with its unit.

:func:`parse_quantity` reads a value in three steps:

1. **the common spellings, without pint** (:func:`quick_quantity`). Importing pint and building
   its registry costs most of a second, more than the whole computation of a single-cylinder
   scene. Nearly every quantity a scene gives is a number followed by one of a few spellings,
   read from a fixed table (:data:`FACTORS`); each factor is pint's own conversion factor to the
   SI unit, applied the way pint applies it (``magnitude * factor``), and
   ``tests/test_quick_units.py`` checks bit for bit that the table and pint agree on every entry.
2. **our own grammar** (:func:`parse`) for anything else: one number and one unit expression,
   nothing evaluated. pint is used only as a dictionary of unit names (prefixes, spellings,
   dimensions), so ``"9**9**9 mm"``, ``"1/0 mm"`` and ``"2*41 mm"`` are refused at once instead of
   hanging or being computed::

       quantity  := number [ws] unit
       number    := [+-] digits [("." | ",") digits] [("e" | "E") [+-] digits(1-3)]
                    (a decimal comma is read as a decimal point: "6,0 MPa" = 6.0 MPa)
       unit      := ["1" ws? "/"] factor { ("*" | "·" | "⋅" | " " | "/") factor }
       factor    := name [ ("^" | "**") [+-] digit | superscript digits ]   |n| <= 4
       name      := letters (with µ, μ, Ω, °, _)

   A text longer than :data:`MAX_LENGTH` characters is refused before it is looked at.
3. **pint's dimensional check**, which catches "82 kg" given for a bore, and the error messages.
"""

from __future__ import annotations

import math
import re
import sys
from functools import lru_cache

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


# The common spellings, read without pint.

# A number as pint's tokenizer reads it, then optional spaces, then the unit spelling.
_QUANTITY = re.compile(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(\S.*?)\s*")

_LENGTH = {
    "m": 1.0,
    "mm": 0.001,
    "cm": 0.01,
    "um": 1e-06,
    "km": 1000.0,
    "meter": 1.0,
    "millimeter": 0.001,
}
_MASS = {"kg": 1.0, "g": 0.001, "kilogram": 1.0, "gram": 0.001}
_PRESSURE = {"Pa": 1.0, "kPa": 1000.0, "MPa": 1000000.0, "GPa": 1000000000.0, "bar": 100000.0}
_TIME = {"s": 1.0, "ms": 0.001, "second": 1.0}
# pint defines the litre as a cubic decimetre: its factor is 0.1 ** 3, one ulp above 0.001.
_LITRE = 0.1**3
_VOLUME = {"m^3": 1.0, "m**3": 1.0, "L": _LITRE, "l": _LITRE, "liter": _LITRE}
_INERTIA = {
    "kg*m^2": 1.0,
    "kg*m**2": 1.0,
    "kg m^2": 1.0,
    "kg m**2": 1.0,
    "kg·m^2": 1.0,
    "kg·m²": 1.0,
}
_STIFFNESS = {"N*m/rad": 1.0, "N m/rad": 1.0, "kN*m/rad": 1000.0, "N*m": 1.0}
_DENSITY = {"kg/m^3": 1.0, "kg/m**3": 1.0}
_VELOCITY = {"m/s": 1.0}
_POWER = {"W": 1.0, "kW": 1000.0, "MW": 1000000.0}

#: kind -> {unit spelling: factor to the SI unit of :data:`SI_UNIT`}
FACTORS = {
    "length": _LENGTH,
    "mass": _MASS,
    "pressure": _PRESSURE,
    "time": _TIME,
    "volume": _VOLUME,
    "moment_of_inertia": _INERTIA,
    "torsional_stiffness": _STIFFNESS,
    "density": _DENSITY,
    "velocity": _VELOCITY,
    "power": _POWER,
}


def quick_quantity(text: str, kind: str) -> float | None:
    """``text`` in the SI unit of ``kind`` when it is a number and a tabled unit, else ``None``."""
    match = _QUANTITY.fullmatch(text)
    if match is None:
        return None
    factor = FACTORS.get(kind, {}).get(match.group(2))
    if factor is None:
        return None
    number = match.group(1)
    magnitude = float(number) if any(c in number for c in ".eE") else int(number)
    value = float(magnitude * factor)
    if abs(value) < sys.float_info.min and re.search(r"[1-9]", number.lower().split("e")[0]):
        return None  # a nonzero number that underflows: pint's path words the refusal
    return value if math.isfinite(value) else None


# The grammar of a quantity as a user types it.

MAX_LENGTH = 64
MAX_EXPONENT = 4

_NUMBER = re.compile(r"\s*([+-]?(?:\d+(?:[.,]\d*)?|[.,]\d+)(?:[eE][+-]?\d{1,3})?)")
_NAME = re.compile(r"(?:[^\W\d⁰¹²³⁴⁵⁶⁷⁸⁹]|°)+", re.UNICODE)
_EXPONENT = re.compile(r"\s*(?:\^|\*\*)\s*([+-]?\d+)")
_SUPERSCRIPTS = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺", "0123456789-+")
_SUPERSCRIPT = re.compile(r"[⁻⁺]?[⁰¹²³⁴⁵⁶⁷⁸⁹]+")
_MULTIPLY = re.compile(r"\s*[*·⋅]\s*|\s+")
_DIVIDE = re.compile(r"\s*/\s*")
_RECIPROCAL = re.compile(r"1\s*/\s*")


class QuantityError(ValueError):
    """The text is not one number and one unit (the message says why, without the example)."""


def parse(text: str, registry) -> tuple[float, dict[str, int]]:
    """Split ``text`` into its number and its units ``{pint unit name: exponent}``.

    Raises :class:`QuantityError` naming what is wrong; nothing in ``text`` is evaluated.
    """
    if len(text) > MAX_LENGTH:
        raise QuantityError(f"longer than {MAX_LENGTH} characters")
    match = _NUMBER.match(text)
    if match is None:
        raise QuantityError("does not start with a number")
    number = float(match.group(1).replace(",", "."))
    if not math.isfinite(number):
        raise QuantityError("the number is out of range")
    if number == 0 and re.search(r"[1-9]", match.group(1).lower().split("e")[0]):
        raise QuantityError("the number is too close to zero to compute with")
    rest = text[match.end() :].strip()
    if not rest:
        raise QuantityError("has no unit")
    return number, _units(rest, registry)


def _units(text: str, registry) -> dict[str, int]:
    units: dict[str, int] = {}
    position, sign = 0, 1
    reciprocal = _RECIPROCAL.match(text)
    if reciprocal:
        position, sign = reciprocal.end(), -1
    while True:
        name_match = _NAME.match(text, position)
        if name_match is None:
            raise QuantityError(f"expected a unit name at {text[position : position + 10]!r}")
        name = name_match.group(0)
        position = name_match.end()
        exponent = 1
        power = _EXPONENT.match(text, position)
        superscript = _SUPERSCRIPT.match(text, position)
        if power:
            exponent, position = int(power.group(1)), power.end()
        elif superscript:
            exponent, position = (
                int(superscript.group(0).translate(_SUPERSCRIPTS)),
                superscript.end(),
            )
        if exponent == 0 or abs(exponent) > MAX_EXPONENT:
            raise QuantityError(
                f"unit exponents are whole numbers from -{MAX_EXPONENT} to {MAX_EXPONENT} (not 0)"
            )
        unit = _unit_name(name, registry)
        units[unit] = units.get(unit, 0) + sign * exponent
        if abs(units[unit]) > MAX_EXPONENT:
            raise QuantityError(f"the unit {name!r} appears with a power above {MAX_EXPONENT}")
        if position == len(text):
            return {u: e for u, e in units.items() if e}
        divide = _DIVIDE.match(text, position)
        multiply = _MULTIPLY.match(text, position)
        if divide:
            if sign == -1 and not reciprocal:
                raise QuantityError("more than one '/' in the unit")
            position, sign = divide.end(), -1
        elif multiply and multiply.end() > position:
            position = multiply.end()
        else:
            raise QuantityError(
                f"unexpected {text[position : position + 10]!r} after the unit {name!r}"
            )
        if position == len(text):
            raise QuantityError("the unit ends with an operator")


def _unit_name(name: str, registry) -> str:
    """``name`` if pint knows it as a unit (with any prefix and plural); only a name, never an expression."""
    try:
        known = bool(registry.parse_unit_name(name))
    except (AttributeError, KeyError, ValueError, TypeError):
        known = False
    return name if known else _unknown(name)


def _unknown(name: str) -> str:
    raise QuantityError(f"unknown unit {name!r}")


# The SI value of a quantity: the quick table, else the grammar and pint.


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
        raise ValueError(
            f"a bare number has no unit; write the {kind} with its unit, e.g. {_example(kind)!r}"
        )
    quick = quick_quantity(text, kind)  # the common spellings without importing pint (same values)
    if quick is not None:
        return quick
    import pint  # lazy: heavy optional import

    registry = _registry()
    example = _example(kind)
    try:
        number, units = parse(text, registry)
    except QuantityError as exc:
        raise ValueError(
            f"cannot read {_shown(text)} as a {kind}: {exc}; write one number and one unit, "
            f"e.g. {example!r}"
        ) from None
    unit = registry.Unit("")
    for name, exponent in units.items():
        unit = unit * registry.Unit(name) ** exponent
    if unit.dimensionless:
        raise ValueError(
            f"{_shown(text)} has no unit; write the {kind} with its unit, e.g. {example!r}"
        )
    try:
        value = float(registry.Quantity(number, unit).to(si).magnitude)
    except pint.errors.DimensionalityError:
        raise ValueError(
            f"{_shown(text)} is not a {kind} (its unit is {unit:~}); e.g. {example!r}"
        ) from None
    except (OverflowError, ZeroDivisionError, ValueError):
        value = math.inf
    if not math.isfinite(value):
        raise ValueError(f"{_shown(text)} is not a finite {kind}; e.g. {example!r}")
    if number != 0 and abs(value) < sys.float_info.min:
        raise ValueError(
            f"{_shown(text)} is too close to zero to compute with (below "
            f"{sys.float_info.min:.3g} {si}); give 0 or a {kind} of a physical size"
        )
    return value


def _shown(text: str) -> str:
    """``text`` quoted and escaped for a message, cut to 40 characters."""
    return repr(text if len(text) <= 40 else text[:37] + "...")


def _example(kind: str) -> str:
    return {
        "length": "82 mm",
        "mass": "0.45 kg",
        "pressure": "0.085 MPa",
        "time": "1.5 ms",
        "volume": "0.5 L",
        "moment_of_inertia": "0.12 kg*m^2",
        "torsional_stiffness": "1.2e5 N*m/rad",
        "density": "7200 kg/m^3",
        "velocity": "50 m/s",
        "power": "55 kW",
    }[kind]


def format_si(value: float, kind: str, unit: str) -> str:
    """Express an SI value in ``unit`` (used for messages and the input table)."""
    registry = _registry()
    return f"{registry.Quantity(value, SI_UNIT[kind]).to(unit).magnitude:g} {unit}"
