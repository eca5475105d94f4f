"""The tables of the balancing section: masses, coefficients, the bays, the summary, the balancing
means and the firing-order explorer."""

from __future__ import annotations

import math

from markupsafe import Markup

from crankdyn.physics import balancing as bal
from crankdyn.plugin.scene_inputs import power_take_off
from crankdyn_builtin.balancing.worked import worked_balancing

from .notation import C_N, circular, master_mass, newton_metres, newtons, summary_symbol
from .vectors import NEGLIGIBLE


def _offset_masses_table(ctx, r):
    """An offset crank-slider's masses, force amplitudes and the acceleration's harmonics as
    amplitude |A_n| and phase psi_n (its series has sine terms and odd orders), of every order
    the section analyses."""
    t = ctx.t
    unit_n = " " + t("balancing.unit_N")
    named = {bal_order(name): name for name in r["acceleration_harmonics"]}
    orders = [named[o["order"]] for o in r["orders"] if o["order"] in named]
    names = [t("balancing.m_s"), t("balancing.m_R")] + [
        Markup(x)
        for x in (
            "<i>C</i> = <i>m</i><sub>R</sub><i>Rω</i><sup>2</sup>",
            "<i>C</i><sub>I</sub> = <i>m</i><sub>s</sub><i>Rω</i><sup>2</sup>",
            "<i>C</i><sub>II</sub> = <i>λC</i><sub>I</sub>",
        )
    ]
    names += [Markup(f"|<i>A</i><sub>{bal_order(n)}</sub>|") for n in orders]
    values = [
        ctx.num(r["reciprocating_mass_kg"], 5) + " " + t("unit.kg"),
        ctx.num(r["rotating_mass_kg"], 5) + " " + t("unit.kg"),
        ctx.num(r["centrifugal_N"]) + unit_n,
        ctx.num(r["first_order_N"]) + unit_n,
        ctx.num(r["second_order_N"]) + unit_n,
    ]
    values += [ctx.num(r["acceleration_harmonics"][n], 4) for n in orders]
    phases = [""] * 5 + [t.fixed(r["acceleration_harmonic_phases_deg"][n], 2) for n in orders]
    table = ctx.table(
        [
            (t("balancing.quantity"), names, None),
            (t("balancing.value"), values, None),
            (Markup(t("balancing.phase") + " <i>ψ</i><sub><i>ν</i></sub>, °"), phases, None),
        ],
        caption=t("balancing.masses_caption"),
        see="balancing.see_masses",
    )
    return table + worked_balancing(ctx, r)


def bal_order(name: str) -> int:
    """The order a Roman numeral of :func:`crankdyn.physics.balancing.roman` names."""
    return {v: k for k, v in bal.ROMAN.items()}.get(name) or int(name)


def _harmonic(t, value: float) -> str:
    """A_ν as the masses table prints it: to six decimals, three significant digits below them
    (A_8 of a usual λ is a few 10⁻⁷)."""
    return t.fixed(value, 6) if abs(value) >= 5e-6 else t.number_g(value, 3)


def _masses_table(ctx, r):
    """Masses, inertia-force amplitudes and acceleration harmonics."""
    if r.get("offset_ratio"):
        return _offset_masses_table(ctx, r)
    t = ctx.t
    # articulated rods: the master cylinder's mass, with the slave rods' shares, its own letter
    master = r.get("slave_reciprocating_mass_kg") is not None
    m_s = master_mass(t, r)
    # A_ν of every even order the section analyses (2, 4, 6 by default; 8 where the scene asks)
    orders = [
        o["order"]
        for o in r["orders"]
        if o["order"] >= 2 and bal.roman(o["order"]) in r["acceleration_harmonics"]
    ] or [2, 4, 6]
    numerals = [bal.roman(n) for n in orders]
    series = r.get("acceleration_series", {})
    masses_table = ctx.table(
        [
            (
                t("balancing.quantity"),
                [t("balancing.m_s_master" if master else "balancing.m_s"), t("balancing.m_R")]
                + [
                    Markup(x)
                    for x in (
                        "<i>C</i> = <i>m</i><sub>R</sub><i>Rω</i><sup>2</sup>",
                        "<i>C</i><sub>I</sub> = " + m_s + "<i>Rω</i><sup>2</sup>",
                        "<i>C</i><sub>II</sub> = <i>λC</i><sub>I</sub>",
                        *(f"<i>A</i><sub>{n}</sub>" for n in orders),
                    )
                ],
                None,
            ),
            (
                t("balancing.value"),
                [
                    t.number_g(r["reciprocating_mass_kg"], 5) + " " + t("unit.kg"),
                    t.number_g(r["rotating_mass_kg"], 5) + " " + t("unit.kg"),
                    ctx.num(r["centrifugal_N"]) + " " + t("balancing.unit_N"),
                    ctx.num(r["first_order_N"]) + " " + t("balancing.unit_N"),
                    ctx.num(r["second_order_N"]) + " " + t("balancing.unit_N"),
                    # one column's decimals: six, as A_2 needs for its four digits beyond λ
                    *(_harmonic(t, r["acceleration_harmonics"][n]) for n in numerals),
                ],
                None,
            ),
            (
                t("balancing.series"),
                [
                    "",
                    "",
                    "",
                    "",
                    "",
                    *(_harmonic(t, series[n]) if n in series else "—" for n in numerals),
                ],
                None,
            ),
        ],
        caption=t("balancing.masses_caption"),
        see="balancing.see_masses",
    )
    return masses_table + worked_balancing(ctx, r)


def one_plane(r) -> bool:
    """All cylinders on one crank (one cylinder, a single-row radial or star): their forces act in
    one plane, so there are no longitudinal moments to tabulate."""
    return len(set(r["cylinder_bays"])) == 1


def coefficients_table(ctx, r):
    """Force and moment coefficients of every order with their hodographs."""
    t = ctx.t
    single = len(r["cylinder_labels"]) == 1  # one cylinder: no moments, no sums
    columns = _force_columns(ctx, r, single)
    if not one_plane(r):
        columns += _moment_columns(ctx, r)
    # a column with a dash in every row (the hodographs of forces the crank arrangement cancels
    # in every order: an in-line five's) says nothing
    columns = [c for c in columns if not all(isinstance(v, str) and v == "—" for v in c[1])]
    return ctx.table(
        columns,
        caption=t(
            "balancing.coefficients_caption_single"
            if one_plane(r)
            else "balancing.coefficients_caption"
        ),
        css_class="data wide",
        see="balancing.see_forces_single"
        if single
        else "balancing.see_coefficients_single"
        if one_plane(r)
        else "balancing.see_coefficients",
    )


def _order_name(o):
    return Markup("<i>C</i>" if o["order"] == 0 else "<i>P</i><sub>" + o["name"][1:] + "</sub>")


def _order_label(o):
    """A row of an engine's resultants: its order as a Roman numeral, C for the rotating masses."""
    return Markup("<i>C</i>" if o["order"] == 0 else o["name"][1:])


def _zero(r, o, kind) -> bool:
    """Whether an order's force or moment coefficient is nil (below rounding for all cylinders)."""
    return o[f"{kind}_coefficient"] <= NEGLIGIBLE * len(r["cylinder_labels"])


def _force_columns(ctx, r, single: bool) -> list[tuple]:
    """The coefficients table's force columns: coefficient, amplitude, hodograph, its axis, its
    motion."""
    t, orders = ctx.t, r["orders"]
    columns = [
        # one cylinder's own forces by their symbols; an engine's resultants (of forces and of
        # moments alike) by their order, C for the rotating masses' (the symbol list's P_ν is one
        # cylinder's force)
        (
            t("balancing.order" if single else "balancing.order_heading"),
            [_order_name(o) if single else _order_label(o) for o in orders],
            None,
        ),
        # one cylinder's largest force is C_ν itself in every order: no ratio to tabulate; the
        # headers in words: P and M alone name other quantities in this section (the bay model's P)
        *(
            []
            if single
            else [
                (
                    t("balancing.head_resultant_force_ratio", scale=C_N),
                    [o["force_coefficient"] for o in orders],
                    4,
                )
            ]
        ),
        (
            t("balancing.head_force_max" if single else "balancing.head_resultant_force")
            + ", "
            + t("balancing.unit_N"),
            [newtons(ctx.t, o["force_max_N"]) for o in orders],
            None,
        ),
        (
            t("balancing.hodograph_axes", scale=C_N),
            [
                "—"
                if _zero(r, o, "force")
                else f"{ctx.t.fixed(o['force_hodograph']['semi_major'] / o['amplitude_N'], 3)} / "
                f"{ctx.t.fixed(o['force_hodograph']['semi_minor'] / o['amplitude_N'], 3)}"
                for o in orders
            ],
            None,
        ),
        (
            t("balancing.major_axis"),
            [
                "—"
                if _zero(r, o, "force") or circular(o["force_hodograph"])
                else axis_text(ctx.t, o["force_hodograph"]["major_axis_deg"])
                for o in orders
            ],
            None,
        ),
        (
            t("balancing.sense"),
            [
                "—"
                if _zero(r, o, "force")
                else t("balancing.sense_" + o["force_hodograph"]["sense"])
                for o in orders
            ],
            None,
        ),
    ]
    return columns


def axis_text(t, axis_deg: float) -> str:
    """An axis's direction from the vertical as the table prints it, to 0.1°: an axis has no
    sense, so 179.99° is the vertical, "0,0" (not "180,0" beside another order's "0,0")."""
    return t.fixed(round(axis_deg % 180.0, 1) % 180.0, 1)


def _moment_columns(ctx, r) -> list[tuple]:
    """The coefficients table's moment columns (cranks in several planes)."""
    t, orders = ctx.t, r["orders"]
    return [
        (
            t("balancing.head_resultant_moment_ratio", scale=f"({C_N}<i>a</i>)"),
            [o["moment_coefficient"] for o in orders],
            4,
        ),
        (
            t("balancing.head_resultant_moment") + ", " + t("unit.Nm"),
            [
                "—" if o["moment_max_Nm"] is None else newton_metres(ctx.t, o["moment_max_Nm"])
                for o in orders
            ],
            None,
        ),
        (
            t("balancing.moment_plane"),
            [
                # a moment turning with or against the shaft at constant size has no plane
                "—"
                if _zero(r, o, "moment") or circular(o["moment_hodograph"])
                else axis_text(ctx.t, o["moment_hodograph"]["major_axis_deg"])
                for o in orders
            ],
            None,
        ),
    ]


def _bay_table(ctx, r):
    """The bay model (F, P, A, B, K, Z) of a V/W/Y/X/radial bay; None for one cylinder a bay."""
    t = ctx.t
    bay_table = None
    plane = "_plane" if one_plane(r) else ""
    if r["bay_model"] is not None:
        bm = r["bay_model"]

        def show(v):  # one row of coefficients in units of C_I: four decimals each
            return (
                ctx.t.fixed(v, 4)
                if not isinstance(v, dict)
                else f"{ctx.t.fixed(v['magnitude'], 4)} ∠{ctx.t.fixed(v['angle_deg'], 1)}°"
            )

        heads = (
            "<i>F</i>/<i>C</i><sub>I</sub>",
            "<i>P</i>/<i>C</i><sub>I</sub>",
            "<i>a</i><sub>e,I</sub>/<i>C</i><sub>I</sub>",
            "<i>b</i><sub>e,I</sub>/<i>C</i><sub>I</sub>",
            # the exact second-order amplitude A_2 C_I (C_II is the textbook's λC_I)
            "<i>K</i>/(<i>A</i><sub>2</sub><i>C</i><sub>I</sub>)",
            "<i>Z</i>/(<i>A</i><sub>2</sub><i>C</i><sub>I</sub>)",
            "<i>a</i><sub>e,II</sub>/(<i>A</i><sub>2</sub><i>C</i><sub>I</sub>)",
            "<i>b</i><sub>e,II</sub>/(<i>A</i><sub>2</sub><i>C</i><sub>I</sub>)",
        )
        keys = ("F", "P", "A_I", "B_I", "K", "Z", "A_II", "B_II")
        bay_table = ctx.table(
            [(h, [show(bm[k])], None) for h, k in zip(heads, keys, strict=True)],
            # all cylinders on one crank: the model is the crank's, no bay among several
            caption=t("balancing.bay_caption" + plane),
            see="balancing.see_bay" + plane,
        )

    return bay_table


def _summary_table(ctx, r):
    """What is balanced by itself and what each balancing means takes."""
    t = ctx.t
    rows = r["summary"]
    single = len(r["cylinder_labels"]) == 1
    if one_plane(r):  # forces in the plane of one crank: no moments (nor in the caption)
        rows = [s for s in rows if not s["quantity"].startswith("M_")]
    # a moment the crank arrangement balances with each crank's cylinders in its plane, which
    # the rods' offset along the pin leaves (the paragraph after the table gives it)
    offset = {x["order"] for x in offset_couples(r)}
    offset_rows = [
        s for s in rows if s["quantity"].startswith("M_") and s["order"] in offset and s["balanced"]
    ]
    summary_table = ctx.table(
        [
            (
                t("balancing.quantity"),
                [summary_symbol(s, "" if single else "Σ") for s in rows],
                None,
            ),
            # one cylinder leaves every force whole and unbalanced: no coefficient or state to give
            *(
                []
                if single
                else [
                    (t("balancing.coefficient"), [s["coefficient"] for s in rows], 4),
                    (
                        t("balancing.state"),
                        [
                            t("balancing.balanced") if s["balanced"] else t("balancing.unbalanced")
                            for s in rows
                        ],
                        None,
                    ),
                ]
            ),
            (
                t("balancing.remedy"),
                [
                    _remedy_text(
                        t,
                        s["remedy"],
                        one_plane(r),
                        _equal_pair(r, s["order"]),
                        couple=s["quantity"].startswith("M_"),
                        order=s["order"],
                    )
                    + (t("balancing.remedy_in_crank_planes") if s in offset_rows else "")
                    # left unbalanced and too small to matter: the conclusions say so too
                    + (
                        t("balancing.remedy_negligible")
                        if s["remedy"] == "none" and _negligible(r, s)
                        else ""
                    )
                    for s in rows
                ],
                None,
            ),
        ],
        caption=t(
            "balancing.summary_caption_single"
            if single
            else "balancing.summary_caption_forces"
            if one_plane(r)
            else "balancing.summary_caption"
        ),
        see="balancing.see_summary_single" if single else "balancing.see_summary",
    )

    return summary_table


#: An unbalanced resultant under this share of one cylinder's first-order inertia force C_I
#: (a moment: of C_I·a, a the cylinder spacing; a rod offset's couple: of C_I·b, b the offset)
#: is said to be negligible, not listed among the unbalanced ones ("ΣP_VI = 4,4 Н" beside
#: ΣP_II = 9426 Н is no finding).
NEGLIGIBLE_SHARE = 0.01


def _summary_amplitude(r, item) -> tuple[float | None, bool]:
    """(amplitude of an item of the summary: N for a force, N·m for a moment, None where the
    results have none; whether it is a force)."""
    force = item["quantity"].startswith("sum_")
    return r["absolute"].get(item["quantity"] + ("_N" if force else "_Nm")), force


def _negligible(r, item) -> bool:
    """Whether ``item``'s amplitude is under :data:`NEGLIGIBLE_SHARE` of C_I (a moment: of C_I·a)."""
    value, force = _summary_amplitude(r, item)
    scale = r["first_order_N"] * (1.0 if force else r["cylinder_spacing_m"] or 0.0)
    return value is not None and scale > 0 and abs(value) < NEGLIGIBLE_SHARE * scale


def _share(r, item) -> float:
    """``item``'s amplitude as a share of C_I (a moment: of C_I·a)."""
    return r["first_order_shares"][item["quantity"]]


def _percent_text(t, items, r) -> str:
    """The largest share of C_I among negligible ``items`` in per cent, two significant digits
    ("0,14"): the real figure, not the 1 % bound they fall under."""
    return t.number_g(100 * max(_share(r, item) for item in items), 2)


def share_base(items) -> str:
    """What the shares of :func:`_percent_text` are of: "C_I" (forces), "C_I·a" (moments) or
    both, in the catalogs' symbol notation."""
    moments = {item["quantity"].startswith("M_") for item in items}
    return {frozenset({False}): "C_I", frozenset({True}): "C_I·a"}.get(
        frozenset(moments), "C_I, C_I·a"
    )


def offset_couples(r) -> list[dict]:
    """The couples of rods side by side on one crank pin (records of ``rod_offset_couples``)
    that are not negligible (:data:`NEGLIGIBLE_SHARE` of C_I·b), by order; [] without them."""
    couples = r.get("rod_offset_couples")
    if not couples:
        return []
    limit = NEGLIGIBLE_SHARE * r["first_order_N"] * couples["offset_m"]
    return [x for x in couples["moments"] if x["moment_Nm"] >= limit]


def _equal_pair(r, order: int) -> bool:
    """Whether the two balance shafts of ``order`` (one each way) carry equal static moments: a
    Lanchester pair; a V's unequal pair is no Lanchester's mechanism."""
    moments = [
        sum(m["mass_radius_kg_m"] for m in shaft["masses"])
        for shaft in r.get("balance_shafts") or ()
        if shaft["order"] == order
    ]
    return len(moments) == 2 and math.isclose(moments[0], moments[1], rel_tol=1e-6)


def _remedy_text(
    t,
    remedy: str,
    one_crank: bool = False,
    equal_pair: bool = True,
    couple: bool = False,
    order: int = 2,
) -> str:
    """The means of one order in words: a Lanchester pair (equal shafts at twice the crank's
    speed against a second-order force; against a couple the shafts carry a mass at each end, and
    a first-order pair is no Lanchester's balancer either) named as such, several means joined by
    "і"; what balances itself is balanced by the crank arrangement, or (all cylinders on one
    crank) by the cylinders' arrangement round it."""
    parts = remedy.split("+")
    left = [t("balancing.remedy_" + part) for part in parts if part.startswith("left_")]
    means = "+".join(part for part in parts if not part.startswith("left_"))
    if means == "shaft_forward+shaft_backward":
        pair = "_couple" if couple else "" if order == 2 else "_plain"
        text = t("balancing.remedy_shaft_pair" + (pair if equal_pair else "_unequal"))
    else:
        text = t("balancing.means_and").join(
            t("balancing.remedy_" + part + ("_plane" if one_crank and part == "self" else ""))
            for part in means.split("+")
        )
    return "; ".join([text, *left])  # a part the means leave, after what they take


def _means_table(ctx, r):
    """Counterweights and balance-shaft masses; None when there are none."""
    t = ctx.t
    # one crank (one cylinder, or a radial's star): no crank numbers, ends or positions along it
    single = len(set(r["cylinder_bays"])) == 1
    means_rows = _means_rows(ctx, r, single)
    if not means_rows:
        return None
    columns = [
        (t("balancing.means"), [x[0] for x in means_rows], None),
        # counterweights alone turn with the shaft: a speed of +1 in every row says nothing
        *(
            [(t("balancing.speed_ratio"), [x[1] for x in means_rows], None)]
            if r["balance_shafts"]
            else []
        ),
        (
            t("balancing.static_moment") + ", " + t("balancing.unit_kg_mm"),
            [x[2] for x in means_rows],
            None,
        ),
        (t("balancing.head_mass") + ", " + t("unit.kg"), [x[3] for x in means_rows], None),
        (t("balancing.angle"), [x[4] for x in means_rows], None),
    ] + (
        []
        if single
        else [
            (
                t("balancing.head_distance_from_crank_1") + ", " + t("unit.mm"),
                [x[5] for x in means_rows],
                None,
            )
        ]
    )
    caption, see = _means_caption(ctx, r, single)
    return ctx.table(columns, caption=caption, css_class="data wide", see=see)


def _means_rows(ctx, r, single: bool) -> list[tuple]:
    """A row per counterweight and per balance-shaft mass: name, speed ratio, m·r, mass, angle,
    position along the shaft."""
    t = ctx.t
    means_rows = []
    positions = [cw["position_m"] for cw in r["counterweights"]] + [
        sm["position_m"] for shaft in r["balance_shafts"] for sm in shaft["masses"]
    ]
    for cw in r["counterweights"]:
        label = (
            t("balancing.counterweight_single")
            if single
            else t("balancing.counterweight", crank=cw["crank"])
        )
        means_rows.append(
            (
                label,
                "+1",
                ctx.num(cw["mass_radius_kg_m"] * 1e3, 4),
                ctx.num(cw["mass_kg"], 4)
                + f" ({ctx.num(cw['mass_per_web_kg'], 4)}\u00a0×\u00a02)",  # one unit in a narrow cell
                _angle(t, cw["angle_from_crank_deg"])
                + "° "
                + t("balancing.from_the_crank" if single else "balancing.from_crank"),
                _position(t, cw["position_m"], positions),
            )
        )
    for shaft in r["balance_shafts"]:
        for sm in shaft["masses"]:
            sense = t("balancing.shaft_" + ("forward" if shaft["speed_ratio"] > 0 else "backward"))
            means_rows.append(
                (
                    # the whole phrase: a participle agrees with the shaft (ru "вращающийся")
                    t(
                        "balancing.shaft_single_"
                        + ("forward" if shaft["speed_ratio"] > 0 else "backward"),
                        order=shaft["order"],
                    )
                    if single
                    else t(
                        "balancing.shaft",
                        order=shaft["order"],
                        sense=sense,
                        end=t("balancing.end_" + _end_name(ctx, sm["end"])),
                    ),
                    f"{shaft['speed_ratio']:+d}".replace("-", "\u2212"),
                    ctx.num(sm["mass_radius_kg_m"] * 1e3, 4),
                    ctx.num(sm["mass_kg"], 4),
                    _angle(t, sm["phase_deg"]) + "° " + t("balancing.from_vertical"),
                    _position(t, sm["position_m"], positions),
                )
            )
    return means_rows


def _angle(t, angle_deg: float) -> str:
    """A mass's angular position to 0.1°, a whole angle without its ",0" (210°, 37,5°)."""
    return t.number_g(round(angle_deg % 360.0, 1) % 360.0, 4)


def _position(t, position_m: float | None, column: list) -> str:
    """A mass's distance from crank 1, mm, with its column's decimals: whole millimetres where
    every position of the column is whole (0, 86, 172), else tenths; "—" where it has none."""
    if position_m is None:
        return "—"
    given = [1e3 * x for x in column if x is not None]
    whole = all(abs(x - round(x)) < 1e-6 for x in given)
    return t.fixed(1e3 * position_m, 0 if whole else 1)


def _means_caption(ctx, r, single: bool) -> tuple[str, str]:
    """The means table's caption (with the radii of the masses) and its announcing sentence."""
    t = ctx.t
    radii = {
        "r_cw": ctx.t.number_g(r["counterweight_radius_m"] * 1e3, 4),
        "r_sh": ctx.t.number_g(r["balance_shaft_radius_m"] * 1e3, 4),
    }
    if not r["balance_shafts"]:
        caption = t("balancing.means_caption_counterweights", **radii)
        see = (
            "balancing.see_means_counterweight"
            if len(r["counterweights"]) == 1
            else "balancing.see_means_counterweights"
        )
    elif not r["counterweights"]:
        caption = t("balancing.means_caption_shafts", shafts=len(r["balance_shafts"]), **radii)
        see = (
            "balancing.see_means_shaft"
            if len(r["balance_shafts"]) == 1
            else "balancing.see_means_shafts"
        )
    elif single:
        caption = t("balancing.means_caption_single", shafts=len(r["balance_shafts"]), **radii)
        see = "balancing.see_means_single"  # one counterweight and one or more shafts
    else:  # one shaft is said in the singular
        caption = t("balancing.means_caption_single", shafts=len(r["balance_shafts"]), **radii)
        see = (
            "balancing.see_means_one_shaft"
            if len(r["balance_shafts"]) == 1
            else "balancing.see_means"
        )
    return caption, see


def _explorer_table(ctx, r):
    """The firing-order explorer's best rows; None when not asked for."""
    t = ctx.t
    explorer_table = None
    if "explorer" in r and r["explorer"]["rows"]:
        x = r["explorer"]
        rows = x["rows"]
        explorer_table = ctx.table(
            [
                ("№", [str(c["rank"]) for c in rows], None),
                (
                    t("balancing.cranks"),
                    ["; ".join(ctx.angle_text(v) for v in c["crank_angles_deg"]) for c in rows],
                    None,
                ),
                (t("balancing.firing_order"), [t.cylinders(c["firing_order"]) for c in rows], None),
                ("Σ<i>C</i>", [c["coefficients"]["sum_C"] for c in rows], 3),
                ("Σ<i>M</i><sub>C</sub>", [c["coefficients"]["M_C"] for c in rows], 3),
                ("Σ<i>P</i><sub>I</sub>", [c["coefficients"]["sum_PI"] for c in rows], 3),
                ("Σ<i>M</i><sub>I</sub>", [c["coefficients"]["M_PI"] for c in rows], 3),
                ("Σ<i>P</i><sub>II</sub>", [c["coefficients"]["sum_PII"] for c in rows], 3),
                ("Σ<i>M</i><sub>II</sub>", [c["coefficients"]["M_PII"] for c in rows], 3),
                (t("balancing.rule_neighbours"), [str(c["neighbours"]) for c in rows], None),
                # cylinders on pins of their own (an in-line engine, a boxer): no pin is shared
                *(
                    [(t("balancing.rule_same_pin"), [str(c["same_pin"]) for c in rows], None)]
                    if r["cylinder_bays"] and len(set(r["cylinder_bays"])) < len(r["cylinder_bays"])
                    else []
                ),
                (t("balancing.rule_same_half"), [str(c["same_half"]) for c in rows], None),
            ],
            caption=t(
                "balancing.explorer_caption" + ("_all" if len(rows) == x["firing_orders"] else ""),
                n=len(rows),
                total=x["firing_orders"],
            ),
            css_class="data wide",
            see="balancing.see_explorer",
        )

    return explorer_table


def _end_name(ctx, end: str) -> str:
    """A shaft mass's end as the note names it: an aircraft engine's take-off end is its
    propeller's."""
    propeller = end == "power" and power_take_off(ctx.scene) == "propeller"
    return "propeller" if propeller else end
