"""A slave cylinder of an articulated rod runs the working cycle in its own volumes.

Independent reference: the slave linkage solved in Cartesian coordinates (tests/
test_articulated_dead_centres.py's slave_travel: master axis
along x, crank pin B = R (cos a, sin a), sin b = lambda sin a, slave pin C = B + r (cos(g1 - b),
sin(g1 - b)), slave piston pin at s along the slave axis with |S - C| = l), its dead centres by
Brent's method on ds/da, every cylinder head at H = R + L + S/(eps - 1) from the shaft axis, the
cylinder volume F (H - s). On the compression and expansion lines, away from the rounding, the
pressure must be the polytrope of that volume: p_a (V_a/V)^n1 and p_z (V_c/V)^n2. A pressure taken
from the master's diagram at the slave's cycle angle misses them by several per cent, and makes a
slave cylinder's work differ from the master's by up to ten per cent where its stroke differs by
less than half a per cent.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import modified
from scipy import optimize
from test_articulated_dead_centres import slave_travel

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.physics import articulated as art
from crankdyn.physics.indicator import indicated_work_J
from crankdyn.plugin.registry import default_registry
from crankdyn.plugin.scene_inputs import slave_cylinder_pressure
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()


def dead_centre(travel, guess, h=1e-4):
    def slope(a):
        return (travel(a + h) - travel(a - h)) / (2 * h)

    return optimize.brentq(slope, guess - 0.3, guess + 0.3, xtol=1e-14)


@pytest.fixture(scope="module")
def radial():
    data = modified("radial9-aircraft", {"analysis": {"stages": ["torque", "balancing"]}})
    return run_scene(scene_from_dict(data, base_dir=examples_dir()), REGISTRY)


def _slaves(run):
    e = run.scene.engine
    bays = run.outputs["bays"].results
    for s in bays["slaves"]:
        geometry = art.SlaveGeometry(
            e.crank_radius_m,
            e.rod_length_m,
            bays["pin_radius_m"],
            math.radians(s["pin_angle_deg"]),
            math.radians(s["bank_angle_deg"]),
            s["slave_rod_length_m"],
        )
        yield s, geometry


def test_slave_pressure_follows_the_polytropes_of_its_own_volume(radial):
    e, c = radial.scene.engine, radial.scene.cycle
    R, L, S = e.crank_radius_m, e.rod_length_m, e.stroke
    area = math.pi * e.bore**2 / 4
    head = R + L + S / (c.compression_ratio - 1)
    checked = 0
    for _, g in _slaves(radial):

        def travel(a, g=g):
            return slave_travel(
                a,
                R,
                L,
                g.pin_radius_m,
                g.pin_angle_rad,
                g.bank_angle_rad,
                g.slave_rod_length_m,
            )

        tdc = dead_centre(travel, g.bank_angle_rad)
        bdc = dead_centre(travel, g.bank_angle_rad + math.pi)
        v_c, v_a = area * (head - travel(tdc)), area * (head - travel(bdc))
        # mid-compression and mid-expansion of the slave's own cycle, deg from its intake TDC
        psi = np.array([270.0, 450.0])
        volume = np.array([area * (head - travel(math.radians(x) + tdc)) for x in psi])
        pressure, got_volume = slave_cylinder_pressure(radial.scene, g, area, psi)
        np.testing.assert_allclose(got_volume, volume, rtol=1e-9)
        expected = [
            c.intake_pressure * (v_a / volume[0]) ** c.compression_index,
            c.max_pressure * (v_c / volume[1]) ** c.expansion_index,
        ]
        np.testing.assert_allclose(pressure, expected, rtol=1e-9)
        checked += 1
    assert checked == 8


def test_a_slave_cylinders_work_follows_its_stroke(radial):
    """Same compression ratio, same cycle: the work grows with the swept volume, so a slave's
    work over the master's stays within 0.1 % of its stroke over the master's."""
    e = radial.scene.engine
    area = math.pi * e.bore**2 / 4
    master = radial.outputs["indicator"].results["indicated_work_J"]
    psi = np.linspace(0.0, 720.0, 14401)[:-1]
    slaves = 0.0
    for s, g in _slaves(radial):
        pressure, volume = slave_cylinder_pressure(radial.scene, g, area, psi)
        work = indicated_work_J(pressure, volume)
        assert work / master == pytest.approx(s["stroke_ratio"], abs=1e-3)
        slaves += work
    total = radial.outputs["bays"].results["indicated_work_J"]
    assert total == pytest.approx(master + slaves, rel=2e-4)
    mean = radial.outputs["torque"].results["mean_Nm"]
    assert mean == pytest.approx(total / (4 * math.pi), rel=1e-4)


def _second_difference(position, alpha, h=1e-4):
    """-d2x/da2 by a central second difference, m/rad^2: the acceleration over omega^2, positive
    towards the shaft at TDC."""
    return -(position(alpha + h) - 2 * position(alpha) + position(alpha - h)) / h**2


def test_the_balance_takes_each_cylinders_own_mass_and_motion(radial):
    """The radial's inertia forces summed cylinder by cylinder, the master's and the slaves' own
    masses and exact motions (the Cartesian linkage above), resolved by an FFT over a turn into
    parts turning with the shaft and against it. The counterweight takes C and the co-rotating
    first order ½·Σm_i·Rω²; the slaves' second harmonic leaves a large co-rotating second order,
    which a balance shaft at 2ω takes; the counter-rotating first order ½·(m_master − m_slave)·Rω²
    and the small counter-rotating second order are left."""
    scene = radial.scene
    e, m = scene.engine, scene.masses
    R, L, w = e.crank_radius_m, e.rod_length_m, e.angular_velocity_rad_s
    bays = radial.outputs["bays"].results
    # the example's [masses] rod_cm_fraction and [articulated] slave_rod, slave_rod_cm_fraction
    rod_fraction, slave_rod, kappa = 0.22, 1.2, 0.47
    lumped = slave_rod * (1 - kappa)  # a slave rod's rotating part at its pin on the master rod
    levers = [
        bays["pin_radius_m"] * math.cos(math.radians(s["pin_angle_deg"])) / L
        for s in bays["slaves"]
    ]
    master = m.piston_group + m.rod * rod_fraction + lumped * sum(levers)
    slave = m.piston_group + slave_rod * kappa
    theta = 2 * np.pi * np.arange(720) / 720
    force = (
        master
        * w**2
        * _second_difference(lambda a: R * np.cos(a) + np.sqrt(L**2 - (R * np.sin(a)) ** 2), theta)
    )
    for s in bays["slaves"]:
        gamma = math.radians(s["bank_angle_deg"])
        linkage = (R, L, bays["pin_radius_m"], math.radians(s["pin_angle_deg"]), gamma)

        def position(a, linkage=linkage, length=s["slave_rod_length_m"]):
            return np.array([slave_travel(x, *linkage, length) for x in np.ravel(a)])

        # the master's crank angle is theta; the slave's axis lies gamma further on
        force = force + slave * w**2 * _second_difference(position, theta) * np.exp(1j * gamma)
    spectrum = np.fft.fft(force) / theta.size
    forward_1, backward_1 = abs(spectrum[1]), abs(spectrum[-1])
    forward_2, backward_2 = abs(spectrum[2]), abs(spectrum[-2])
    assert forward_1 == pytest.approx(0.5 * (master + 8 * slave) * R * w**2, rel=1e-6)
    assert backward_1 == pytest.approx(0.5 * (master - slave) * R * w**2, rel=1e-6)

    b = radial.outputs["balancing"].results
    assert b["reciprocating_mass_kg"] == pytest.approx(master, rel=1e-12)
    assert b["slave_reciprocating_mass_kg"] == pytest.approx(slave, rel=1e-12)
    assert b["time_domain_check"]["agrees"]
    (cw,) = b["counterweights"]
    assert cw["mass_radius_kg_m"] * w**2 == pytest.approx(b["centrifugal_N"] + forward_1, rel=1e-6)
    (shaft,) = b["balance_shafts"]
    assert shaft["speed_ratio"] == 2
    (mass,) = shaft["masses"]
    assert mass["mass_radius_kg_m"] * (2 * w) ** 2 == pytest.approx(forward_2, rel=1e-5)
    left = {(x["order"], x["sense"]): x["force_N"] for x in b["parts_left"]}
    assert left == pytest.approx(
        {(1, "backward"): backward_1, (2, "backward"): backward_2}, rel=1e-5
    )
    assert b["absolute"]["sum_PII_N"] == pytest.approx(forward_2 + backward_2, rel=1e-5)
    assert forward_2 > 0.25 * b["first_order_N"]  # the textbook's equal cylinders give none
