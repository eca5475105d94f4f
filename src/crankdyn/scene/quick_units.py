"""The common unit strings of a scene ("82 mm", "0.085 MPa", "0.12 kg*m^2") read without pint.

Importing pint and building its registry costs most of a second, more than the whole
computation of a single-cylinder scene. Nearly every quantity a scene gives is a number
followed by one of a few spellings, so those are read here from a fixed table; anything
else (other prefixes, unusual spellings, a unit of the wrong kind, malformed text) returns
``None`` and goes to pint in :func:`crankdyn.units.parse_quantity`, which also words the
error messages. Each factor is pint's own conversion factor to the SI unit, applied the way
pint applies it (``magnitude * factor``), and ``tests/test_quick_units.py`` checks bit for bit
that this table and pint agree on every entry.
"""

from __future__ import annotations

import math
import re
import sys

# A number as pint's tokenizer reads it, then optional spaces, then the unit spelling.
_QUANTITY = re.compile(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(\S.*?)\s*")

_LENGTH = {"m": 1.0, "mm": 0.001, "cm": 0.01, "um": 1e-06, "km": 1000.0, "meter": 1.0, "millimeter": 0.001}
_MASS = {"kg": 1.0, "g": 0.001, "kilogram": 1.0, "gram": 0.001}
_PRESSURE = {"Pa": 1.0, "kPa": 1000.0, "MPa": 1000000.0, "GPa": 1000000000.0, "bar": 100000.0}
_TIME = {"s": 1.0, "ms": 0.001, "second": 1.0}
# pint defines the litre as a cubic decimetre: its factor is 0.1 ** 3, one ulp above 0.001.
_LITRE = 0.1 ** 3
_VOLUME = {"m^3": 1.0, "m**3": 1.0, "L": _LITRE, "l": _LITRE, "liter": _LITRE}
_INERTIA = {"kg*m^2": 1.0, "kg*m**2": 1.0, "kg m^2": 1.0, "kg m**2": 1.0, "kg·m^2": 1.0, "kg·m²": 1.0}
_STIFFNESS = {"N*m/rad": 1.0, "N m/rad": 1.0, "kN*m/rad": 1000.0, "N*m": 1.0}
_DENSITY = {"kg/m^3": 1.0, "kg/m**3": 1.0}
_VELOCITY = {"m/s": 1.0}
_POWER = {"W": 1.0, "kW": 1000.0, "MW": 1000000.0}

#: kind -> {unit spelling: factor to the SI unit of :data:`crankdyn.units.SI_UNIT`}
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
