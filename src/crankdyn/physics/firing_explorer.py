"""Crank arrangements and firing orders: enumerate the even-firing ones and rank them (Poda 2007 §4.1-4.2, §6).

For a cylinder count, layout, stroke count and bank angle this module lists every crank
arrangement (lag of each crank behind crank 1) and every firing order that fire evenly,
every ``cycle/i`` degrees (textbook eq. 37-40), with cylinder 1 firing first and crank 1 as
the reference. Each firing order is scored

* by its balance (textbook §6): the coefficients ``sum_C``, ``M_C``, ``sum_PI``, ``M_PI``,
  ``sum_PII``, ``M_PII`` of :mod:`crankdyn.physics.balancing` (forces over C, C_I, C_II;
  moments further over the cylinder spacing a);
* by the firing rules of §4.2: ``neighbours`` - consecutive firings of adjacent cylinders of one
  bank (rule 2: they overload the main journal between them); ``same_pin`` - consecutive
  firings of two cylinders on one crank pin (rule 3); ``same_half`` - consecutive firings on the
  same side of the middle of the crankshaft (rule 2: "on different sides of the centre of mass").

Ranking is lexicographic, best first, by what each arrangement would cost to balance:
first the first-order unbalance that needs balance shafts (the counter-rotating parts of the
first-order force and moment), then the second order (``sum_PII + M_PII``, shafts at 2w), then
what crankshaft counterweights cure (``sum_C + M_C`` and the co-rotating first-order parts:
textbook §6.2, Q = F + C), then ``neighbours``, ``same_pin``, ``same_half``, then the firing order
itself (so the ranking is reproducible). For in-line engines the first key is just
``sum_PI + M_PI``; a 90-degree cross-plane V8 (a pure rotating couple, cured by counterweights)
ranks above the flat-plane V8 (a second-order force of 4 sqrt(2) C_II). Balance depends
only on the crank arrangement, so arrangements are ranked first and the firing orders of an
arrangement are scored only while they can still reach the requested top of the table:
for an in-line 8 that is all 5040 orders; for an in-line 12 the 1 247 400 arrangements are
scored for balance (vectorised) and only the best-balanced tiers are expanded into their
32 firing orders each (see README, "Firing-order explorer").

Counting (four-stroke, even cylinder count i per row, one crank per cylinder): the crank
angles are the i/2 multiples of 720/i, each used by two cranks; cylinder 1's crank is fixed
at 0, so there are (i-1)!/2^(i/2-1) arrangements and 2^(i/2-1) firing orders on each, i.e.
(i-1)! firing orders in all.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from . import balancing as bal
from . import layout as lay

RULE_KEYS = ("neighbours", "same_pin", "same_half")
COEFFICIENT_KEYS = ("sum_C", "M_C", "sum_PI", "M_PI", "sum_PII", "M_PII")
_TIER_TOL = 1e-7
#: Firing orders one exploration ranks and lists at most (``top``, or every one): an in-line 9
#: has 40 320; an in-line 10 (362 880) or a W24 (21 934 080) listed in full would take gigabytes.
MAX_RANKED_ORDERS = 50_000
#: Crank arrangements ((cranks − 1)! of them, crank 1 fixed) up to which a search runs with every
#: report: a scene's default firing order is taken from it, a given one compared with its best.
MAX_SEARCHED_ARRANGEMENTS = 50_000


def small_search(cranks: int) -> bool:
    """Whether the arrangements of ``cranks`` cranks are few enough to search with every report
    (:data:`MAX_SEARCHED_ARRANGEMENTS`; an in-line nine's 40 320 are, a ten's 362 880 not)."""
    return math.factorial(max(cranks - 1, 0)) <= MAX_SEARCHED_ARRANGEMENTS


class TooManyFiringOrders(ValueError):
    """More firing orders were asked for than :data:`MAX_RANKED_ORDERS`."""

    def __init__(self, firing_orders: int, wanted: int):
        super().__init__(
            f"this engine has {firing_orders:,} even-firing orders; at most "
            f"{MAX_RANKED_ORDERS:,} are ranked and listed at once"
        )
        self.firing_orders = firing_orders
        self.wanted = wanted


@dataclass(frozen=True)
class NoEvenFiring:
    """Why no crank arrangement fires evenly (or why none was searched): ``code`` one of
    ``bank_grid`` (a shared pin's bank angle off the firing grid: ``unit_deg``, ``interval_deg``),
    ``same_phase`` (cylinders on one pin would fire together), ``too_many`` (more than ``limit``
    arrangements), ``none``; ``str()`` is the English sentence."""

    code: str
    values: dict[str, float] = field(default_factory=dict)

    def __str__(self) -> str:
        v = self.values
        if self.code == "bank_grid":
            return (
                f"the bank angles must be multiples of {v['unit_deg']:g} deg for cylinders on one "
                f"crank pin to fire every {v['interval_deg']:g} deg (crankdyn models the banks on "
                "shared crank pins; split pins, one per cylinder, are not modelled)"
            )
        if self.code == "same_phase":
            return "cylinders on one crank pin would fire at the same phase"
        if self.code == "too_many":
            return (
                f"more than {int(v['limit']):,} crank arrangements: beyond an exhaustive search "
                "(see the README)"
            )
        return "no crank arrangement fires evenly"


@dataclass(frozen=True)
class Candidate:
    """One ranked firing order."""

    rank: int
    crank_angles_deg: tuple[float, ...]
    firing_order: tuple[str, ...]
    coefficients: dict[str, float]
    neighbours: int
    same_pin: int
    same_half: int


@dataclass
class Exploration:
    """Result of :func:`explore`."""

    cylinders: int
    layout: str
    strokes: int
    bank_angle_deg: float | None
    interval_deg: float
    arrangements: int = 0  # even-firing crank arrangements
    firing_orders: int = 0  # even-firing firing orders in all
    scored_firing_orders: int = 0  # firing orders whose rule scores were computed
    rows: list[Candidate] = field(default_factory=list)
    reason: NoEvenFiring | None = None  # why nothing fires evenly
    located_rank: int | None = None  # rank of the firing order passed as ``locate``
    located: Candidate | None = None


def _setup(cylinders: int, layout: str, strokes: int, bank_angle_deg: float | None):
    entries = lay.cylinder_labels(layout, cylinders)
    axes = lay.bank_axes_deg(layout, bank_angle_deg, cylinders)
    labels = [e[0] for e in entries]
    banks = np.array([e[1] for e in entries])
    bays = np.array([e[2] for e in entries])
    psi = np.array([axes[b] for b in banks], dtype=float)
    return labels, banks, bays, psi


def _phase_unit(cylinders: int, strokes: int) -> tuple[int, Fraction]:
    """(V, u): the even-firing phases mod 360 are the V multiples of u = 360/V degrees."""
    interval = Fraction(180 * strokes, cylinders)
    values = {(k * interval) % 360 for k in range(cylinders)}
    count = len(values)
    return count, Fraction(360, count)


def enumerate_arrangements(
    cylinders: int,
    layout: str,
    strokes: int,
    bank_angle_deg: float | None = None,
    limit: int = 3_000_000,
):
    """All even-firing crank arrangements as integer phase indices.

    Returns ``(lags, unit_deg, multiplicity, bank_offsets, reason)``: ``lags`` has shape
    (arrangements, cranks), crank lag = ``lags * unit_deg`` (crank 1 first, always 0);
    ``multiplicity`` is how many cylinders share each firing phase mod 360 (2 for a four-stroke
    engine with an even cylinder count, else 1). ``reason`` (:class:`NoEvenFiring`) says why there is
    none (or that there are more than ``limit``).
    """
    labels, banks, bays, psi = _setup(cylinders, layout, strokes, bank_angle_deg)
    count, unit = _phase_unit(cylinders, strokes)
    multiplicity = cylinders // count
    ratios = [Fraction(angle).limit_denominator(10**6) / unit for angle in psi.tolist()]
    refine = math.lcm(*(r.denominator for r in ratios))
    shared_pins = bool(np.any(np.bincount(bays) > 1))
    if refine != 1 and shared_pins:
        interval = float(Fraction(180 * strokes, cylinders))
        return (
            np.zeros((0, int(bays.max()) + 1), dtype=np.int16),
            float(unit),
            multiplicity,
            None,
            NoEvenFiring("bank_grid", {"unit_deg": float(unit), "interval_deg": interval}),
        )
    # A cylinder with a crank pin of its own (a boxer's) may sit at a bank angle off the firing
    # grid: its crank then turns by a fraction of the grid, so the lags are counted in the finer
    # unit unit/refine, and only every refine-th phase can take a firing.
    unit, count = unit / refine, count * refine
    capacity = np.where(np.arange(count) % refine == 0, multiplicity, 0)
    bank_offset = np.array([int(r * refine) % count for r in ratios], dtype=np.int64)
    n_bays = int(bays.max()) + 1
    increments = _bay_increments(bays, bank_offset, count)
    fits_alone = np.all(increments <= capacity, axis=2).any(axis=1)  # some lag of each bay fits
    if not np.all(fits_alone):
        return (
            np.zeros((0, n_bays), dtype=np.int16),
            float(unit),
            multiplicity,
            bank_offset,
            NoEvenFiring("same_phase"),
        )
    lags = np.zeros((1, 1), dtype=np.int16)
    counts = increments[0, 0][None, :].copy()
    too_many = (
        np.zeros((0, n_bays), dtype=np.int16),
        float(unit),
        multiplicity,
        bank_offset,
        NoEvenFiring("too_many", {"limit": float(limit)}),
    )
    for bay in range(1, n_bays):
        # Every prefix completes to at least one arrangement, so counting the next level's prefixes
        # before building them bounds the memory by ``limit`` rows.
        step = increments[bay]
        fits = [np.all(counts + step[lag] <= capacity, axis=1) for lag in range(count)]
        if sum(int(ok.sum()) for ok in fits) > limit:
            return too_many
        new_lags, new_counts = [], []
        for lag, ok in enumerate(fits):
            if np.any(ok):
                new_lags.append(
                    np.hstack([lags[ok], np.full((int(ok.sum()), 1), lag, dtype=np.int16)])
                )
                new_counts.append(counts[ok] + step[lag])
        if not new_lags:
            lags = np.zeros((0, lags.shape[1] + 1), dtype=np.int16)
            break
        lags, counts = np.vstack(new_lags), np.vstack(new_counts)
    reason = None if len(lags) else NoEvenFiring("none")
    return lags, float(unit), multiplicity, bank_offset, reason


def _bay_increments(bays: np.ndarray, bank_offset: np.ndarray, count: int) -> np.ndarray:
    """increments[bay, lag index] -> the firing-phase counts that bay's cylinders add with that
    crank lag; bays differ in their banks when a boxer puts its odd and even cylinders on
    opposite sides."""
    n_bays = int(bays.max()) + 1
    increments = np.zeros((n_bays, count, count), dtype=np.int16)
    for bay in range(n_bays):
        for lag in range(count):
            for o in bank_offset[bays == bay]:
                increments[bay, lag, (lag + o) % count] += 1
    return increments


def balance_coefficients(
    lags_deg: np.ndarray,
    psi_deg: np.ndarray,
    bays: np.ndarray,
    vertical_deg: float,
    chunk: int = 100_000,
) -> dict[str, np.ndarray]:
    """Textbook balance coefficients of many crank arrangements at once (rows of ``lags_deg``)."""
    out = {k: np.empty(len(lags_deg)) for k in COEFFICIENT_KEYS}
    for start in range(0, len(lags_deg), chunk):
        g = bal.geometry(psi_deg, bays, lags_deg[start : start + chunk], vertical_deg)
        part = slice(start, start + chunk)
        rot = bal.rotating_model(g)
        out["sum_C"][part] = np.abs(rot.force_forward)
        out["M_C"][part] = np.abs(rot.moment_forward)
        for n, name in ((1, "I"), (2, "II")):
            model = bal.reciprocating_model(g, n)
            out[f"sum_P{name}"][part] = model.force_max
            out[f"M_P{name}"][part] = model.moment_max
            if n == 1:
                for key, value in (
                    ("PI_forward", model.force_forward),
                    ("PI_backward", model.force_backward),
                    ("M_PI_forward", model.moment_forward),
                    ("M_PI_backward", model.moment_backward),
                ):
                    out.setdefault(key, np.empty(len(lags_deg)))[part] = np.abs(value)
    return out


def _balance_coefficients_indexed(
    lags: np.ndarray,
    phase: np.ndarray,
    unit_deg: float,
    count: int,
    psi_deg: np.ndarray,
    bays: np.ndarray,
    vertical_deg: float,
    chunk: int = 200_000,
) -> dict[str, np.ndarray]:
    """:func:`balance_coefficients` for phases that are whole multiples of ``unit_deg``: the unit
    vectors come from small tables instead of complex exponentials (same numbers, ~5x faster)."""
    g = bal.geometry(psi_deg, bays, np.zeros(int(bays.max()) + 1), vertical_deg)
    steps = np.radians(np.arange(count) * unit_deg)
    crank_table = np.exp(1j * (-steps - np.radians(vertical_deg)))  # crank direction by lag index
    out = {
        k: np.empty(len(lags))
        for k in COEFFICIENT_KEYS + ("PI_forward", "PI_backward", "M_PI_forward", "M_PI_backward")
    }
    for start in range(0, len(lags), chunk):
        part = slice(start, start + chunk)
        unit = crank_table[lags[part]]
        out["sum_C"][part] = np.abs(unit.sum(axis=1))
        out["M_C"][part] = np.abs(unit @ g.crank_position)
        for n, name in ((1, "I"), (2, "II")):
            forward_table = 0.5 * np.exp(1j * (g.cylinder_axis_rad[:, None] - n * steps[None, :]))
            backward_table = 0.5 * np.exp(1j * (g.cylinder_axis_rad[:, None] + n * steps[None, :]))
            cyl = np.arange(len(bays))[None, :]
            f = forward_table[cyl, phase[part]]
            b = backward_table[cyl, phase[part]]
            ff, bb = f.sum(axis=1), b.sum(axis=1)
            mf, mb = f @ g.cylinder_position, b @ g.cylinder_position
            out[f"sum_P{name}"][part] = np.abs(ff) + np.abs(bb)
            out[f"M_P{name}"][part] = np.abs(mf) + np.abs(mb)
            if n == 1:
                out["PI_forward"][part], out["PI_backward"][part] = np.abs(ff), np.abs(bb)
                out["M_PI_forward"][part], out["M_PI_backward"][part] = np.abs(mf), np.abs(mb)
    return out


def balance_scores(c: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(shafts_I, second, counterweights): what needs first-order balance shafts (the
    counter-rotating first-order force and moment, per unit C_I), the second-order unbalance
    (sum_PII + M_PII), and what crankshaft counterweights cure (sum_C + M_C and the co-rotating
    first-order parts). Lower is better in each."""
    shafts = c["PI_backward"] + c["M_PI_backward"]
    second = c["sum_PII"] + c["M_PII"]
    counterweights = c["sum_C"] + c["M_C"] + c["PI_forward"] + c["M_PI_forward"]
    return shafts, second, counterweights


def _clean(value: float) -> float:
    """Round-off (below 1e-12 of one cylinder's amplitude) shown as an exact zero."""
    return 0.0 if abs(value) < 1e-12 else float(value)


def _tiers(values: np.ndarray) -> np.ndarray:
    """Integer tiers of ``values``: equal within _TIER_TOL share a tier, lower is better."""
    if len(values) == 0:
        return np.zeros(0, dtype=int)
    order = np.argsort(values, kind="stable")
    steps = np.concatenate([[0], np.diff(values[order]) > _TIER_TOL]).cumsum()
    tiers = np.empty(len(values), dtype=int)
    tiers[order] = steps
    return tiers


def _firing_sequences(
    phase: np.ndarray, multiplicity: int, count: int, cylinders: int, strokes: int
) -> np.ndarray:
    """All firing sequences (cylinder indices in firing order) of arrangements with the given
    cylinder phase indices; shape (arrangements, orders_per_arrangement, cylinders)."""
    a = len(phase)
    if multiplicity == 1:
        if strokes == 2:
            slot = phase
        else:  # four-stroke, odd count: the phase p*u is fired at p*u or p*u + 360, whichever is a multiple of 720/i
            slot = (phase + cylinders * (phase % 2)) // 2
        seq = np.empty((a, cylinders), dtype=np.int16)
        np.put_along_axis(
            seq,
            slot.astype(np.int64),
            np.broadcast_to(np.arange(cylinders), (a, cylinders)),
            axis=1,
        )
        return seq[:, None, :]
    order = np.argsort(phase, axis=1, kind="stable").reshape(a, count, 2)
    bits = ((np.arange(2 ** (count - 1))[:, None] >> np.arange(count - 1)[None, :]) & 1).astype(
        bool
    )
    bits = np.hstack([np.zeros((len(bits), 1), dtype=bool), bits])  # phase 0: cylinder 1 first
    first = np.where(bits[None, :, :], order[:, None, :, 1], order[:, None, :, 0])
    second = np.where(bits[None, :, :], order[:, None, :, 0], order[:, None, :, 1])
    return np.concatenate([first, second], axis=2).astype(np.int16)


def _rules(seq: np.ndarray, banks: np.ndarray, bays: np.ndarray) -> dict[str, np.ndarray]:
    """Consecutive firings (cylinder indices ``seq``, cyclic) that textbook §4.2 avoids: of
    neighbouring cylinders of one bank (next to each other in the bank along the shaft: a
    boxer's bank has a cylinder on every other crank), of two cylinders on one crank pin, and of
    cylinders on the same side of the shaft's middle."""
    nxt = np.roll(seq, -1, axis=-1)
    bank_a, bank_b = banks[seq], banks[nxt]
    bay_a, bay_b = bays[seq], bays[nxt]
    middle = 0.5 * (bays.max())
    # each cylinder's place in its bank along the shaft
    place = np.empty(len(banks), dtype=np.int64)
    for bank in np.unique(banks):
        members = np.flatnonzero(banks == bank)
        place[members[np.argsort(bays[members], kind="stable")]] = np.arange(members.size)
    neighbours = ((bank_a == bank_b) & (np.abs(place[seq] - place[nxt]) == 1)).sum(axis=-1)
    same_pin = (
        ((bay_a == bay_b) & (seq != nxt)).sum(axis=-1)
        if bays.max() < len(bays) - 1
        else np.zeros(seq.shape[:-1], int)
    )
    side_a, side_b = np.sign(bay_a - middle), np.sign(bay_b - middle)
    same_half = ((side_a == side_b) & (side_a != 0)).sum(axis=-1)
    return {"neighbours": neighbours, "same_pin": same_pin, "same_half": same_half}


def explore(
    cylinders: int,
    layout: str = "inline",
    strokes: int = 4,
    bank_angle_deg: float | None = None,
    top: int | None = 10,
    locate: tuple[tuple[float, ...], tuple[str, ...]] | None = None,
) -> Exploration:
    """Enumerate and rank the even-firing crank arrangements and firing orders.

    Parameters
    ----------
    cylinders, layout, strokes, bank_angle_deg
        As in the scene's [engine] table (layout conventions of :mod:`crankdyn.physics.layout`).
    top : int or None
        Number of ranked rows to return; None ranks every firing order (each one scored).
        TooManyFiringOrders when more than :data:`MAX_RANKED_ORDERS` rows would be listed.
    locate : (crank lags in deg, firing order labels), optional
        A firing order whose rank is wanted (e.g. the scene's own).

    Returns
    -------
    Exploration
    """
    labels, banks, bays, psi = _setup(cylinders, layout, strokes, bank_angle_deg)
    result = Exploration(cylinders, layout, strokes, bank_angle_deg, 180.0 * strokes / cylinders)
    lags, unit, multiplicity, bank_offset, reason = enumerate_arrangements(
        cylinders, layout, strokes, bank_angle_deg
    )
    if reason:
        result.reason = reason
        return result
    count, per_arrangement = _count_orders(
        result, len(lags), cylinders // multiplicity, multiplicity, top
    )
    vertical = bal.vertical_axis_deg(layout, bank_angle_deg)
    # The phase of a cylinder (its TDC, mod 360) is its crank lag plus its bank angle: both whole
    # multiples of the unit, so the vector models work from small tables of unit vectors. The
    # unit may be a fraction of the firing grid (a boxer's); the firings sit on the grid.
    fine_count = round(360.0 / unit)
    phase = (lags[:, bays] + bank_offset[None, :]) % fine_count
    coefficients = _balance_coefficients_indexed(lags, phase, unit, fine_count, psi, bays, vertical)
    tier = _balance_tier(coefficients)
    scorer = _FiringScorer(
        result,
        phase // (fine_count // count),
        multiplicity,
        count,
        cylinders,
        strokes,
        banks,
        bays,
        tier,
    )
    by_tier = np.argsort(tier, kind="stable")
    groups = np.split(by_tier, np.flatnonzero(np.diff(tier[by_tier])) + 1)
    evaluated, evaluated_tiers = _evaluate_best_tiers(groups, top, scorer)

    def candidate(rank: int, rows: dict[str, np.ndarray], i: int) -> Candidate:
        """Row ``i`` of the evaluated ``rows`` as the candidate of this engine ranked ``rank``."""
        return _candidate(rank, rows, i, lags, unit, labels, coefficients)

    result.rows += _ranked_rows(evaluated, top, candidate)
    found = (
        _locate(
            locate, lags, unit, fine_count, labels, tier, groups, evaluated_tiers, scorer.evaluate
        )
        if locate is not None
        else None
    )
    if found is not None:
        rows, i, own_tier = found
        result.located_rank = int(np.sum(tier < own_tier)) * per_arrangement + i + 1
        result.located = candidate(result.located_rank, rows, i)
    return result


def _balance_tier(coefficients: dict[str, np.ndarray]) -> np.ndarray:
    """Each arrangement's balance tier: lexicographic over the balance-shaft, second-order and
    counterweight scores (:func:`balance_scores`), lower is better."""
    shafts, second, counterweights = balance_scores(coefficients)
    t1, t2, t3 = _tiers(shafts), _tiers(second), _tiers(counterweights)
    return (t1 * (int(t2.max()) + 1) + t2) * (int(t3.max()) + 1) + t3  # lexicographic


@dataclass
class _FiringScorer:
    """What scoring the firing orders of a set of arrangements needs; counts them on ``result``."""

    result: Exploration
    phase: np.ndarray
    multiplicity: int
    count: int
    cylinders: int
    strokes: int
    banks: np.ndarray
    bays: np.ndarray
    tier: np.ndarray

    def evaluate(self, members: np.ndarray) -> dict[str, np.ndarray]:
        """Every firing order of the given arrangements, with its rule scores, sorted best first."""
        cylinders = self.cylinders
        seqs = _firing_sequences(
            self.phase[members], self.multiplicity, self.count, cylinders, self.strokes
        )
        rules = _rules(seqs, self.banks, self.bays)
        self.result.scored_firing_orders += seqs.shape[0] * seqs.shape[1]
        flat: dict[str, np.ndarray] = {k: v.reshape(-1) for k, v in rules.items()}
        flat["arrangement"] = np.repeat(members, seqs.shape[1])
        flat["tier"] = self.tier[flat["arrangement"]]
        flat["sequence"] = seqs.reshape(-1, cylinders)
        keys = [flat["sequence"][:, c] for c in range(cylinders - 1, -1, -1)]
        keys += [flat["same_half"], flat["same_pin"], flat["neighbours"], flat["tier"]]
        order = np.lexsort(keys)
        return {k: v[order] for k, v in flat.items()}


def _evaluate_best_tiers(groups, top: int | None, scorer: _FiringScorer):
    """(evaluated rows of each tier, best first; the same by tier) of the best balance tiers,
    until they hold ``top`` firing orders (all of them for None)."""
    evaluated: list[dict[str, np.ndarray]] = []
    evaluated_tiers: dict[int, dict[str, np.ndarray]] = {}
    total = 0
    for members in groups:
        if top is not None and total >= top:
            break
        rows = scorer.evaluate(members)
        evaluated.append(rows)
        evaluated_tiers[int(scorer.tier[members[0]])] = rows
        total += len(rows["tier"])
    return evaluated, evaluated_tiers


def _ranked_rows(evaluated, top: int | None, candidate) -> list[Candidate]:
    """The first ``top`` (all for None) evaluated firing orders as ranked candidates."""
    ranked: list[Candidate] = []
    rank = 0
    for rows in evaluated:
        for i in range(len(rows["tier"])):
            if top is not None and rank >= top:
                break
            rank += 1
            ranked.append(candidate(rank, rows, i))
    return ranked


def _count_orders(
    result: Exploration, arrangements: int, count: int, multiplicity: int, top: int | None
) -> tuple[int, int]:
    """(count, firing orders per arrangement); the counts set on ``result``. TooManyFiringOrders
    when more than :data:`MAX_RANKED_ORDERS` rows would be ranked and listed."""
    per_arrangement = 2 ** (count - 1) if multiplicity == 2 else 1
    result.arrangements = arrangements
    result.firing_orders = arrangements * per_arrangement
    wanted = result.firing_orders if top is None else min(top, result.firing_orders)
    if wanted > MAX_RANKED_ORDERS:
        raise TooManyFiringOrders(result.firing_orders, wanted)
    return count, per_arrangement


def _candidate(
    rank: int, rows: dict[str, np.ndarray], i: int, lags, unit: float, labels, coefficients
) -> Candidate:
    """Row ``i`` of the evaluated ``rows`` as a ranked :class:`Candidate` (crank angles in deg)."""
    a = int(rows["arrangement"][i])
    return Candidate(
        rank=rank,
        crank_angles_deg=tuple(float(x) * unit for x in lags[a]),
        firing_order=tuple(labels[int(c)] for c in rows["sequence"][i]),
        coefficients={k: _clean(coefficients[k][a]) for k in COEFFICIENT_KEYS},
        neighbours=int(rows["neighbours"][i]),
        same_pin=int(rows["same_pin"][i]),
        same_half=int(rows["same_half"][i]),
    )


def _locate(locate, lags, unit: float, count: int, labels, tier, groups, evaluated_tiers, evaluate):
    """(evaluated rows of its tier, its index there, its tier) of the firing order ``locate`` =
    (crank lags in deg, firing order labels), or None when it is not an even-firing arrangement
    of this engine."""
    steps = np.array([(a % 360.0) / unit for a in locate[0]])
    if np.any(np.abs(steps - np.round(steps)) > 1e-9):  # a crank off the even-firing grid (270°)
        return None
    want = np.round(steps).astype(int) % count
    match = (
        np.nonzero(np.all(lags == want[None, :], axis=1))[0]
        if len(want) == lags.shape[1]
        else np.array([], dtype=int)
    )
    index = {label: i for i, label in enumerate(labels)}
    if not len(match) or not all(x in index for x in locate[1]):
        return None
    a = int(match[0])
    own_tier = int(tier[a])
    rows = evaluated_tiers.get(own_tier)
    if rows is None:
        rows = evaluate(groups[[int(tier[g[0]]) for g in groups].index(own_tier)])
    sequence = np.array([index[x] for x in locate[1]])
    hit = np.nonzero(
        (rows["arrangement"] == a) & np.all(rows["sequence"] == sequence[None, :], axis=1)
    )[0]
    return (rows, int(hit[0]), own_tier) if len(hit) else None


def count_firing_orders(cylinders: int) -> int:
    """Even-firing firing orders of an in-line engine, two- or four-stroke: (i - 1)! (closed form)."""
    return math.factorial(cylinders - 1)


def second_order_moment_rank(
    cylinders: int,
    layout: str,
    strokes: int,
    bank_angle_deg: float | None,
    crank_angles_deg,
    limit: int = 50_000,
) -> dict | None:
    """Where a crank arrangement's second-order moment coefficient ``M_PII`` stands among those
    of every even-firing firing order of the engine (the moment depends on the cranks only, so
    each arrangement counts with its firing orders): ``coefficient``, ``orders`` in all,
    ``larger`` and ``smaller`` (orders of a larger and a smaller moment, to :data:`_TIER_TOL`).
    None where the arrangement does not fire evenly or there are more than ``limit``
    arrangements."""
    lags, unit, multiplicity, bank_offset, reason = enumerate_arrangements(
        cylinders, layout, strokes, bank_angle_deg, limit=limit
    )
    if reason:
        return None
    _labels, _banks, bays, psi = _setup(cylinders, layout, strokes, bank_angle_deg)
    moments = balance_coefficients(
        lags.astype(float) * unit, psi, bays, bal.vertical_axis_deg(layout, bank_angle_deg)
    )["M_PII"]
    want = np.array([round((a % 360.0) / unit) % round(360.0 / unit) for a in crank_angles_deg])
    if len(want) != lags.shape[1]:
        return None
    match = np.nonzero(np.all(lags == want[None, :], axis=1))[0]
    if not len(match):
        return None
    own = float(moments[match[0]])
    count = cylinders // multiplicity
    per_arrangement = 2 ** (count - 1) if multiplicity == 2 else 1
    return {
        "coefficient": _clean(own),
        "orders": len(lags) * per_arrangement,
        "larger": int(np.sum(moments > own + _TIER_TOL)) * per_arrangement,
        "smaller": int(np.sum(moments < own - _TIER_TOL)) * per_arrangement,
    }


def better_balanced(
    cylinders: int,
    layout: str,
    strokes: int,
    bank_angle_deg: float | None,
    crank_angles_deg,
    firing_order,
) -> tuple[Candidate, tuple[str, ...]] | None:
    """(the top-ranked even-firing order, the :data:`COEFFICIENT_KEYS` it frees the engine of)
    when it frees it of a force or moment (of the centrifugal forces, of the first or second
    order) that the given crank arrangement and firing order leave, and leaves none the given one
    does not; else None.

    A firing order fixes the cranks of an engine whose cylinders each have a crank: written in
    another numbering of the cylinders (a boxer numbered by banks, not along the shaft) it
    gives another crankshaft, e.g. one with all four throws of a flat four in line.
    """
    try:
        found = explore(
            cylinders,
            layout,
            strokes,
            bank_angle_deg,
            top=1,
            locate=(tuple(crank_angles_deg), tuple(firing_order)),
        )
    except (lay.LayoutError, ValueError):
        return None
    if not found.rows or found.located is None:
        return None
    best, own = found.rows[0].coefficients, found.located.coefficients
    freed = tuple(k for k in COEFFICIENT_KEYS if own[k] > _TIER_TOL and best[k] <= _TIER_TOL)
    worse = any(best[k] > own[k] + _TIER_TOL for k in COEFFICIENT_KEYS)
    return (found.rows[0], freed) if freed and not worse else None
