"""The worked substitution of the bearings stage: the largest specific pressure of the most loaded
crank pin and main journal, p_max = Q_max/(d B), each equal to its row of the results tables."""

from __future__ import annotations

from markupsafe import Markup

from crankdyn.report.typeset import journal_name as printed_journal
from crankdyn.report.worked import (
    WorkedBlock,
    WorkedStep,
    printed_fixed,
    printed_g,
    worked_markup,
)


def _pressure_step(ctx, quantity, load_html, record, key, diameter_m, width_m) -> WorkedStep:
    """p_max = load/(d B) in SI, as the where-lines give the symbols: the load as the table prints it
    (kN, ·10³ to N), the bearing's size in mm (·10⁻³ to m), the result in Pa (·10⁻⁶ to the table's MPa)."""
    t = ctx.t
    q_txt, q = printed_fixed(t, record["max_N"] / 1e3, 2)
    d_txt, d = printed_g(t, diameter_m * 1e3)  # as given, or as assumed to 0.1 mm
    b_txt, b = printed_g(t, width_m * 1e3)
    return WorkedStep(
        quantity,
        "<i>p</i><sub>max</sub>",
        f"{load_html}/(<i>d B</i>)",
        f"{q_txt}·10<sup>3</sup>/({d_txt}·10<sup>−3</sup>·{b_txt}·10<sup>−3</sup>)·10<sup>−6</sup>",
        record["max_MPa"],
        2,
        t("unit.MPa"),
        {"Q": q, "d_mm": d, "B_mm": b},
        exact={"Q": record["max_N"] / 1e3, "d_mm": diameter_m * 1e3, "B_mm": width_m * 1e3},
        row_key=key,
    )


def most_loaded(records) -> list:
    """The pins (journals) of ``records`` whose largest load is the largest to rounding (1e-9), in
    the tables' order: a tie is decided by no digit beyond the round-off."""
    peak = max(x["max_N"] for x in records)
    return [x for x in records if x["max_N"] >= peak * (1 - 1e-9)]


def journal_name(journal: dict) -> str:
    """A main journal's name as the report prints it ("0–1"; the results keep the identifier "0-1")."""
    return printed_journal(journal["journal"])


def loads_equal(records) -> bool:
    """Whether every pin (journal) of ``records`` carries the same largest load, to rounding (1e-9)."""
    return len(records) > 1 and len(most_loaded(records)) == len(records)


def pin_rows(pins: list[dict]) -> tuple[list[dict], list[str]]:
    """The pins table's rows and their crank labels: one row "1…4" for pins that print alike
    (identical cylinders, each on a crank of its own: the same loads shifted in phase), which the
    table repeated four times; an ellipsis, not the en dash of a main journal's name "1–2" (the
    journal between cranks 1 and 2), which reads the same."""
    printed = {
        (
            round(p["max_N"] / 1e3, 2),
            round(p["mean_N"] / 1e3, 2),
            round(p["max_MPa"], 2),
            round(p["mean_MPa"], 2),
            round(p["oil_hole_deg"]) % 360,
        )
        for p in pins
    }
    if len(pins) > 1 and len(printed) == 1:
        return pins[:1], [_span(str(pins[0]["crank"]), str(pins[-1]["crank"]), len(pins))]
    return pins, [str(p["crank"]) for p in pins]


def _span(first: str, last: str, count: int) -> str:
    """The first and the last of ``count`` labels a row stands for: "1…4"; two are both named,
    "1Л, 1П" (a range of two reads as if there were more between them)."""
    return f"{first}, {last}" if count == 2 else f"{first}…{last}"


def rod_rows(rods: list[dict], cylinder=str) -> tuple[list[dict], list[str]]:
    """The rod bearings table's rows and their cylinder labels as ``cylinder`` prints them (the
    translator's, "1Л"): one row "1L…4R" for bearings that print alike (identical cylinders: the
    same loads shifted in phase), as :func:`pin_rows`."""
    printed = {
        (
            round(x["max_N"] / 1e3, 2),
            round(x["mean_N"] / 1e3, 2),
            round(x["max_MPa"], 2),
            round(x["mean_MPa"], 2),
        )
        for x in rods
    }
    if len(rods) > 1 and len(printed) == 1:
        first, last = cylinder(rods[0]["cylinder"]), cylinder(rods[-1]["cylinder"])
        return rods[:1], [_span(first, last, len(rods))]
    return rods, [cylinder(x["cylinder"]) for x in rods]


def worked_bearing(ctx, r, kind: str) -> Markup:
    """After the pins table (``kind`` "pin"), the rod bearings table ("rod": several side by side
    on each pin) or the journals table ("journal"): p_max of the most loaded one."""
    dims = r["dimensions"]
    records = {"pin": r["crank_pins"], "rod": r.get("rod_bearings"), "journal": r["main_journals"]}[
        kind
    ]
    tied = most_loaded(records)
    record = tied[0]
    if kind == "pin":
        labels = pin_rows(records)[1]
        # the table's row: one "1…4" for pins that print alike
        key = labels[0] if len(labels) == 1 else str(record["crank"])
        load_html = "<i>Q</i><sub>max</sub>"
        size = dims["crank_pin_diameter_m"], dims["crank_pin_width_m"]
    elif kind == "rod":
        labels = rod_rows(records, ctx.t.cylinder)[1]
        key = labels[0] if len(labels) == 1 else ctx.t.cylinder(record["cylinder"])
        load_html = "<i>Q</i><sub>max</sub>"
        size = dims["crank_pin_diameter_m"], record["width_m"]
    else:
        key, load_html = journal_name(record), "<i>R</i><sub>max</sub>"
        size = dims["main_journal_diameter_m"], dims["main_journal_width_m"]
    step = _pressure_step(ctx, f"{kind}_pressure_max", load_html, record, key, *size)
    # "the most loaded" only where one is: a single crank pin has no rival, equal loads have no first
    variant = (
        "_single"
        if len(records) == 1
        else "_equal"
        if loads_equal(records)
        else "_tied"
        if len(tied) > 1
        else ""
    )
    if variant == "_equal" and len(records) == 2 and ctx.t.has(f"bearings.worked_{kind}_equal_two"):
        variant = "_equal_two"  # "both", not "all"
    names = {"pin": lambda x: str(x["crank"]), "rod": lambda x: ctx.t.cylinder(x["cylinder"])}
    others = ctx.t.join_and([names.get(kind, journal_name)(x) for x in tied[1:]])
    note = ctx.t(f"bearings.worked_{kind}{variant}", label=key, others=others, n=len(tied) - 1)
    return worked_markup(
        ctx, WorkedBlock("bearings", ctx.last_table_number, None, [step], note=note)
    )
