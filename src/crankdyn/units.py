"""Unit strings at the input boundary ("82 mm", "0.085 MPa") turned into SI floats.

pint does the parsing: it knows every prefix and spelling a user may type, and its
dimensional check is what catches "82 kg" given for a bore.
"""

from __future__ import annotations

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
    import pint  # lazy: heavy optional import

    registry = _registry()
    try:
        quantity = registry.Quantity(text.strip())
    except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError, ValueError, TypeError,
            AttributeError, SyntaxError, KeyError, AssertionError) as exc:
        raise ValueError(f"cannot read {text!r} as a {kind} ({exc.__class__.__name__}); "
                         f"write a number and a unit, e.g. {_example(kind)!r}") from None
    if not isinstance(quantity, registry.Quantity) or quantity.dimensionless:
        raise ValueError(f"{text!r} has no unit; write the {kind} with its unit, e.g. {_example(kind)!r}")
    try:
        value = float(quantity.to(si).magnitude)
    except pint.errors.DimensionalityError:
        raise ValueError(f"{text!r} is not a {kind}; e.g. {_example(kind)!r}") from None
    if value != value or value in (float("inf"), float("-inf")):
        raise ValueError(f"{text!r} is not a finite {kind}")
    return value


def _example(kind: str) -> str:
    return {"length": "82 mm", "mass": "0.45 kg", "pressure": "0.085 MPa", "time": "1.5 ms",
            "volume": "0.5 L", "moment_of_inertia": "0.12 kg*m^2", "torsional_stiffness": "1.2e5 N*m/rad",
            "density": "7200 kg/m^3", "velocity": "50 m/s"}[kind]


def format_si(value: float, kind: str, unit: str) -> str:
    """Express an SI value in ``unit`` (used for messages and the input table)."""
    registry = _registry()
    return f"{registry.Quantity(value, SI_UNIT[kind]).to(unit).magnitude:g} {unit}"
