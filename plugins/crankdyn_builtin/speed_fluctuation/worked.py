"""The worked substitution of the speed-fluctuation stage: the coefficient of cyclic irregularity
from the speeds the section states, δ = (ω_max − ω_min)/ω_m, ω_m = (ω_max + ω_min)/2."""

from __future__ import annotations

import math

from markupsafe import Markup

from crankdyn.report.typeset import symbol_html
from crankdyn.report.worked import WorkedBlock, WorkedStep, printed, worked_markup


def speed_digits(omega_max: float, omega_min: float) -> int:
    """Significant digits that print the extreme speeds apart, their difference to two digits
    (272,20 and 272,33 rad/s, not 272,2 and 272,3), at least four."""
    spread = omega_max - omega_min
    if spread <= 0 or omega_max <= 0:
        return 4
    return max(4, math.floor(math.log10(omega_max)) - math.floor(math.log10(spread)) + 2)


def worked_speed_fluctuation(ctx, r) -> Markup:
    """δ from the range of the speed and its mean as the text prints them: the range to 4
    significant digits (the difference of two speeds printed to 4 digits would carry only two, so
    the text states the range itself), the mean with the extreme speeds' digits
    (:func:`speed_digits`: 104,65, not 104,6, beside a range of 0,5232)."""
    t = ctx.t
    omega_range = r["omega_max_rad_s"] - r["omega_min_rad_s"]
    omega_mid = 0.5 * (r["omega_max_rad_s"] + r["omega_min_rad_s"])
    range_txt, range_printed = printed(t, omega_range)
    mid_txt, mid_printed = printed(
        t, omega_mid, speed_digits(r["omega_max_rad_s"], r["omega_min_rad_s"])
    )
    mean = symbol_html("mean_angular_velocity", t.language)
    step = WorkedStep(
        "speed_irregularity",
        "<i>δ</i>",
        f"(<i>ω</i><sub>max</sub> − <i>ω</i><sub>min</sub>)/{mean}",
        f"{range_txt}/{mid_txt}",
        r["irregularity"],
        0,
        "",
        {"omega_range": range_printed, "omega_mid": mid_printed},
        significant=4,
        exact={"omega_range": omega_range, "omega_mid": omega_mid},
    )
    return worked_markup(ctx, WorkedBlock("speed_fluctuation", "", None, [step]))
