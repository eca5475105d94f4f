"""Forces of all cylinders of a bay on their common crank pin; articulated rods (Poda 2007 §3.3,
table B.2)."""

from __future__ import annotations

import math

import numpy as np

from crankdyn.physics import articulated as art
from crankdyn.physics import firing_explorer as fe
from crankdyn.physics import forces as phys
from crankdyn.physics import layout as lay
from crankdyn.physics.indicator import indicated_work_J
from crankdyn.plugin.contracts import (
    BAY_LOADS,
    FORCES,
    GAS_PRESSURE,
    KINEMATICS,
    ArticulatedOptions,
    BayLoads,
    PinSizeOptions,
    RodOffsetOptions,
)
from crankdyn.plugin.scene_inputs import (
    articulated_rod_masses_kg,
    engine_layout,
    rod_offset_m,
    slave_cylinder_pressure,
    slave_geometries,
    slave_rod_kg,
)
from crankdyn.plugin.types import StageOutput
from crankdyn.scene import options

from .plan import plan_data

#: The scene table of the articulated rods (:class:`crankdyn.plugin.contracts.ArticulatedOptions`).
ARTICULATED = "articulated"


def applies(scene) -> str | None:
    if scene.masses is None:
        return "the scene has no [masses]"
    if scene.engine.rod_type == "articulated" and scene.engine.mechanism != "crank_slider":
        # the slave rods' linkage is solved on the central crank-slider's master rod
        return "articulated rods are built on a central crank-slider's master rod"
    return None


def _wrapped_deg(angle: float) -> float:
    """An angle difference in (-180, 180] deg."""
    return -((-angle + 180.0) % 360.0 - 180.0)


def _true_firing(layout, slaves, slave_info) -> dict:
    """Firing at the true dead centres: each slave fires its TDC shift later than its nominal delay (the
    slaves of every bay sit like those of bay 0); the intervals between firings in firing order."""
    shift_of = {}
    bay0 = layout.bay(0)
    for (slave, _), info in zip(slaves, slave_info, strict=True):
        shift_of[bay0.index(slave)] = info["tdc_shift_deg"]
    true_delay = {}
    for k in range(layout.cranks):
        for j, c in enumerate(layout.bay(k)):
            true_delay[c.label] = c.firing_delay_deg + shift_of.get(j, 0.0)
    delays = np.array([true_delay[label] for label in layout.firing_order])
    intervals = np.diff(np.append(delays, delays[0] + layout.cycle_deg))
    return {
        "firing_intervals_nominal_deg": layout.firing_intervals_deg().tolist(),
        "firing_intervals_deg": [float(x) for x in intervals],
        "firing_angles_true_deg": {
            label: float(v % layout.cycle_deg) for label, v in true_delay.items()
        },
    }


def _firing_notes(scene, layout) -> list:
    """The note on a firing order (and crank arrangement) this calculation chose; an uneven firing
    is explained in the section, from the crank arrangement."""
    if not scene.firing_order_chosen:
        return []
    cranks_chosen = "crank_angles_deg" not in scene.engine.model_fields_set
    key = "bays.note_firing_chosen" if cranks_chosen else "bays.note_firing_order_chosen"
    if layout.cylinders_per_bay == 1:  # no two cylinders share a pin: no rule about them
        key += "_own_pins"
    return [
        (
            key,
            {
                "order": tuple(layout.firing_order),
                "cranks": tuple(float(x) for x in layout.crank_lag_deg),
            },
        )
    ]


def _slave_cylinder(
    scene,
    layout,
    slave,
    g,
    alpha_local,
    angle,
    gas,
    clearance_m3: float,
    reciprocating_kg: float,
    area: float,
) -> tuple[tuple, dict, dict, float]:
    """One slave cylinder of an articulated bay: (its row for the bay's pin forces, its summary,
    its table, its indicated work in J). Its own cycle angle is timed from its true TDC (the
    linkage moves it from the bank angle); its pressure follows its own volume
    (``slave_cylinder_pressure``), a measured trace's is the master's at that angle."""
    e, w = scene.engine, scene.engine.angular_velocity_rad_s
    R, L = e.crank_radius_m, e.rod_length_m
    sm = art.slave_motion(alpha_local, g, w)
    x_tdc, a_tdc, x_bdc, a_bdc = art.slave_dead_centres(g)
    accel = -sm.piston_acceleration_m_s2  # displacement from TDC grows as x falls
    delta = (slave.firing_delay_deg - layout.bay(0)[0].firing_delay_deg) % layout.cycle_deg
    delta += math.degrees(a_tdc) - math.degrees(g.bank_angle_rad)
    slave_angle = (angle - delta) % layout.cycle_deg
    if gas.source == "theoretical":
        p_slave, slave_volume = slave_cylinder_pressure(scene, g, area, slave_angle)
    else:  # a measured trace is known by crank angle only: the master's, at the slave's own angle
        p_slave = np.interp(slave_angle, angle, gas.pressure_Pa, period=layout.cycle_deg)
        slave_volume = clearance_m3 + area * (x_tdc - sm.piston_position_m)
    p1_slave = (
        p_slave - e.crankcase_pressure + phys.inertia_pressure_Pa(reciprocating_kg, accel, area)
    )
    row = (sm.pin_a_m, sm.pin_n_m, sm.slave_rod_angle_rad, p1_slave, g.bank_angle_rad)
    stroke = x_tdc - x_bdc
    info = {
        "cylinder": slave.label,
        "bank_angle_deg": math.degrees(g.bank_angle_rad),
        "pin_angle_deg": math.degrees(g.pin_angle_rad),
        "slave_rod_length_m": g.slave_rod_length_m,
        "slave_rod_length_textbook_m": art.slave_rod_length_textbook_m(
            L, g.pin_radius_m, R / L, g.bank_angle_rad
        ),
        "stroke_m": stroke,
        "stroke_ratio": stroke / e.stroke,
        "tdc_master_angle_deg": math.degrees(a_tdc),
        # true dead centres: how far the linkage moves them from the bank angle
        "tdc_shift_deg": _wrapped_deg(math.degrees(a_tdc) - math.degrees(g.bank_angle_rad)),
        "bdc_shift_deg": _wrapped_deg(math.degrees(a_bdc) - math.degrees(g.bank_angle_rad) - 180.0),
    }
    table = {
        "crank_angle_deg": angle,
        "slave_displacement_m": x_tdc - sm.piston_position_m,
        "slave_velocity_m_s": -sm.piston_velocity_m_s,
        "slave_acceleration_m_s2": accel,
        "slave_rod_angle_deg": np.degrees(sm.slave_rod_angle_rad),
        "slave_total_Pa": p1_slave,
    }
    return row, info, table, indicated_work_J(p_slave, slave_volume)


def _rotating_mass_terms(scene, opts, slaves, rod_length_m: float, rod_rotating_kg: float) -> dict:
    """The terms of the bay's rotating mass m_R = m_cp + 2 m_w + m_rR + (m_sr (1 − κ_s) + m_sp)
    Σ_l (1 − r cos γ_1l / L) (textbook fig. 9: each slave's rotating part and pin at its pin,
    split statically between the big end and the master's piston pin), kg."""
    m = scene.masses
    slave_rod = slave_rod_kg(scene, opts, slaves)
    lumped = slave_rod * (1 - opts.slave_rod_cm_fraction) + opts.slave_pin
    levers = sum(1 - g.pin_radius_m * math.cos(g.pin_angle_rad) / rod_length_m for _, g in slaves)
    rod_rotating_kg = float(rod_rotating_kg)
    return {
        "crank_pin_kg": m.crank_pin,
        "crank_web_kg": m.crank_web,
        "rod_rotating_kg": rod_rotating_kg,
        "slave_rod_kg": slave_rod,
        "slave_rod_cm_fraction": opts.slave_rod_cm_fraction,
        "slave_pin_kg": opts.slave_pin,
        "slave_pin_given": "slave_pin" in opts.model_fields_set,
        "slave_lumped_kg": lumped,
        "slave_lever_sum": float(levers),
        "rods_kg": rod_rotating_kg + lumped * float(levers),
        "total_kg": m.crank_pin + 2 * m.crank_web + rod_rotating_kg + lumped * float(levers),
    }


def run(scene, inputs) -> StageOutput:
    motion, gas, forces = inputs[KINEMATICS], inputs[GAS_PRESSURE], inputs[FORCES]
    e = scene.engine
    layout = engine_layout(scene)
    results = _layout_results(e, layout)
    bdc = float(motion.extra.get("bdc_crank_angle_deg", 180.0))
    if abs(bdc - 180.0) > 1e-6:  # an offset crank-slider's strokes are not half-turns
        results["bdc_crank_angle_deg"] = bdc
    if layout.cranks > 1:  # a one-crank engine's front-view scheme shows all it has
        offset, source = _rod_offset_m(scene, layout)
        results["plan"] = plan_data(layout, e.bore, e.cylinder_spacing, offset)
        results["plan"]["rod_offset_source"] = source
    notes = _firing_notes(scene, layout)
    if scene.firing_order_chosen:
        results["firing_order_chosen"] = True
        if "crank_angles_deg" not in e.model_fields_set:  # the crank arrangement chosen too
            results["second_order_rank"] = fe.second_order_moment_rank(
                e.cylinders, e.layout, e.strokes, e.bank_angle_deg, layout.crank_lag_deg
            )
    if e.rod_type != "articulated":
        tables: dict = {}
        tangential, radial, centrifugal, centrifugal_rod, work_all = _side_by_side_bays(
            scene, layout, motion, gas, forces
        )
    else:
        tangential, radial, centrifugal, centrifugal_rod, work_all, tables = _articulated_bays(
            scene, layout, motion, gas, forces, results, notes
        )
    results["centrifugal_Pa"] = centrifugal
    results["centrifugal_rod_Pa"] = centrifugal_rod
    # one cylinder's c of the forces section, which the bay's c_Σ is set against
    results["forces_centrifugal_Pa"] = forces.centrifugal_Pa
    results["piston_area_m2"] = forces.piston_area_m2
    results["indicated_work_J"] = work_all
    # each cylinder's part of the crank's t goes to the torque check, not to the results file
    parts = results.pop("cylinder_tangential_Pa", None)
    loads = BayLoads(
        crank_angle_deg=motion.crank_angle_deg,
        tangential_Pa=tangential,
        radial_Pa=radial,
        centrifugal_Pa=centrifugal,
        centrifugal_rod_Pa=centrifugal_rod,
        piston_area_m2=forces.piston_area_m2,
        crank_radius_m=e.crank_radius_m,
        layout=layout,
        indicated_work_J=work_all,
        cylinder_tangential_Pa=parts,
    )
    return StageOutput(data={BAY_LOADS: loads}, results=results, tables=tables, notes=notes)


def _layout_results(e, layout) -> dict:
    """The engine's layout, firing order, crank arrangement, cylinder phases and strokes."""
    results = {
        "layout": e.layout,
        "cylinders": e.cylinders,
        "cranks": layout.cranks,
        "strokes": e.strokes,
        "rod_type": e.rod_type,
        "firing_order": list(layout.firing_order),
        "crank_angles_deg": list(layout.crank_lag_deg),
        "even_firing": layout.even_firing,
        "firing_intervals_deg": layout.firing_intervals_deg().tolist(),
        "cylinder_phases": lay.cylinder_phases(layout),
    }
    results["stroke_sequence"] = _stroke_sequence(
        e.strokes, results["cylinder_phases"]
    )  # the table of strokes
    return results


def _side_by_side_bays(scene, layout, motion, gas, forces):
    """Central or fork-and-blade rods: every cylinder acts on its pin like a single one, at its
    own cycle angle. (tangential, radial per crank, centrifugal, its rods' part, Pa; work, J)"""
    e, m = scene.engine, scene.masses
    step, n = scene.analysis.angle_step_deg, len(motion.crank_angle_deg)
    tangential = np.zeros((layout.cranks, n))
    radial = np.zeros((layout.cranks, n))
    for c in layout.cylinders:
        shift = lay.grid_shift(c.firing_delay_deg, step)
        tangential[c.bay] += np.roll(forces.tangential_Pa, shift)
        radial[c.bay] += np.roll(forces.radial_Pa, shift)
    _, rod_rot = phys.rod_mass_split_kg(m.rod, e.rod_length_m, scene.rod_cm_from_big_end_m)
    rods_rotating = rod_rot * layout.cylinders_per_bay
    R, w, area = e.crank_radius_m, e.angular_velocity_rad_s, forces.piston_area_m2
    crank_rotating = m.crank_pin + 2 * m.crank_web
    centrifugal = phys.centrifugal_pressure_Pa(rods_rotating + crank_rotating, R, w, area)
    centrifugal_rod = phys.centrifugal_pressure_Pa(rods_rotating, R, w, area)
    return tangential, radial, centrifugal, centrifugal_rod, gas.indicated_work_J * e.cylinders


def _articulated_bays(scene, layout, motion, gas, forces, results: dict, notes: list):
    """A master rod and its slave rods on each pin: the bay's forces from the master rod's statics
    (textbook table B.2), each bay shifted by its cycle delay; ``results`` and ``notes`` get the
    slaves' data. (tangential, radial per crank, centrifugal, its rods' part, Pa; work, J; tables)"""
    e, m = scene.engine, scene.masses
    angle, area = motion.crank_angle_deg, forces.piston_area_m2
    R, L, w = e.crank_radius_m, e.rod_length_m, e.angular_velocity_rad_s
    _, rod_rot = phys.rod_mass_split_kg(m.rod, L, scene.rod_cm_from_big_end_m)
    opts = options(scene, ARTICULATED, ArticulatedOptions)
    slaves = slave_geometries(scene, layout, opts, ARTICULATED)
    s_rec, recip_master, rot_master = articulated_rod_masses_kg(scene, opts, slaves)
    alpha_local = np.radians(angle % 360.0)
    gas_Pa = gas.pressure_Pa - e.crankcase_pressure
    p1_master = gas_Pa + phys.inertia_pressure_Pa(
        m.piston_group + recip_master, motion.piston_acceleration_m_s2, area
    )
    slave_rows, slave_info, tables = [], [], {}
    # a measured trace's slave volume: the master's clearance above its own TDC
    clearance = float(gas.volume_m3.min())
    work_bay = gas.indicated_work_J
    for slave, g in slaves:
        row, info, table, work = _slave_cylinder(
            scene,
            layout,
            slave,
            g,
            alpha_local,
            angle,
            gas,
            clearance,
            m.piston_group + s_rec,
            area,
        )
        work_bay += work
        slave_rows.append(row)
        slave_info.append(info)
        tables[f"slave_{slave.label}"] = table
    t_bay, z_bay, n_bay = art.bay_crank_pin_forces(
        alpha_local, motion.rod_angle_rad, p1_master, R, L, slave_rows
    )
    parts = art.bay_tangential_contributions(
        alpha_local, motion.rod_angle_rad, p1_master, R, L, slave_rows
    )
    labels = [layout.bay(0)[0].label] + [slave.label for slave, _ in slaves]
    results["cylinder_tangential_Pa"] = dict(zip(labels, parts, strict=True))
    tangential, radial = _bays_shifted(layout, t_bay, z_bay, scene.analysis.angle_step_deg)
    crank_rotating = m.crank_pin + 2 * m.crank_web
    centrifugal = phys.centrifugal_pressure_Pa(rot_master + crank_rotating, R, w, area)
    centrifugal_rod = phys.centrifugal_pressure_Pa(rot_master, R, w, area)
    results.update(_true_firing(layout, slaves, slave_info))
    if results["firing_intervals_deg"] != results["firing_intervals_nominal_deg"]:
        notes.append(_true_intervals_note(scene, layout, tangential, slave_info))
    results.update(
        {
            "pin_radius_m": opts.pin_radius,
            "slaves": slave_info,
            "master_reciprocating_mass_kg": m.piston_group + recip_master,
            "master_rod_rotating_mass_kg": rot_master,
            "rotating_mass_terms": _rotating_mass_terms(scene, opts, slaves, L, rod_rot),
        }
    )
    tables["bay"] = {
        "crank_angle_deg": angle,
        "master_side_Pa": n_bay,
        "bay_tangential_Pa": t_bay,
        "bay_radial_Pa": z_bay,
        # only the master rod bears on the pin: the bay's forces and its reduced rotating part
        "pin_load_Pa": np.hypot(z_bay + centrifugal_rod, t_bay),
    }
    own_volumes = gas.source == "theoretical"
    notes.append(("bays.note_articulated" + ("" if own_volumes else "_trace"), {}))
    work_all = work_bay * layout.cranks
    return tangential, radial, centrifugal, centrifugal_rod, work_all, tables


def _true_intervals_note(scene, layout, tangential, slave_info) -> tuple[str, dict]:
    """The note on the true firing intervals the slave rods make uneven: every bay is bay 0
    shifted by its master's delay, so the torque may still repeat within the cycle."""
    period = lay.sampled_period_deg(
        tangential.sum(axis=0), scene.analysis.angle_step_deg, layout.cycle_deg
    )
    shift = largest_tdc_shift(slave_info)
    if period >= layout.cycle_deg:
        return ("bays.note_true_intervals", {"shift": shift})
    return ("bays.note_true_intervals_period", {"shift": shift, "period": float(period)})


def _bays_shifted(layout, t_bay, z_bay, step_deg: float):
    """Bay 0's forces on every crank pin, each bay shifted by its master cylinder's delay."""
    tangential = np.zeros((layout.cranks, len(t_bay)))
    radial = np.zeros((layout.cranks, len(t_bay)))
    master = layout.bay(0)[0]
    for k in range(layout.cranks):
        shift = lay.grid_shift(
            (layout.bay(k)[0].firing_delay_deg - master.firing_delay_deg) % layout.cycle_deg,
            step_deg,
        )
        tangential[k] = np.roll(t_bay, shift)
        radial[k] = np.roll(z_bay, shift)
    return tangential, radial


def _stroke_sequence(strokes: int, phases: list[dict]) -> dict | None:
    """The table of strokes' data (:func:`crankdyn.physics.layout.stroke_sequence`): a four-stroke
    engine's, None for a two-stroke or where the strokes begin too often for a table."""
    sequence = lay.stroke_sequence([p["cycle_delay_deg"] for p in phases]) if strokes == 4 else None
    if sequence is None:
        return None
    step, rows = sequence
    return {"step_deg": step, "rows": [[list(run) for run in runs] for runs in rows]}


def largest_tdc_shift(slaves) -> float:
    """The slaves' largest TDC shift from their bank angles (deg), to the hundredth, as the
    slaves' table, the section's text and the method note give it."""
    return round(max(abs(x["tdc_shift_deg"]) for x in slaves), 2)


def _rod_offset_m(scene, layout) -> tuple[float, str]:
    """(how far apart along the shaft the cylinders of one crank lie, m; where it comes from):
    the balancing table's ``rod_offset`` or one big-end bearing's width (:func:`rod_offset_m`),
    0 in one plane."""
    given = options(scene, "balancing", RodOffsetOptions).rod_offset
    return rod_offset_m(scene, layout, given, options(scene, "bearings", PinSizeOptions))
