"""The balancing section's notation: the letters it declares, and forces and vectors as written."""

from __future__ import annotations

import math

from markupsafe import Markup

from crankdyn.plugin.types import Symbol


def circular(hodograph: dict) -> bool:
    """Whether a hodograph is a circle to the table's three decimals: it has no major axis (an
    angle "0,0°" beside the semi-axes 1,000 / 1,000 would mean nothing)."""
    return (
        round(hodograph["semi_major"], 9) == 0
        or abs(hodograph["semi_major"] - hodograph["semi_minor"]) <= 5e-4 * hodograph["semi_major"]
    )


#: The most significant digits a force or moment is printed with: a large engine's are not given
#: to the newton (ΣM_II = 1 249 300 Н·м, not 1 249 297,6).
MOST_DIGITS = 5


def _to_digits(t, value: float, decimals: int) -> str:
    """``value`` to ``decimals`` decimals, or to :data:`MOST_DIGITS` significant digits where
    that is fewer, written without an exponent (1 249 300)."""
    if value == 0:
        return t.fixed(value, decimals)
    exponent = math.floor(math.log10(abs(value)))
    if abs(round(value, MOST_DIGITS - 1 - exponent)) >= 10.0 ** (exponent + 1):
        exponent += 1  # rounded up to the next power of ten (9999.96 to 10 000)
    places = min(decimals, MOST_DIGITS - 1 - exponent)
    return t.fixed(round(value, places), max(places, 0))


def newtons(t, force_N: float) -> str:
    """A force as the table of orders and the conclusions print it: whole newtons (C = 17 235 Н),
    two significant digits under 10 N, where whole newtons would print a small unbalanced force
    as 0 or 1 Н, at most :data:`MOST_DIGITS` significant digits."""
    return _to_digits(t, force_N, 0) if abs(force_N) >= 10 else t.number_g(force_N, 2)


def newton_metres(t, moment_Nm: float) -> str:
    """A moment as the table of orders and the conclusions print it: to 0.1 N·m, two significant
    digits under 1 N·m, where tenths would print a small unbalanced moment as 0,0 or 0,1, at most
    :data:`MOST_DIGITS` significant digits."""
    return _to_digits(t, moment_Nm, 1) if abs(moment_Nm) >= 1 else t.number_g(moment_Nm, 2)


#: The amplitude a table of orders divides by, as its headers print it (the catalogs' ``{scale}``).
C_N = "<i>C</i><sub><i>ν</i></sub>"


def summary_symbol(s, sum_sign: str = "Σ") -> Markup:
    """ΣC, ΣP_II, ΣM_I as the summary table prints them; one cylinder's without the sum sign (C, P_II),
    as its table of orders and its text write them."""
    kind, base = s["quantity"].split("_", 1)
    if kind == "sum":
        return Markup(
            f"{sum_sign}<i>C</i>"
            if base == "C"
            else f"{sum_sign}<i>P</i><sub>" + base[1:] + "</sub>"
        )
    return Markup(f"{sum_sign}<i>M</i><sub>" + ("C" if base == "C" else base[1:]) + "</sub>")


def scale_symbol(s) -> str:
    """What table 6.3 divides a sum by: C_n (C for the centrifugal forces), and a moment also by a."""
    kind, base = s["quantity"].split("_", 1)
    order = base[1:] if base.startswith("P") else ""
    scale = f"C_{order}" if order else "C"
    return scale if kind == "sum" else f"({scale}·a)"


def plain_symbol(s, sum_sign: str = "Σ") -> str:
    """``ΣP_I``, ``ΣM_II``, ``ΣC``: the symbol as table 6.3 prints it (typeset with its subscript);
    ``sum_sign=""`` for one cylinder's own force (``P_I``)."""
    kind, base = s["quantity"].split("_", 1)
    order = base[1:] if base.startswith("P") else ""
    if kind == "sum":
        return f"{sum_sign}P_{order}" if order else sum_sign + base
    return f"{sum_sign}M_{order or base}"


#: The offset crank-slider's phase of an acceleration harmonic (meaning: symbol.balancing.<key>).
SYMBOLS = {
    "harmonic_phase": Symbol("ψ", {"en": "ν"}, "°", html="<i>ψ</i><sub><i>ν</i></sub>"),
    # upright, as in e^{jα}: the only upright j of the note (i numbers the cylinders; the italic j
    # with a subscript is the piston's acceleration)
    "imaginary_unit": Symbol("j", {}, "", html="j"),
    # articulated rods: the master cylinder's reciprocating mass with the slave rods' shares at its
    # piston pin (the forces section's m_s is one cylinder's, without them)
    "master_reciprocating_mass": Symbol("m", {"en": "s.m", "uk": "s.гол", "ru": "s.гл"}, "unit.kg"),
}

#: The master cylinder's reciprocating mass as the balancing section writes it (articulated rods).
MASTER_MASS = {
    "en": "<i>m</i><sub>s.m</sub>",
    "uk": "<i>m</i><sub>s.гол</sub>",
    "ru": "<i>m</i><sub>s.гл</sub>",
}


def master_mass(t, r) -> str:
    """m_s as the balancing section writes it: the master cylinder's own letter with articulated
    rods (its mass holds the slave rods' shares), else m_s."""
    if r.get("slave_reciprocating_mass_kg") is None:
        return "<i>m</i><sub>s</sub>"
    return MASTER_MASS.get(t.language, MASTER_MASS["en"])
