"""Each cylinder's part of the crank torque of a master rod with slave rods.

Independent reference, written here: virtual work on the linkage solved in Cartesian coordinates
(master axis along x, crank pin B = R (cos a, sin a), sin b = lambda sin a, slave pin
C = B + r (cos(g1 - b), sin(g1 - b)), slave piston pin S = s u on the slave axis u = (cos g, sin g)
with |S - C| = l). With massless rods and wall reactions normal to the cylinders, the torque a
piston force p (towards the shaft) gives the crank is -p ds/da, s the piston's distance from the
shaft axis; ds/da is taken here by the complex step (exact to rounding). So each cylinder's part
t_i of the crank pin's tangential force must satisfy t_i R = -p_i ds_i/da, and the parts must sum
to the bay's t of the master rod's statics.
"""

from __future__ import annotations

import numpy as np
import pytest

from crankdyn.physics import articulated as art

R, L, PIN_RADIUS = 0.075, 0.275, 0.060
SLAVES = [  # (bank angle g, pin angle g1, slave rod length l), m and rad
    (2 * np.pi * k / 7, 2 * np.pi * k / 7, 0.2167 + 0.0005 * k) for k in range(1, 7)
]


def _master_travel(a):
    b = np.arcsin(R / L * np.sin(a))
    return R * np.cos(a) + L * np.cos(b)


def _slave_point(a, g, g1, length):
    """(C, S) of one slave rod at crank angle ``a`` (complex ``a`` allowed)."""
    b = np.arcsin(R / L * np.sin(a))
    cx = R * np.cos(a) + PIN_RADIUS * np.cos(g1 - b)
    cy = R * np.sin(a) + PIN_RADIUS * np.sin(g1 - b)
    p = cx * np.cos(g) + cy * np.sin(g)
    s = p + np.sqrt(p * p - (cx * cx + cy * cy) + length * length)
    return (cx, cy), s


def _derivative(f, a, h=1e-30):
    return np.imag(f(a + 1j * h)) / h


@pytest.fixture(scope="module")
def bay():
    rng = np.random.default_rng(7)
    a = np.linspace(0.0, 2 * np.pi, 73)
    b = np.arcsin(R / L * np.sin(a))
    master_force = rng.normal(0.0, 2e6, a.size)
    rows, forces, travel_rates = [], [master_force], [_derivative(_master_travel, a)]
    for g, g1, length in SLAVES:
        (cx, cy), s = _slave_point(a, g, g1, length)
        sx, sy = s * np.cos(g), s * np.sin(g)
        slave_beta = g - np.arctan2(sy - cy, sx - cx)
        force = rng.normal(0.0, 2e6, a.size)
        rows.append((cx, cy, slave_beta, force, g))
        forces.append(force)
        travel_rates.append(
            _derivative(lambda x, g=g, g1=g1, length=length: _slave_point(x, g, g1, length)[1], a)
        )
    return a, b, master_force, rows, forces, travel_rates


def test_each_cylinders_part_is_its_virtual_work(bay):
    a, b, master_force, rows, forces, travel_rates = bay
    parts = art.bay_tangential_contributions(a, b, master_force, R, L, rows)
    assert len(parts) == 1 + len(SLAVES)
    for part, force, rate in zip(parts, forces, travel_rates, strict=True):
        expected = -force * rate / R
        assert np.max(np.abs(part - expected)) <= 1e-9 * np.max(np.abs(force))


def test_the_parts_sum_to_the_bays_tangential_force(bay):
    a, b, master_force, rows, _, _ = bay
    whole, _, _ = art.bay_crank_pin_forces(a, b, master_force, R, L, rows)
    parts = art.bay_tangential_contributions(a, b, master_force, R, L, rows)
    assert np.max(np.abs(np.sum(parts, axis=0) - whole)) <= 1e-9 * np.max(np.abs(whole))
    # the slaves' parts are not nothing: the sum is not the master's alone
    assert np.max(np.abs(whole - parts[0])) > 0.1 * np.max(np.abs(whole))
