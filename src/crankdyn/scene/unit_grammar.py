"""A quantity as a user types it: one number and one unit expression, nothing else.

The grammar is ours; pint is used only as a dictionary of unit names (prefixes,
spellings, dimensions). No text is ever evaluated, so ``"9**9**9 mm"``, ``"1/0 mm"``
and ``"2*41 mm"`` are refused at once instead of hanging or being computed::

    quantity  := number [ws] unit
    number    := [+-] digits [("." | ",") digits] [("e" | "E") [+-] digits(1-3)]
                 (a decimal comma is read as a decimal point: "6,0 MPa" = 6.0 MPa)
    unit      := ["1" ws? "/"] factor { ("*" | "·" | "⋅" | " " | "/") factor }
    factor    := name [ ("^" | "**") [+-] digit | superscript digits ]   |n| <= 4
    name      := letters (with µ, μ, Ω, °, _)

A text longer than :data:`MAX_LENGTH` characters is refused before it is looked at.
"""

from __future__ import annotations

import math
import re

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
    rest = text[match.end():].strip()
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
            raise QuantityError(f"expected a unit name at {text[position:position + 10]!r}")
        name = name_match.group(0)
        position = name_match.end()
        exponent = 1
        power = _EXPONENT.match(text, position)
        superscript = _SUPERSCRIPT.match(text, position)
        if power:
            exponent, position = int(power.group(1)), power.end()
        elif superscript:
            exponent, position = int(superscript.group(0).translate(_SUPERSCRIPTS)), superscript.end()
        if exponent == 0 or abs(exponent) > MAX_EXPONENT:
            raise QuantityError(f"unit exponents are whole numbers from -{MAX_EXPONENT} to {MAX_EXPONENT} (not 0)")
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
            raise QuantityError(f"unexpected {text[position:position + 10]!r} after the unit {name!r}")
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
