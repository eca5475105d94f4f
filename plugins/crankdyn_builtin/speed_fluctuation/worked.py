"""The worked substitution of the speed-fluctuation stage: the coefficient of cyclic irregularity
from the extreme speeds the section states, δ = (ω_max − ω_min)/ω_m, ω_m = (ω_max + ω_min)/2."""

from __future__ import annotations

from markupsafe import Markup

from crankdyn.report.worked import WorkedBlock, WorkedStep, printed, worked_markup


def worked_speed_fluctuation(ctx, r) -> Markup:
    """δ with the speeds as the text prints them (6 significant digits), equal to the δ it states."""
    t = ctx.t
    hi_txt, hi = printed(t, r["omega_max_rad_s"], 6)
    lo_txt, lo = printed(t, r["omega_min_rad_s"], 6)
    step = WorkedStep(
        "speed_irregularity",
        "<i>δ</i>",
        "2(<i>ω</i><sub>max</sub> − <i>ω</i><sub>min</sub>)/(<i>ω</i><sub>max</sub> + <i>ω</i><sub>min</sub>)",
        f"2·({hi_txt} − {lo_txt})/({hi_txt} + {lo_txt})",
        r["irregularity"],
        0,
        "",
        {"omega_max": hi, "omega_min": lo},
        significant=4,
        exact={"omega_max": r["omega_max_rad_s"], "omega_min": r["omega_min_rad_s"]},
    )
    return worked_markup(ctx, WorkedBlock("speed_fluctuation", "", None, [step]))
