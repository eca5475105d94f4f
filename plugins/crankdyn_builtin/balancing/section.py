"""The balancing section: its conclusions in words, the letters it declares, and render."""

from __future__ import annotations

from functools import partial

from crankdyn.plugin.contracts import COUNTERWEIGHTS
from crankdyn.plugin.types import StageOutput
from crankdyn.scene import options

from .figures import MAX_MODEL_PANELS, _models_figure, models_left_out, star_figure
from .notation import circular, master_mass, newton_metres, newtons, plain_symbol, scale_symbol
from .options import LEAVE_SHARE, BalancingOptions, flies_without_shafts
from .tables import (
    NEGLIGIBLE_SHARE,
    _bay_table,
    _explorer_table,
    _masses_table,
    _means_table,
    _negligible,
    _percent_text,
    _share,
    _summary_amplitude,
    _summary_table,
    axis_text,
    coefficients_table,
    offset_couples,
    one_plane,
    share_base,
)
from .vectors import NEGLIGIBLE


def _conclude(ctx, r, left_without_means: str, no_shafts: str) -> None:
    """The section's conclusions: what stays unbalanced, which means are fitted (or, with none,
    what the crank arrangement leaves: ``left_without_means``, :func:`_left_without_means`)."""
    t = ctx.t
    unbalanced = [s for s in r["summary"] if not s["balanced"]]
    single = len(r["cylinder_labels"]) == 1
    ctx.find(_finding(t, r, unbalanced, single))
    plane = "_plane" if one_plane(r) and not single else ""
    negligible = [s for s in unbalanced if _negligible(r, s)]
    significant = [s for s in unbalanced if s not in negligible]
    first = len(ctx.conclusions)
    if significant and single:  # one cylinder: coefficients are all 1; say the forces
        amplitudes = {o["name"]: o["force_max_N"] for o in r["orders"]}
        ctx.conclude(
            t(
                "balancing.conclusion_unbalanced_single",
                items=", ".join(
                    f"{plain_symbol(s, '')} = {newtons(t, amplitudes[s['quantity'].split('_', 1)[1]])} {t('balancing.unit_N')}"
                    for s in significant
                    if s["quantity"].startswith("sum_")
                ),
            )
        )
    elif significant:
        # the amplitude, and the textbook's coefficient times the scale it divides by (C_n = |A_n|·C_I,
        # table 8.2): "ΣP_II = 9426 Н (4,000·|A_2|C_I)" multiplies out, where "ΣP_II/C_II = 4,000" beside
        # the textbook's C_II = λC_I did not; with counterweights or shafts fitted (the next
        # conclusion) these are what the crank arrangement alone leaves
        fitted = bool(r["counterweights"] or r["balance_shafts"])
        ctx.conclude(
            t(
                "balancing.conclusion_unbalanced" + ("_without_means" if fitted else ""),
                items=", ".join(_unbalanced_item(ctx, r, s) for s in significant),
            )
        )
    elif not negligible:
        ctx.conclude(t("balancing.conclusion_balanced" + plane))
    if negligible:  # not "only these" where the slave cylinders leave parts of orders too
        alone = not significant and not r.get("parts_left")
        _conclude_negligible(ctx, r, negligible, single, alone=alone)
    means = bool(r["counterweights"] or r["balance_shafts"])  # their sentence says it itself
    if r.get("rod_type") == "articulated" and len(ctx.conclusions) > first and not means:
        # what the balance stated rests on: the master cylinder's masses in every cylinder
        ctx.conclusions[-1] += " " + t(
            "balancing.conclusion_articulated",
            master=ctx.num(r["reciprocating_mass_kg"]),
            slave=ctx.num(r["slave_reciprocating_mass_kg"] or r["reciprocating_mass_kg"]),
        )
    if r["counterweights"] or r["balance_shafts"]:
        sentence = _means_sentence(t, r)
        # the negligible ones were said just before: not listed again among what stays
        residuals = [s for s in _left_unbalanced(r, unbalanced) if not _negligible(r, s)]
        if residuals and all(_summary_amplitude(r, s)[0] is not None for s in residuals):
            # what the means leave, with values: the conclusions said only what they balance
            said = sum(1 for s in _left_unbalanced(r, unbalanced) if _negligible(r, s))
            left = _left_after_means(t, r, residuals, "" if single else "Σ", negligible_said=said)
            if mass_difference_items(t, r):  # not "only ΣP_IV": the slaves' parts follow
                left += t("balancing.left_also_slave_parts")
            sentence += f" {left[:1].upper()}{left[1:]}."
        ctx.conclude(sentence)
    elif left_without_means:  # the decision the section states: no means, the mounts
        why = " " + t(no_shafts, what=_second_order_left(t, r)) if no_shafts else ""
        ctx.conclude(t("balancing.no_means_left", left=left_without_means) + why)
    if r.get("internal_moment_Nm") and not r["counterweights"]:  # they would bend the shaft
        ctx.conclude(
            t(
                "balancing.conclusion_internal_moment",
                moment=t.number_g(r["internal_moment_Nm"], 4),
                coefficient=multiple_prefix(t, r["internal_moment_coefficient"]),
            )
        )
    _conclude_slaves_and_offset(ctx, r)


def multiple_prefix(t, value: float) -> str:
    """``value`` as the factor written before a product ("1,732·"), or "" for one (C·a, not 1·C·a)."""
    text = t.number_g(value, 4)
    return "" if text == "1" else f"{text}·"


def _finding(t, r, unbalanced, single: bool) -> str:
    """The abstract's words on the balance: which resultants stay unbalanced (with the fitted
    means, if any), by their symbols ("ΣP_II, ΣP_IV") or with their values, or none; what only
    the slave cylinders leave; the couples of rods side by side on one pin."""
    left = [s for s in _left_unbalanced(r, unbalanced) if not _negligible(r, s)]
    means = _changing_means(r)
    plane = "_plane" if one_plane(r) and not single else ""
    finding = (
        t(
            "balancing.finding_unbalanced_means" if means else "balancing.finding_unbalanced",
            count=len(left),
            items=", ".join(plain_symbol(s, "" if single else "Σ") for s in left),
        )
        if left
        else t(
            ("balancing.finding_balanced_means" if means else "balancing.finding_balanced") + plane
        )
    )
    small = [s for s in _left_unbalanced(r, unbalanced) if _negligible(r, s)]
    residuals = _left_unbalanced(r, unbalanced)
    valued = residuals and all(_summary_amplitude(r, s)[0] is not None for s in residuals)
    # the negligible residuals are not results of their own: named after the others, as such
    big = (
        [s for s in residuals if not _negligible(r, s)]
        if small and len(small) < len(residuals)
        else residuals
    )
    if means and valued:
        # what the means leave, in one sentence: each residual with its value and share of C_I
        finding = _small_besides(
            t,
            r,
            _left_after_means(t, r, big, "" if single else "Σ", rest=big is not residuals),
            big,
            small,
            single,
        )
    elif valued and not single and any(s["balanced"] for s in r["summary"]):
        # no means: what the crank arrangement balances by itself, and what it leaves, with values
        finding = _small_besides(
            t, r, _left_after_means(t, r, big, "Σ", scheme=True), big, small, single
        )
    elif small:  # the abstract names them too, as the table leaves them
        finding = t(
            "balancing.finding_negligible",
            finding=finding,
            items=", ".join(plain_symbol(s, "" if single else "Σ") for s in small),
            share=_percent_text(t, small, r),
            base=share_base(small),
        )
    shaft_items = _left_without_shafts(t, r, "" if single else "Σ")
    if shaft_items:  # what the shafts take, so the counterweights alone are judged too
        gender = shaft_items[0][1] if len(shaft_items) == 1 else "many"
        finding = t(
            "balancing.finding_without_shafts"
            if r["counterweights"]
            else "balancing.finding_without_shafts_alone",
            finding=finding,
            left=t("balancing.left_" + gender),
            items=t.join_and([text for text, _ in shaft_items]),
            count=len(r["balance_shafts"]),
            n=len(shaft_items),
        )
    return _finding_couples(t, r, finding)


def _changing_means(r) -> bool:
    """Whether the balancing means change a free force or moment: counterweights that change
    none (on every crank of an in-line six) are no means the abstract's "after the means" could
    speak of, the crank arrangement balancing alone."""
    return bool(
        r["balance_shafts"] or (r["counterweights"] and not _counterweights_internal_only(r))
    )


def _finding_couples(t, r, finding: str) -> str:
    """``finding`` followed by what only the slave cylinders leave, the couples of rods side by
    side on one pin and the couple of a balance shaft beside the crankshaft, where there are any."""
    parts_left = mass_difference_items(t, r, whole_orders=False)
    if parts_left:  # the abstract names the whole orders left among the unbalanced already
        finding = t("balancing.finding_articulated", finding=finding, items=", ".join(parts_left))
    couples = rod_offset_items(t, r)
    if couples:  # forces balanced in one plane say nothing of the rods' offset
        finding = t("balancing.finding_rod_offset", finding=finding, items=", ".join(couples))
    if r.get("shaft_beside_couple_per_100mm_Nm"):  # its forces balance, not their arm
        finding = t(
            "balancing.finding_shaft_beside",
            finding=finding,
            per=newton_metres(t, r["shaft_beside_couple_per_100mm_Nm"]),
        )
    return finding


def _conclude_slaves_and_offset(ctx, r) -> None:
    """The conclusions on what only the slave cylinders leave and on the couples of rods side by
    side on one crank pin, where there are any."""
    t = ctx.t
    left_by_masses = mass_difference_items(t, r)
    if left_by_masses:
        ctx.conclude(mass_difference_sentence(t, left_by_masses))
    couples = rod_offset_items(t, r)
    if couples:
        ctx.conclude(
            t(
                "balancing.rod_offset_conclusion",
                offset=t.number_g(r["rod_offset_couples"]["offset_m"] * 1e3, 4),
                items=", ".join(couples),
            )
        )


def rod_offset_items(t, r) -> list[str]:
    """ "ΣM_I = 101 Н·м (turning against the shaft)": the couples of rods side by side on one
    crank pin that are not negligible (:func:`offset_couples`), by order."""
    items = []
    for x in offset_couples(r):
        against = x["forward_Nm"] <= 1e-9 * x["moment_Nm"]
        items.append(
            f"ΣM_{x['name']} = {t.fixed(x['moment_Nm'], 0)} {t('unit.Nm')}"
            + (f" ({t('balancing.rod_offset_backward')})" if against else "")
        )
    return items


def mass_difference_items(t, r, whole_orders: bool = True) -> list[str]:
    """What only the slave cylinders' lighter reciprocating masses leave unbalanced, as a text
    names it: whole orders ("the second-order forces ΣP_II = 219 N (3,9 % of C_I)") and parts of
    orders whose other part the means take ("the part of the first-order forces turning against
    the shaft, 391 N (6,9 % of C_I)")."""
    items = []
    for n in (r.get("orders_left_for_masses") or ()) if whole_orders else ():
        names = ["sum_" + o["name"] for o in r["orders"] if o["order"] == n]
        force = r["absolute"].get(names[0] + "_N") if names else None
        if force is None:
            continue
        name = names[0]
        items.append(
            t(
                "balancing.order_left",
                order_words=orders_in_words(t, [n]),
                symbol=plain_symbol({"quantity": name}),
                force=newtons(t, force),
                share=t.number_g(100 * force / r["first_order_N"], 2),
            )
        )
    return items + part_items(t, r.get("parts_left") or ())


def part_items(t, parts) -> list[str]:
    """Rotating parts of orders (records of ``parts_left``) as a text names them: "the part of the
    first-order forces turning against the shaft, 391 N (6,9 % of C_I)"."""
    return [
        t(
            "balancing.part_left",
            order_words=orders_in_words(t, [part["order"]]),
            sense=t("balancing.sense_" + part["sense"]),
            force=newtons(t, part["force_N"]),
            share=t.number_g(100 * part["share_of_first_order"], 2),
        )
        for part in parts
    ]


def _rod_offset_sentence(t, r) -> str:
    """The section's paragraph on the couples of rods side by side on one crank pin, or "";
    fork-and-blade rods, which work in one plane, are said to make none."""
    if r.get("rod_type") == "fork" and len(set(r.get("cylinder_bays", []))) < len(
        r.get("cylinder_labels", [])
    ):
        return t("balancing.rod_offset_fork")
    items = rod_offset_items(t, r)
    if not items:
        return ""
    couples = r["rod_offset_couples"]
    return t(
        "balancing.rod_offset" + ("_cranks" if couples["cranks"] > 1 else ""),
        offset=t.number_g(couples["offset_m"] * 1e3, 4),
        means=t(
            "balancing.rod_offset_means_"
            + (
                "shafts"
                if r["balance_shafts"]
                else "counterweights"
                if r["counterweights"]
                else "none"
            )
        ),
        taken={"given": "", "pin_width": t("balancing.rod_offset_pin_width")}.get(
            couples["offset_source"], t("balancing.rod_offset_taken")
        ),
        items=", ".join(items),
    )


def slaves_balanced_sentence(t, r) -> str:
    """The parts of the balanced orders that only the slave cylinders give but the means balance
    (a radial's co-rotating second-order part): said, so that a reader does not take them for
    the star's own; "" where there are none."""
    parts = r.get("slave_parts_balanced") or []
    if not parts:
        return ""
    large = all(part["share_of_first_order"] >= LEAVE_SHARE for part in parts)
    return _items_sentence(
        t,
        "balancing.slaves_balanced" if large else "balancing.slaves_balanced_given",
        part_items(t, parts),
    )


def mass_difference_sentence(t, items: list[str]) -> str:
    """Why what the masses' difference leaves gets no balancing means."""
    return _items_sentence(t, "balancing.mass_difference", items)


def _items_sentence(t, key: str, items: list[str]) -> str:
    """The sentence ``key`` on ``items``, listed with "and" before the last, and the pronouns
    that refer back to one item or to several."""
    return t(
        key,
        items=t("balancing.ordinals_and").join([", ".join(items[:-1]), items[-1]])
        if len(items) > 1
        else items[0],
        them=t("balancing.them_many" if len(items) > 1 else "balancing.them_one"),
        them_nom=t("balancing.them_nom_many" if len(items) > 1 else "balancing.them_nom_one"),
    )


def _conclude_negligible(ctx, r, negligible, single: bool, alone: bool) -> None:
    """ "ΣP_VI = 4,4 Н is under 1 % of C_I, negligible": after the unbalanced ones, or alone."""
    t = ctx.t
    items = []
    for item in negligible:
        value, force = _summary_amplitude(r, item)
        amplitude = newtons(t, value) if force else newton_metres(t, value)
        items.append(
            f"{plain_symbol(item, '' if single else 'Σ')} = {amplitude} "
            f"{t('balancing.unit_N') if force else t('unit.Nm')}"
        )
    moments = any(not item["quantity"].startswith("sum_") for item in negligible)
    forces = any(item["quantity"].startswith("sum_") for item in negligible)
    if moments and not forces:  # a moment is a share of C_I·a, not of a force
        reference = t("balancing.negligible_reference_moments_only")
    else:
        reference = t("balancing.negligible_reference") + (
            " " + t("balancing.negligible_reference_moment") if moments else ""
        )
    kind = "_forces_moments" if forces and moments else ("_moments" if moments else "_forces")
    # one force or moment: said in the singular, its adjectives of its gender
    one = "" if len(negligible) > 1 else "_one_" + ("moment" if moments else "force")
    if one:
        kind = ("_moment" if moments else "_force") + "_one"
    # named by their orders ("сили шостого порядку"), unless the centrifugal forces are among them
    orders = sorted({item["order"] for item in negligible})
    what = (
        t(f"balancing.negligible{kind}_of", orders=orders_in_words(t, orders), count=len(orders))
        if orders and min(orders) >= 1
        else t("balancing.negligible" + kind)
    )
    ctx.conclude(
        t(
            ("balancing.conclusion_only_negligible" if alone else "balancing.conclusion_negligible")
            + one,
            items=", ".join(items),
            percent=_percent_text(t, negligible, r),
            reference=reference,
            what=what,
        )
    )


def _left_without_shafts(t, r, sign: str) -> list[tuple[str, str]]:
    """What each order's balance shafts cancel, which counterweights alone would leave, each
    with the grammatical gender of its noun (``"masculine"``: a moment, ``"feminine"``: a force
    or a part): the order's resultant (``момент ΣM_II = 188,7 Н·м``) where shafts turn both ways,
    else the part turning against (or with) the shaft, each with its amplitude. A shaft set
    may take an order's force and its moment both (a 270° twin's first order)."""
    items = []
    for order in sorted({shaft["order"] for shaft in r["balance_shafts"]}):
        shafts = [shaft for shaft in r["balance_shafts"] if shaft["order"] == order]
        directions = {shaft["speed_ratio"] > 0 for shaft in shafts}
        parts = []  # the order's parts turning one way: its force's and its moment's
        for moment in (False, True):
            if moment and any(shaft["moment_Nm"] is None for shaft in shafts):
                continue
            value = sum(shaft["moment_Nm"] if moment else shaft["force_N"] for shaft in shafts)
            scale = r["first_order_N"] * ((r["cylinder_spacing_m"] or 1.0) if moment else 1.0)
            if value <= 1e-9 * scale:  # nothing taken (shafts against a couple: no force)
                continue
            prefix = "M_" if moment else "sum_"
            item = next(
                s for s in r["summary"] if s["order"] == order and s["quantity"].startswith(prefix)
            )
            values = {
                "symbol": plain_symbol(item, sign),
                "value": t.number_g(value, 4) if moment else newtons(t, value),
                "unit": t("unit.Nm") if moment else t("balancing.unit_N"),
            }
            if len(directions) == 2:
                key = "balancing.resultant_moment" if moment else "balancing.resultant_force"
                items.append((t(key, **values), "masculine" if moment else "feminine"))
            else:
                parts.append(values)
        if parts:
            forward = directions == {True}
            if len(parts) == 1:  # "the counter-rotating part of ΣP_I (10 199 N)"
                key = "balancing.part_forward" if forward else "balancing.part_backward"
                items.append((t(key, **parts[0]), "feminine"))
            else:  # the force's and the moment's parts named once: "… parts of ΣP_I (…) and ΣM_I (…)"
                key = "balancing.parts_forward" if forward else "balancing.parts_backward"
                named = t.join_and([t("balancing.part_value", **values) for values in parts])
                items.append((t(key, items=named), "many"))
    return items


def _small_besides(t, r, finding: str, big, small, single: bool) -> str:
    """``finding`` on the residuals ``big``, followed by the negligible ones (``small``) named as
    the rest, negligible, where ``big`` left them out."""
    if not small or any(s in big for s in small):
        return finding
    return t(
        "balancing.finding_negligible_besides" + ("_one" if len(small) == 1 else ""),
        finding=finding,
        items=t.join_and(
            f"{plain_symbol(s, '' if single else 'Σ')} = {_amplitude_text(t, r, s)}" for s in small
        ),
        share=_percent_text(t, small, r),
        base=share_base(small),
    )


def _amplitude_text(t, r, item) -> str:
    """A residual's amplitude with its unit: "4,5 Н", "13,6 Н·м"."""
    value, force = _summary_amplitude(r, item)
    if force:
        return f"{newtons(t, value)} {t('balancing.unit_N')}"
    return f"{newton_metres(t, value)} {t('unit.Nm')}"


def _left_after_means(
    t,
    r,
    residuals,
    sign: str,
    scheme: bool = False,
    negligible_said: int = 0,
    rest: bool = False,
) -> str:
    """ "after the means, only ΣP_IV = 81 Н and ΣP_VI = 1,8 Н (1,4 % and 0,03 % of C_I) stay
    unbalanced": the values and their shares of C_I (of C_I·a for a moment), in one sentence;
    with ``scheme`` (no means) what the crank arrangement balances comes first;
    ``negligible_said``: how many negligible residuals, named before, are left out (not "only");
    ``rest``: the negligible ones follow (:func:`_small_besides`), so these are not "the only"."""
    items, shares, scales = [], [], []
    for item in residuals:
        value, force = _summary_amplitude(r, item)
        amplitude = newtons(t, value) if force else newton_metres(t, value)
        unit = t("balancing.unit_N") if force else t("unit.Nm")
        items.append(f"{plain_symbol(item, sign)} = {amplitude} {unit}")
        shares.append(f"{t.number_g(100 * _share(r, item), 2)} %")
        scales.append("C_I" if force else "C_I·a")
    if len(set(scales)) == 1:
        listed = t.join_and(items)
        shares_text = t("balancing.share_of", shares=t.join_and(shares), scale=scales[0])
    else:  # forces and moments: each its own scale
        listed = t.join_and(
            f"{i} ({t('balancing.share_of', shares=s, scale=c)})"
            for i, s, c in zip(items, shares, scales, strict=True)
        )
        shares_text = ""
    listed += f" ({shares_text})" if shares_text else ""
    chosen = [] if scheme else chosen_part_items(t, r)
    if chosen:  # the part the scene chose to leave comes first, with its own value and share
        # after a list that has its own "and", joined by a comma: "A, B = 1 and C = 2 (…)"
        if len(items) > 1:
            listed = ", ".join([*chosen, listed])
        else:
            listed = t.join_and([*chosen, listed] if items else chosen)
    if scheme:
        balanced = [plain_symbol(s, sign) for s in r["summary"] if s["balanced"]]
        return t(
            "balancing.finding_left_scheme",
            count=len(items),
            items=listed,
            balanced=t.join_and(balanced),
        )
    # what the slave cylinders or the rods' offset along the pin also leave follows: these are
    # not the only residuals then
    more = bool(r.get("parts_left") or rod_offset_items(t, r))
    key = (
        "balancing.finding_left_means"
        + (
            "_parts"
            if more
            else "_negligible" + ("_one" if negligible_said == 1 else "")
            if negligible_said
            else "_plane"
            if forces_only(t, r)
            else ""
        )
        + ("_rest" if rest and not (more or negligible_said) else "")
    )
    return t(key, count=len(items) + len(chosen), items=listed)


def chosen_part_items(t, r) -> list[str]:
    """The rotating parts the scene chose to leave unbalanced (``parts_left_chosen``), as a
    list of what stays names them: "the half of the first-order force turning against the
    shaft, 4124 N (50 % of C_I)"; a part's force and its moment each where it is not nil."""
    single = len(r["cylinder_labels"]) == 1
    items = []
    for part in r.get("parts_left_chosen") or ():
        words = {
            "order_words": orders_in_words(t, [part["order"]]),
            "sense": t("balancing.sense_" + part["sense"]),
        }
        if part["share_of_first_order"] > NEGLIGIBLE_SHARE:
            items.append(
                t(
                    "balancing.part_left_chosen" + ("_single" if single else ""),
                    force=newtons(t, part["force_N"]),
                    share=t.number_g(100 * part["share_of_first_order"], 2),
                    **words,
                )
            )
        moment, a = part.get("moment_Nm"), r.get("cylinder_spacing_m")
        if moment and a and moment > NEGLIGIBLE_SHARE * r["first_order_N"] * a:
            items.append(
                t(
                    "balancing.part_left_chosen_moment",
                    moment=newton_metres(t, moment),
                    share=t.number_g(100 * moment / (r["first_order_N"] * a), 2),
                    **words,
                )
            )
    return items


def forces_only(t, r) -> bool:
    """Whether the inertia forces have no moments to speak of: all cylinders work in one plane
    across the shaft (one cylinder, a star) and no rods lie side by side along the pin."""
    return one_plane(r) and not rod_offset_items(t, r)


def _left_unbalanced(r, unbalanced) -> list:
    """The unbalanced resultants the fitted means leave: those of an order no balance shaft or
    counterweight balances (``residual.balanced_orders``; the centrifugal forces, order 0, by
    counterweights)."""
    balanced = set((r.get("residual") or {}).get("balanced_orders") or ())
    if r["counterweights"]:
        balanced.add(0)
    return [s for s in unbalanced if s["order"] not in balanced]


def _unbalanced_item(ctx, r, item) -> str:
    """ "ΣP_II = 9426 Н (4,000·|A_2|C_I)", "ΣM_I = 12,5 Н·м (0,5000·C_I·a)": an unbalanced sum's
    amplitude with the coefficient and the one-cylinder amplitude it multiplies (as table 8.2
    divides); "ΣP_II/C_II = 4,000" without an amplitude to print."""
    value, force = _summary_amplitude(r, item)
    coefficient = ctx.num(item["coefficient"], 4)
    if value is None:
        return f"{plain_symbol(item)}/{scale_symbol(item)} = {coefficient}"
    unit = ctx.t("balancing.unit_N") if force else ctx.t("unit.Nm")
    amplitude = newtons(ctx.t, value) if force else newton_metres(ctx.t, value)
    order = item[
        "order"
    ]  # 0: the centrifugal forces; A_1 = 1: the first order's amplitude is C_I itself
    # a word joiner after the bar: "(4,000·|A4|" is not parted from "CI)" at a line's end
    scale = "C" if order == 0 else "C_I" if order == 1 else f"|A_{order}|\u2060C_I"
    return f"{plain_symbol(item)} = {amplitude} {unit} ({coefficient}·{scale if force else scale + '·a'})"


def _counterweights_means(t, r) -> str:
    """The counterweights among the means: how many, and (an engine of several cranks) on whose
    webs, as the means table lists them crank by crank."""
    counterweights = r["counterweights"]
    bodies = counterweight_bodies(counterweights)
    if len(r["cylinder_labels"]) == 1:
        return t("balancing.means_counterweights", n=bodies)
    cranks = [str(cw["crank"]) for cw in counterweights]
    if len(r["crank_directions_deg"]) == 1:
        where = t("balancing.webs_single_crank")
    elif counterweights_on_every_crank(r):
        if bodies == 2 * len(cranks):  # "two on the webs of every crank (10 in all)", not "10 on"
            return t("balancing.means_counterweights_two_every", n=bodies)
        where = t("balancing.webs_every_crank")
    else:
        where = t("balancing.webs_cranks", k=len(cranks), labels=t.join_and(cranks))
    return t("balancing.means_counterweights_webs", n=bodies, cranks=where)


def counterweights_on_every_crank(r) -> bool:
    """Whether counterweights sit on the webs of every crank of a shaft of three or more cranks
    (each crank's own forces cancelled where they act, not by a couple of the end cranks')."""
    cranks = {cw["crank"] for cw in r.get("counterweights") or ()}
    return len(r["crank_directions_deg"]) > 2 and len(cranks) == len(r["crank_directions_deg"])


def counterweight_bodies(counterweights: list[dict]) -> int:
    """How many counterweights there are: the means table gives each crank's as its mass, that
    of one web's times the webs carrying one (m (m_web × 2)), so that many each."""
    return sum(
        round(cw["mass_kg"] / cw["mass_per_web_kg"]) if cw["mass_per_web_kg"] > 0 else 2
        for cw in counterweights
    )


def _means_sentence(t, r) -> str:
    """What the fitted means are, and what is balanced with them: the shafts' own orders, and
    the crank arrangement's part where it balances an order (or the centrifugal forces) alone."""
    shaft_orders = sorted({shaft["order"] for shaft in r["balance_shafts"]})
    means = []
    if r["counterweights"]:
        means.append(_counterweights_means(t, r))
    if r["balance_shafts"]:
        means.append(
            t(
                "balancing.means_shafts",
                n=len(r["balance_shafts"]),
                k=len(shaft_orders),
                orders=", ".join(map(str, shaft_orders)),
            )
        )
    balanced = r["residual"]["balanced_orders"]
    single = len(r["cylinder_labels"]) == 1
    key = "balancing.conclusion_means_single" if single else "balancing.conclusion_means"
    if single and not balanced:  # counterweights for the centrifugal force alone
        key = "balancing.conclusion_means_single_centrifugal"
    elif single and r.get("parts_left_chosen"):  # the counterweights' half of P_I alone
        key = "balancing.conclusion_means_single_left"
    what = balanced_by_means(t, r)
    if not single and not what:  # counterweights that change no free force or moment
        key = "balancing.conclusion_means_plain"
    elif r["counterweights"] and r["balance_shafts"] and _counterweights_internal_only(r):
        key = "balancing.conclusion_means_shafts"  # not "they": the counterweights balance none
    sentence = t(
        key,
        means=t("balancing.means_and").join(means),
        what=what,
        orders=", ".join(map(str, balanced)),
        orders_words=orders_in_words(t, balanced) if balanced else "",
        count=len(balanced),
        checked=t("balancing.checked_real"),
    )
    by_scheme = balanced_by_scheme(t, r)
    if by_scheme and not single:
        key = "balancing.scheme_balances" + ("_plane" if one_plane(r) else "")
        sentence += " " + t(key, what=by_scheme)
    if r.get("shaft_beside_couple_per_100mm_Nm"):  # its forces balance, not their arm
        sentence += " " + t(
            "balancing.conclusion_shaft_beside",
            per=newton_metres(t, r["shaft_beside_couple_per_100mm_Nm"]),
        )
    if r["counterweights"] and _counterweights_internal_only(r):
        sentence += " " + t("balancing.counterweights_internal")
        if r.get("internal_moment_Nm"):
            sentence += " " + t(
                "balancing.internal_moment_relieved",
                moment=t.number_g(r["internal_moment_Nm"], 4),
                coefficient=multiple_prefix(t, r["internal_moment_coefficient"]),
            )
    return sentence


#: What counterweights can balance: the centrifugal forces and the co-rotating first order, and
#: their moments.
_COUNTERWEIGHT_TARGETS = frozenset({"sum_C", "M_C", "sum_PI", "M_PI"})


def _counterweights_internal_only(r) -> bool:
    """Whether the crank arrangement balances all that counterweights could (a boxer's, an
    in-line six's): fitted counterweights then only relieve the main bearings."""
    rows = [s for s in r["summary"] if s["quantity"] in _COUNTERWEIGHT_TARGETS]
    return bool(rows) and all(s["balanced"] for s in rows)


def _fitted(r, item) -> bool:
    """Whether the fitted means take ``item`` (a row of the summary) entirely: each part of its
    remedy (counterweights, a shaft of its order) is fitted."""
    if item["balanced"] or item["remedy"] in ("self", "none"):
        return False
    shaft_orders = {shaft["order"] for shaft in r["balance_shafts"]}
    # a part the means leave (a slave cylinders' counter-rotating one) is said on its own
    taken = [part for part in item["remedy"].split("+") if not part.startswith("left_")]
    return all(
        bool(r["counterweights"]) if part == "counterweights" else item["order"] in shaft_orders
        for part in taken
    )


def balanced_by_means(t, r) -> str:
    """What the fitted means balance, in words with the symbols ("момент сил інерції другого
    порядку (ΣM_II)"): only the forces and moments the crank arrangement leaves and a fitted
    counterweight or shaft takes."""
    fitted = [s for s in r["summary"] if _fitted(r, s)]
    # an order whose other rotating part the means leave (a slave cylinders' part): only the part
    # the means take is balanced, named as such
    phrases = [_items_in_words(t, r, [s for s in fitted if "left_" not in s["remedy"]])]
    for left, key in (("left_backward", "forward"), ("left_forward", "backward")):
        parts = [s for s in fitted if left in s["remedy"]]
        if parts:
            symbols = ", ".join(plain_symbol(s, "Σ") for s in parts)
            phrases.append(t("balancing.what_parts_" + key, symbols=symbols, count=len(parts)))
    return t("balancing.means_and").join(phrase for phrase in phrases if phrase)


def balanced_by_scheme(t, r) -> str:
    """What the crank arrangement balances by itself, every order analysed (a list of the means'
    orders alone would read as the whole: a V6 whose means take the first order also has its
    ΣP_II balanced by its cranks), in words with the symbols; "" where it balances none."""
    orders = {s["order"] for s in r["summary"]}
    plane = one_plane(r)  # cylinders in one plane across the shaft: no moments to speak of
    offset = {x["order"] for x in offset_couples(r)}  # moments the rods' offset leaves
    return _items_in_words(
        t,
        r,
        [
            s
            for s in r["summary"]
            if s["balanced"]
            and s["order"] in orders
            and not ((plane or s["order"] in offset) and s["quantity"].startswith("M_"))
        ],
    )


def _items_in_words(t, r, items) -> str:
    """ "відцентрові сили та їхній момент, сили інерції першого порядку і момент сил інерції
    другого порядку (ΣC, ΣM_C, ΣP_I, ΣM_II)": summary rows grouped by order and kind."""
    if not items:
        return ""
    parts = []
    centrifugal = {s["quantity"] for s in items if s["order"] == 0}
    if centrifugal:
        kind = (
            "both" if len(centrifugal) == 2 else ("forces" if "sum_C" in centrifugal else "moment")
        )
        parts.append(t("balancing.what_centrifugal_" + kind))
    forces = sorted(
        {s["order"] for s in items if s["order"] > 0 and s["quantity"].startswith("sum_")}
    )
    moments = sorted(
        {s["order"] for s in items if s["order"] > 0 and s["quantity"].startswith("M_")}
    )
    both = [n for n in forces if n in moments]
    groups = (
        [("both", both)]
        if both and both == forces == moments
        else [("forces", forces), ("moments", moments)]
    )
    for kind, orders in groups:
        if orders:
            parts.append(
                t(
                    "balancing.what_" + kind,
                    orders_words=orders_in_words(t, orders),
                    count=len(orders),
                )
            )
    joined = (
        parts[0]
        if len(parts) == 1
        else ", ".join(parts[:-1]) + t("balancing.means_and") + parts[-1]
    )
    sign = "" if len(r["cylinder_labels"]) == 1 else "Σ"  # one cylinder's own forces: no sums
    return f"{joined} ({', '.join(plain_symbol(s, sign) for s in items)})"


def orders_in_words(t, orders) -> str:
    """ "першого і другого": the orders as ordinal words (a text writes "сили першого порядку", not
    "сили порядку 1"), the last joined by "and"; an order above ten in digits."""
    words = t("balancing.ordinals").split("|")
    named = [words[n - 1] if 1 <= n <= len(words) else str(n) for n in orders]
    if not named:  # no order (counterweights for the centrifugal forces alone)
        return ""
    return (
        named[0]
        if len(named) == 1
        else ", ".join(named[:-1]) + t("balancing.ordinals_and") + named[-1]
    )


def _left_without_means(r) -> str:
    """ "ΣM_II, ΣM_IV": the resultants a crank arrangement without balancing means leaves, that
    are not negligible; "" where it leaves none (or means are fitted)."""
    if r["counterweights"] or r["balance_shafts"]:
        return ""
    unbalanced = [s for s in r["summary"] if not s["balanced"]]
    return ", ".join(plain_symbol(s) for s in unbalanced if not _negligible(r, s))


def second_order_left_by_default(ctx, r) -> str:
    """The catalog key of the sentence on why no second-order shafts are fitted, where the
    default orders (:func:`crankdyn_builtin.balancing.options.balance_orders_for`) leave a
    second-order force or moment that is not negligible: an aircraft's (its mount takes it) or
    any other engine's; "" where the scene names the means, they take the second order, or one
    cylinder's means say it themselves (``balancing.second_left_single``)."""
    scene = ctx.scene
    if scene is None or r["means_given"] or len(r["cylinder_labels"]) == 1:
        return ""
    if 2 in (r.get("residual") or {}).get("balanced_orders", ()):
        return ""
    if not _second_order_items(r):
        return ""
    return "balancing.no_shafts_aircraft" if flies_without_shafts(scene) else "balancing.no_shafts"


def _second_order_items(r) -> list:
    """The second-order resultants the cranks leave that are not negligible."""
    return [
        s for s in r["summary"] if s["order"] == 2 and not s["balanced"] and not _negligible(r, s)
    ]


def _second_order_left(t, r) -> str:
    """ "ΣP_II and ΣM_II": :func:`_second_order_items` by their symbols."""
    return t.join_and([plain_symbol(s) for s in _second_order_items(r)])


#: A pulsating moment whose plane lies within this angle of the vertical (the horizontal) is said
#: to act in the vertical (horizontal) plane, deg: the table prints the plane to 0.1°.
_PLANE_TOLERANCE_DEG = 0.05


def same_star_sentence(t, r) -> str:
    """Why an in-line engine's moments of higher orders have the first order's coefficient (an
    in-line five's ΣM_IV and ΣM_VI, a three's ΣM_II): with its cranks νξ_i repeats ξ_i or −ξ_i
    (mod 360°) at every cylinder (results key ``first_star_repeats``). "" where no order whose
    moment is not nil does."""
    sign = {item["order"]: item["sign"] for item in r.get("first_star_repeats") or ()}
    items = [
        (
            plain_symbol({"quantity": "M_" + o["name"]}),
            f"{int(o['order'])}\u202fξ_i ≡ {'' if sign[int(o['order'])] > 0 else '−'}ξ_i",
        )
        for o in r["orders"]
        if int(o["order"]) in sign
    ]
    if not items:
        return ""
    return t(
        "balancing.same_star" + ("_one" if len(items) == 1 else ""),
        moments=t.join_and([symbol for symbol, _ in items]),
        congruences=t.join_and([congruence for _, congruence in items]),
    )


def free_motion_sentence(t, r, kind: str) -> str:
    """How the engine's free forces (``kind="force"``) or moments (``"moment"``) act, in words:
    those of the coefficients table that are not negligible (:data:`NEGLIGIBLE_SHARE` of C_I, a
    moment's of C_I·a); a pulsating one along which line (a moment: in which plane; the vertical
    one rocks the engine about a transverse axis, the horizontal one swings it about the vertical
    axis), a rotating one with or against the shaft; those that act alike said together. "" where
    there are none, for one cylinder, and for a moment where all cylinders lie in one plane."""
    if len(r["cylinder_labels"]) == 1 or (kind == "moment" and one_plane(r)):
        return ""
    alike: dict[tuple[str, str, int], list[str]] = {}
    for o in r["orders"]:
        if o[f"{kind}_coefficient"] * o["amplitude_N"] < NEGLIGIBLE_SHARE * r["first_order_N"]:
            continue
        hodograph = o[f"{kind}_hodograph"]
        angle = axis_text(t, hodograph["major_axis_deg"])
        speed = max(1, int(o["order"]))  # ν·ω: the centrifugal force and order 1 turn at ω
        if circular(hodograph):
            key = f"balancing.{kind}_turns_" + hodograph["sense"] + ("_at" if speed > 1 else "")
        elif hodograph["sense"] != "line":
            key = f"balancing.{kind}_ellipse_" + hodograph["sense"]
        else:
            axis = hodograph["major_axis_deg"] % 180.0
            vertical = min(axis, 180.0 - axis) <= _PLANE_TOLERANCE_DEG
            horizontal = abs(axis - 90.0) <= _PLANE_TOLERANCE_DEG
            key = f"balancing.{kind}_line_" + (
                "vertical" if vertical else "horizontal" if horizontal else "at"
            )
        quantity = ("M_" if kind == "moment" else "sum_") + o["name"]
        # a rotating one's speed is said; pulsating ones act alike whatever their order
        said_speed = speed if key.endswith("_at") else 0
        alike.setdefault((key, angle, said_speed), []).append(plain_symbol({"quantity": quantity}))
    items = [
        t(key, symbol=t.join_and(symbols), n=len(symbols), angle=angle, speed=speed)
        for (key, angle, speed), symbols in alike.items()
    ]
    if not items:
        return ""
    one = sum(len(symbols) for symbols in alike.values()) == 1  # "The free moment ΣM_II pulsates"
    return t(f"balancing.{kind}s_motion" + ("_one" if one else ""), items="; ".join(items))


def shaft_beside_sentence(t, r) -> str:
    """A counter-rotating first-order shaft lies beside the crankshaft: the part of P_I it
    balances and its own force are equal and opposite but a distance apart, a couple rocking the
    engine about an axis parallel to the shaft (given per 100 mm, the shaft's place not being
    given); "" where no shaft leaves one (compute._shaft_beside_couple)."""
    per = r.get("shaft_beside_couple_per_100mm_Nm")
    if not per:
        return _shafts_offset_sentence(t, r)
    single = len(r["cylinder_labels"]) == 1
    return t(
        "balancing.shaft_beside_single" if single else "balancing.shaft_beside",
        force=newtons(t, r["shaft_beside_force_N"]),
        per=newton_metres(t, per),
    )


def _shafts_offset_sentence(t, r) -> str:
    """Balance shafts that leave no couple beside the crankshaft: each cancels a moment only (its
    masses' forces add up to zero: a couple acts alike wherever it is applied), or shafts of a
    pair turning in opposite directions share a force (placed symmetrically about the cylinder
    axis, their couples cancel); "" without shafts."""
    shafts = r["balance_shafts"]
    if not shafts:
        return ""
    speeds = {s["speed_ratio"] for s in shafts}
    with_force = [s for s in shafts if s["force_N"] > NEGLIGIBLE * r["first_order_N"]]
    if not with_force:
        return t("balancing.shafts_offset_couples", n=len(shafts))
    if all(-s["speed_ratio"] in speeds for s in with_force):
        return t("balancing.shafts_offset_pairs")
    return ""  # a shaft's force without a partner: its couple depends on where it is


def render(output: StageOutput, ctx) -> str | None:
    r = output.results
    star = star_figure(ctx, r)
    masses_table = _masses_table(ctx, r)
    models_figure = _models_figure(ctx, r)
    bay_table = _bay_table(ctx, r)  # numbered as the section shows them: the bay's model first
    coef_table = coefficients_table(ctx, r)
    coef_number = ctx.last_table_number if coef_table else None
    summary_table = _summary_table(ctx, r)
    means_table = _means_table(ctx, r)
    explorer_table = _explorer_table(ctx, r)
    items = mass_difference_items(ctx.t, r)
    left_without_means = _left_without_means(r)
    no_shafts = second_order_left_by_default(ctx, r)
    _conclude(ctx, r, left_without_means, no_shafts)
    return ctx.render_template(
        "sections/balancing.html.j2",
        r=r,
        every_crank=counterweights_on_every_crank(r),
        star=star,
        masses_table=masses_table,
        models_figure=models_figure,
        models_left_out=[str(order) for order in models_left_out(r)],
        model_panels=MAX_MODEL_PANELS,
        coef_number=coef_number,
        join_and=ctx.t.join_and,
        coef_table=coef_table,
        bay_table=bay_table,
        summary_table=summary_table,
        means_table=means_table,
        # counterweights the crank arrangement leaves nothing free to balance: said at their table
        counterweights_internal=bool(r["counterweights"]) and _counterweights_internal_only(r),
        explorer_table=explorer_table,
        rank_tied=_rank_tied_with_first(r.get("explorer")),
        # the internal moment's factor before C·a, as the conclusions write it
        internal_factor=(
            multiple_prefix(ctx.t, r["internal_moment_coefficient"])
            if r.get("internal_moment_Nm")
            else ""
        ),
        spacing=r["cylinder_spacing_m"],
        orders_in_words=partial(orders_in_words, ctx.t),
        mass_difference=mass_difference_sentence(ctx.t, items) if items else "",
        slaves_balanced=slaves_balanced_sentence(ctx.t, r),
        unbalanced=ctx.t(
            "balancing.unbalanced_forces"
            if forces_only(ctx.t, r)
            else "balancing.unbalanced_forces_moments"
        ),
        rod_offset=_rod_offset_sentence(ctx.t, r),
        # the rods' couples the section gives (not negligible): "the couples given above"
        offset_shown=bool(offset_couples(r)),
        shaft_beside=shaft_beside_sentence(ctx.t, r),
        free_motion=" ".join(
            filter(
                None,
                [free_motion_sentence(ctx.t, r, kind) for kind in ("force", "moment")]
                + [same_star_sentence(ctx.t, r)],
            )
        ),
        master_mass=master_mass(ctx.t, r),  # plain text: the equation's markup is the template's
        masses_where=ctx.t(
            "balancing.masses_own"
            if r.get("rod_type") == "articulated"
            else "balancing.masses_equal"
        ),
        left_without_means=left_without_means,
        # the negligible residuals the crank arrangement leaves ("ΣP_VI"), named where it is said
        # to balance the free forces and moments
        small_left=", ".join(
            plain_symbol(s, "Σ") for s in r["summary"] if not s["balanced"] and _negligible(r, s)
        ),
        no_shafts=ctx.t(no_shafts, what=_second_order_left(ctx.t, r)) if no_shafts else "",
        means_what=balanced_by_means(ctx.t, r)
        if r["counterweights"] or r["balance_shafts"]
        else "",
    )


def _rank_tied_with_first(explorer) -> bool:
    """Whether the assignment's firing order, ranked below the first, balances exactly as well
    (the first's mirror order, 1-4-2-6-3-5 beside 1-5-3-6-2-4): "2nd of 120" alone reads worse."""
    if not explorer or not explorer.get("scene") or not explorer.get("rows"):
        return False
    if explorer.get("scene_rank") in (None, 1):
        return False
    own, first = explorer["scene"]["coefficients"], explorer["rows"][0]["coefficients"]
    return own.keys() == first.keys() and all(
        abs(own[k] - first[k]) <= 1e-9 * max(1.0, abs(first[k])) for k in own
    )


def taken_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The radii of the means' masses the calculation takes where it fits means whose radius the
    scene does not give: the counterweights' at R, the balance shafts' at R/2."""
    opts = options(scene, "balancing", BalancingOptions)
    fitted = ctx.data(COUNTERWEIGHTS)
    if fitted is None:
        return []
    t, mm = ctx.t, ctx.t("unit.mm")
    radius_mm = scene.engine.crank_radius_m * 1e3
    rows = []
    if fitted.fitted and opts.counterweight_radius is None:
        rows.append((t("balancing.input_counterweight_radius"), "", t.number_g(radius_mm, 4), mm))
    if fitted.balance_shafts and opts.balance_shaft_radius is None:
        one = "_one" if fitted.balance_shafts == 1 else ""
        label = t("balancing.input_balance_shaft_radius" + one)
        rows.append((label, "", t.number_g(radius_mm / 2, 4), mm))
    return rows


def input_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The [balancing] table's given sizes for the report's table of the task's data: the radii
    of the counterweights' and balance-shaft masses' centres and the rods' offset along the pin,
    where the scene gives them (a default it leaves is no datum of the task)."""
    opts = options(scene, "balancing", BalancingOptions)
    t, mm = ctx.t, ctx.t("unit.mm")
    fitted = ctx.data(COUNTERWEIGHTS)
    # one balance shaft fitted (a single's counter-rotating one, a twin's): its masses, singular
    one_shaft = fitted is not None and fitted.balance_shafts == 1
    rows = []
    for key in ("counterweight_radius", "balance_shaft_radius", "rod_offset"):
        value = getattr(opts, key)
        if value is not None:
            label = f"balancing.input_{key}" + (
                "_one" if key == "balance_shaft_radius" and one_shaft else ""
            )
            # a radius of means the calculation did not fit: said, or the table reads as if it had
            unused = fitted is not None and (
                (key == "counterweight_radius" and not fitted.fitted)
                or (key == "balance_shaft_radius" and fitted.balance_shafts == 0)
            )
            text = t(label) + (" " + t(f"balancing.{key}_unused") if unused else "")
            rows.append((text, "", t.number_g(value * 1e3, 4), mm))
    if opts.first_order_backward == "left":  # a choice of the assignment's, as the radii are
        rows.append((t("balancing.input_first_order_backward"), "", t("balancing.input_left"), ""))
    return rows
