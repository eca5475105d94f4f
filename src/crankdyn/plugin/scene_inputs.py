"""A scene's values as the shared physics functions take them, for every plugin that needs them.

The engine's layout, the articulated rods' geometry and the mass rotating with a crank pin, the
working cycle's parameters and the checks of a one-cylinder mechanism are read the same way by
several stages and mechanisms; they live here, in the core library, so that no plugin imports
another (the import-linter contract ``independence`` in pyproject.toml).
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from ..errors import Problem, SceneError
from ..physics import articulated as art
from ..physics import bearings as brg
from ..physics import forces as phys
from ..physics import indicator as ind
from ..physics import layout as lay
from ..physics.speed_fluctuation import CrankTrain
from ..scene import options as scene_options
from .contracts import ArticulatedOptions, BayLoads, PinSizeOptions


def power_take_off(scene) -> str:
    """What the shaft's power take-off end carries, by ``engine.application``: ``"propeller"``
    (an aircraft engine), ``"drive"`` (a boat's: an outboard motor's flywheel sits at the other
    end; a motorcycle's primary drive, whose alternator rotor, the flywheel, is usually at the
    other end) or ``"flywheel"``."""
    application = scene.engine.application if scene is not None else None
    return {
        "aircraft": "propeller",
        "marine": "drive",
        "outboard": "drive",
        "motorcycle": "drive",
    }.get(application or "", "flywheel")


def engine_layout(scene) -> lay.EngineLayout:
    """The scene's engine layout; a :class:`SceneError` naming the field it cannot be built from."""
    e = scene.engine
    try:
        return lay.build_layout(
            e.layout,
            e.strokes,
            e.cylinders,
            e.bank_angle_deg,
            e.firing_order,
            e.crank_angles_deg,
            e.rod_type,
            e.uneven_firing,
        )
    except lay.LayoutError as exc:
        raise SceneError(Problem(exc.field, exc.value, str(exc))) from None


def _pin_angle_rad(opts: ArticulatedOptions, j: int, gamma_rad: float) -> float:
    if opts.pin_angles_deg is not None:
        return math.radians(opts.pin_angles_deg[j])
    if opts.pin_angle_deg is not None:
        return math.radians(opts.pin_angle_deg)
    return gamma_rad


def slave_geometries(
    scene, layout, opts: ArticulatedOptions, table: str
) -> list[tuple[lay.Cylinder, art.SlaveGeometry]]:
    """(slave cylinder, geometry) for the slave rods of bay 0 (their length given, or for equal
    compression ratios when the scene gives one, else the textbook's L - pin radius, eq. (4)).
    ``opts`` is the scene table ``table``, which the problems name."""
    e = scene.engine
    R, L = e.crank_radius_m, e.rod_length_m
    bay = layout.bay(0)
    master = bay[0]
    slaves = [c for c in bay if not c.master]
    if opts.pin_angles_deg is not None and len(opts.pin_angles_deg) != len(slaves):
        raise SceneError(
            Problem(
                f"{table}.pin_angles_deg",
                opts.pin_angles_deg,
                f"needs one angle per slave rod ({len(slaves)})",
            )
        )
    out = []
    for j, slave in enumerate(slaves):
        gamma = math.radians(slave.axis_deg - master.axis_deg)
        pin_angle = _pin_angle_rad(opts, j, gamma)
        if opts.pin_radius >= L:
            raise SceneError(
                Problem(
                    f"{table}.pin_radius", opts.pin_radius, "must be shorter than the master rod"
                )
            )
        geometry = art.SlaveGeometry(R, L, opts.pin_radius, pin_angle, gamma, L - opts.pin_radius)
        try:
            if opts.slave_rod_length is not None:
                length = opts.slave_rod_length
            elif scene.cycle is not None and scene.cycle.compression_ratio is not None:
                length = art.slave_rod_length_equal_compression_m(
                    geometry, scene.cycle.compression_ratio
                )
            else:
                length = L - opts.pin_radius  # textbook eq. (4)
            geometry = art.SlaveGeometry(R, L, opts.pin_radius, pin_angle, gamma, length)
            art.slave_motion(np.linspace(0, 2 * np.pi, 721), geometry)
        except ValueError as exc:
            raise SceneError(
                Problem(f"{table}.slave_rod_length", opts.slave_rod_length, str(exc))
            ) from None
        out.append((slave, geometry))
    return out


def rod_offset_m(scene, layout, given_m, pin: PinSizeOptions) -> tuple[float, str]:
    """(distance along the shaft between the planes of central rods side by side on a crank pin,
    m; where it comes from): ``given_m`` (the balancing table's ``rod_offset``: "given"), else one
    big-end bearing's width, ``pin``'s given crank-pin width (the bearings table's) shared by the
    rods on the pin ("pin_width") or of the typical proportions the bearing stage takes, 0.45 of
    a pin 0.63 of the bore or of the given diameter, each to 0.1 mm ("typical"); 0 and "none"
    where the rods share a plane (one rod a pin, fork or articulated rods)."""
    e = scene.engine
    if e.rod_type != "central" or layout.cylinders_per_bay < 2:
        return 0.0, "none"
    if given_m is not None:
        return float(given_m), "given"
    # the pin the bearing stage takes: the given length, or the typical one
    per_pin = brg.big_end_bearings_on_pin(e.rod_type, layout.cylinders_per_bay)
    _, width = brg.crank_pin_size_m(e.bore, per_pin, pin.crank_pin_diameter, pin.crank_pin_width)
    source = "pin_width" if pin.crank_pin_width is not None else "typical"
    return brg.big_end_bearing_width_m(width, per_pin), source


def slave_rod_kg(scene, opts: ArticulatedOptions, slaves) -> float:
    """A slave rod's mass, kg: the scene's, or the master rod's scaled by the slave rod's length
    over the master's (``slaves`` from :func:`slave_geometries`)."""
    if opts.slave_rod is not None:
        return float(opts.slave_rod)
    return float(scene.masses.rod * slaves[0][1].slave_rod_length_m / scene.engine.rod_length_m)


def articulated_rod_masses_kg(
    scene, opts: ArticulatedOptions, slaves
) -> tuple[float, float, float]:
    """(slave rod's share at its piston pin, reduced master rod's reciprocating and rotating
    masses), kg. Reduced master rod (textbook fig. 9): each slave's rotating part and pin lumped at
    its pin, split statically between the big end and the master's piston pin; ``slaves`` from
    :func:`slave_geometries`."""
    e, m = scene.engine, scene.masses
    rod_rec, rod_rot = phys.rod_mass_split_kg(m.rod, e.rod_length_m, scene.rod_cm_from_big_end_m)
    slave_rod = slave_rod_kg(scene, opts, slaves)
    s_rot = slave_rod * (1 - opts.slave_rod_cm_fraction)
    recip_master, rot_master = float(rod_rec), float(rod_rot)
    for _, g in slaves:
        dr, dq = art.reduced_master_rod_masses(
            0.0, 0.0, e.rod_length_m, s_rot, opts.slave_pin, g.pin_radius_m, g.pin_angle_rad
        )
        recip_master += dr
        rot_master += dq
    return slave_rod * opts.slave_rod_cm_fraction, recip_master, rot_master


def articulated_reciprocating_masses_kg(
    scene, layout, opts: ArticulatedOptions, table: str
) -> tuple[float, float]:
    """(master, slave) cylinder's reciprocating mass, kg: the piston group with the master rod's
    reduced share, and with the slave rod's share at its piston pin."""
    slaves = slave_geometries(scene, layout, opts, table)
    slave_share, master_share, _ = articulated_rod_masses_kg(scene, opts, slaves)
    piston = scene.masses.piston_group
    return piston + master_share, piston + slave_share


def rotating_mass_per_crank_kg(
    scene, layout, opts: ArticulatedOptions | None, table: str = ""
) -> float:
    """Mass rotating with one crank pin, reduced to the crank radius (kg): the rods' rotating
    shares (an articulated bay: the reduced master rod, textbook fig. 9) plus pin and webs.

    The mass the bay stage turns into the centrifugal force c; it needs no pressures, so
    balancing can use it in a scene without a working cycle. ``opts``: the scene's articulated
    rods, the scene table ``table`` (read by the caller); None for other rods.
    """
    e, m = scene.engine, scene.masses
    _, rod_rot = phys.rod_mass_split_kg(m.rod, e.rod_length_m, scene.rod_cm_from_big_end_m)
    crank_rotating = m.crank_pin + 2 * m.crank_web
    if e.rod_type != "articulated":
        return rod_rot * layout.cylinders_per_bay + crank_rotating
    slaves = slave_geometries(scene, layout, opts, table)
    return articulated_rod_masses_kg(scene, opts, slaves)[2] + crank_rotating


def crank_train(scene, bays: BayLoads) -> CrankTrain:
    """The reduced-inertia masses of the scene's engine.

    m_s = piston group + the rod's reciprocating part (eq. 17) for every cylinder; with
    articulated rods each cylinder's own (:func:`articulated_reciprocating_masses_kg`: the reduced
    master rod's at a master piston, the slave rod's share at a slave's), as the bay stage takes
    them; m_R from the centrifugal term c = -m_R R omega^2 / F_p of the bay loads, so it holds
    whatever the bay stage lumped on the crank pin (all rods of the bay, the pin and the webs
    reduced to R). Articulated slave pistons are taken to move like the master (the textbook's
    assumption).
    """
    e, m = scene.engine, scene.masses
    layout = bays.layout
    rod_rec, _ = phys.rod_mass_split_kg(m.rod, e.rod_length_m, scene.rod_cm_from_big_end_m)
    omega = e.angular_velocity_rad_s
    rotating = -bays.centrifugal_Pa * bays.piston_area_m2 / (bays.crank_radius_m * omega**2)
    cylinders = layout.cylinders
    reciprocating = np.full(len(cylinders), m.piston_group + float(rod_rec))
    if e.rod_type == "articulated":
        opts = scene_options(scene, "articulated", ArticulatedOptions)
        master, slave = articulated_reciprocating_masses_kg(scene, layout, opts, "articulated")
        reciprocating = np.array([master if c.master else slave for c in cylinders])
    return CrankTrain(
        phase_rad=np.radians([c.firing_delay_deg for c in cylinders]),
        crank_of_cylinder=np.array([c.bay for c in cylinders]),
        reciprocating_kg=reciprocating,
        rotating_kg=float(rotating),
        cranks=layout.cranks,
        crank_radius_m=bays.crank_radius_m,
        rod_ratio=e.rod_ratio_value,
        articulated=e.rod_type == "articulated",
    )


def cycle_parameters(scene) -> ind.CycleParameters:
    """The theoretical cycle's parameters of the scene's ``[cycle]``."""
    c = scene.cycle
    try:
        return _cycle_parameters(scene, c)
    except ValueError as exc:
        # a two-stroke's exhaust ports shorten its compression: ρ and p_z are checked against
        # the actual compression ratio from the port closing, which the scene's fields do not see
        raise SceneError(_ported_cycle_problem(c, str(exc))) from None


def _ported_cycle_problem(c, message: str) -> Problem:
    """The refusal of a cycle whose ρ or p_z do not fit the actual compression ratio."""
    if message.startswith("pre_expansion_ratio"):
        return Problem("cycle.pre_expansion_ratio", c.pre_expansion_ratio, message)
    if message.startswith("max_pressure_"):
        return Problem("cycle.max_pressure", c.max_pressure, message)
    return Problem("cycle.rounding.exhaust_opens_before_bdc_deg", "(see message)", message)


def _cycle_parameters(scene, c) -> ind.CycleParameters:
    return ind.CycleParameters(
        strokes=scene.engine.strokes,
        ignition=c.ignition,
        compression_ratio=c.compression_ratio,
        intake_pressure_Pa=c.intake_pressure,
        compression_index=c.compression_index,
        max_pressure_Pa=c.max_pressure,
        pre_expansion_ratio=c.pre_expansion_ratio,
        expansion_index=c.expansion_index,
        exhaust_pressure_Pa=c.exhaust_pressure
        if c.exhaust_pressure is not None
        else c.intake_pressure,
        lost_stroke_fraction=_lost_stroke_fraction(scene),
    )


def _lost_stroke_fraction(scene) -> float:
    """A two-stroke's exhaust ports' lost stroke fraction ψ by the central crank-slider (the
    indicator takes the mechanism's own displacement); 0 for a four-stroke cycle."""
    c = scene.cycle
    if scene.engine.strokes != 2 or c.source != "theoretical" or c.rounding is None:
        return 0.0
    return ind.lost_stroke_fraction(
        c.rounding.exhaust_opens_before_bdc_deg, scene.engine.rod_ratio_value
    )


def slave_cylinder_pressure(
    scene, geometry: art.SlaveGeometry, piston_area_m2: float, cycle_angle_deg
) -> tuple[np.ndarray, np.ndarray]:
    """(absolute pressure Pa, volume m³) of an articulated rod's slave cylinder at its own cycle
    angles (deg from its own TDC that starts the cycle, as the master's angle counts).

    The slave cylinder runs the scene's cycle (p_a, p_z, n₁, n₂, ρ, p_r and the rounding) in its
    own volumes: the clearance and the swept volume of its own dead centres under the common
    cylinder head (:func:`crankdyn.physics.articulated.deck_height_m`), its BDC where its piston
    turns, not 180° after TDC. Its pressure therefore follows its own volume, as a cylinder's
    does, and the work of its cycle is that of its own p–V loop.
    """
    rounding = rounding_parameters(scene)
    e = scene.engine
    cycle = _slave_cycle(
        geometry,
        cycle_parameters(scene),
        rounding,
        e.crank_radius_m,
        e.rod_length_m,
        piston_area_m2,
    )
    psi = np.asarray(cycle_angle_deg, dtype=float)
    volume = cycle.volume_at(psi)
    pressure = ind.rounded_pressure_Pa(
        psi,
        volume,
        cycle.clearance_m3,
        cycle.params,
        rounding,
        volume_function=cycle.volume_at,
        junction_deg=cycle.junction_deg,
    )
    return pressure, volume


@dataclasses.dataclass(frozen=True)
class _SlaveCycle:
    params: ind.CycleParameters  # the slave's own compression ratio and BDC
    clearance_m3: float
    deck_height_m: float
    tdc_master_rad: float
    area_m2: float
    geometry: art.SlaveGeometry
    junction_deg: float

    def volume_at(self, psi_deg):
        """The slave cylinder's volume, m³, at its own cycle angles (deg)."""
        master = np.radians(np.asarray(psi_deg, dtype=float)) + self.tdc_master_rad
        return art.slave_cylinder_volume_m3(master, self.geometry, self.deck_height_m, self.area_m2)


@functools.lru_cache(maxsize=256)
def _slave_cycle(
    geometry: art.SlaveGeometry,
    params: ind.CycleParameters,
    rounding: ind.RoundingParameters,
    crank_radius_m: float,
    rod_length_m: float,
    area_m2: float,
) -> _SlaveCycle:
    """A slave cylinder's own cycle: its parameters, clearance and volume, and the junction of
    its combustion rounding, which depend on the geometry alone (found once for every angle grid
    and step the calculation asks for)."""
    deck = art.deck_height_m(crank_radius_m, rod_length_m, params.compression_ratio)
    x_tdc, a_tdc, x_bdc, a_bdc = art.slave_dead_centres(geometry)
    own = dataclasses.replace(
        params,
        compression_ratio=(deck - x_bdc) / (deck - x_tdc),
        bdc_deg=math.degrees((a_bdc - a_tdc) % (2 * math.pi)),
    )
    clearance = area_m2 * (deck - x_tdc)
    cycle = _SlaveCycle(own, clearance, deck, a_tdc, area_m2, geometry, math.nan)

    def volumes(angle_deg, rows):
        return cycle.volume_at(angle_deg)

    junction = ind.combustion_junctions_deg([own], [rounding], np.array([clearance]), volumes)[0]
    return dataclasses.replace(cycle, junction_deg=float(junction))


def _pressure_rise_Pa(scene) -> float:
    """The rise p_c″ − p_c of the rounding: the scene's, else the usual one kept to a quarter of
    the theoretical cycle's p_c (:func:`ind.usual_pressure_rise_Pa`)."""
    r = scene.cycle.rounding
    if "pressure_rise_to_tdc" in r.model_fields_set:
        return float(r.pressure_rise_to_tdc)
    return ind.usual_pressure_rise_Pa(cycle_parameters(scene))


def rounding_parameters(scene) -> ind.RoundingParameters:
    """The rounding of the theoretical diagram, ``[cycle.rounding]`` with the textbook's defaults."""
    r, c = scene.cycle.rounding, scene.cycle
    # Textbook mid-range defaults: spark advance 20-25 deg, diesel injection advance 10-40 deg.
    advance = (
        r.ignition_advance_deg
        if r.ignition_advance_deg is not None
        else (22.0 if c.ignition == "spark" else DIESEL_ADVANCE_DEG)
    )
    delay = r.combustion_delay_deg
    if delay is None:
        delay = ind.default_combustion_delay_deg(
            c.ignition, advance, scene.engine.rpm, r.combustion_delay_time
        )
    if r.ignition_advance_deg is None and c.ignition == "diesel":
        # A diesel's delay 6·n·τ grows with the speed; the advance taken by default leaves
        # combustion starting before top dead centre at any speed the scene gives.
        advance = default_diesel_advance_deg(delay)
    if 0 <= delay < 90 and 0 < advance < 90 and delay >= advance:
        raise SceneError(_delay_problem(scene, advance, delay))
    four_stroke = scene.engine.strokes == 4
    try:
        return ind.RoundingParameters(
            ignition_advance_deg=advance,
            combustion_delay_deg=delay,
            pressure_rise_to_tdc_Pa=_pressure_rise_Pa(scene),
            peak_pressure_fraction=peak_pressure_fraction(scene),
            peak_angle_after_tdc_deg=r.peak_angle_after_tdc_deg,
            exhaust_opens_before_bdc_deg=r.exhaust_opens_before_bdc_deg,
            # Valve overlap and intake closing exist only in the four-stroke cycle.
            exhaust_closes_after_tdc_deg=r.exhaust_closes_after_tdc_deg if four_stroke else 0.0,
            intake_opens_before_tdc_deg=r.intake_opens_before_tdc_deg if four_stroke else 0.0,
            intake_closes_after_bdc_deg=r.intake_closes_after_bdc_deg if four_stroke else 0.0,
        )
    except ValueError as exc:
        raise SceneError(Problem("cycle.rounding", "(see message)", str(exc))) from None


#: The actual peak pressure over the theoretical p_z taken when the scene gives none: a spark-
#: ignition engine's 0.85 (the method's p_z′ = (0.8…0.9)·p_z, Poda 2007 §3.1), a diesel's 1
#: (its combustion goes on at a nearly constant pressure at the start of expansion: p_zд = p_z,
#: Kolchin and Demidov).
PEAK_PRESSURE_FRACTION = {"spark": 0.85, "diesel": 1.0}


def peak_pressure_fraction(scene) -> float:
    """p_z′/p_z of the rounded diagram: the scene's, or :data:`PEAK_PRESSURE_FRACTION`."""
    given = scene.cycle.rounding.peak_pressure_fraction
    return float(given) if given is not None else PEAK_PRESSURE_FRACTION[scene.cycle.ignition]


#: The diesel injection advance taken when none is given, deg (textbook 10-40 deg).
DIESEL_ADVANCE_DEG = 18.0
#: Crank degrees between the start of combustion and top dead centre that the default diesel
#: advance keeps at least, deg.
DIESEL_COMBUSTION_LEAD_DEG = 4.0


def default_diesel_advance_deg(delay_deg: float) -> float:
    """The injection advance taken when a diesel's scene gives none, deg: 18° or, when the
    ignition delay reaches that far, the delay plus 4° rounded up to a whole degree."""
    return max(DIESEL_ADVANCE_DEG, float(math.ceil(delay_deg + DIESEL_COMBUSTION_LEAD_DEG)))


def _delay_problem(scene, advance: float, delay: float) -> Problem:
    """The ignition delay reaching past the advance, named by the fields the user can change
    (either value may be a default: the delay of a diesel grows with the speed, 6·n·τ)."""
    r = scene.cycle.rounding
    advance_text = (
        f"{advance:g} deg" if r.ignition_advance_deg is not None else f"{advance:g} deg by default"
    )
    if r.combustion_delay_deg is not None:
        return Problem(
            "cycle.rounding.combustion_delay_deg",
            delay,
            f"must be less than the advance cycle.rounding.ignition_advance_deg ({advance_text}),"
            " so that combustion starts before top dead centre",
        )
    time_ms = (r.combustion_delay_time if r.combustion_delay_time is not None else 1.5e-3) * 1e3
    given = "combustion_delay_time" in r.model_fields_set
    time_text = f"{time_ms:g} ms" if given else f"{time_ms:g} ms by default"
    return Problem(
        "cycle.rounding.ignition_advance_deg",
        advance if r.ignition_advance_deg is not None else f"{advance:g} (default)",
        f"must be more than the ignition delay 6·n·τ = {delay:g} deg (engine.rpm = "
        f"{scene.engine.rpm:g}, cycle.rounding.combustion_delay_time = {time_text}):"
        " give a larger advance or a shorter delay time",
    )


def single_mechanism_problems(
    scene, what: str, multi_cylinder_tables: tuple[str, ...] = ()
) -> list[Problem]:
    """Problems of a scene that gives multi-cylinder keys to a one-cylinder mechanism (``what``
    names it in the messages), or one of the plugin tables ``multi_cylinder_tables`` that only a
    multi-cylinder engine reads."""
    e = scene.engine
    problems = []
    if e.cylinders != 1:
        problems.append(
            Problem("engine.cylinders", e.cylinders, f"the {what} is computed for one cylinder: 1")
        )
    if e.layout != "inline":
        problems.append(
            Problem("engine.layout", e.layout, f"the {what} has one cylinder; leave layout out")
        )
    if e.rod_type != "central":
        problems.append(
            Problem(
                "engine.rod_type", e.rod_type, f"the {what} has a single rod; leave rod_type out"
            )
        )
    for name in ("bank_angle_deg", "firing_order", "crank_angles_deg", "cylinder_spacing"):
        if getattr(e, name) is not None:
            problems.append(
                Problem(
                    f"engine.{name}",
                    getattr(e, name),
                    f"applies to multi-cylinder engines only; the {what} has one cylinder",
                )
            )
    for table in multi_cylinder_tables:
        if table in scene.plugin_tables():
            problems.append(
                Problem(
                    table,
                    f"[{table}]",
                    f"applies to multi-cylinder engines only; the {what} has one cylinder",
                )
            )
    return problems
