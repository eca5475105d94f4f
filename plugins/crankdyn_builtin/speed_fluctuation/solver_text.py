"""How the speed-fluctuation section and its figures write the solver studies: the table of the
runs, a tolerance in scientific notation or as a power of ten, the digits that differ."""

from __future__ import annotations

import math

from crankdyn.report.i18n import superscript


def _solver_table(ctx, records, caption, see, twist=False):
    t = ctx.t
    rows = [r for r in records if not r.get("reference")]
    columns = [
        (t("speed_fluctuation.col_method"), [r["method"] for r in rows], None),
        (
            t("speed_fluctuation.col_rtol"),
            [
                _sci(r["rtol"], t.decimal_separator).replace("1,0·", "").replace("1.0·", "")
                for r in rows
            ],
            None,
        ),
        (t("speed_fluctuation.col_steps"), [_steps_text(ctx, r) for r in rows], None),
        (t("speed_fluctuation.col_nfev"), [str(r["nfev"]) for r in rows], None),
        (t("speed_fluctuation.col_njev"), [f"{r['njev']}/{r['nlu']}" for r in rows], None),
        (t("speed_fluctuation.col_time"), [r["time_s"] * 1e3 for r in rows], 1),
        (
            t("speed_fluctuation.col_error"),
            [_error_text(ctx, r["error_relative"]) for r in rows],
            None,
        ),
    ]
    if twist:
        columns.append(
            (
                t("speed_fluctuation.col_error_twist"),
                [_error_text(ctx, r.get("error_twist_relative")) for r in rows],
                None,
            )
        )
    return ctx.table(columns, caption=caption, see=see)


def _steps_text(ctx, r):
    if r["success"]:
        return str(r["steps"])
    if r["steps_needed"] is None:
        return "—"
    return ctx.t(
        "speed_fluctuation.steps_stopped",
        steps=r["steps"],
        percent=ctx.num(100 * r["progress"], 2),
        needed=ctx.num(r["steps_needed"], 2),
    )


def _error_text(ctx, value):
    return _sci(value, ctx.t.decimal_separator)


def _sci(value, separator: str = ".") -> str:
    """1.2·10⁻⁵ style for errors and tolerances in the text (— when missing)."""
    if value is None or not math.isfinite(value):
        return "—"
    if value == 0:
        return "0"
    mantissa, exponent = f"{value:.1e}".split("e")
    return f"{mantissa.replace('.', separator)}·10{superscript(int(exponent))}".replace("-", "−")


def _power_of_ten(value: float, t) -> str:
    """A tolerance as a figure label: ``10⁻³`` (Unicode superscripts), never ``1e-03``."""
    exponent = math.log10(value) if value > 0 else float("nan")
    if math.isfinite(exponent) and abs(exponent - round(exponent)) < 1e-9:
        return f"10{superscript(int(round(exponent)))}"
    return t.number_g(value, 2)


def _digits_that_differ(relative: float, least: int = 4, most: int = 8) -> int:
    """Significant digits that show two values a relative difference apart as different: two
    beyond the first that differs ("δ = 0,0100014, the energy method 0,0100000 (0,014 %)"),
    where four digits printed 0,01000 twice beside a difference."""
    if not relative or not math.isfinite(relative):
        return least
    return int(min(most, max(least, math.ceil(-math.log10(abs(relative))) + 2)))
