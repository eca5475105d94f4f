"""The torque stage's computation: crankshaft loads and the engine's output torque
(Poda 2007 §4.3-4.4, tables B.3 and B.4), for one scene (``run``) or many (``run_many``).
"""

from __future__ import annotations

import numpy as np

from crankdyn.physics import crankshaft as cs
from crankdyn.physics import layout as lay
from crankdyn.physics.extrema import first_argmax, first_argmin
from crankdyn.plugin.contracts import (
    BAY_LOADS,
    CRANK_LOADS,
    ENGINE_TORQUE,
    GAS_PRESSURE,
    CrankLoads,
    EngineTorque,
)
from crankdyn.plugin.types import StageOutput


def applies(scene) -> str | None:
    if scene.masses is None:
        return "the scene has no [masses]"
    return None


def run(scene, inputs, *, period_deg: float | None = None) -> StageOutput:
    """The loads and torque of ``scene``; ``period_deg`` is its torque's sampled period when
    ``run_many`` has measured it for many scenes at once."""
    bays = inputs[BAY_LOADS]
    e = scene.engine
    layout = bays.layout
    angle = bays.crank_angle_deg
    R, area = bays.crank_radius_m, bays.piston_area_m2
    pin, journal = cs.running_torques(bays.tangential_Pa)
    q = cs.resultant_Pa(bays.tangential_Pa, bays.radial_Pa, bays.centrifugal_Pa)
    torque = journal[-1] * R * area
    work_all = bays.indicated_work_J
    results = {
        **_mean_torque_results(e, torque, work_all),
        **_torque_extremes(torque, angle),
        # measured on the torque itself: cycle/cylinders for even firing of identical cylinders, longer
        # when the firing is uneven or the cylinders differ (articulated slave rods)
        "period_deg": (
            lay.sampled_period_deg(torque, scene.analysis.angle_step_deg, layout.cycle_deg)
            if period_deg is None
            else period_deg
        ),
        "period_even_firing_deg": layout.torque_period_deg,
        #: F_p·R: a specific tangential force (Pa) times it is the torque it makes (N·m)
        "torque_per_specific_force_m3": R * area,
        "non_uniformity": cs.torque_non_uniformity(torque),
        # each cylinder's cycle delay: its own crank angle alpha_i = alpha - delay (mod the cycle)
        "cylinder_cycle_delays_deg": [
            {k: p[k] for k in ("cylinder", "crank", "cycle_delay_deg")}
            for p in lay.cylinder_phases(layout)
        ],
        "indicated_power_W": 1e3
        * cs.indicated_power_kW(work_all / e.cylinders, e.cylinders, e.strokes, e.rpm),
        "journals": [
            _journal_range(
                lay.journal_label(k + 1), journal[k] * R * area
            )  # as the bearings' journals
            for k in range(layout.cranks)
        ],
        "dangerous": _dangerous_loads(bays, q, journal, angle),
    }
    gas = inputs.get(GAS_PRESSURE)
    slaves = _slave_work(e, layout, work_all, gas)
    if slaves is not None:
        results["slave_work"] = slaves
    if e.effective_power is not None:
        results.update(_effective_results(e, results["indicated_power_W"], gas))
    columns = _torque_columns(angle, bays, q, pin, journal, torque)
    data = {
        ENGINE_TORQUE: EngineTorque(
            crank_angle_deg=angle,
            torque_Nm=torque,
            cylinders=e.cylinders,
            strokes=e.strokes,
            indicated_work_J=work_all,
            angular_velocity_rad_s=e.angular_velocity_rad_s,
        ),
        CRANK_LOADS: CrankLoads(
            crank_angle_deg=angle,
            tangential_Pa=bays.tangential_Pa,
            radial_Pa=bays.radial_Pa,
            resultant_Pa=q,
            pin_torque_Pa=pin,
            journal_torque_Pa=journal,
            centrifugal_Pa=bays.centrifugal_Pa,
            piston_area_m2=area,
            crank_radius_m=R,
        ),
    }
    return StageOutput(data=data, results=results, tables={"torque": columns})


def _effective_results(e, indicated_power_W: float, gas) -> dict:
    """The effective output (N_e given): mechanical efficiency and mean effective torque."""
    return cs.effective_output(
        indicated_power_W,
        e.effective_power,
        e.angular_velocity_rad_s,
        # every cylinder's gas exchange as the diagram's (a slave cylinder's stroke differs a
        # little from its master's; its pumping loop is not computed on its own)
        pumping_power_W=0.0
        if gas is None
        else 1e3 * cs.indicated_power_kW(gas.pumping_work_J, e.cylinders, e.strokes, e.rpm),
    )


def _mean_torque_results(e, torque, work_all: float) -> dict:
    """The mean output torque against the one from the indicated work and from the power."""
    revolutions = e.strokes / 2
    mean = float(np.mean(torque))
    from_work = work_all / (2 * np.pi * revolutions)
    from_power = cs.torque_from_power_Nm(work_all / e.cylinders, e.cylinders, e.strokes, e.rpm)
    return {
        "mean_Nm": mean,
        "mean_from_work_Nm": from_work,
        "mean_deviation_percent": 100 * (mean - from_work) / from_work if from_work else None,
        "mean_from_power_Nm": from_power,
        "mean_vs_power_deviation_percent": 100 * (mean - from_power) / from_power
        if from_power
        else None,
    }


def _slave_work(e, layout, work_all: float, gas) -> dict | None:
    """Articulated rods: the master cylinder's indicated work per cycle and the slave cylinders'
    mean one (J), and one cylinder's mean torque (N·m) from the master's, when the slaves' work
    differs: the same indicator diagram over a slave's own volume curve gives another work, so
    the engine's mean torque is not the cylinders' count times one cylinder's."""
    if gas is None or e.rod_type != "articulated" or e.cylinders == layout.cranks:
        return None
    master = float(gas.indicated_work_J)
    slave = (work_all - layout.cranks * master) / (e.cylinders - layout.cranks)
    if master <= 0 or abs(slave - master) <= 1e-6 * master:
        return None
    revolutions = e.strokes / 2
    return {
        "master_J": master,
        "slave_J": slave,
        "master_torque_Nm": master / (2 * np.pi * revolutions),
        "difference_percent": 100 * (slave - master) / master,
    }


def _torque_extremes(torque, angle) -> dict:
    """The largest and smallest output torque with their crank angles."""
    i_max, i_min = first_argmax(torque), first_argmin(torque)
    return {
        "max_Nm": float(torque[i_max]),
        "max_crank_angle_deg": float(angle[i_max]),
        "min_Nm": float(torque[i_min]),
        "min_crank_angle_deg": float(angle[i_min]),
    }


def _dangerous_loads(bays, q, journal, angle) -> list[dict]:
    """Each crank's dangerous combinations of loads (:func:`crankdyn.physics.crankshaft.
    dangerous_combinations`) with the loads at their shaft angles."""
    combos = cs.dangerous_combinations(bays.radial_Pa, bays.tangential_Pa, q, journal)
    return [
        {
            "crank": k + 1,
            **{
                kind: {
                    "shaft_angle_deg": float(angle[i]),
                    "z_Pa": float(bays.radial_Pa[k, i]),
                    "t_Pa": float(bays.tangential_Pa[k, i]),
                    "q_Pa": float(q[k, i]),
                    "journal_t_Pa": float(journal[k, i]),
                }
                for kind, i in combo.items()
            },
        }
        for k, combo in enumerate(combos)
    ]


def _torque_columns(angle, bays, q, pin, journal, torque) -> dict:
    """The torque table: each crank's loads and running torques, then the output torque."""
    columns = {"crank_angle_deg": angle}
    for k in range(bays.layout.cranks):
        columns[f"crank{k + 1}_radial_Pa"] = bays.radial_Pa[k]
        columns[f"crank{k + 1}_tangential_Pa"] = bays.tangential_Pa[k]
        columns[f"crank{k + 1}_resultant_Pa"] = q[k]
        columns[f"crank{k + 1}_pin_torque_Pa"] = pin[k]
        columns[f"journal{k + 1}_torque_Pa"] = journal[k]
    columns["output_torque_Nm"] = torque
    return columns


def sampled_periods_deg(values, cycle_deg: float, rtol: float = 1e-9) -> np.ndarray:
    """``physics.layout.sampled_period_deg`` of each row of ``values`` (points x angles over
    ``cycle_deg``), the rows tested together: per row the smallest cycle/k (a whole number of
    steps) by which the samples repeat within ``rtol`` x their range, deg."""
    v = np.asarray(values, dtype=float)
    count, n = v.shape
    tol = rtol * np.maximum(np.maximum(np.ptp(v, axis=1), np.max(np.abs(v), axis=1)), 1e-300)
    period = np.full(count, float(cycle_deg))
    open_rows = np.arange(count)
    for k in range(n, 1, -1):
        if n % k or not open_rows.size:
            continue
        shift = n // k
        # the first sample rejects most shifts: only the rows it passes are compared in full
        rows = open_rows[np.abs(v[open_rows, -shift] - v[open_rows, 0]) <= tol[open_rows]]
        if rows.size:
            repeats = np.max(np.abs(np.roll(v[rows], shift, axis=1) - v[rows]), axis=1) <= tol[rows]
            period[rows[repeats]] = cycle_deg / k
            open_rows = np.setdiff1d(open_rows, rows[repeats])
    return period


def _output_torque_Nm(bays):
    """The engine's output torque over the cycle, N·m (eq. 46)."""
    return cs.running_torques(bays.tangential_Pa)[1][-1] * bays.crank_radius_m * bays.piston_area_m2


def run_many(scenes, inputs) -> list[StageOutput]:
    """``run`` over many scenes at once (a sweep's points): the torques' periods, the search over
    the cycle's divisors that dominates a point, measured over points x angles; each scene's loads
    then as ``run`` gives them. Scenes on other grids or cycles: ``run`` one by one."""
    bays = [given[BAY_LOADS] for given in inputs]
    first = bays[0]
    if not all(
        b.layout.cycle_deg == first.layout.cycle_deg
        and np.array_equal(b.crank_angle_deg, first.crank_angle_deg)
        for b in bays
    ):
        return [run(scene, given) for scene, given in zip(scenes, inputs, strict=False)]
    torques = np.stack([_output_torque_Nm(b) for b in bays])
    periods = sampled_periods_deg(torques, first.layout.cycle_deg)
    return [
        run(scene, given, period_deg=float(period))
        for scene, given, period in zip(scenes, inputs, periods, strict=False)
    ]


def _journal_range(name: str, torque_Nm) -> dict:
    """A main journal's running torque over the cycle: its largest magnitude, its largest and
    smallest values and the amplitude (M_max − M_min)/2 a fatigue check of the journal takes."""
    high, low = float(np.max(torque_Nm)), float(np.min(torque_Nm))
    return {
        "journal": name,
        "max_abs_Nm": float(np.max(np.abs(torque_Nm))),
        "max_Nm": high,
        "min_Nm": low,
        "amplitude_Nm": (high - low) / 2,
    }
