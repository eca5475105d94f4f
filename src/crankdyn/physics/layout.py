"""Engine layouts: banks, bays, crank arrangement and firing order (Poda 2007 §4.1-4.2, §6).

Conventions
-----------
* Cylinders are numbered from the free end of the crankshaft; the shaft turns clockwise
  seen from that end. All angles are measured in the direction of rotation.
* Bank axis angles ``psi`` are measured from the axis of bank 0 (the master bank, "L").
  A crank that points along bank 0's axis at shaft angle 0 reaches bank b's axis at
  shaft angle ``psi_b``.
* ``crank_lag_deg[k]`` is the shaft rotation by which crank k trails crank 1: crank k
  points where crank 1 pointed ``crank_lag_deg[k]`` degrees earlier.
* ``firing_delay_deg`` of a cylinder is the shaft angle, after cylinder 1 starts its
  cycle (TDC at the start of intake for four-stroke, firing TDC for two-stroke), at
  which that cylinder starts its own cycle. Then its cycle angle is
  ``alpha_i = (theta - delay_i) mod cycle`` (textbook eq. 42-43 with
  delay = Delta alpha_0i) and, geometrically, ``delay_i = psi_i + lag_k(i)  (mod 360)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from itertools import product
from math import gcd

import numpy as np

LAYOUT_BANKS = {"inline": 1, "V": 2, "boxer": 2, "W": 3, "Y": 3, "X": 4}
BANK_LETTERS = {1: ("",), 2: ("L", "R"), 3: ("L", "C", "R"), 4: ("A", "B", "C", "D")}
#: What a refused order of a V, W or X engine is told about its banks' letters.
BANK_ORDER_HINT = (
    "; the banks are lettered in the direction of rotation (clockwise, seen from the free end): "
    "a crank reaches bank L's axis first and bank R's the bank angle later, so of two cylinders "
    "on one pin the L one fires first by the bank angle (or by it plus 360 deg)"
)
_TOL = 1e-6


class LayoutError(ValueError):
    """An inconsistent layout; ``field`` names the scene key to blame."""

    def __init__(self, field: str, value, message: str):
        super().__init__(message)
        self.field = field
        self.value = value


@dataclass(frozen=True)
class Cylinder:
    """One cylinder of the engine."""

    label: str
    bank: int
    bay: int  # crank index from the free end, 0-based
    axis_deg: float  # psi, bank axis angle from bank 0, deg
    firing_delay_deg: float  # delay after cylinder 1 starts its cycle, deg in [0, cycle)
    master: bool  # carries the master (or a central/fork) rod; False for an articulated slave


@dataclass(frozen=True)
class EngineLayout:
    """Geometry and timing of a whole engine."""

    layout: str
    strokes: int
    bank_angle_deg: float | None
    cylinders: tuple[Cylinder, ...]
    crank_lag_deg: tuple[float, ...]
    firing_order: tuple[str, ...]
    even_firing: bool

    @property
    def cycle_deg(self) -> float:
        return 180.0 * self.strokes

    @property
    def cranks(self) -> int:
        return len(self.crank_lag_deg)

    @property
    def cylinders_per_bay(self) -> int:
        return len(self.cylinders) // self.cranks

    def bay(self, k: int) -> list[Cylinder]:
        return [c for c in self.cylinders if c.bay == k]

    def firing_intervals_deg(self) -> np.ndarray:
        """Shaft angle between consecutive firings, in firing order (closing interval last)."""
        by_label = {c.label: c for c in self.cylinders}
        delays = np.array([by_label[label].firing_delay_deg for label in self.firing_order])
        return np.diff(np.append(delays, self.cycle_deg))

    @property
    def torque_period_deg(self) -> float:
        """Period of the output torque for even firing: 180*tau/i (textbook §4.3)."""
        return self.cycle_deg / len(self.cylinders)


def bank_axes_deg(layout: str, bank_angle_deg: float | None, cylinders: int) -> list[float]:
    """Axis angle of every bank (or every cylinder of a radial star) from bank 0, deg."""
    if layout == "inline":
        return [0.0]
    if layout == "radial":
        return [360.0 * k / cylinders for k in range(cylinders)]
    if layout == "boxer":
        return [0.0, 180.0]
    if bank_angle_deg is None:
        raise ValueError(f"the {layout} layout needs a bank angle")
    gamma = float(bank_angle_deg)
    if layout == "V":
        return [0.0, gamma]
    if layout in ("W", "Y"):
        return [0.0, gamma, 2.0 * gamma]
    if layout == "X":
        return [0.0, gamma, 180.0, 180.0 + gamma]
    raise LayoutError("engine.layout", layout, "unknown layout")


def cylinder_labels(layout: str, cylinders: int) -> list[tuple[str, int, int]]:
    """(label, bank, bay) of every cylinder, cylinders numbered from the free end."""
    if layout == "radial":
        return [(str(k + 1), k, 0) for k in range(cylinders)]
    banks = LAYOUT_BANKS[layout]
    if layout == "boxer" and cylinders % 2 == 0:
        # A boxer gives every cylinder its own crank pin: numbered along the shaft from the free
        # end, the odd cylinders in bank 0 and the even ones opposite them in bank 1, so that
        # neighbouring opposed pistons can move out and in together (their cranks 180° apart).
        return [(str(k + 1), k % 2, k) for k in range(cylinders)]
    if cylinders % banks:
        raise LayoutError(
            "engine.cylinders",
            cylinders,
            f"a {layout} engine has {banks} banks, so the cylinder count must be a multiple of {banks}",
        )
    bays = cylinders // banks
    if banks == 1:
        return [(str(k + 1), 0, k) for k in range(bays)]
    letters = BANK_LETTERS[banks]
    return [(f"{k + 1}{letters[b]}", b, k) for k in range(bays) for b in range(banks)]


def _normalise_label(label) -> str:
    return str(label).strip().upper().replace(" ", "")


def _check_layout_fields(
    layout: str, strokes: int, cylinders: int, bank_angle_deg: float | None, rod_type: str
) -> None:
    """Refuse (LayoutError naming the field) a bank angle that is missing, out of range or not
    applicable, an uneven-firing radial, and articulated rods on an in-line engine."""
    if layout in ("V", "W", "Y", "X"):
        if bank_angle_deg is None:
            raise LayoutError(
                "engine.bank_angle_deg",
                None,
                f"required for a {layout} engine (angle between banks)",
            )
        if layout in ("W", "Y") and not 0 < 2 * bank_angle_deg < 360:
            raise LayoutError(
                "engine.bank_angle_deg", bank_angle_deg, "must be < 180 for three banks"
            )
        if layout == "X" and not 0 < bank_angle_deg < 180:
            raise LayoutError(
                "engine.bank_angle_deg", bank_angle_deg, "must be > 0 and < 180 for an X engine"
            )
    elif bank_angle_deg is not None and layout in ("inline", "radial", "boxer"):
        raise LayoutError(
            "engine.bank_angle_deg",
            bank_angle_deg,
            f"does not apply to a {layout} engine (remove it)",
        )
    if layout == "radial" and (cylinders < 3 or cylinders % 2 == 0 and strokes == 4):
        raise LayoutError(
            "engine.cylinders",
            cylinders,
            "a four-stroke radial (one row) needs an odd number "
            "of cylinders, at least 3, for even firing",
        )
    if rod_type == "articulated" and layout in ("inline", "boxer"):
        raise LayoutError(
            "engine.rod_type",
            rod_type,
            "articulated rods need several cylinders on one crank (V, W, Y, X or radial)",
        )


def _firing_order(
    firing_order: list | None, labels: list[str], layout: str, strokes: int
) -> list[str]:
    """The firing order as normalised cylinder labels: a permutation of ``labels`` read as a cycle
    from the reference cylinder ``labels[0]`` (an order written from another cylinder is the same
    cycle); default for one cylinder and for a radial: every second cylinder."""
    cylinders = len(labels)
    if firing_order is None:
        if cylinders == 1:
            firing_order = [labels[0]]
        elif layout == "radial":
            step = 2 if strokes == 4 else 1
            firing_order = [labels[(step * k) % cylinders] for k in range(cylinders)]
        else:
            raise LayoutError(
                "engine.firing_order",
                None,
                f"required for a {cylinders}-cylinder engine; cylinder labels: {', '.join(labels)}",
            )
    order = [_normalise_label(x) for x in firing_order]
    unknown = [x for x in order if x not in labels]
    if unknown:
        raise LayoutError(
            "engine.firing_order",
            firing_order,
            f"labels {', '.join(unknown)} do not exist in this layout; labels: {', '.join(labels)}",
        )
    repeated = sorted({x for x in order if order.count(x) > 1})
    missing = [x for x in labels if x not in order]
    if repeated or missing or len(order) != cylinders:
        raise LayoutError(
            "engine.firing_order",
            firing_order,
            "must name every cylinder exactly once"
            + (f"; repeated: {', '.join(repeated)}" if repeated else "")
            + (f"; missing: {', '.join(missing)}" if missing else ""),
        )
    # The order is a cycle: written from any cylinder it is the same engine; the calculation
    # counts from the reference cylinder, so the cycle is read from there.
    start = order.index(labels[0])
    return order[start:] + order[:start]


def _shared_crank_message(first: str, other: str, psi: dict, delay: dict, interval: float) -> str:
    """Why two cylinders on one crank pin cannot fire evenly in the order given, and whether any
    order could: the bank angle fixes their spacing, and even firing needs that spacing to be a
    whole number of firing intervals (mod 360 deg)."""
    apart = (psi[other] - psi[first]) % 360
    text = (
        f"cylinders {first} and {other} share a crank, so they fire {apart:g} deg apart "
        f"(mod 360) by the bank angle, but even firing every {interval:g} deg puts them "
        f"{(delay[other] - delay[first]) % 360:g} deg apart; "
    )
    remainder = apart % interval
    if min(remainder, interval - remainder) > _TOL:
        return text + (
            f"no firing order fires evenly with this bank angle on shared crank pins (even firing "
            f"needs the bank angle to be a multiple of {interval:g} deg; an engine whose crank "
            "pins are split per cylinder fires evenly otherwise, but crankdyn models the banks on "
            "shared pins only); give crank_angles_deg with uneven_firing = true to compute the "
            "engine with shared pins"
        )
    return text + "choose another firing order, or give crank_angles_deg with uneven_firing = true"


def build_layout(
    layout: str,
    strokes: int,
    cylinders: int,
    bank_angle_deg: float | None,
    firing_order: list | None,
    crank_angles_deg: list[float] | None,
    rod_type: str = "central",
    uneven_firing: bool = False,
) -> EngineLayout:
    """Validate a layout description and derive every cylinder's bank, bay and firing delay.

    Raises LayoutError naming the scene field at fault.
    """
    cycle = 180.0 * strokes
    _check_layout_fields(layout, strokes, cylinders, bank_angle_deg, rod_type)
    axes = bank_axes_deg(layout, bank_angle_deg, cylinders)
    entries = cylinder_labels(layout, cylinders)
    labels = [e[0] for e in entries]
    bank_of = {e[0]: e[1] for e in entries}
    places = _CylinderPlaces(
        labels=labels,
        bank_of=bank_of,
        bay_of={e[0]: e[2] for e in entries},
        psi={label: axes[bank_of[label]] for label in labels},
        bays=max(e[2] for e in entries) + 1,
    )
    order = _firing_order(firing_order, labels, layout, strokes)
    firing_order = order if firing_order is None else firing_order  # the messages below quote it
    if crank_angles_deg is None:
        delay, lags = _even_firing_cranks(places, order, cycle / cylinders, firing_order)
        even = True
    else:
        delay, lags, even = _given_cranks_firing(
            places, order, cycle, crank_angles_deg, firing_order, uneven_firing
        )
    cylinders_list = tuple(
        Cylinder(
            label=lab,
            bank=bank_of[lab],
            bay=places.bay_of[lab],
            axis_deg=places.psi[lab],
            firing_delay_deg=delay[lab] % cycle,
            master=(rod_type != "articulated") or bank_of[lab] == 0,
        )
        for lab in labels
    )
    return EngineLayout(
        layout=layout,
        strokes=strokes,
        bank_angle_deg=bank_angle_deg,
        cylinders=cylinders_list,
        crank_lag_deg=tuple(lags),
        firing_order=tuple(order),
        even_firing=even,
    )


@dataclass(frozen=True)
class _CylinderPlaces:
    """Where each cylinder (by label) sits: its bank, its bay (crank) and its axis angle psi."""

    labels: list[str]
    bank_of: dict[str, int]
    bay_of: dict[str, int]
    psi: dict[str, float]
    bays: int


def _even_firing_cranks(
    places: _CylinderPlaces, order: list[str], interval: float, firing_order
) -> tuple[dict[str, float], list[float]]:
    """(firing delay of each cylinder, crank lags) of even firing every ``interval`` deg in
    ``order``; cylinders on one crank that cannot fire so raise LayoutError."""
    psi = places.psi
    delay = {label: k * interval for k, label in enumerate(order)}
    lags = []
    for bay in range(places.bays):
        members = [lab for lab in places.labels if places.bay_of[lab] == bay]
        candidates = [(delay[lab] - psi[lab]) % 360.0 for lab in members]
        if any(_angle_distance(c, candidates[0]) > _TOL for c in candidates):
            first, other = (
                members[0],
                next(
                    m
                    for m, c in zip(members, candidates, strict=True)
                    if _angle_distance(c, candidates[0]) > _TOL
                ),
            )
            raise LayoutError(
                "engine.firing_order",
                firing_order,
                _shared_crank_message(first, other, psi, delay, interval),
            )
        lags.append(candidates[0])
    return delay, lags


def _given_cranks_firing(
    places: _CylinderPlaces,
    order: list[str],
    cycle: float,
    crank_angles_deg: list[float],
    firing_order,
    uneven_firing: bool,
) -> tuple[dict[str, float], list[float], bool]:
    """(firing delay of each cylinder, crank lags from crank 1, even firing) of the given crank
    angles fired in ``order``; an order that does not fit the cranks, or uneven firing not
    declared, raises LayoutError."""
    if len(crank_angles_deg) != places.bays:
        raise LayoutError(
            "engine.crank_angles_deg",
            crank_angles_deg,
            f"must have one angle per crank: {places.bays} values, crank 1 first",
        )
    labels, psi = places.labels, places.psi
    lags = [float(a) % 360.0 for a in crank_angles_deg]
    base = (psi[labels[0]] + lags[0]) % 360.0
    geometric = {lab: (psi[lab] + lags[places.bay_of[lab]] - base) % 360.0 for lab in labels}
    delay = _crank_firing_delays(order, geometric, cycle, crank_angles_deg, firing_order)
    intervals = np.diff([delay[lab] for lab in order] + [cycle])
    even = bool(np.all(np.abs(intervals - cycle / len(labels)) < _TOL))
    lags = [(lag - lags[0]) % 360.0 for lag in lags]
    if not even and not uneven_firing:
        raise LayoutError(
            "engine.crank_angles_deg",
            crank_angles_deg,
            "gives uneven firing intervals ("
            + ", ".join(f"{x:g}" for x in intervals)
            + " deg); set engine.uneven_firing = true if that is intended",
        )
    return delay, lags, even


def _crank_firing_delays(
    order: list[str], geometric: dict[str, float], cycle: float, crank_angles_deg, firing_order
) -> dict[str, float]:
    """The firing delay of each cylinder: the next in ``order`` fires when its crank comes round
    (``geometric``: its TDC angle after the first's); an order that does not close within one
    cycle raises LayoutError."""
    steps = []
    for prev, nxt in zip(order[:-1], order[1:], strict=True):
        step = (geometric[nxt] - geometric[prev]) % 360.0
        steps.append(step if step > _TOL else 360.0)
    steps = _most_even_steps(steps, cycle)
    delay = {order[0]: 0.0}
    for (prev, nxt), step in zip(zip(order[:-1], order[1:], strict=True), steps, strict=True):
        delay[nxt] = delay[prev] + step
    closing = cycle - delay[order[-1]]
    if len(order) > 1 and (
        closing <= _TOL
        or _angle_distance(closing % 360.0, (geometric[order[0]] - geometric[order[-1]]) % 360.0)
        > _TOL
    ):
        banked = any(str(label)[-1:].isalpha() for label in firing_order)
        raise LayoutError(
            "engine.firing_order",
            firing_order,
            f"this firing order does not fit the crank arrangement {crank_angles_deg} within one "
            f"{cycle:g}-deg cycle" + (BANK_ORDER_HINT if banked else ""),
        )
    return delay


#: Firing orders of at most this many cylinders are searched for their most even timing.
_MOST_EVEN_SEARCH = 13


def _most_even_steps(steps: list[float], cycle: float) -> list[float]:
    """The shaft angles between consecutive firings: each cylinder of a four-stroke engine passes
    its TDC twice a cycle, so each step may be one turn longer than the crank's own (a 45° V-twin
    on one pin fires 405° and 315° apart, or 45° and 675°). Of the timings that close within the
    cycle, the one whose intervals stray least from the even cycle/n (then the earliest) is taken;
    a timing that can fire evenly is unchanged."""
    n = len(steps) + 1
    if cycle <= 360.0 + _TOL or n > _MOST_EVEN_SEARCH:
        return steps
    even = cycle / n
    best, best_key = steps, None
    for extra in product((0.0, 360.0), repeat=len(steps)):
        trial = [s + e for s, e in zip(steps, extra, strict=True)]
        closing = cycle - sum(trial)
        if closing <= _TOL:
            continue
        intervals = np.array([*trial, closing])
        key = (round(float(np.max(np.abs(intervals - even))), 9), sum(extra))
        if best_key is None or key < best_key:
            best, best_key = trial, key
    return best


def _angle_distance(a: float, b: float) -> float:
    d = (a - b) % 360.0
    return min(d, 360.0 - d)


def cycle_angle_deg(
    shaft_angle_deg: np.ndarray, firing_delay_deg: float, cycle_deg: float
) -> np.ndarray:
    """Cycle angle of a cylinder at the given shaft angles (textbook eq. 42-43), deg in [0, cycle)."""
    return np.mod(np.asarray(shaft_angle_deg) - firing_delay_deg, cycle_deg)


def grid_shift(firing_delay_deg: float, step_deg: float, grid_deg: float | None = None) -> int:
    """Number of grid steps in a firing delay; the delay must be a whole number of steps.

    ``grid_deg`` (the engine's base grid, :func:`grid_deg`) lets a refusal name the nearest
    steps that work.
    """
    shift = firing_delay_deg / step_deg
    if abs(shift - round(shift)) > 1e-6:
        hint = ""
        if grid_deg is not None:
            hint = "; the nearest steps that work: " + ", ".join(
                f"{x:.12g}" for x in nearest_steps_deg(grid_deg, step_deg)
            )
        raise LayoutError(
            "analysis.angle_step_deg",
            step_deg,
            f"must divide the firing delays and bank angles (a delay of {firing_delay_deg:g} deg occurs)"
            + hint,
        )
    return int(round(shift))


def _fraction(angle_deg: float):
    """An angle as an exact fraction of degrees (layout angles are rational: 720/7, 40, 22.5 ...)."""
    return Fraction(float(angle_deg)).limit_denominator(10_000)


def grid_deg(cycle_deg: float, angles_deg) -> float:
    """The engine's base grid: the largest angle (deg) that divides the cycle and every angle given.

    Every step that divides the cycle, the firing delays and the bank angles is this grid over a
    whole number k, and every grid/k works. The greatest common divisor of rational numbers
    a/b and c/d is gcd(a d, c b)/(b d).
    """
    g = _fraction(cycle_deg)
    for angle in angles_deg:
        f = _fraction(angle) % _fraction(cycle_deg)
        if f == 0:
            continue
        num = gcd(g.numerator * f.denominator, f.numerator * g.denominator)
        g = type(g)(num, g.denominator * f.denominator)
    return float(g)


def layout_grid_deg(layout: EngineLayout) -> float:
    """:func:`grid_deg` of a layout: cycle, firing delays and bank-axis angles."""
    angles = [c.firing_delay_deg for c in layout.cylinders] + [c.axis_deg for c in layout.cylinders]
    return grid_deg(layout.cycle_deg, angles)


def step_on_grid_deg(grid: float, target_deg: float) -> float:
    """The largest step grid/k (k = 1, 2, ...) not larger than ``target_deg``."""
    k = max(1, int(np.ceil(grid / target_deg - 1e-9)))
    return grid / k


def nearest_steps_deg(grid: float, step_deg: float) -> list[float]:
    """The steps grid/k just above and just below ``step_deg`` (one if it is above the grid)."""
    below = step_on_grid_deg(grid, step_deg)
    k = round(grid / below)
    return [grid / (k - 1), below] if k > 1 else [below]


def uneven_warning(layout: EngineLayout) -> str | None:
    if layout.even_firing:
        return None
    return (
        "uneven firing: intervals "
        + ", ".join(f"{x:g}" for x in layout.firing_intervals_deg())
        + " deg"
    )


def sampled_period_deg(values, step_deg: float, cycle_deg: float, rtol: float = 1e-9) -> float:
    """The shortest period (deg) of a curve sampled at ``step_deg`` over ``cycle_deg``: the smallest
    cycle/k (a whole number of steps) by which the samples repeat within ``rtol`` x their range.

    For even firing of identical cylinders this is cycle/cylinders (textbook §4.3); uneven firing or
    cylinders that differ (articulated slave rods) give a longer one, up to the whole cycle.
    """
    v = np.asarray(values, dtype=float)
    n = len(v)
    tol = rtol * max(float(np.ptp(v)), float(np.max(np.abs(v))) if n else 0.0, 1e-300)
    for k in range(n, 1, -1):
        if n % k:
            continue
        shift = n // k
        if np.max(np.abs(np.roll(v, shift) - v)) <= tol:
            return cycle_deg / k
    return float(cycle_deg)


def cylinder_phases(layout: EngineLayout) -> list[dict]:
    """Each cylinder's crank (1-based, from the free end), that crank's lag behind crank 1 (deg),
    its axis angle from bank 0 (deg), and the delay of its working cycle after cylinder 1's (deg):
    the shift by which its forces enter the sums on the crank pins and the shaft (its own crank
    angle is alpha - delay, mod the cycle)."""
    return [
        {
            "cylinder": c.label,
            "crank": c.bay + 1,
            "crank_lag_deg": float(layout.crank_lag_deg[c.bay]),
            "axis_deg": float(c.axis_deg),
            "cycle_delay_deg": float(c.firing_delay_deg),
        }
        for c in layout.cylinders
    ]


#: A four-stroke cylinder's strokes in the order its own crank angle passes them from the TDC at
#: the start of intake (0°): intake, compression, expansion (the power stroke), exhaust.
FOUR_STROKES = ("intake", "compression", "expansion", "exhaust")


def stroke_sequence(
    cycle_delays_deg: list[float], max_columns: int = 12
) -> tuple[float, list[list[tuple[str, int]]]] | None:
    """The table of strokes of a four-stroke engine: for each cylinder (its working cycle delayed
    by ``cycle_delays_deg`` after cylinder 1's), its strokes over cylinder 1's crank angle 0…720°
    as runs of (stroke, columns), a column being ``step`` degrees: the largest step every
    cylinder's strokes begin on (the greatest common divisor of 180° and the delays). Cylinder i
    is in stroke ⌊((α − Δα_0i) mod 720°)/180°⌋ of :data:`FOUR_STROKES`. None when the delays are
    not whole degrees or the step would make more than ``max_columns`` columns (an uneven firing
    order on odd angles): no table a page can hold."""
    delays = [d % 720.0 for d in cycle_delays_deg]
    if any(abs(d - round(d)) > 1e-6 for d in delays):
        return None
    step = 180
    for d in delays:
        step = gcd(step, int(round(d)) % 180 or 180)
    if 720 // step > max_columns:
        return None
    rows = []
    for d in delays:
        strokes = [
            FOUR_STROKES[int(((c * step - round(d)) % 720) // 180)] for c in range(720 // step)
        ]
        runs: list[tuple[str, int]] = []
        for stroke in strokes:
            if runs and runs[-1][0] == stroke:
                runs[-1] = (stroke, runs[-1][1] + 1)
            else:
                runs.append((stroke, 1))
        rows.append(runs)
    return float(step), rows


def journal_label(journal: int) -> str:
    """A main journal's identifier in the results: the cranks it lies between, "0-1" for journal 0
    at the free end, "k-(k+1)" for the one after crank k (the textbook's naming)."""
    return f"{journal}-{journal + 1}"
