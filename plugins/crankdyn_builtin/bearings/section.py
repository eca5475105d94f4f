"""The ``bearings`` stage's section: ``render``, the tables and the conclusions of its text."""

from __future__ import annotations

from markupsafe import Markup

from crankdyn.physics import bearings as brg
from crankdyn.plugin.contracts import COUNTERWEIGHTS
from crankdyn.plugin.scene_inputs import engine_layout
from crankdyn.plugin.types import StageOutput, Symbol
from crankdyn.scene import options
from crankdyn_builtin.bearings.worked import (
    journal_name,
    loads_equal,
    most_loaded,
    pin_rows,
    rod_rows,
    worked_bearing,
)

from .compute import _dimensions, main_pressure_verdict, pin_pressure_within_limits
from .figures import _polar_diagrams, _shared_pins, _side_by_side, _unrolled_figure, _wear_figure
from .options import BearingOptions


def oil_hole_printed(diagram: dict) -> float:
    """The oil hole's angle as the note prints it, in whole degrees of [0, 360): 359,7° is 0°."""
    return float(round(diagram["oil_hole_deg"]) % 360)


def _load_range(ctx, kind: str, load: dict, name) -> str:
    """What a load diagram shows, in a sentence: the load's range over the cycle and its mean."""
    if "min_crank_angle_deg" not in load:
        return ""
    t = ctx.t
    return t(
        f"bearings.range_{kind}",
        name=name,
        min=t.fixed(load["min_N"] / 1e3, 2),
        max=t.fixed(load["max_N"] / 1e3, 2),
        mean=t.fixed(load["mean_N"] / 1e3, 2),
        min_angle=ctx.angle_text(load["min_crank_angle_deg"]),
        max_angle=ctx.angle_text(load["max_crank_angle_deg"]),
    )


def render(output: StageOutput, ctx) -> str | None:
    r = output.results
    f = output.tables.arrays("bearings")
    angle = f["crank_angle_deg"]
    single = len(r["crank_pins"]) == 1  # one crank: no neighbouring cranks, no choice of crank pin
    figures = _side_by_side(_polar_diagrams(ctx, r, f, angle, single))
    figures.append(_wear_figure(ctx, output.tables.arrays("wear"), r))
    figures.append(_unrolled_figure(ctx, f, r, angle, single))
    table_pins = _pins_table(ctx, r, single)
    if r.get("rod_bearings_per_pin"):
        table_pins += _rods_table(ctx, r)
    table_journals, journals_table_number = _journals_table(ctx, r, single)
    table_journals += worked_bearing(ctx, r, "journal")
    # identical cylinders on cranks of their own: the same load on every pin, shifted in phase
    pins_equal = loads_equal(r["crank_pins"])
    _conclude(ctx, r, single, pins_equal, journals_table_number)
    journal_names = ", ".join(journal_name(r["main_journals"][j - 1]) for j in r["drawn_journals"])
    loaded = centrifugal_journal(r)
    return ctx.render_template(
        "sections/bearings.html.j2",
        r=r,
        figures=figures,
        table_pins=table_pins,
        analysis=_load_ranges(ctx, r, single),
        table_journals=table_journals,
        dims=r["dimensions"],
        shared_pins=_shared_pins(ctx, r),
        # the rods on one crank pin (the engine's cylinders shared equally by its pins)
        rods_per_pin=ctx.scene.engine.cylinders // len(r["crank_pins"]) if ctx.scene else 1,
        single=single,
        journal_names=journal_names,
        pins_equal=pins_equal,
        application=ctx.scene.engine.application if ctx.scene is not None else None,
        other_applications=OTHER_APPLICATIONS,
        rolling=_rolling_supports(ctx.scene),
        rolling_loads=_rolling_loads(ctx, r) if _rolling_supports(ctx.scene) else {},
        centrifugal=None if loaded is None else _centrifugal_params(ctx, r, loaded),
        pressure_within=_pressure_within(ctx, r),
        main_pressure=_main_pressure(ctx, r),
        master_rod_mass=MASTER_ROD_MASS.get(ctx.t.language, MASTER_ROD_MASS["en"]),
    )


#: The master rod's rotating part (with the slave rods' shares) as the section writes it.
MASTER_ROD_MASS = {
    "en": "<i>m</i><sub>rR.m</sub>",
    "uk": "<i>m</i><sub>rR.гол</sub>",
    "ru": "<i>m</i><sub>rR.гл</sub>",
}


def _pressure_within(ctx, r) -> str:
    """The sentence that the big-end bearings' pressures are within the allowable ones of the
    engine's kind (the plausibility rule speaks where they are not); "" otherwise."""
    if ctx.scene is None:
        return ""
    within = pin_pressure_within_limits(ctx.scene, r)
    if within is None:
        return ""
    return ctx.t(
        f"bearings.pin_pressure_within_{within['kind']}",
        p_mean=ctx.t.fixed(within["p_mean"], 2),
        p_max=ctx.t.fixed(within["p_max"], 2),
        mean_limit=ctx.t.number_g(within["mean_limit"], 3),
        max_limit=ctx.t.number_g(within["max_limit"], 3),
    )


def _main_pressure_params(ctx, verdict: dict, journals: list[dict]) -> dict:
    """The main bearings' pressures and allowable ones as the journals' table prints them."""
    t = ctx.t
    return {
        "p_mean": t.fixed(verdict["p_mean"], 2),
        "p_max": t.fixed(verdict["p_max"], 2),
        **_journals_at(ctx, verdict, journals),
        "mean_limit": t.number_g(verdict["mean_limit"], 3),
        "max_limit": t.number_g(verdict["max_limit"], 3),
        "engines": t(f"bearings.engines_{verdict['kind']}"),
        "exceeded": t(f"bearings.exceeded_{verdict['exceeded']}") if verdict["exceeded"] else "",
        "area_needed": ctx.num(verdict["area_needed_m2"] * 1e6),
    }


def _journals_at(ctx, verdict: dict, journals: list[dict]) -> dict:
    """The journals of the largest mean and of the largest pressure, each after its pressure
    (``mean_at``, ``max_at``, with a leading space), once after the second where they are one;
    every journal whose pressure the table prints alike is named (an in-line five's 2–3 and
    3–4), not the first of them alone."""
    t = ctx.t

    def alike(key: str, value: float) -> list[str]:
        return [journal_name(j) for j in journals if t.fixed(j[key], 2) == t.fixed(value, 2)]

    mean_labels = alike("mean_MPa", verdict["p_mean"]) or [journal_name(verdict["mean_journal"])]
    max_labels = alike("max_MPa", verdict["p_max"]) or [journal_name(verdict["max_journal"])]

    def at(labels: list[str], both: bool = False) -> str:
        key = "bearings.journal_at" + ("_both" if both else "")
        if len(labels) == 1:
            return " " + t(key, label=labels[0])
        return " " + t(key + "_many", labels=t.join_and(labels))

    if mean_labels == max_labels:
        return {"mean_at": "", "max_at": at(max_labels, both=True)}
    return {"mean_at": at(mean_labels), "max_at": at(max_labels)}


def _main_pressure(ctx, r) -> str:
    """The sentence comparing the main bearings' largest mean and peak pressures with the
    allowable ones of the engine's kind, with the journal's d·B they need where they exceed."""
    verdict = None if ctx.scene is None else main_pressure_verdict(ctx.scene, r)
    if verdict is None:
        return ""
    params = _main_pressure_params(ctx, verdict, r["main_journals"])
    if not verdict["exceeded"]:
        return ctx.t("bearings.main_pressure_within", **params)
    sizes = r["dimensions"]
    diameter_m = sizes["main_journal_diameter_m"]
    # sizes assumed from typical ratios: the verdict is said to rest on them
    assumed = {"main_journal_diameter", "main_journal_width"} & set(sizes.get("defaulted", ()))
    prefix = (
        ctx.t(
            "bearings.main_pressure_assumed",
            diameter=ctx.t.number_g(diameter_m * 1e3, 4),
            width=ctx.t.number_g(sizes["main_journal_width_m"] * 1e3, 4),
        )
        + " "
        if assumed
        else ""
    )
    suffix = _centrifugal_suffix(r, verdict)
    return (
        prefix
        + ctx.t(
            "bearings.main_pressure_above" + suffix,
            **params,
            diameter=ctx.t.number_g(diameter_m * 1e3, 4),
            width_needed=ctx.num(verdict["area_needed_m2"] / diameter_m * 1e3),
        )
        + _none_fitted(ctx, suffix)
    )


def _none_fitted(ctx, suffix: str) -> str:
    """Where counterweights are asked for the main bearings and the balancing section fitted
    none (the free forces need none), the sentence that says so (with a leading space); ""."""
    if not suffix or ctx.data(COUNTERWEIGHTS) is None:
        return ""
    return (
        "" if ctx.data(COUNTERWEIGHTS).fitted else " " + ctx.t("bearings.counterweights_not_fitted")
    )


def _centrifugal_suffix(r, verdict: dict) -> str:
    """ "_centrifugal" where the journal of the largest mean pressure is loaded chiefly by the
    neighbouring cranks' centrifugal forces (:func:`centrifugal_journal`): counterweights, which
    would take that load off, are the remedy before a larger journal (a V12's journal needed a
    width that left no room for its webs)."""
    loaded = centrifugal_journal(r)
    return "_centrifugal" if loaded is not None and loaded is verdict["mean_journal"] else ""


def _pressure_conclusion(ctx, r) -> str:
    """The conclusion on the bearings' pressures: the big-end bearings' where they are within the
    allowable ones (the plausibility rule concludes where they are not), the main bearings'
    within or above theirs, with the digits the tables print."""
    if ctx.scene is None:
        return ""
    t = ctx.t
    sentences = []
    pin = pin_pressure_within_limits(ctx.scene, r)
    if pin is not None:
        sentences.append(
            t(
                "bearings.conclusion_pin_pressure_within",
                p_mean=t.fixed(pin["p_mean"], 2),
                p_max=t.fixed(pin["p_max"], 2),
                mean_limit=t.number_g(pin["mean_limit"], 3),
                max_limit=t.number_g(pin["max_limit"], 3),
                engines=t(f"bearings.engines_{pin['kind']}"),
            )
        )
    verdict = main_pressure_verdict(ctx.scene, r)
    if verdict is not None:
        suffix = _centrifugal_suffix(r, verdict) if verdict["exceeded"] else ""
        key = "above" + suffix if verdict["exceeded"] else "within"
        sentences.append(
            t(
                f"bearings.conclusion_main_pressure_{key}",
                **_main_pressure_params(ctx, verdict, r["main_journals"]),
            )
            + _none_fitted(ctx, suffix)
        )
    return " ".join(sentences)


def _pins_table(ctx, r, single: bool) -> str:
    """The crank pins' loads, pressures and oil holes, with their worked substitutions; with
    several big-end bearings side by side on a pin, the pins' loads and oil holes only (each
    bearing's pressure is its own rod's: :func:`_rods_table`)."""
    t = ctx.t
    pins, pin_labels = pin_rows(r["crank_pins"])
    side_by_side = bool(r.get("rod_bearings_per_pin"))
    pressures = [
        ("<i>p</i><sub>max</sub>, " + t("unit.MPa"), [p["max_MPa"] for p in pins], 2),
        ("<i>p</i><sub>mean</sub>, " + t("unit.MPa"), [p["mean_MPa"] for p in pins], 2),
    ]
    caption = "bearings.pins_table_caption_single" if single else "bearings.pins_table_caption"
    table = ctx.table(
        [
            # one crank pin: no column naming it
            *([] if single else [(t("bearings.crank"), pin_labels, None)]),
            ("<i>Q</i><sub>max</sub>, " + t("unit.kN"), [p["max_N"] / 1e3 for p in pins], 2),
            ("<i>Q</i><sub>mean</sub>, " + t("unit.kN"), [p["mean_N"] / 1e3 for p in pins], 2),
            *([] if side_by_side else pressures),
            (t("bearings.oil_hole"), [oil_hole_printed(p) for p in pins], 0),
        ],
        caption=t(caption + ("_shared" if side_by_side else "")),
        see=("bearings.see_pins_single" if single else "bearings.see_pins")
        + ("_shared" if side_by_side else ""),
    )
    return table if side_by_side else table + worked_bearing(ctx, r, "pin")


def _rods_table(ctx, r) -> str:
    """The big-end bearings side by side on the pins: each one's own rod's load and pressure over
    its own width, with the worked substitution of the most loaded one."""
    t = ctx.t
    rods, labels = rod_rows(r["rod_bearings"], ctx.t.cylinder)
    width_mm = r["rod_bearings"][0]["width_m"] * 1e3
    return (
        ctx.table(
            [
                (t("bearings.cylinder"), labels, None),
                ("<i>Q</i><sub>max</sub>, " + t("unit.kN"), [x["max_N"] / 1e3 for x in rods], 2),
                ("<i>Q</i><sub>mean</sub>, " + t("unit.kN"), [x["mean_N"] / 1e3 for x in rods], 2),
                ("<i>p</i><sub>max</sub>, " + t("unit.MPa"), [x["max_MPa"] for x in rods], 2),
                ("<i>p</i><sub>mean</sub>, " + t("unit.MPa"), [x["mean_MPa"] for x in rods], 2),
            ],
            caption=t("bearings.rods_table_caption", width=t.number_g(width_mm, 4)),
            see="bearings.see_rods",
        )
        + worked_bearing(ctx, r, "rod")
        + _rod_above_pin(ctx, r)
    )


def _rod_above_pin(ctx, r) -> str:
    """Where one rod's bearing carries more than the pin does from all its rods (a diesel's
    firing rod while its neighbour's inertia pulls the other way): why, as a paragraph; "" else."""
    rod = max(x["max_N"] for x in r["rod_bearings"])
    pin = max(x["max_N"] for x in r["crank_pins"])
    if round(rod / 1e3, 2) <= round(pin / 1e3, 2):  # as the tables print them, in kN
        return ""
    text = ctx.t(
        "bearings.rod_above_pin", rod=ctx.t.fixed(rod / 1e3, 2), pin=ctx.t.fixed(pin / 1e3, 2)
    )
    return Markup("<p>{}</p>").format(text)


def _journals_table(ctx, r, single: bool) -> tuple[str, str]:
    """(the main journals' loads, pressures and oil holes, the table's number)."""
    t = ctx.t
    journals = r["main_journals"]
    table = ctx.table(
        [
            (t("bearings.journal"), [journal_name(j) for j in journals], None),
            ("<i>R</i><sub>max</sub>, " + t("unit.kN"), [j["max_N"] / 1e3 for j in journals], 2),
            ("<i>R</i><sub>mean</sub>, " + t("unit.kN"), [j["mean_N"] / 1e3 for j in journals], 2),
            ("<i>p</i><sub>max</sub>, " + t("unit.MPa"), [j["max_MPa"] for j in journals], 2),
            ("<i>p</i><sub>mean</sub>, " + t("unit.MPa"), [j["mean_MPa"] for j in journals], 2),
            (t("bearings.oil_hole"), [oil_hole_printed(j) for j in journals], 0),
        ],
        caption=t(
            "bearings.journals_table_caption_single"
            if single  # no preceding crank
            else "bearings.journals_table_caption"
        ),
        see="bearings.see_journals",
    )
    return table, ctx.last_table_number


#: A main journal whose mean load is at least this share the cranks' unbalanced centrifugal
#: forces is said to be loaded chiefly by them.
CENTRIFUGAL_SHARE = 0.5


def centrifugal_journal(r: dict) -> dict | None:
    """The main journal of the largest mean load when the cranks' centrifugal forces, not
    balanced by counterweights on its two neighbouring cranks, give at least
    :data:`CENTRIFUGAL_SHARE` of it; else None (the steady centrifugal load shows in the mean,
    not in the peak, which the gas forces set). A journal carries its neighbouring cranks' loads
    only (a statically determinate shaft), so counterweights elsewhere do not relieve it."""
    journals = r["main_journals"]
    if len(journals) < 3:
        return None
    journal = mean_loaded(journals)
    index = next(j for j, other in enumerate(journals) if other is journal)
    if {index, index + 1} & set(r.get("counterweight_cranks", [])):
        return None
    if journal.get("centrifugal_N", 0.0) < CENTRIFUGAL_SHARE * journal["mean_N"]:
        return None
    return journal


def mean_loaded(journals: list[dict]) -> dict:
    """The main journal of the largest mean load (the first of equal ones, to the printed kN)."""
    return mean_loaded_all(journals)[0]


def mean_loaded_all(journals: list[dict]) -> list[dict]:
    """The main journals of the largest mean load, to the printed kN, in the table's order."""
    top = max(round(j["mean_N"] / 1e3, 2) for j in journals)
    return [j for j in journals if round(j["mean_N"] / 1e3, 2) == top]


def _centrifugal_params(ctx, r: dict, journal: dict) -> dict:
    others = [journal_name(j) for j in mean_loaded_all(r["main_journals"]) if j is not journal]
    return {
        "label": journal_name(journal),
        # journals the table prints alike are named with it (an in-line five's 2–3 and 3–4)
        "alike": ctx.t("bearings.journal_alike", n=len(others), others=ctx.t.join_and(others))
        if others
        else "",
        "centrifugal": ctx.num(journal["centrifugal_N"] / 1e3),
        "mean": ctx.t.fixed(journal["mean_N"] / 1e3, 2),  # as the journals' table prints it
        "share": ctx.num(100 * journal["centrifugal_N"] / journal["mean_N"], 2),
        "c": ctx.num(r["crank_centrifugal_N"] / 1e3),
    }


def _conclude(ctx, r, single: bool, pins_equal: bool, journals_table_number) -> None:
    """The finding and the conclusion: the drawn crank pin's and the most loaded journal's loads,
    pressures and oil holes, with the digits the tables print."""
    t = ctx.t
    pin = r["crank_pins"][r["drawn_pins"][0] - 1]
    # the digits of the crank pins' table, as the conclusion gives them
    ctx.find(t("bearings.finding", q_max=t.fixed(pin["max_N"] / 1e3, 2)))
    rolling = _rolling_supports(ctx.scene)
    if rolling:  # said before the plain-bearing verdicts, which it makes a guide only
        ctx.conclude(t("bearings.conclusion_" + rolling, **_rolling_loads(ctx, r)))
    # the digits of table 7.1, which the conclusion repeats
    conclusion = (
        "bearings.conclusion_single"
        if single
        else "bearings.conclusion_equal"
        if pins_equal
        else "bearings.conclusion"
    )
    tied = most_loaded(r["main_journals"])
    journal = tied[0]
    journal_key = (
        "bearings.conclusion_journal_equal"
        if loads_equal(r["main_journals"])
        else "bearings.conclusion_journal_tied"
        if len(tied) > 1
        else "bearings.conclusion_journal"
    )
    side_by_side = bool(r.get("rod_bearings_per_pin"))
    ctx.conclude(
        t(
            conclusion + ("_shared" if side_by_side else ""),
            k=pin["crank"],
            q_max=ctx.t.fixed(pin["max_N"] / 1e3, 2),
            p_mean=ctx.t.fixed(pin["mean_MPa"], 2),
            oil=ctx.t.fixed(oil_hole_printed(pin), 0),
        )  # as the tables print it
        + " "
        + (_rod_conclusion(ctx, r) + " " if side_by_side else "")
        + t(
            journal_key,
            label=journal_name(journal),
            labels=t.join_and([journal_name(j) for j in tied]),
            r_max=ctx.t.fixed(journal["max_N"] / 1e3, 2),
            p_mean=ctx.t.fixed(journal["mean_MPa"], 2),
            oil=ctx.t.fixed(oil_hole_printed(journal), 0),
            table=journals_table_number,
        )
    )
    by_mean = mean_loaded_all(r["main_journals"])
    if all(m is not j for m in by_mean for j in tied) and not loads_equal(r["main_journals"]):
        # the peak and the mean pick different journals (a steady centrifugal load): both said;
        # journals that print alike (an in-line five's 2–3 and 3–4) are named together
        printed = {
            (ctx.t.fixed(j["max_N"] / 1e3, 2), ctx.t.fixed(j["mean_MPa"], 2)) for j in by_mean
        }
        alike = len(by_mean) > 1 and len(printed) == 1
        first = max(by_mean, key=lambda j: j["max_N"])
        ctx.conclude(
            t(
                "bearings.conclusion_journal_mean_tied"
                if alike
                else "bearings.conclusion_journal_mean",
                label=journal_name(first),
                labels=t.join_and([journal_name(j) for j in by_mean]),
                r_max=ctx.t.fixed(first["max_N"] / 1e3, 2),
                p_mean=ctx.t.fixed(first["mean_MPa"], 2),
            )
        )
    loaded = centrifugal_journal(r)
    if loaded is not None:
        ctx.conclude(t("bearings.conclusion_centrifugal", **_centrifugal_params(ctx, r, loaded)))
    pressures = _pressure_conclusion(ctx, r)
    # another engine than a car's or a tractor's: said before the verdicts it qualifies, which
    # then read as what those pressures would need
    guided = "" if rolling or not pressures else _guided_application(ctx, r)
    if guided:
        ctx.conclude(guided)
    if pressures:
        ctx.conclude(pressures)


#: The applications whose engines the car and tractor engines' allowable pressures only guide.
OTHER_APPLICATIONS = ("stationary", "marine", "outboard", "aircraft", "motorcycle")


def _guided_application(ctx, r) -> str:
    """Where this engine is not a car or tractor engine (and runs on plain bearings), the
    conclusion that the car and tractor engines' allowable pressures of its verdicts only guide
    it; "" otherwise."""
    scene, t = ctx.scene, ctx.t
    if scene is None or not (r.get("crank_pins") or r.get("main_journals")):
        return ""
    application = scene.engine.application
    if application not in OTHER_APPLICATIONS:
        return ""
    return t("bearings.conclusion_allowables_guide", kind=t(f"bearings.application_{application}"))


def _rolling_supports(scene) -> str | None:
    """Why the engine's supports are usually rolling bearings, as a catalog key's ending: a small
    spark-ignition two-stroke (crankcase scavenging; its one big end in the singular) or a
    radial aircraft engine; None otherwise."""
    if scene is None:
        return None
    if scene.engine.strokes == 2 and scene.cycle is not None and scene.cycle.ignition == "spark":
        return "two_stroke_rolling_single" if scene.engine.cylinders == 1 else "two_stroke_rolling"
    radial = scene.engine.layout == "radial"  # a flat or in-line aircraft engine runs on plain ones
    return "aircraft_supports" if scene.engine.application == "aircraft" and radial else None


def _rolling_loads(ctx, r) -> dict:
    """The largest mean equivalent loads of rolling bearings (kN, as the tables print loads) at
    the big ends and at the main supports (``rod``, ``main``)."""

    def largest(bearings: list[dict]) -> str:
        return ctx.t.fixed(max(b["rolling_equivalent_N"] for b in bearings) / 1e3, 2)

    return {"rod": largest(r["rod_bearings"]), "main": largest(r["main_bearings"])}


def _rod_conclusion(ctx, r) -> str:
    """The most loaded big-end bearing of those side by side on the pins: its own rod's largest
    load and its mean pressure, with the digits its table prints."""
    tied = most_loaded(r["rod_bearings"])
    rod = tied[0]
    two = ctx.scene is not None and ctx.scene.engine.cylinders == 2  # "both", not "all"
    return ctx.t(
        ("bearings.conclusion_rod_equal" + ("_two" if two else ""))
        if loads_equal(r["rod_bearings"])
        else "bearings.conclusion_rod",
        cylinder=ctx.t.cylinder(rod["cylinder"]),
        q_max=ctx.t.fixed(rod["max_N"] / 1e3, 2),
        p_mean=ctx.t.fixed(rod["mean_MPa"], 2),
    )


def _load_ranges(ctx, r, single: bool) -> str:
    """What the drawn pins' and journals' diagrams show, a sentence each."""
    analysis = [
        _load_range(ctx, "pin_single" if single else "pin", r["crank_pins"][k - 1], k)
        for k in r["drawn_pins"]
    ]
    analysis += [
        _load_range(
            ctx, "journal", r["main_journals"][j - 1], journal_name(r["main_journals"][j - 1])
        )
        for j in r["drawn_journals"]
    ]
    return " ".join(a for a in analysis if a)


#: The crank's angle from the cylinder axis of an offset crank-slider and the axes of the bearing
#: diagrams (symbol.bearings.<key>).
_ROD = {"en": "r", "uk": "ш", "ru": "ш"}
SYMBOLS = {
    "axis_crank_angle": Symbol("φ", {}, "°"),
    "rod_axis_z": Symbol("z", _ROD, ""),
    "rod_axis_t": Symbol("t", _ROD, ""),
    "frame_axis_y": Symbol("y", {}, ""),
    "frame_axis_x": Symbol("x", {}, ""),
    # articulated rods: the master rod's rotating part with the slave rods' shares (the forces
    # section's m_rR is one rod's)
    "master_rod_rotating_mass": Symbol(
        "m", {"en": "rR.m", "uk": "rR.гол", "ru": "rR.гл"}, "unit.kg"
    ),
    # one crank between two journals: its load formula for crank 1, the only one
    "crank_span_one": Symbol("l", {"en": "1"}, "unit.mm", html="<i>l</i><sub>1</sub>"),
    "span_before_one": Symbol("l", {"en": "1"}, "unit.mm", html="<i>l</i>′<sub>1</sub>"),
    "span_after_one": Symbol("l", {"en": "1"}, "unit.mm", html="<i>l</i>″<sub>1</sub>"),
    "crank_force_one": Symbol("F", {"en": "1"}, "unit.MPa", html="<b><i>F</i></b><sub>1</sub>"),
    "crank_t_unit_one": Symbol("e", {"en": "t"}, "", html="<b>e</b><sub><i>t</i></sub>"),
    "crank_z_unit_one": Symbol("e", {"en": "z"}, "", html="<b>e</b><sub><i>z</i></sub>"),
    "journal_load_first": Symbol(
        "R", {"en": "0–1"}, "unit.MPa", html="<b><i>R</i></b><sub>0–1</sub>"
    ),
    "journal_load_second": Symbol(
        "R", {"en": "1–2"}, "unit.MPa", html="<b><i>R</i></b><sub>1–2</sub>"
    ),
    # a rolling bearing's life check (where the supports are usually rolling bearings)
    "rolling_mean_load": Symbol("P", {"en": "m"}, "unit.kN"),
    "rolling_angles": Symbol("n", {"en": "α"}, ""),
    "rolling_load_rating": Symbol("C", {"en": "r"}, "unit.kN"),
    "rolling_life": Symbol("L", {"en": "10"}, ""),
}


#: The journal sizes a scene may give ([bearings]), in the order table 1.1 lists them.
_SIZES = ("crank_pin_diameter", "crank_pin_width", "main_journal_diameter", "main_journal_width")


def input_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The journal sizes the scene gives, for the report's table of the task's data."""
    return _size_rows(scene, ctx, given=True)


def taken_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The journal sizes the calculation takes from the typical proportions (the scene gives
    none of them), for the table of the values taken."""
    return _size_rows(scene, ctx, given=False)


def _size_rows(scene, ctx, given: bool) -> list[tuple[str, str, str, str]]:
    opts = options(scene, "bearings", BearingOptions)
    layout = engine_layout(scene)
    rods_per_pin = brg.big_end_bearings_on_pin(scene.engine.rod_type, layout.cylinders_per_bay)
    sizes = dict(zip(_SIZES, _dimensions(scene, opts, rods_per_pin)[:4], strict=True))
    t = ctx.t
    return [
        (t(f"bearings.input_{name}"), "", t.number_g(sizes[name] * 1e3, 4), t("unit.mm"))
        for name in _SIZES
        if (getattr(opts, name) is not None) == given
    ]
