"""Loads on crank pins, main journals and their bearings; polar and wear diagrams (Poda 2007 §5).

Frames (all two-dimensional, in the plane of a crank):

* engine frame: unit ``a`` along the axis of bank 0 (away from the shaft), unit ``n``
  perpendicular to it in the direction of rotation at TDC;
* crank k frame at shaft angle theta: the crank points at phi_k = theta - lag_k from ``a``;
  ``e_z = -(cos phi, sin phi)`` (from the crank pin towards the shaft axis) and
  ``e_t = (-sin phi, cos phi)`` (direction of rotation) — the axes of the textbook's t, z;
* rod frame: ``e_zr`` from the small end to the big end, ``e_tr`` turned from it as e_t is
  from e_z; it coincides with the crank frame at TDC and turns by -(alpha + beta) relative
  to the crank frame (textbook §5.1).

All loads are specific (Pa per unit piston area) unless the name says N or MPa-on-bearing.
"""

from __future__ import annotations

import numpy as np

#: Typical proportions of car and tractor engines (Kolchin and Demidov), taken where a scene gives
#: no journal sizes: the crank pin's diameter over the bore, and the width of each big-end bearing
#: over the pin's diameter where rods sit side by side on it (a V's pin is then 0.9·d long).
TYPICAL_PIN_DIAMETER_PER_BORE = 0.63
TYPICAL_ROD_BEARING_WIDTH_PER_DIAMETER = 0.45
#: A crank pin's typical length per diameter with one rod on it.
TYPICAL_PIN_WIDTH_PER_DIAMETER = 0.60
#: The exponent of a roller or needle bearing's life in its load (ISO 281:2007: L = (C/P)^p,
#: p = 10/3; a ball bearing's is 3).
ROLLER_LIFE_EXPONENT = 10.0 / 3.0

from .extrema import first_argmax, first_argmin


def crank_axes(crank_position_rad):
    """(e_t, e_z) of a crank at position phi (from ``a`` in the direction of rotation), each (2, N)."""
    phi = np.asarray(crank_position_rad, dtype=float)
    e_z = np.array([-np.cos(phi), -np.sin(phi)])
    e_t = np.array([-np.sin(phi), np.cos(phi)])
    return e_t, e_z


def counterweight_crank_load_Pa(crank, specific_force_Pa, angle_from_crank_rad, cranks: int):
    """(t, z) per crank, arrays (cranks,), of counterweights' centrifugal forces in crank axes [Pa].

    A counterweight at ``angle_from_crank_rad`` psi from its crank (in the direction of
    rotation) pulls along cos psi u + sin psi e_t, u the crank's outward direction = -e_z
    (:func:`crank_axes`): t = p sin psi, z = -p cos psi; opposite the pin (psi = pi) it adds p to
    z, as the rotating masses' c (negative) takes from it. ``crank``: the 0-based crank of each
    counterweight; ``specific_force_Pa``: its m r omega^2 per piston area.
    """
    p = np.asarray(specific_force_Pa, dtype=float)
    psi = np.asarray(angle_from_crank_rad, dtype=float)
    t, z = np.zeros(cranks), np.zeros(cranks)
    np.add.at(t, np.asarray(crank, dtype=int), p * np.sin(psi))
    np.add.at(z, np.asarray(crank, dtype=int), -p * np.cos(psi))
    return t, z


def crank_pin_load(tangential_Pa, radial_Pa, centrifugal_rod_Pa):
    """Load of the rod(s) on the crank pin in crank axes: (t, z + c_rod), textbook §5.1, fig. 17."""
    return np.asarray(tangential_Pa, dtype=float), np.asarray(
        radial_Pa, dtype=float
    ) + centrifugal_rod_Pa


def rod_bearing_load(pin_t_Pa, pin_z_Pa, crank_angle_rad, rod_angle_rad):
    """Load of the crank pin on the rod bearing, in rod axes (t_r, z_r).

    The force is the reverse of the pin load, and the rod frame is turned by (alpha + beta)
    against the crank frame (textbook §5.1, fig. 18-20):
    ``(t_r, z_r) = -R(alpha + beta) (t, z)`` with R the rotation taking crank-frame components
    into rod-frame components.
    """
    angle = np.asarray(crank_angle_rad) + np.asarray(rod_angle_rad)
    c, s = np.cos(angle), np.sin(angle)
    t, z = np.asarray(pin_t_Pa), np.asarray(pin_z_Pa)
    # Crank-frame components rotated into the rod frame (rod frame lags by alpha + beta).
    t_r = c * t - s * z
    z_r = s * t + c * z
    return -t_r, -z_r


def big_end_bearings_on_pin(rod_type: str, cylinders_per_pin: int) -> int:
    """Number of big-end bearings that share the length of one crank pin.

    Parameters
    ----------
    rod_type : {"central", "fork", "articulated"}
        How the rods of one crank pin sit on it.
    cylinders_per_pin : int
        Cylinders (rods) acting on one crank pin, 1 or more.

    Returns
    -------
    int
        ``cylinders_per_pin`` for central rods side by side, each with a bearing of its own;
        1 for a fork rod (the blade rod runs on the outside of the fork rod's bearing shell)
        and for a master rod (the slave rods hang on its big end): that one bearing carries the
        whole pin load.
    """
    return cylinders_per_pin if rod_type == "central" else 1


def drawn_size_m(value_m: float) -> float:
    """A size taken from a typical ratio as a drawing gives it, m: to 0.1 mm; a size under 10 mm
    (a model engine's) to three significant digits."""
    return round(value_m * 1e4) / 1e4 if value_m >= 0.01 else float(f"{value_m:.3g}")


def crank_pin_size_m(
    bore_m: float, rods_per_pin: int, diameter_m: float | None = None, width_m: float | None = None
) -> tuple[float, float]:
    """(diameter, length) of a crank pin, m: the given ones, or the typical proportions a drawing
    gives (:func:`drawn_size_m`): d = 0.63 D, B = 0.6 d with one rod, 0.45 d for each of the
    rods side by side on it (Kolchin and Demidov's ratios: one rod's 0.6 d would leave each of
    two rods 0.3 d)."""
    d = diameter_m or drawn_size_m(TYPICAL_PIN_DIAMETER_PER_BORE * bore_m)
    per_diameter = (
        TYPICAL_PIN_WIDTH_PER_DIAMETER
        if rods_per_pin == 1
        else rods_per_pin * TYPICAL_ROD_BEARING_WIDTH_PER_DIAMETER
    )
    return float(d), float(width_m or drawn_size_m(per_diameter * d))


def big_end_bearing_width_m(pin_width_m: float, bearings_on_pin: int) -> float:
    """Width B_r of one big-end bearing, m: the crank pin's width shared equally by the big-end
    bearings side by side on it, ``B_r = B / n`` (n from :func:`big_end_bearings_on_pin`)."""
    return pin_width_m / bearings_on_pin


def own_rod_bearing_load(
    tangential_Pa, radial_Pa, centrifugal_one_rod_Pa, crank_angle_rad, rod_angle_rad
):
    """Load of the crank pin on the big-end bearing of one rod among several on a shared pin.

    Parameters
    ----------
    tangential_Pa, radial_Pa : array (N,)
        t and z of this rod's cylinder alone (Pa per piston area), in crank axes, at the
        shaft angles of the grid (textbook table B.2 of one cylinder).
    centrifugal_one_rod_Pa : float
        c_r of this rod's rotating part alone, -m_rR R omega^2 / F_p, Pa (negative).
    crank_angle_rad, rod_angle_rad : array (N,)
        alpha_i (the crank's angle from this cylinder's axis) and beta_i of this rod.

    Returns
    -------
    (t_r, z_r) : arrays (N,)
        The load in this rod's axes, Pa: ``-Pi(alpha_i + beta_i) (t_i, z_i + c_r)`` (textbook
        §5.1, fig. 17-20, applied to one rod: the bearing carries its own rod's force only;
        the other rods' forces reach the pin through their own bearings).
    """
    pin_t, pin_z = crank_pin_load(tangential_Pa, radial_Pa, centrifugal_one_rod_Pa)
    return rod_bearing_load(pin_t, pin_z, crank_angle_rad, rod_angle_rad)


def to_frame(vector_a, vector_n, e_t, e_z):
    """Components (t, z) of an engine-frame vector in the axes (e_t, e_z)."""
    return vector_a * e_t[0] + vector_n * e_t[1], vector_a * e_z[0] + vector_n * e_z[1]


def crank_force_engine_frame(tangential_Pa, radial_Pa, centrifugal_Pa, crank_position_rad):
    """The force a crank receives at its pin (t e_t + (z + c) e_z) in engine-frame components (a, n)."""
    e_t, e_z = crank_axes(crank_position_rad)
    t = np.asarray(tangential_Pa)
    zc = np.asarray(radial_Pa) + centrifugal_Pa
    return t * e_t[0] + zc * e_z[0], t * e_t[1] + zc * e_z[1]


def journal_loads(crank_forces_a, crank_forces_n, share_before, share_after):
    """Loads J transmitted to every main journal by the cranks, each crank a beam on two supports.

    Parameters
    ----------
    crank_forces_a, crank_forces_n : array (cranks, N)
        Engine-frame components of the force on each crank, Pa.
    share_before, share_after : array (cranks,)
        l''/l and l'/l of each crank (eq. 48-49): the parts carried by the journal before
        and after it; they add to 1.

    Returns
    -------
    (J_a, J_n) : arrays (cranks + 1, N); journal 0 is at the free end, journal k lies after crank k.
    """
    fa, fn = np.asarray(crank_forces_a), np.asarray(crank_forces_n)
    cranks, n = fa.shape
    ja, jn = np.zeros((cranks + 1, n)), np.zeros((cranks + 1, n))
    for k in range(cranks):
        ja[k] += share_before[k] * fa[k]
        jn[k] += share_before[k] * fn[k]
        ja[k + 1] += share_after[k] * fa[k]
        jn[k + 1] += share_after[k] * fn[k]
    return ja, jn


def polar_summary(t_Pa, z_Pa, piston_area_m2, diameter_m, width_m, crank_angle_deg=None):
    """Largest, smallest and mean load (N) and the largest and mean bearing pressure (MPa) over
    the cycle (textbook §5.1 end); with ``crank_angle_deg`` also the angles of the largest and
    the smallest load (the first of equal ones, :mod:`crankdyn.physics.extrema`)."""
    magnitude = np.hypot(t_Pa, z_Pa) * piston_area_m2
    area = diameter_m * width_m
    out = {
        "max_N": float(magnitude.max()),
        "mean_N": float(magnitude.mean()),
        "rolling_equivalent_N": rolling_equivalent_load_N(magnitude),
        "min_N": float(magnitude.min()),
        "max_MPa": float(magnitude.max() / area / 1e6),
        "mean_MPa": float(magnitude.mean() / area / 1e6),
    }
    if crank_angle_deg is not None:
        angle = np.asarray(crank_angle_deg, dtype=float)
        out["max_crank_angle_deg"] = float(angle[first_argmax(magnitude)])
        out["min_crank_angle_deg"] = float(angle[first_argmin(magnitude)])
    return out


def rolling_equivalent_load_N(load_N, exponent: float = ROLLER_LIFE_EXPONENT) -> float:
    r"""Mean equivalent load of a rolling bearing whose load varies over the engine's cycle.

    .. math:: P_m = \left(\frac{1}{n}\sum_{i=1}^{n} Q_i^{\,p}\right)^{1/p}

    the constant load that gives the bearing the same rating life as the varying one (Harris
    and Kotzalas 2007, the mean effective load of a load cycle; ISO 281:2007 for the life
    L = (C/P)^p in millions of revolutions). The loads are sampled at equal steps of crank
    angle over the cycle, so each counts for the same number of revolutions: the relative speed
    of the bearing's rings is taken as constant (a main bearing's exactly; a big-end bearing's
    varies by about ±λ with the rod's swing).

    Parameters
    ----------
    load_N : array_like
        Magnitude of the bearing's load at equal steps of crank angle over one cycle, N.
    exponent : float
        Life exponent p: 10/3 for roller and needle bearings (default), 3 for ball bearings.

    Returns
    -------
    float
        P_m, N.
    """
    load = np.abs(np.asarray(load_N, dtype=float))
    peak = load.max()
    if peak == 0.0:
        return 0.0
    # scaled by the peak so that the power stays well inside the floating-point range
    return float(peak * np.mean((load / peak) ** exponent) ** (1.0 / exponent))


def _surface_distance_deg(psi_deg, contact_deg):
    """Angle between surface points and contact points on the circle, 0 ... 180 deg."""
    return np.abs((psi_deg - contact_deg + 180.0) % 360.0 - 180.0)


def _run_starts_and_ends(start, end, weight, points: int):
    """Difference array (length ``points``) of runs [start, end) of surface points on a circle,
    each adding its weight; ``end`` may pass ``points``, the run then goes on from 0."""
    wraps = end > points
    diff = np.bincount(start, weight, points + 1)
    diff -= np.bincount(np.where(wraps, points, end), weight, points + 1)
    diff[0] += weight[wraps].sum()
    diff -= np.bincount(end[wraps] - points, weight[wraps], points + 1)
    return diff[:points]


def _run_bounds(contact, spread_deg: float, resolution_deg: float, points: int):
    """(first, last, hit): the first and last surface index (unwrapped) of each load's run, and
    whether the run holds a point, by the distance test ``|psi - contact| <= spread`` on the circle.

    The run is [ceil(lower), floor(upper)] of lower, upper = (contact -+ spread)/resolution; only a
    load whose bound falls within 1e-6 of a surface point, where the test's rounding decides, is
    settled by the test itself, stepping from the estimate (at a 0.01 deg step the test over every
    load, seven times a diagram, would be a third of the bearings stage)."""
    lower, upper = (contact - spread_deg) / resolution_deg, (contact + spread_deg) / resolution_deg
    first, last = np.ceil(lower).astype(np.int64), np.floor(upper).astype(np.int64)
    hit = last >= first
    near = (np.abs(lower - np.round(lower)) < 1e-6) | (np.abs(upper - np.round(upper)) < 1e-6)
    if near.any():
        c = contact[near]

        def covered(k):
            return _surface_distance_deg(np.mod(k, points) * resolution_deg, c) <= spread_deg

        f = np.floor(lower[near]).astype(np.int64) - 1
        for _ in range(3):
            f += ~covered(f)
        g = np.floor(upper[near]).astype(np.int64) + 1
        for _ in range(3):
            g -= ~covered(g)
        first[near], last[near], hit[near] = f, g, covered(f) & (g >= f)
    return first, last, hit


def wear_diagram(
    contact_t, contact_z, weight, spread_deg: float = 60.0, resolution_deg: float = 1.0
):
    """Wear (load-intensity) diagram around a journal or bearing surface.

    Each load presses the surface evenly over +-``spread_deg`` around its contact point
    (the usual construction of the wear diagram; 60 deg by convention). The contact point
    is the direction (``contact_t``, ``contact_z``) in the part's axes; ``weight`` its
    magnitude. Surface angles psi are measured from +z towards +t; ``resolution_deg`` must
    divide 360 and ``spread_deg`` lie below 180.

    Returns (psi_deg, wear) with wear in the units of ``weight`` (summed over the cycle).

    A load covers a contiguous run of surface points, so each load adds its weight to the two
    ends of its run in a difference array and one cumulative sum gives the diagram: linear in
    the number of crank angles (a surface-by-crank-angle matrix cost 360 operations per angle,
    half a second per diagram at a 0.01 deg step). The run's ends are decided by the same
    distance test, ``|psi - contact| <= spread`` on the circle, that defines the diagram.
    """
    points = int(round(360.0 / resolution_deg))
    psi = np.arange(0.0, 360.0, resolution_deg)
    contact = np.degrees(np.arctan2(contact_t, contact_z)) % 360.0
    weight = np.broadcast_to(np.asarray(weight, dtype=float), contact.shape)
    first, last, hit = _run_bounds(contact, spread_deg, resolution_deg, points)
    start = np.mod(first[hit], points)
    end = start + (last - first + 1)[hit]
    wear = np.cumsum(_run_starts_and_ends(start, end, weight[hit], points))
    # where no load presses, exactly nothing (the cumulative sum would leave its rounding there)
    pressed = np.cumsum(_run_starts_and_ends(start, end, np.ones(start.size), points))
    wear[pressed < 0.5] = 0.0
    return psi, wear


def least_loaded_arc(psi_deg, wear, tolerance: float = 0.05):
    """(start_deg, end_deg, centre_deg) of the widest arc where wear <= min + tolerance*(max - min).

    The centre is the recommended oil-hole position (textbook §5: the oil hole goes into the
    least-loaded part of the surface).
    """
    psi = np.asarray(psi_deg)
    w = np.asarray(wear, dtype=float)
    low = w <= w.min() + tolerance * (w.max() - w.min())
    if low.all():
        return 0.0, 360.0, 0.0
    step = psi[1] - psi[0]
    # Rotate so that the scan starts on a loaded point: arcs then never wrap around.
    start = int(np.argmin(low))
    rolled = np.roll(low, -start)
    best, best_len, run_start = (0, 0), 0, None
    for i, flag in enumerate(np.append(rolled, False)):
        if flag and run_start is None:
            run_start = i
        elif not flag and run_start is not None:
            if i - run_start > best_len:
                best, best_len = (run_start, i - 1), i - run_start
            run_start = None
    a = psi[(best[0] + start) % len(psi)]
    b = psi[(best[1] + start) % len(psi)]
    centre = (a + ((b - a) % 360.0) / 2.0) % 360.0
    return float(a), float(b + step) % 360.0, float(centre)
