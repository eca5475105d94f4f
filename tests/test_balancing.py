"""Balancing: vector models against the real forces, textbook closed forms, counterweights and shafts."""

from __future__ import annotations

import functools
import json
import math
import re

import numpy as np
import pytest
from conftest import modified, shared_html

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.errors import SceneError
from crankdyn.physics import balancing as bal
from crankdyn.physics.layout import build_layout
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()
SQRT3 = math.sqrt(3.0)
BUNDLED = [
    "petrol-1cyl",
    "diesel-1cyl",
    "two-stroke-1cyl",
    "diesel-rk-trace",
    "inline3-petrol",
    "inline4-petrol",
    "inline6-diesel-trace",
    "v8-petrol",
    "radial9-aircraft",
]
INLINE8_CROSS = {"engine": {"cylinders": 8, "firing_order": [1, 6, 2, 5, 8, 3, 7, 4]}}
# other stages' tables in the example are not ours to adapt to eight cylinders
INLINE8_CROSS.update({"flywheel": None, "torsion": None})
RADIAL_CENTRAL = {"engine": {"rod_type": "central"}, "articulated": None}


@functools.cache
def _run(name: str, changes_json: str = "{}"):
    scene = scene_from_dict(modified(name, json.loads(changes_json)), base_dir=examples_dir())
    return run_scene(
        scene, REGISTRY, ["balancing"]
    )  # and its prerequisites only: keeps the tests fast


def run(name, changes=None):
    return _run(name, json.dumps(changes or {}, sort_keys=True))


def balancing(name, changes=None) -> dict:
    return run(name, changes).outputs["balancing"].results


# ----------------------------------------------------------------------------- independent time-domain sum


def exact_acceleration(alpha, R, lam, w):
    """j = R w^2 (cos a + lam (cos 2a + lam^2 sin^4 a) / (1 - lam^2 sin^2 a)^(3/2)), written out independently."""
    s2 = np.sin(alpha) ** 2
    return (
        R
        * w**2
        * (np.cos(alpha) + lam * (np.cos(2 * alpha) + lam**2 * s2**2) / (1 - lam**2 * s2) ** 1.5)
    )


def vertical_of(layout) -> float:
    """The engine's vertical (a convention, stated in the module docstring): the cylinder axis of an in-line
    engine and cylinder 1 of a radial, the bisector of the first two banks of a V or X, the middle bank of a
    W or Y, horizontal cylinders for a boxer."""
    axes = sorted({c.axis_deg for c in layout.cylinders if c.bay == 0})
    if layout.layout in ("inline", "radial"):
        return 0.0
    if layout.layout == "boxer":
        return 90.0
    if layout.layout in ("W", "Y"):
        return axes[1]
    return axes[1] / 2  # V, X: banks at 0 and gamma (X also 180, 180 + gamma)


def direct_sum(layout, m_s, m_R, R, lam, w, a, theta):
    """Real forces (x, y) and moments (about the middle of the row), cylinder by cylinder, in plain trigonometry."""
    v = math.radians(vertical_of(layout))
    fx = np.zeros_like(theta)
    fy = np.zeros_like(theta)
    mx = np.zeros_like(theta)
    my = np.zeros_like(theta)
    centre = (layout.cranks - 1) / 2
    for c in layout.cylinders:
        alpha = theta - math.radians(layout.crank_lag_deg[c.bay] + c.axis_deg)
        force = m_s * exact_acceleration(alpha, R, lam, w)
        phi = math.radians(c.axis_deg) - v
        z = (c.bay - centre) * a
        fx += force * math.sin(phi)
        fy += force * math.cos(phi)
        mx += z * force * math.sin(phi)
        my += z * force * math.cos(phi)
    for k, lag in enumerate(layout.crank_lag_deg):
        direction = theta - math.radians(lag) - v
        C = m_R * R * w**2
        z = (k - centre) * a
        fx += C * np.sin(direction)
        fy += C * np.cos(direction)
        mx += z * C * np.sin(direction)
        my += z * C * np.cos(direction)
    return fy + 1j * fx, my + 1j * mx  # the module writes a planar vector as y + i x


LAYOUTS = {
    "inline3": ("inline", 4, 3, None, [1, 3, 2], None),
    "inline4": ("inline", 4, 4, None, [1, 3, 4, 2], None),
    "inline5": ("inline", 4, 5, None, [1, 2, 4, 5, 3], None),
    "inline6": ("inline", 4, 6, None, [1, 5, 3, 6, 2, 4], None),
    "inline8-cross": ("inline", 4, 8, None, [1, 6, 2, 5, 8, 3, 7, 4], None),
    "inline6-two-stroke": ("inline", 2, 6, None, [1, 4, 2, 6, 3, 5], None),
    "V2-90-uneven": ("V", 4, 2, 90, ["1L", "1R"], [0]),
    "V8-90-cross": (
        "V",
        4,
        8,
        90,
        ["1L", "1R", "4L", "3L", "3R", "2L", "2R", "4R"],
        [0, 90, 270, 180],
    ),
    "V12-60": ("V", 4, 12, 60, None, [0, 240, 120, 120, 240, 0]),
    "W12-60": ("W", 4, 12, 60, None, [0, 180, 180, 0]),
    "Y3-120": ("Y", 2, 3, 120, ["1L", "1C", "1R"], None),
    "X8-90": ("X", 4, 8, 90, None, [0, 180]),
    "boxer4": ("boxer", 4, 4, None, None, [0, 180, 180, 0]),
    "boxer6": ("boxer", 4, 6, None, None, [0, 180, 120, 300, 240, 60]),
    "radial9": ("radial", 4, 9, None, None, None),
    "radial5-two-stroke": ("radial", 2, 5, None, None, None),
}


def _layout(name):
    kind, strokes, cylinders, gamma, order, cranks = LAYOUTS[name]
    if (
        order is None
    ):  # any firing order the crank arrangement fits: let the explorer-free helper find one
        from crankdyn.physics.firing_explorer import explore

        if cranks is None:
            layout = build_layout(kind, strokes, cylinders, gamma, None, None)
            return layout
        rows = explore(cylinders, kind, strokes, gamma, top=None).rows
        row = next(r for r in rows if np.allclose(r.crank_angles_deg, cranks))
        order = list(row.firing_order)
    return build_layout(kind, strokes, cylinders, gamma, order, cranks, uneven_firing=True)


MASSES = bal.Masses(
    reciprocating_kg=0.61,
    rotating_kg=1.17,
    crank_radius_m=0.043,
    rod_ratio=0.29,
    angular_velocity_rad_s=550.0,
)


@pytest.mark.parametrize("name", list(LAYOUTS))
def test_vector_method_equals_direct_sum_of_real_forces(name):
    """Acceptance: the vector models (orders 1, 2, 4, ... to convergence) reproduce the real forces and
    moments summed cylinder by cylinder, to 1e-9 relative, for every layout."""
    layout = _layout(name)
    g = bal.geometry_from_layout(layout)
    m = MASSES
    theta = np.linspace(0, 2 * np.pi, 997, endpoint=False)
    a = 0.1
    f_direct, m_direct = direct_sum(
        layout,
        m.reciprocating_kg,
        m.rotating_kg,
        m.crank_radius_m,
        m.rod_ratio,
        m.angular_velocity_rad_s,
        a,
        theta,
    )
    n_max = bal.orders_needed(m.rod_ratio)
    assert 12 <= n_max <= 24
    orders = [1] + list(range(2, n_max + 1, 2))
    f_vec, m_vec = bal.vector_method_sum(g, m, theta, orders, a)
    scale = layout.cranks * m.centrifugal_N + len(layout.cylinders) * m.first_order_N * (
        1 + m.rod_ratio
    )
    assert np.max(np.abs(f_vec - f_direct)) < 1e-9 * scale
    assert np.max(np.abs(m_vec - m_direct)) < 1e-9 * scale * a * max(layout.cranks / 2, 1)
    # the module's own time-domain sum is the same thing
    f_td, m_td = bal.time_domain_sum(g, m, theta, a)
    assert np.max(np.abs(f_td - f_direct)) < 1e-12 * scale


@pytest.mark.parametrize("name", BUNDLED)
def test_bundled_examples_pass_the_time_domain_check(name):
    check = balancing(name)["time_domain_check"]
    assert check["agrees"]
    assert check["force_deviation_relative"] < 1e-9 and check["moment_deviation_relative"] < 1e-9
    assert check["orders"][:4] == [1, 2, 4, 6]


def test_acceleration_series_from_fft_and_power_series():
    for lam in (0.15, 0.25, 0.3, 0.4):
        a = bal.acceleration_harmonics(lam)
        series = bal.acceleration_series(lam)
        assert a[1] == pytest.approx(1.0, abs=1e-14)
        assert np.max(np.abs(a[3::2])) < 1e-14  # no odd orders beyond the first
        for n in (2, 4, 6):
            assert abs(a[n] - series[n]) < 2 * lam**9, (lam, n)
        assert abs(a[8] - series[8]) < 2 * lam**9
        # the series reconstructs the exact acceleration
        alpha = np.linspace(0, 2 * np.pi, 101)
        rebuilt = sum(a[n] * np.cos(n * alpha) for n in range(len(a)))
        assert np.max(np.abs(rebuilt - exact_acceleration(alpha, 1.0, lam, 1.0))) < 1e-13


# ----------------------------------------------------------------------------- textbook closed forms


def _small(results, keys):
    return all(results["coefficients"][k] < 1e-12 for k in keys)


ALL = ("sum_C", "M_C", "sum_PI", "M_PI", "sum_PII", "M_PII")


@pytest.mark.parametrize(
    "name, changes", [("inline6-diesel-trace", None), ("inline4-petrol", INLINE8_CROSS)]
)
def test_inline6_and_inline8_cross_fully_balanced(name, changes):
    r = balancing(name, changes)
    assert _small(r, ALL)
    assert not r["counterweights"] and not r["balance_shafts"]
    assert all(s["balanced"] for s in r["summary"] if s["order"] in (0, 1, 2))


def test_inline4_flat_crank_leaves_only_second_order_force():
    r = balancing("inline4-petrol")
    assert _small(r, ("sum_C", "M_C", "sum_PI", "M_PI", "M_PII"))
    assert r["coefficients"]["sum_PII"] == pytest.approx(4.0, abs=1e-12)
    # textbook form 4 C_II; absolutely 4 A_2 C_I with the exact second harmonic
    A2 = r["acceleration_harmonics"]["II"]
    assert r["absolute"]["sum_PII_N"] == pytest.approx(4 * A2 * r["first_order_N"], rel=1e-12)
    assert r["second_order_N"] == pytest.approx(0.28 * r["first_order_N"], rel=1e-12)
    second = next(o for o in r["orders"] if o["order"] == 2)
    assert second["force_hodograph"]["sense"] == "line" and second["force_hodograph"][
        "major_axis_deg"
    ] == pytest.approx(0)
    # Lanchester: a pair of equal shafts at +2w and -2w, each carrying 2 C_II' / (2w)^2 in all
    speeds = {s["speed_ratio"]: s for s in r["balance_shafts"]}
    assert set(speeds) == {2, -2}
    for s in speeds.values():
        total = sum(m["mass_radius_kg_m"] for m in s["masses"])
        assert total == pytest.approx(
            2 * A2 * r["first_order_N"] / (2 * 2 * math.pi * 5600 / 60) ** 2, rel=1e-9
        )


def test_inline3_moments_sqrt3():
    r = balancing("inline3-petrol")
    c = r["coefficients"]
    assert _small(r, ("sum_C", "sum_PI", "sum_PII"))
    assert c["M_PI"] == pytest.approx(SQRT3, abs=1e-12)
    assert c["M_PII"] == pytest.approx(SQRT3, abs=1e-12)
    assert c["M_C"] == pytest.approx(SQRT3, abs=1e-12)
    a = 0.084
    assert r["absolute"]["M_PI_Nm"] == pytest.approx(SQRT3 * r["first_order_N"] * a, rel=1e-12)
    assert r["absolute"]["M_PII_Nm"] == pytest.approx(
        SQRT3 * r["acceleration_harmonics"]["II"] * r["first_order_N"] * a, rel=1e-12
    )
    # an in-line engine's reciprocating moments act in the plane of the cylinder axes
    first = next(o for o in r["orders"] if o["order"] == 1)
    assert first["moment_hodograph"]["sense"] == "line"
    assert first["moment_hodograph"]["major_axis_deg"] == pytest.approx(0, abs=1e-9)


def test_radial_central_rods_constant_rotating_first_order():
    r = balancing("radial9-aircraft", RADIAL_CENTRAL)
    first = next(o for o in r["orders"] if o["order"] == 1)
    C_I = r["first_order_N"]
    assert first["force_forward"]["magnitude"] == pytest.approx(4.5 * C_I, rel=1e-12)
    assert first["force_backward"]["magnitude"] < 1e-12 * C_I
    h = first["force_hodograph"]
    assert h["semi_major"] == pytest.approx(h["semi_minor"]) and h["sense"] == "forward"
    assert first["force_forward"]["angle_deg"] == pytest.approx(
        r["crank_directions_deg"][0], abs=1e-9
    )  # with the crank
    # directly: sum of C_I cos(alpha_i) along each cylinder axis is (z/2) C_I along the crank
    theta = np.linspace(0, 2 * np.pi, 73)
    psi = np.radians(np.arange(9) * 40.0)
    fx = sum(C_I * np.cos(theta - p) * np.sin(p) for p in psi)
    fy = sum(C_I * np.cos(theta - p) * np.cos(p) for p in psi)
    np.testing.assert_allclose(fx, 4.5 * C_I * np.sin(theta), atol=1e-9 * C_I)
    np.testing.assert_allclose(fy, 4.5 * C_I * np.cos(theta), atol=1e-9 * C_I)
    # the counterweight takes it whole: C and (z/2) C_I, opposite the crank
    (cw,) = r["counterweights"]
    w = 2 * math.pi * 2100 / 60
    assert cw["mass_radius_kg_m"] * w**2 == pytest.approx(r["centrifugal_N"] + 4.5 * C_I, rel=1e-12)
    assert cw["angle_from_crank_deg"] == pytest.approx(180.0)


def test_textbook_six_cylinder_two_stroke_example():
    """Textbook fig. 26: sum C = 0, M_C = 2 sqrt(3) C a, M_I = 2 sqrt(3) C_I a cos(alpha + 30), second order balanced;
    the counterweights on cranks 1 and 6: 2 sqrt(3) C a = 5 (2 m_c) r_c w^2 a."""
    layout = build_layout("inline", 2, 6, None, [1, 4, 2, 6, 3, 5], None)
    assert layout.crank_lag_deg == (0, 120, 240, 60, 300, 180)
    g = bal.geometry_from_layout(layout)
    rot, first, second = (
        bal.rotating_model(g),
        bal.reciprocating_model(g, 1),
        bal.reciprocating_model(g, 2),
    )
    assert abs(rot.force_forward) < 1e-12 and abs(rot.moment_forward) == pytest.approx(2 * SQRT3)
    assert first.force_max < 1e-12 and first.moment_max == pytest.approx(2 * SQRT3)
    assert second.force_max < 1e-12 and second.moment_max < 1e-12
    h = bal.hodograph(complex(first.moment_forward), complex(first.moment_backward), 1)
    assert h.sense == "line" and h.theta_at_max_deg in (pytest.approx(30.0), pytest.approx(150.0))
    m = MASSES
    means = bal.design_means(g, m, bal.acceleration_harmonics(m.rod_ratio), balance_orders=[])
    assert [cw.position for cw in means.counterweights] == [-2.5, 2.5]
    for cw in means.counterweights:
        assert cw.mass_radius_kg_m == pytest.approx(
            2 * SQRT3 / 5 * m.rotating_kg * m.crank_radius_m, rel=1e-12
        )


@pytest.mark.parametrize("gamma", [30.0, 60.0, 72.0, 90.0, 120.0, 135.0, 180.0])
def test_v_bay_model_matches_textbook_formulas(gamma):
    g = math.radians(gamma)
    axes = [-g / 2, g / 2]
    F, P = bal.bay_vectors(axes, 1)
    K, Z = bal.bay_vectors(axes, 2)
    assert F == pytest.approx(1.0) and P == pytest.approx(math.cos(g), abs=1e-12)  # eq. 64-66
    assert K == pytest.approx(math.cos(g / 2)) and Z == pytest.approx(
        math.cos(1.5 * g), abs=1e-12
    )  # eq. 74-76
    h1, h2 = bal.hodograph(F, P, 1), bal.hodograph(K, Z, 2)
    assert h1.x_amplitude == pytest.approx(
        1 - math.cos(g), abs=1e-12
    )  # eq. 62 (semi-axes are lengths)
    assert h1.y_amplitude == pytest.approx(1 + math.cos(g), abs=1e-12)
    assert h2.x_amplitude == pytest.approx(
        abs(math.cos(g / 2) - math.cos(1.5 * g)), abs=1e-12
    )  # eq. 71-72
    assert h2.y_amplitude == pytest.approx(abs(math.cos(g / 2) + math.cos(1.5 * g)), abs=1e-12)


@pytest.mark.parametrize("gamma", [30.0, 45.0, 60.0, 72.0])
def test_w_bay_model_matches_textbook_formulas(gamma):
    g = math.radians(gamma)
    F, P = bal.bay_vectors([-g, 0.0, g], 1)
    K, Z = bal.bay_vectors([-g, 0.0, g], 2)
    assert F == pytest.approx(1.5) and P == pytest.approx(
        0.5 + math.cos(2 * g), abs=1e-12
    )  # eq. 77-80
    assert K == pytest.approx(0.5 + math.cos(g)) and Z == pytest.approx(
        0.5 + math.cos(3 * g), abs=1e-12
    )  # eq. 81-82
    h2 = bal.hodograph(K, Z, 2)
    assert h2.x_amplitude == pytest.approx(abs(math.cos(g) - math.cos(3 * g)), abs=1e-12)
    assert h2.y_amplitude == pytest.approx(abs(1 + math.cos(g) + math.cos(3 * g)), abs=1e-12)


def test_v8_stage_reports_the_bay_model_and_a_pure_rotating_couple():
    r = balancing("v8-petrol")
    bm = r["bay_model"]
    assert bm["F"] == pytest.approx(1.0) and bm["P"] == pytest.approx(0.0, abs=1e-12)
    assert bm["K"] == pytest.approx(math.sqrt(0.5)) and bm["Z"] == pytest.approx(-math.sqrt(0.5))
    c = r["coefficients"]
    assert c["M_PI"] == pytest.approx(math.sqrt(10)) and c["M_C"] == pytest.approx(math.sqrt(10))
    assert _small(r, ("sum_C", "sum_PI", "sum_PII", "M_PII"))
    first = next(o for o in r["orders"] if o["order"] == 1)
    assert first["moment_backward"]["magnitude"] < 1e-9  # cured by counterweights alone
    assert len(r["counterweights"]) == 2 and not r["balance_shafts"]


# ----------------------------------------------------------------------------- balancing means


@pytest.mark.parametrize("name", BUNDLED)
def test_means_cancel_what_they_were_sized_for(name):
    """Acceptance: with the counterweights and shafts added to the time-domain sum, the rotating forces and
    orders 1 and 2 vanish; what remains is exactly the higher orders."""
    res = balancing(name)["residual"]
    assert res["vanishes"]
    assert res["force_deviation_relative"] < 1e-9 and res["moment_deviation_relative"] < 1e-9


@pytest.mark.parametrize(
    "name",
    [
        "inline3",
        "inline4",
        "inline5",
        "V2-90-uneven",
        "V12-60",
        "W12-60",
        "Y3-120",
        "X8-90",
        "boxer4",
        "radial9",
        "inline6-two-stroke",
    ],
)
@pytest.mark.parametrize(
    "counterweights, forward",
    [("ends", "crankshaft"), ("every_crank", "crankshaft"), ("ends", "shaft")],
)
def test_balancing_every_order_leaves_nothing(name, counterweights, forward):
    layout = _layout(name)
    g = bal.geometry_from_layout(layout)
    m = MASSES
    harmonics = bal.acceleration_harmonics(m.rod_ratio)
    n_max = bal.orders_needed(m.rod_ratio)
    orders = [1] + list(range(2, n_max + 1, 2))
    means = bal.design_means(g, m, harmonics, orders, counterweights, forward)
    theta = np.linspace(0, 2 * np.pi, 541, endpoint=False)
    a = 0.095
    f_real, m_real = direct_sum(
        layout,
        m.reciprocating_kg,
        m.rotating_kg,
        m.crank_radius_m,
        m.rod_ratio,
        m.angular_velocity_rad_s,
        a,
        theta,
    )
    f_means, m_means = means.forces(theta, m.angular_velocity_rad_s, a)
    scale = layout.cranks * m.centrifugal_N + len(layout.cylinders) * m.first_order_N
    assert np.max(np.abs(f_real + f_means)) < 1e-9 * scale
    assert np.max(np.abs(m_real + m_means)) < 1e-9 * scale * a * layout.cranks
    if forward == "crankshaft":
        assert 1 not in means.shafts  # the co-rotating first order is on the crankshaft
    for masses_ in means.shafts.values():
        assert all(x.mass_radius_kg_m > 0 for x in masses_)


def test_inline_twin_shafts_are_a_lanchester_pair():
    """first_order_forward = shaft on an in-line 3: two equal first-order shafts turning in opposite directions."""
    r = balancing("inline3-petrol", {"balancing": {"first_order_forward": "shaft"}})
    speeds = {s["speed_ratio"]: s for s in r["balance_shafts"]}
    assert {1, -1, 2, -2} <= set(speeds)
    for n in (1, 2):
        plus = sorted(x["mass_radius_kg_m"] for x in speeds[n]["masses"])
        minus = sorted(x["mass_radius_kg_m"] for x in speeds[-n]["masses"])
        assert plus == pytest.approx(minus, rel=1e-12)
    # first-order moment sqrt(3) C_I a = pair of shafts, each with masses at both ends l apart: 2 * 2 F l/2 = ...
    a, w = 0.084, 2 * math.pi * 6000 / 60
    l_half = a  # masses in the planes of cranks 1 and 3
    per_mass = speeds[1]["masses"][0]["mass_radius_kg_m"] * w**2
    assert 2 * (2 * per_mass * l_half) == pytest.approx(SQRT3 * r["first_order_N"] * a, rel=1e-12)
    assert r["residual"]["vanishes"]


def test_balance_orders_radii_and_spacing_options():
    base = balancing("inline3-petrol")
    r = balancing(
        "inline3-petrol",
        {
            "balancing": {
                "balance_orders": [1],
                "balance_shaft_spacing": "300 mm",
                "counterweight_radius": "80 mm",
            }
        },
    )
    assert {s["speed_ratio"] for s in r["balance_shafts"]} == {-1}
    assert r["balance_shafts"][0]["spacing_m"] == pytest.approx(0.3)
    # a longer lever needs less mass: moment / spacing
    assert r["balance_shafts"][0]["masses"][0]["mass_radius_kg_m"] == pytest.approx(
        base["balance_shafts"][0]["masses"][0]["mass_radius_kg_m"] * 0.168 / 0.3, rel=1e-12
    )
    assert r["counterweights"][0]["mass_kg"] == pytest.approx(
        base["counterweights"][0]["mass_kg"] / 2, rel=1e-12
    )
    assert r["residual"]["vanishes"]
    second = [s for s in r["summary"] if s["order"] == 2 and not s["balanced"]]
    assert second and all(s["remedy"] == "none" for s in second)


def test_without_cylinder_spacing_moments_are_per_unit_a():
    result = run("inline3-petrol", {"engine": {"cylinder_spacing": None}})
    r = result.outputs["balancing"].results
    assert r["coefficients"]["M_PI"] == pytest.approx(SQRT3)
    assert r["absolute"]["M_PI_Nm"] is None and r["cylinder_spacing_m"] is None
    assert (
        r["counterweights"] and r["residual"]["vanishes"]
    )  # sizes need no a (the lever is a multiple of a)
    assert any(key == "balancing.note_no_spacing" for key, _ in result.outputs["balancing"].notes)


@pytest.mark.parametrize(
    "table, field",
    [
        ({"include_orders": [1, 3]}, "balancing.include_orders"),
        ({"include_orders": [2, 4]}, "balancing.include_orders"),
        ({"balance_orders": [1, 1]}, "balancing.balance_orders"),
        ({"counterweights": "middle"}, "balancing.counterweights"),
        ({"counterweight_radius": 40}, "balancing.counterweight_radius"),
        ({"explore_top": 0}, "balancing.explore_top"),
        ({"radius": "40 mm"}, "balancing.radius"),
    ],
)
def test_bad_balancing_table_names_the_field(table, field):
    scene = scene_from_dict(
        modified("inline3-petrol", {"balancing": table}), base_dir=examples_dir()
    )
    with pytest.raises(SceneError) as info:
        run_scene(scene, REGISTRY)
    assert field in {p.field for p in info.value.problems}


def test_shaft_spacing_needs_cylinder_spacing():
    scene = scene_from_dict(
        modified(
            "inline3-petrol",
            {
                "engine": {"cylinder_spacing": None},
                "balancing": {"balance_shaft_spacing": "300 mm"},
            },
        ),
        base_dir=examples_dir(),
    )
    with pytest.raises(SceneError) as info:
        run_scene(scene, REGISTRY)
    assert info.value.problems[0].field == "balancing.balance_shaft_spacing"


def test_no_masses_no_balancing():
    result = run("kinematics-only")
    assert "balancing" not in result.stages_run and "[masses]" in result.plan.skipped["balancing"]


# ----------------------------------------------------------------------------- report


@pytest.mark.parametrize(
    "name, language",
    [
        ("inline3-petrol", "en"),
        ("inline3-petrol", "uk"),
        ("v8-petrol", "ru"),
        ("petrol-1cyl", "en"),
    ],
)
def test_balancing_section_renders(name, language):
    result = run(name)
    rendered = render_html(result, REGISTRY, language)
    assert not rendered.missing_translations, rendered.missing_translations
    assert 'data-stage="balancing"' in rendered.linked_html
    figures = [f.name for f in rendered.figures]
    assert any("crank_diagrams" in f for f in figures) and any(
        "vector_models" in f for f in figures
    )
    if name == "inline3-petrol":  # explore = true in the example
        assert "1–3–2" in rendered.linked_html


def test_results_json_ready_and_csv_table():
    result = run("v8-petrol")
    out = result.outputs["balancing"]
    text = json.dumps(out.results)  # plain floats, no numpy or complex values
    assert "NaN" not in text
    frame = out.tables["balancing"]
    assert {
        "shaft_angle_deg",
        "force_x_N",
        "force_y_N",
        "moment_x_Nm",
        "moment_y_Nm",
        "residual_force_x_N",
    } <= set(frame)
    assert len(frame) == 720


def test_order_vectors_of_a_flat_inline4():
    """The vector-method piece of the stage on its own: a flat-crank inline 4 cancels its first order
    and its rotating forces, and the four second-order forces add up (coefficient 4, Poda's table)."""
    from crankdyn_builtin.balancing.vectors import order_vectors

    g = bal.geometry_from_layout(_layout("inline4"))
    harmonics = bal.harmonics_for(MASSES.rod_ratio, bal.orders_needed(MASSES.rod_ratio))
    models = {
        0: bal.rotating_model(g),
        1: bal.reciprocating_model(g, 1),
        2: bal.reciprocating_model(g, 2),
    }
    C, C_I = MASSES.centrifugal_N, MASSES.first_order_N
    coefficients, absolute, orders = order_vectors(g, models, (1, 2), C, C_I, harmonics, 0.1)
    assert coefficients["sum_C"] < 1e-12 and coefficients["sum_PI"] < 1e-12
    assert coefficients["sum_PII"] == pytest.approx(4.0, abs=1e-12)
    assert absolute["sum_PII_N"] == pytest.approx(4.0 * abs(harmonics[2]) * C_I, rel=1e-12)
    assert [o["order"] for o in orders] == [0, 1, 2]


@pytest.mark.parametrize(
    "args, expected",
    [
        ((0, True, False, False), "self"),
        ((0, False, True, False), "counterweights"),
        ((1, False, True, True), "counterweights+shaft_backward"),
        ((2, False, True, True), "shaft_forward+shaft_backward"),
        ((4, False, True, True), "none"),
    ],
)
def test_remedy_names_the_means(args, expected):
    from crankdyn_builtin.balancing.means import remedy

    assert remedy(*args, balance_orders=(1, 2), first_order_forward="crankshaft") == expected


def test_a_single_cylinder_gets_a_counterweight_and_one_first_order_shaft_by_default():
    """Single-cylinder engines are built with a counterweight (C and the co-rotating half of P_I)
    and at most one counter-rotating shaft; the second order's two Lanchester shafts are asked for
    explicitly. More cylinders keep [1, 2] (an in-line four's second order needs the pair)."""
    one = balancing("petrol-1cyl")
    assert len(one["counterweights"]) == 1
    assert [s["speed_ratio"] for s in one["balance_shafts"]] == [-1]
    assert one["residual"]["balanced_orders"] == [1] and one["residual"]["vanishes"]
    asked = balancing("petrol-1cyl", {"balancing": {"balance_orders": [1, 2]}})
    assert sorted(s["speed_ratio"] for s in asked["balance_shafts"]) == [-2, -1, 2]
    four = balancing("inline4-petrol")
    assert four["residual"]["balanced_orders"] == [1, 2]
    assert sorted(s["speed_ratio"] for s in four["balance_shafts"]) == [-2, 2]


@pytest.mark.parametrize(
    "language, one, several",
    [
        ("en", "P_II remains", "P_II, P_IV remain"),
        (
            "uk",
            "незрівноваженою залишається величина P_II",
            "незрівноваженими залишаються величини P_II, P_IV",
        ),
        (
            "ru",
            "неуравновешенной остаётся величина P_II",
            "неуравновешенными остаются величины P_II, P_IV",
        ),
    ],
)
def test_the_abstracts_finding_agrees_in_number_with_what_stays_unbalanced(language, one, several):
    """One force left unbalanced 'remains', two 'remain' (the abstract read 'P_II remain'; then
    'незрівноваженими залишається ΣP_IV', a plural adjective: the word 'величина' carries the number)."""
    from crankdyn.report.i18n import translator

    t = translator(language, REGISTRY.catalogs)
    assert one in t("balancing.finding_unbalanced_means", count=1, items="P_II")
    assert several in t("balancing.finding_unbalanced_means", count=2, items="P_II, P_IV")


def test_the_vector_models_titles_set_the_orders_numeral_upright(tmp_path):
    """ΣP_I/C_I sets its Roman numerals upright in the figure, as the text does."""
    from crankdyn.cli import main

    out = tmp_path / "out"
    assert (
        main(
            [
                "report",
                str(examples_dir() / "petrol-1cyl.toml"),
                "-o",
                str(out),
                "--format",
                "html",
                "-q",
                "--stages",
                "balancing",
            ]
        )
        == 0
    )
    svg = "".join(
        p.read_text(encoding="utf-8") for p in (out / "figures").glob("*vector_models*.svg")
    )
    # divided by the dotted circle's radius |A_2| C_I, not by the textbook's C_II = λC_I
    assert r"$P_{\mathrm{II}}/(|A_{2}|C_{\mathrm{I}})$" in svg and "P_{II}" not in svg
    # one cylinder's own forces, no sums (no "ΣC/C" over a single crank), here as in its tables
    section = re.search(
        r'data-stage="balancing">.*?</section>',
        (out / "report.html").read_text(encoding="utf-8"),
        flags=re.S,
    ).group(0)
    assert r"\Sigma" not in svg and "Σ" not in section
    # one cylinder: no moments in the summary table, nor in its caption; each force is whole and
    # unbalanced, so neither table gives a coefficient (always 1) or a state (always unbalanced)
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "The forces and their balancing means" in html
    assert "Balance of the forces" not in html
    assert "<th>Coefficient</th>" not in section and ">unbalanced<" not in section
    assert "Largest force, in units of" not in section


@pytest.mark.parametrize(
    "name, changes, language, expected",
    [
        # no [balancing]: the note says that it chose the means, and names the radii it took
        ("v8-petrol", None, "ru", "Средства уравновешивания заданием не определены"),
        ("petrol-1cyl", None, "uk", "Засобів зрівноваження завдання не задає"),
        # the example's [balancing] gives the radii: the means are the assignment's
        ("inline3-petrol", None, "uk", None),
        ("v8-petrol", {"balancing": {"balance_orders": [1]}}, "en", None),
    ],
)
def test_the_note_says_when_it_chose_the_balancing_means(name, changes, language, expected):
    result = run(name, changes)
    r = result.outputs["balancing"].results
    html = render_html(result, REGISTRY, language).linked_html
    chosen = (
        "Средства уравновешивания заданием не определены",
        "Засобів зрівноваження завдання не задає",
        "assignment names no balancing",
    )
    if expected is None:
        assert r["means_given"] and not any(c in html for c in chosen)
        return
    assert not r["means_given"] and expected in html
    radius_mm = r["counterweight_radius_m"] * 1e3
    crank_radius_mm = result.scene.engine.stroke * 1e3 / 2  # R, the default centre of mass
    assert radius_mm == pytest.approx(crank_radius_mm)
    shown = f"{crank_radius_mm:g}".replace(".", ",")
    assert f"{shown} мм" in html.replace("\u00a0", " ").replace("\u202f", " ")


def test_an_engine_that_needs_no_means_names_the_internal_moments_on_its_bearings():
    """An in-line six balances its free forces and moments by its cranks (nothing to add), but the
    centrifugal forces' internal moments load the main bearings: the note says so."""
    changes = {
        "engine": {"cylinders": 6, "firing_order": [1, 5, 3, 6, 2, 4]},
        "flywheel": None,
        "torsion": None,
    }
    result = run("inline4-petrol", changes)
    r = result.outputs["balancing"].results
    html = render_html(result, REGISTRY, "ru").linked_html
    assert not r["counterweights"] and not r["balance_shafts"]
    assert "Внутренние моменты центробежных сил при этом нагружают коренные опоры" in html
    single = render_html(run("petrol-1cyl"), REGISTRY, "ru").linked_html
    assert "Внутренние моменты центробежных сил" not in single


def test_the_abstract_says_what_the_counterweights_alone_would_leave():
    """An in-line three's shafts take the counter-rotating half of ΣM_I, √3/2·C_I·a, and the
    second-order couple ΣM_II = √3·|A_2|·C_I·a (two shafts, one each way): the abstract names both
    as what the counterweights alone would leave."""
    from conftest import as_read, shared_html, shared_run

    b = shared_run("inline3-petrol", None, ("balancing",)).outputs["balancing"].results
    scale = b["first_order_N"] * b["cylinder_spacing_m"]
    loads = {s["speed_ratio"]: s["moment_Nm"] for s in b["balance_shafts"]}
    assert loads[-1] == pytest.approx(math.sqrt(3) / 2 * scale, rel=1e-9)
    second = math.sqrt(3) * abs(b["acceleration_harmonics"]["II"]) * scale
    assert loads[2] + loads[-2] == pytest.approx(second, rel=1e-9)
    text = as_read(re.sub(r"<[^>]+>", "", shared_html("inline3-petrol", None, "ru").linked_html))
    expected = (
        ", а без уравновешивающих валов, только с противовесами, неуравновешенными остались бы также "
        f"вращающаяся навстречу валу составляющая ΣMI ({loads[-1]:.1f}\u202fН·м) "
        f"и момент ΣMII = {second:.0f}\u202fН·м"
    ).replace(".", ",")
    assert expected in text


#: The in-line four as a flat four (cranks 0/180/180/0 by the firing order 1-3-2-4): it balances
#: its forces of every order and its first-order moment, and leaves ΣM_II (and higher even orders).
FLAT_FOUR = {"engine": {"layout": "boxer", "firing_order": [1, 3, 2, 4]}}
#: The default means (the example asks for the second order too).
FLYING_FLAT_FOUR = {"engine": {**FLAT_FOUR["engine"], "application": "aircraft"}, "balancing": None}


def test_a_flat_four_aircraft_engine_gets_no_second_order_shafts_and_says_where_its_moment_goes():
    from conftest import as_read, shared_html, shared_run

    car = shared_run("inline4-petrol", FLAT_FOUR, ("balancing",)).outputs["balancing"].results
    assert sorted(s["speed_ratio"] for s in car["balance_shafts"]) == [-2, 2]
    flying = shared_run("inline4-petrol", FLYING_FLAT_FOUR).outputs["balancing"].results
    assert not flying["balance_shafts"] and not flying["counterweights"]
    left = {s["quantity"] for s in flying["summary"] if not s["balanced"]}
    assert left == {"M_PII", "M_PIV", "M_PVI"}  # forces and first-order moment cancel in pairs
    text = as_read(
        re.sub(r"<[^>]+>", "", shared_html("inline4-petrol", FLYING_FLAT_FOUR, "ru").linked_html)
    )
    section = "оставленное неуравновешенным (ΣMII, ΣMIV) вызывает колебания двигателя на его опорах"
    assert text.count(section) == 2  # in the section and in the conclusions
    assert text.count("гасит амортизированная подмоторная рама") == 2
    assert "Уравновешивающие валы второго порядка не предусмотрены" not in text
    # the abstract names what the cranks balance and what they leave, with the values
    # the opposed cylinders balance with the cranks: the engine's scheme, not its cranks'
    assert "схема двигателя уравновешивает ΣC, ΣMC, ΣPI, ΣMI, ΣPII, ΣPIV и ΣPVI; " in text
    assert "уравновешивает схема колен" not in text and "уравновешено схемой колен" not in text
    assert re.search(r"неуравновешенными остаются ΣMII = \d+,\d\sН·м и ΣMIV = ", text)
    # the negligible ΣM_VI after them, as such
    assert re.search(
        r", а также ΣMVI = [\d,]+\sН·м – пренебрежимо малая величина \([\d,]+\s% от CI·a\)",
        text,
    )
    # a free moment is left: the note no longer says that the cranks balance every one of them
    assert "Свободные силы и моменты двигателя взаимно уравновешены" not in text
    assert "Противовесы коленчатого вала не уравновешивают" not in text  # there are none
    # a flat engine's main bearings are plain ones, judged as such
    assert "подшипниками качения" not in text


def test_an_engine_left_with_a_second_order_moment_by_default_says_why_it_has_no_shafts():
    """Second-order shafts are fitted only where asked for (a radial's balancer aside): by default
    the flat four keeps its ΣM_II, and the section and its conclusion say what two shafts at 2ω
    would take and why they are left out; a car's reason is not an aircraft's."""
    from conftest import as_read, shared_html, shared_run

    car = {**FLAT_FOUR, "balancing": None}
    r = shared_run("inline4-petrol", car, ("balancing",)).outputs["balancing"].results
    assert r["residual"]["balanced_orders"] == [1] and not r["balance_shafts"]
    # a radial's balancer takes the second order with the first, by default too
    assert balancing("radial9-aircraft")["residual"]["balanced_orders"] == [1, 2]
    left = {s["quantity"] for s in r["summary"] if not s["balanced"]}
    assert left == {"M_PII", "M_PIV", "M_PVI"}
    page = shared_html("inline4-petrol", car, "ru", ("balancing",)).linked_html
    text = as_read(re.sub(r"<[^>]+>", "", page))
    why = "Уравновешивающие валы второго порядка не предусмотрены: для уравновешивания ΣMII нужны"
    assert text.count(why) == 2  # in the section and in the conclusions
    assert "подмоторная рама" not in text
    # asked for, the shafts take it and the sentence goes
    asked = shared_html("inline4-petrol", FLAT_FOUR, "ru", ("balancing",)).linked_html
    assert "не предусмотрены" not in asked


def test_shafts_without_counterweights_leave_no_counterweights_in_the_abstract():
    from conftest import as_read, shared_html

    text = as_read(
        re.sub(r"<[^>]+>", "", shared_html("inline4-petrol", FLAT_FOUR, "ru").linked_html)
    )
    assert ", а без уравновешивающих валов неуравновешенным остался бы также момент ΣMII = " in text
    assert "только с противовесами" not in text


def test_a_270_degree_twins_first_order_shaft_is_said_to_take_its_force_and_its_moment():
    """A 270° twin's first-order shaft takes the counter-rotating parts of ΣP_I and of ΣM_I: the
    abstract names both, the force's and the moment's, after one plural noun."""
    from conftest import TWIN_270_ENGINE, as_read, shared_html, shared_run

    twin = {
        "engine": TWIN_270_ENGINE,
        "balancing": {"balance_orders": [1]},
    }
    b = shared_run("inline3-petrol", twin, ("balancing",)).outputs["balancing"].results
    (shaft,) = [s for s in b["balance_shafts"] if s["order"] == 1]
    assert shaft["force_N"] > 0 and shaft["moment_Nm"] > 0
    text = as_read(re.sub(r"<[^>]+>", "", shared_html("inline3-petrol", twin, "ru").linked_html))
    force = f"ΣPI ({shaft['force_N']:.0f}\u202fН)"
    moment = f"ΣMI ({shaft['moment_Nm']:.1f}\u202fН·м)".replace(".", ",")
    # both parts named by one plural noun, not "составляющая …" twice
    assert (
        "неуравновешенными остались бы также вращающиеся навстречу валу составляющие "
        f"{force} и {moment}"
    ) in text
    assert "составляющая ΣPI" not in text


@pytest.mark.parametrize(("example", "changes"), [("inline4-petrol", None), ("v8-petrol", None)])
def test_the_amplitudes_multiply_out_to_their_last_printed_digit(example, changes):
    """C = m_R R ω² with the printed factors gives the printed C to its last digit: a mass
    rounded to four digits (1,129 for 1,1285 kg) would move it by several newtons."""
    from conftest import as_read, shared_html

    text = as_read(re.sub(r"<[^>]+>", "", shared_html(example, changes, "ru").linked_html))
    found = re.findall(r"(C|CI) = m[Rs]Rω2 = ([\d,]+)·([\d,]+)·([\d,]+)2 = ([\d\s]+?)\sН", text)
    assert {name for name, *_ in found} == {"C", "CI"}
    for _, mass, radius, omega, result in found:
        m, r, w = (float(x.replace(",", ".")) for x in (mass, radius, omega))
        assert m * r * w**2 == pytest.approx(
            float(re.sub(r"\s", "", result)), abs=0.5 + 2e-5 * m * r * w**2
        )


def test_a_radials_second_order_part_of_its_slaves_is_said_to_be_theirs_where_it_is_balanced():
    """In a nine-cylinder star of alike cylinders the second-order forces cancel, both parts
    (Σ e^{∓jφ_i} and Σ e^{3jφ_i} vanish for the axes φ_i = 40°·i): what ΣP_II a radial has comes
    from its slave cylinders. The co-rotating part is too large to leave, the means balance it,
    and the section says whose it is; with the counter-rotating part left, the two make the
    table's largest ΣP_II."""
    from conftest import as_read, shared_html, shared_run

    slaves = shared_run("radial9-aircraft", None, ("bays",)).outputs["bays"].results["slaves"]
    phi = np.radians([0.0] + [s["bank_angle_deg"] for s in slaves])
    for k in (-1, 1, 3):
        assert abs(np.exp(1j * k * phi).sum()) < 1e-12
    b = shared_run("radial9-aircraft", None, ("balancing",)).outputs["balancing"].results
    (forward,) = b["slave_parts_balanced"]
    assert (forward["order"], forward["sense"]) == (2, "forward")
    assert forward["share_of_first_order"] > 0.1  # more than the share a shaft is spared for
    (backward,) = [p for p in b["parts_left"] if p["order"] == 2]
    (order,) = [o for o in b["orders"] if o["order"] == 2]
    assert forward["force_N"] + backward["force_N"] == pytest.approx(order["force_max_N"], rel=1e-9)
    text = as_read(
        re.sub(
            r"<[^>]+>", "", shared_html("radial9-aircraft", None, "en", ("balancing",)).linked_html
        )
    )
    force = f"{forward['force_N']:,.0f}".replace(",", "\u202f")
    assert (
        "their arrangement would also balance the part of the second-order forces "
        f"turning with the shaft, {force}\u202fN"
    ) in text.replace("&#39;", "'")
    assert "only the slave cylinders give it too, but that is more than a few per cent" in text


#: The in-line four made a three with the default means: its first-order couple takes a shaft.
INLINE_THREE = {"engine": {"cylinders": 3, "firing_order": [1, 3, 2]}, "balancing": None}


@pytest.mark.parametrize(
    "example, changes, moments",
    [
        ("petrol-1cyl", None, False),
        ("radial9-aircraft", None, False),
        ("inline4-petrol", INLINE_THREE, True),
    ],
)
def test_moments_are_named_only_where_the_cylinders_give_them(example, changes, moments):
    """A single cylinder's or a star's forces act in one plane across the shaft: what the means
    leave and what leaving them out would leave are forces, not "forces and moments"; an in-line
    engine's cylinders lie in several planes and keep the moments."""
    from conftest import shared_html

    page = shared_html(example, changes, "ru", ("balancing",)).linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", page).split())
    assert "если вибрации двигателя с неуравновешенными силами" in text
    assert ("с неуравновешенными силами и моментами" in text) is moments
    assert "из сил инерции и их моментов" not in text or moments


@pytest.mark.parametrize(
    "example, language",
    [
        ("petrol-1cyl", "uk"),
        ("petrol-1cyl", "en"),
        ("radial9-aircraft", "ru"),
        ("inline4-petrol", "en"),
        ("v8-petrol", "uk"),
        ("offset-crank-engine", "uk"),
    ],
)
def test_no_order_to_balance_leaves_the_counterweights_for_the_centrifugal_forces(
    example, language
):
    """``balance_orders = []`` (documented: the counterweights are sized for the centrifugal forces
    only) renders a note that says so: no order is named as balanced, none as "the orders ",
    and the check sentence speaks of the rotating forces alone."""
    from conftest import shared_html, shared_run

    changes = {"balancing": {"balance_orders": []}}
    run = shared_run(example, changes, ("balancing",))
    assert run.outputs["balancing"].results["residual"]["balanced_orders"] == []
    text = " ".join(
        re.sub(r"<[^>]+>", "", shared_html(example, changes, language, ("balancing",)).linked_html)
        .replace("&#39;", "'")
        .split()
    )
    assert "balancing." not in text  # no catalog key left unrendered
    assert not re.search(r"(order|orders|порядка|порядків|порядков|порядку) (,|\.|vanish)", text)
    if example == "petrol-1cyl" and language == "en":
        assert (
            "The balancing means: two counterweights. With them the centrifugal force is "
            "balanced (checked by adding them to the cylinder's real forces); the inertia forces "
            "are left unbalanced."
        ) in text


def test_the_conclusions_say_what_the_balancing_means_leave_with_values():
    """The conclusions said what the means balance and not what stays: an in-line three keeps
    ΣM_IV and ΣP_VI after its counterweights and shafts; the sentence gives ΣM_IV with its value,
    as the table of resultants does, and the negligible ΣP_VI, said the sentence before, not again
    as if it were not negligible."""
    from conftest import as_read, shared_html, shared_run

    b = shared_run("inline3-petrol", None, ("balancing",)).outputs["balancing"].results
    left = {s["quantity"] for s in b["summary"] if not s["balanced"]} - {"M_C", "M_PI", "M_PII"}
    assert left == {"M_PIV", "sum_PVI"}
    page = shared_html("inline3-petrol", None, "ru").linked_html
    conclusions = page[page.index('class="conclusions"') :]
    text = as_read(re.sub(r"<[^>]+>", "", conclusions))
    assert re.search(
        r"Средства уравновешивания: [^\n]*\. После установки средств уравновешивания, кроме "
        r"названной выше пренебрежимо малой величины, неуравновешенной остаётся "
        r"ΣMIV = \d+,\d Н·м \(",
        text.replace("\u202f", " "),
    ), text[:3000]


def test_an_axis_a_hair_short_of_180_degrees_is_printed_as_the_vertical():
    """A 45° V-twin's first-order hodograph lies along the V's bisector: its axis came out at
    179.99...°, printed "180,0" beside the other orders' "0,0" for the same direction."""
    from crankdyn.report.i18n import translator
    from crankdyn_builtin.balancing.tables import axis_text

    t = translator("uk")
    assert axis_text(t, 179.99999999) == "0,0"
    assert axis_text(t, 180.0) == "0,0"
    assert axis_text(t, 0.04) == "0,0"
    assert axis_text(t, 90.04) == "90,0"
    assert axis_text(t, 135.26) == "135,3"


def test_a_vector_models_arrows_end_on_their_vectors_tips():
    """Fig. "vector models" gives the dotted circle as C_ν: an arrow f = 1,000·C_I must reach it.
    matplotlib stops an annotation's arrow 2 pt short of each end (besides the stroke's own
    allowance at the head), which on a panel 3 cm wide read as f ≈ 0,8·C_I."""
    import numpy as np
    from matplotlib.path import Path

    from crankdyn.report.figures import prepare
    from crankdyn_builtin.balancing.figures import _models_drawing

    prepare()
    f, b = 1j * np.exp(0.4j), 0.7071 * np.exp(-0.3j)
    fig = _models_drawing([(1, "PI", 1, [("force", f, b, 1.7)])], False, 2, "")
    fig.canvas.draw()
    ax = fig.axes[0]
    gaps = []
    for annotation in ax.texts:
        patch = getattr(annotation, "arrow_patch", None)
        if patch is None:
            continue
        path = patch.get_path()  # in points (the figure's 72 dpi), as drawn
        points = path.vertices[path.codes != Path.CLOSEPOLY]
        end = ax.transData.transform([annotation.xy])[0]
        gaps.append(float(np.min(np.hypot(*(points - end).T))))
    # drawn as (imaginary, real): f from the origin, b from f's tip; the head's tip stops short
    # only by the stroke's allowance (about the line's width, 1.2 pt)
    assert len(gaps) == 2
    assert max(gaps) < 1.6, gaps


@pytest.mark.parametrize("name, shafts_fitted", [("v8-petrol", False), ("inline3-petrol", True)])
def test_the_means_describe_balance_shafts_only_where_shafts_are_fitted(name, shafts_fitted):
    """A cross-plane V8 balances with counterweights alone: its means paragraph gives the general
    rule for orders that need shafts but describes no shaft's masses; an in-line three fits both."""
    import re

    from conftest import shared_html, shared_run

    results = shared_run(name).outputs["balancing"].results
    assert bool(results["balance_shafts"]) is shafts_fitted and results["counterweights"]
    text = re.sub(r"<[^>]+>", "", shared_html(name, None, "en").linked_html)
    assert "needs a balance shaft turning at ν·ω" in text
    assert (
        "A balance shaft carries two masses, in the planes of the end cranks" in text
    ) is shafts_fitted


def _table_cells(html: str, caption: str) -> list[list[str]]:
    import html as html_lib
    import re

    for table in re.findall(r"<table.*?</table>", html, flags=re.S):
        if caption in re.sub(r"<[^>]+>", "", table):
            return [
                [
                    html_lib.unescape(re.sub(r"<[^>]+>", "", cell)).strip()
                    for cell in re.findall(r"<t[dh][^>]*>(.*?)</t[dh]>", row, flags=re.S)
                ]
                for row in re.findall(r"<tr.*?</tr>", table, flags=re.S)
            ]
    raise AssertionError(f"no table {caption!r}")


def test_a_balancing_tables_columns_keep_one_count_of_decimals():
    """The acceleration series to six decimals in both columns, the bay model's coefficients to
    four, a mass's position along the shaft in whole millimetres and its angle without ",0"."""
    import re

    from conftest import shared_html

    three = shared_html("inline3-petrol", None, "en").linked_html
    masses = _table_cells(three, "Masses, amplitudes of the forces and coefficients")
    series = [row[1:] for row in masses if row[0] in ("A2", "A4", "A6")]
    assert len(series) == 3
    assert all(re.fullmatch(r"−?0\.\d{6}", cell) for row in series for cell in row), series
    means = _table_cells(three, "Counterweights")
    assert [row[-1] for row in means[1:]] and all(
        re.fullmatch(r"\d+", row[-1]) for row in means[1:]
    ), means
    assert all(",0°" not in row[4] and ".0°" not in row[4] for row in means[1:]), means
    bay = _table_cells(shared_html("v8-petrol", None, "en").linked_html, "model of one bay")
    assert all(re.fullmatch(r"−?\d\.\d{4}", cell) for cell in bay[1]), bay


def test_counterweights_where_the_cranks_balance_everything_they_could_are_said_to_relieve_bearings():
    """A boxer four balances its centrifugal and first-order forces and moments by its cranks:
    counterweights fitted on every crank change none of the free forces, and the conclusion says
    what they are for; the in-line three's counterweights, which balance ΣM_C and ΣM_I, get no
    such sentence."""
    import re

    from conftest import FLAT_FOUR_ENGINE, shared_html, shared_run

    boxer = {"engine": FLAT_FOUR_ENGINE, "balancing": {"counterweights": "every_crank"}}
    results = shared_run("v8-petrol", boxer, ("balancing",)).outputs["balancing"].results
    assert results["counterweights"]
    targets = {"sum_C", "M_C", "sum_PI", "M_PI"}
    assert all(s["balanced"] for s in results["summary"] if s["quantity"] in targets)
    said = "The counterweights change none of the engine's free forces and moments"
    text = re.sub(r"<[^>]+>", "", shared_html("v8-petrol", boxer, "en", ("balancing",)).linked_html)
    assert said in text.replace("&#39;", "'")
    three = re.sub(r"<[^>]+>", "", shared_html("inline3-petrol", None, "en").linked_html)
    assert said not in three.replace("&#39;", "'")


def test_a_first_order_on_a_shaft_of_its_own_is_not_said_to_be_on_the_counterweights():
    """With the co-rotating first order put on a balance shaft, the counterweight is sized for
    the centrifugal force alone (m_R·R) and the means paragraph says so, where it said
    "Q = F + C"; with it on the crankshaft, the counterweight carries both."""
    import re

    from conftest import shared_html, shared_run

    shaft = {"balancing": {"first_order_forward": "shaft"}}
    r = shared_run("petrol-1cyl", shaft, ("balancing",)).outputs["balancing"].results
    forward = [s for s in r["balance_shafts"] if s["order"] == 1 and s["speed_ratio"] > 0]
    assert forward and r["counterweights"]
    text = re.sub(
        r"<[^>]+>", "", shared_html("petrol-1cyl", shaft, "en", ("balancing",)).linked_html
    )
    text = text.replace("&#39;", "'")
    assert "the counterweight's force Q = C, the centrifugal force" in text
    assert "Q = F + C" not in text
    plain = re.sub(
        r"<[^>]+>", "", shared_html("petrol-1cyl", None, "en", ("balancing",)).linked_html
    )
    assert "Q = F + C" in plain


def test_the_given_means_radii_and_rod_offset_are_among_the_task_data():
    """Radii of the counterweights' and shafts' masses and the rods' offset the scene gives stand
    in table 1.1 with the engine's data (they were in a later caption only); defaults stand among
    the values taken (table 1.2)."""
    import re

    from conftest import V_TWIN_ENGINE, shared_html

    given = {
        "engine": V_TWIN_ENGINE,
        "balancing": {
            "counterweight_radius": "42 mm",
            "balance_shaft_radius": "25 mm",
            "rod_offset": "18 mm",
        },
    }
    html = shared_html("v8-petrol", given, "en", ("balancing",)).linked_html
    text = re.sub(r"<[^>]+>", "|", html).replace("&#39;", "'")
    table = text[text.index("Table 1.1") : text.index("Table 1.2") if "Table 1.2" in text else None]
    for name, value in (
        ("Radius of the counterweights' centre of mass", "42"),
        ("Radius of the balance-shaft masses' centre of mass", "25"),
        ("Distance between the planes of the rods side by side on a crank pin", "18"),
    ):
        assert re.search(re.escape(name) + r"\|+" + value + r"\|+mm", table), name
    plain = shared_html("v8-petrol", None, "en", ("balancing",)).linked_html
    plain = re.sub(r"<[^>]+>", "|", plain).replace("&#39;", "'")
    given_table = plain[plain.index("Table 1.1") : plain.index("Table 1.2")]
    assert "Radius of the counterweights' centre of mass" not in given_table
    # the default radius R = 43 mm stands among the values taken
    taken = plain[plain.index("Table 1.2") :]
    assert re.search(r"Radius of the counterweights' centre of mass\|+43\|+mm", taken)


@pytest.mark.parametrize(
    ("example", "said"),
    [
        # the cross-plane V8's first-order couple turns with the shaft at a constant size (the
        # counterweights' task), as its centrifugal one does
        ("v8-petrol", "The free moments act as follows: ΣMC and ΣMI turn with the shaft at a "),
        # an in-line engine's inertia forces all lie along the vertical cylinder axes: their
        # couples pulsate in the vertical plane; the centrifugal couple turns with the shaft
        (
            "inline3-petrol",
            "ΣMC turns with the shaft at a constant size; ΣMI, ΣMII, and ΣMIV pulsate in the "
            "vertical plane through the shaft's axis and rock the engine about the horizontal axis across the shaft.",
        ),
    ],
)
def test_the_free_moments_motion_is_said_in_words(example, said):
    import re
    from html import unescape

    from conftest import shared_html

    html = shared_html(example, None, "en", ("balancing",)).linked_html
    text = unescape(re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html)))
    assert said in text


def test_a_single_cylinders_balance_shaft_beside_the_crankshaft_leaves_a_couple():
    """One counter-rotating first-order shaft balances the backward half of P_I, C_I/2, but
    beside the crankshaft: the couple, C_I/2 per metre of the shafts' distance, is said per
    100 mm; a shaft-free engine says nothing of it."""
    import re

    from conftest import shared_html, shared_run

    single = {"balancing": {"balance_orders": [1]}}
    r = shared_run("petrol-1cyl", single, ("balancing",)).outputs["balancing"].results
    assert [(s["order"], s["speed_ratio"]) for s in r["balance_shafts"]] == [(1, -1)]
    html = shared_html("petrol-1cyl", single, "en", ("balancing",)).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html)).replace("&#39;", "'")
    per = f"{r['first_order_N'] / 2 * 0.1:.1f}"
    assert f"form a couple of amplitude {per} N·m for every 100 mm of that distance" in text
    none = shared_html("petrol-1cyl", {"balancing": {"balance_orders": []}}, "en", ("balancing",))
    assert "for every 100 mm of that distance" not in none.linked_html


#: A 270° in-line twin (the in-line 4 example with two cylinders on cranks 0° and 270°)
#: whose first order is balanced by counterweights and one counter-rotating shaft.
TWIN_270 = {
    "engine": {
        "cylinders": 2,
        "firing_order": [1, 2],
        "crank_angles_deg": [0, 270],
        "uneven_firing": True,
    },
    "balancing": {"balance_orders": [1]},
}


def test_a_twins_counter_rotating_shaft_beside_the_crankshaft_leaves_its_force_times_the_distance():
    """A 270° twin's backward first-order parts do not cancel: |Σb_I| = C_I/2·|1 + e^(−j·270°)|
    = C_I·√2/2 is the one shaft's own force, and beside the crankshaft it forms a couple of that
    force per metre of the shafts' distance, said per 100 mm (not "the offset changes nothing")."""
    import re

    from conftest import shared_html, shared_run

    r = shared_run("inline4-petrol", TWIN_270, ("balancing",)).outputs["balancing"].results
    (shaft,) = r["balance_shafts"]
    assert shaft["speed_ratio"] == -1
    backward = r["first_order_N"] / 2 * abs(1 + np.exp(-1j * np.radians(270.0)))
    assert r["shaft_beside_force_N"] == pytest.approx(backward, rel=1e-9)
    assert shaft["force_N"] == pytest.approx(backward, rel=1e-9)
    assert r["shaft_beside_couple_per_100mm_Nm"] == pytest.approx(0.1 * backward, rel=1e-9)
    html = shared_html("inline4-petrol", TWIN_270, "en", ("balancing",)).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html)).replace("&#39;", "'")
    assert f"form a couple of amplitude {0.1 * backward:.1f} N·m for every 100 mm" in text
    assert "changes none of the forces and moments" not in text
    assert "side offset of the shafts does not change" not in text


def test_shafts_that_cancel_a_couple_only_may_lie_anywhere_beside_the_crankshaft():
    """The in-line 3's first-order couple shaft: its masses' forces add up to zero, so no couple
    is left beside the crankshaft and the note says why."""
    from conftest import shared_html, shared_run

    r = shared_run("inline3-petrol", None, ("balancing",)).outputs["balancing"].results
    assert r["balance_shafts"]
    assert all(s["force_N"] < 1e-6 * r["first_order_N"] for s in r["balance_shafts"])
    assert r["shaft_beside_couple_per_100mm_Nm"] is None
    html = shared_html("inline3-petrol", None, "en", ("balancing",)).linked_html
    assert "a couple acts alike wherever it is applied" in html


def test_a_single_cylinders_counterweight_for_the_centrifugal_force_alone_is_said_so():
    """No order to balance: the counterweight is sized for C alone, Q = C, and the note says
    so, not Q = F + C."""
    import re

    from conftest import shared_html, shared_run

    bare = {"balancing": {"balance_orders": []}}
    r = shared_run("petrol-1cyl", bare, ("balancing",)).outputs["balancing"].results
    (cw,) = r["counterweights"]
    omega = shared_run("petrol-1cyl", bare, ("balancing",)).scene.engine.angular_velocity_rad_s
    assert cw["mass_radius_kg_m"] * omega**2 == pytest.approx(r["centrifugal_N"], rel=1e-9)
    html = shared_html("petrol-1cyl", bare, "en", ("balancing",)).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html))
    assert "inertia force Q = C, C being the centrifugal force" in text
    assert "Q = F + C" not in text


def test_the_means_name_the_cranks_of_their_counterweights_and_only_what_they_balance():
    """The conclusions counted a web's counterweight as one ("four counterweights" beside a table
    of two cranks' rows), said "they balance ." of counterweights that change no free force or
    moment, and the means table's caption put a plural without a numeral in the genitive."""
    from conftest import shared_html

    def text(changes, language):
        page = shared_html("inline4-petrol", changes, language, ("balancing",)).linked_html
        return " ".join(re.sub(r"<[^>]+>", "", page).replace("&#39;", "'").split())

    every = {"balancing": {"counterweights": "every_crank"}}
    ru = text(every, "ru")
    assert (
        "Средства уравновешивания: по два противовеса на щеках каждого колена (всего 8) и два" in ru
    )
    assert "Противовесы (центр масс на радиусе" in ru
    assert "и уравновешивающие валы (центр масс на радиусе" in ru
    # the counterweights on every crank balance no free force here: the shafts balance ΣP_II
    assert "; валы уравновешивают силы инерции второго порядка" in ru, ru
    assert "; they balance" not in text(every, "en")
    # and the section says so at the counterweights' table, after the method's general words
    # on what counterweights cancel: there and in the conclusions
    said = "The counterweights change none of the engine's free forces and moments"
    assert text(every, "en").count(said) == 2
    internal = {"balancing": {"counterweights": "every_crank", "balance_orders": []}}
    en = text(internal, "en")
    assert "The balancing means: two counterweights on the webs of every crank (8 in all). " in en
    # each crank's counterweights cancel that crank's forces: no couple of the end cranks'
    assert "each crank's counterweights cancel that crank's own forces" in en
    assert "form a couple that cancels the moments of both" not in en
    assert "they balance ." not in en and "The counterweights change none of the engine" in en
    v8 = " ".join(
        re.sub(
            r"<[^>]+>", "", shared_html("v8-petrol", None, "uk", ("balancing",)).linked_html
        ).split()
    )
    assert "Засоби зрівноваження: чотири противаги на щоках колін 1 і 4; вони зрівноважують" in v8


def test_the_residual_check_gives_the_moments_left_after_the_means():
    """The check after the means spoke of forces only, while an in-line three's means are sized
    for moments: the remainder's moments are given too, and they are the fourth order's moment
    by the vector method (√3·|A_4|·C_I·a) within the higher orders' share."""
    from conftest import shared_html, shared_run

    r = shared_run("inline3-petrol", None, ("balancing",)).outputs["balancing"].results
    moment = r["residual"]["moment_max_Nm"]
    fourth = next(o["moment_max_Nm"] for o in r["orders"] if o.get("order") == 4)
    assert moment == pytest.approx(fourth, rel=0.02)
    page = shared_html("inline3-petrol", None, "en", ("balancing",)).linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", page).split()).replace("\u202f", " ")
    assert (
        f"Their moments likewise reduce to those of the orders left unbalanced: {moment:.3g} N·m"
        in text
    )


def test_the_internal_moments_of_the_centrifugal_forces_are_given_with_their_value():
    """An in-line six balances its centrifugal forces and their moment by its cranks, yet they
    bend the shaft and the crankcase between the halves: √3·C·a, given where no means are needed;
    an in-line four with balance shafts and no counterweights gets C·a; counterweights on every
    crank relieve it ("without them")."""
    from conftest import shared_html, shared_run

    def text(example, changes=None):
        page = shared_html(example, changes, "en", ("balancing",)).linked_html
        return " ".join(re.sub(r"<[^>]+>", "", page).replace("&#39;", "'").split())

    for example, coefficient in (("inline6-diesel-trace", math.sqrt(3.0)), ("inline4-petrol", 1.0)):
        r = shared_run(example, None, ("balancing",)).outputs["balancing"].results
        moment = coefficient * r["centrifugal_N"] * r["cylinder_spacing_m"]
        assert r["internal_moment_Nm"] == pytest.approx(moment, rel=1e-12)
        found = re.search(
            r"the largest (?:of these internal moments )?is ([\d\u202f.]+) N·m \(([\d.]+·)?C·a\)",
            text(example),
            re.I,
        )
        assert found, example
        assert float(found.group(1).replace("\u202f", "")) == pytest.approx(moment, rel=5e-4)
        # a factor of one is not written (C·a, not 1·C·a)
        factor = float(found.group(2).rstrip("·")) if found.group(2) else 1.0
        assert factor == pytest.approx(coefficient, rel=5e-4)
        assert (found.group(2) is None) == (coefficient == 1.0)
    assert "The largest of these internal moments is" in text("inline6-diesel-trace")
    assert "Counterweights on the webs of every crank would relieve them" in text("inline4-petrol")
    every = {"balancing": {"counterweights": "every_crank", "balance_orders": []}}
    assert "Without them the largest internal moment would be" in text("inline4-petrol", every)
    v8 = shared_run("v8-petrol", None, ("balancing",)).outputs["balancing"].results
    assert v8["internal_moment_Nm"] is None  # a cross-plane V8's ΣM_C is free: no internal moment
    # no means at all, ΣP_II left to the mounts (a straight eight's ΣP_IV alike): the section and
    # the conclusions still give the internal moment and its remedy
    none = {"balancing": {"balance_orders": []}}
    r = shared_run("inline4-petrol", none, ("balancing",)).outputs["balancing"].results
    assert not r["counterweights"] and not r["balance_shafts"]
    page = text("inline4-petrol", none)
    moment = f"{r['internal_moment_Nm']:.4g}"  # C·a, to four digits
    # scoped to the free forces: the internal moments' counterweights are advised just after
    assert "No means balancing the free forces and moments are fitted" in page
    assert "Counterweights on the webs of every crank would relieve them" in page
    conclusions = page[page.rindex("Conclusions") :]
    assert (
        f"still bend the crankshaft and the crankcase between the cranks with internal moments "
        f"of up to {moment} N·m (C·a)"
    ) in conclusions.replace("\u202f", ""), conclusions


def test_negligible_moments_alone_are_a_share_of_c_i_a_not_of_a_force():
    """A boxer four's only negligible remainder is a moment (ΣM_VI): the conclusion compared it
    with "one cylinder's first-order inertia force amplitude C_I" and then, in brackets, with
    C_I·a; it is now a share of C_I·a alone."""
    import html as html_lib

    from conftest import shared_html

    boxer = {"engine": {"layout": "boxer", "firing_order": [1, 3, 2, 4]}}
    page = shared_html("inline4-petrol", boxer, "en", ("balancing",)).linked_html
    text = html_lib.unescape(" ".join(re.sub(r"<[^>]+>", "", page).split()))
    assert re.search(
        r"Besides them, the unbalanced moment of the sixth order \(ΣMVI = [\d.]+ N·m\) is at most "
        r"[\d.]+ % of CI·a \(one cylinder's first-order inertia force amplitude CI times the "
        r"cylinder spacing a\) and negligible\.",
        text,
    )


def test_a_single_cylinders_shaft_beside_the_crankshaft_leaves_its_couple_in_the_conclusions():
    """The conclusions said the first order is balanced, while the section said the counter-
    rotating shaft beside the crankshaft leaves a couple of C_I/2 times the shafts' distance:
    the conclusions now say it too, per 100 mm."""
    import html as html_lib

    from conftest import shared_html, shared_run

    r = shared_run("petrol-1cyl", None, ("balancing",)).outputs["balancing"].results
    page = shared_html("petrol-1cyl", None, "en", ("balancing",)).linked_html
    conclusions = page[page.index('class="conclusions"') :]
    text = html_lib.unescape(" ".join(re.sub(r"<[^>]+>", "", conclusions).split()))
    found = re.search(
        r"leaves a first-order couple of amplitude ([\d.]+) N·m for every 100 mm", text
    )
    assert found, text[:600]
    assert float(found.group(1)) == pytest.approx(0.5 * r["first_order_N"] * 0.1, rel=5e-3)


def test_a_v_engines_note_names_no_cylinder_1_it_does_not_have():
    """A V engine's cylinders are 1L, 1R, …: "cylinder 1" (the balancing means' phases, the
    torque's cycle shifts, the bearings' axes and angle marks, the list of symbols) named one it
    does not have; the note says "the first cylinder" instead."""
    from conftest import shared_html

    page = shared_html("v8-petrol", None, "en").linked_html
    text = " ".join(re.sub(r"<[^>]+>", " ", page).split())
    assert not re.findall(r".{40}\bcylinder 1(?![\dLR]).{20}", text)
    assert "with the first cylinder at its TDC" in text


def test_the_masses_table_gives_a_of_every_order_analysed():
    """A scene that asks for the eighth order gets ΣP_VIII in the tables of orders: the masses
    table then gives A_8 too (a row without its coefficient cannot be checked), three
    significant digits where six decimals would print a few 10⁻⁷ as 0."""
    from conftest import shared_html, shared_run

    eight = {"balancing": {"include_orders": [1, 2, 4, 6, 8]}}
    r = shared_run("inline4-petrol", eight, ("balancing",)).outputs["balancing"].results
    page = shared_html("inline4-petrol", eight, "en", ("balancing",)).linked_html
    table = page[page.index("Masses, amplitudes") :]
    table = table[: table.index("</table>")]
    assert "<i>A</i><sub>8</sub>" in table and "<i>A</i><sub>6</sub>" in table
    a8 = r["acceleration_harmonics"]["VIII"]
    mantissa, exponent = f"{a8:.2e}".split("e")
    printed = f"{mantissa.replace('-', '−')}·10{str(int(exponent)).translate(SUPERSCRIPT)}"
    assert printed in table, printed
    plain = shared_html("inline4-petrol", None, "en", ("balancing",)).linked_html
    plain = plain[plain.index("Masses, amplitudes") :]
    assert "<i>A</i><sub>8</sub>" not in plain[: plain.index("</table>")]


SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


@pytest.mark.parametrize(
    ("orders", "said"),
    [
        ([1], "Параметры противовесов и уравновешивающего вала приведены"),
        ([1, 2], "Параметры противовесов и уравновешивающих валов приведены"),
    ],
)
def test_means_table_is_announced_with_its_shafts_counted(orders, said):
    """Counterweights and one balance shaft (the three-cylinder's first-order moment shaft) are
    announced with the shaft in the singular; with the second order's pair, in the plural."""
    from conftest import shared_html

    html = shared_html("inline3-petrol", {"balancing": {"balance_orders": orders}}, "ru")
    assert said in " ".join(html.linked_html.split())


@pytest.mark.parametrize(
    ("orders", "label"),
    [
        ([1], "Радиус центра масс противовесов уравновешивающего вала"),
        ([1, 2], "Радиус центра масс противовесов уравновешивающих валов"),
    ],
)
def test_given_shaft_radius_names_the_shafts_fitted(orders, label):
    """The given radius of the balance-shaft masses names one shaft (the three-cylinder's
    first-order moment shaft) in the singular and the second order's pair with it in the plural."""
    from conftest import shared_html

    html = shared_html(
        "inline3-petrol",
        {"balancing": {"balance_orders": orders, "balance_shaft_radius": "22 mm"}},
        "ru",
    )
    text = " ".join(html.linked_html.split())
    assert label + "<" in text.replace("</td>", "<").replace(" <", "<")


def _unit_text(html) -> str:
    import re

    return re.sub(r"<[^>]+>", "", " ".join(html.linked_html.split()))


def test_a_single_may_leave_the_counter_rotating_first_order_half():
    """``first_order_backward = "left"``: no balance shaft; the counterweights (Q = F + C, as with
    a shaft) leave half of C_I = m_s R ω² turning against the shaft, which the residual check,
    the summary, the given data, the abstract and the conclusions all say."""
    import math

    from conftest import shared_run

    run = shared_run("petrol-1cyl", {"balancing": {"first_order_backward": "left"}})
    r = run.outputs["balancing"].results
    e = run.scene.engine
    omega = math.pi * e.rpm / 30
    c_i = r["reciprocating_mass_kg"] * e.crank_radius_m * omega**2
    assert r["balance_shafts"] == []
    (part,) = r["parts_left_chosen"]
    assert (part["order"], part["sense"]) == (1, "backward")
    assert part["force_N"] == pytest.approx(c_i / 2, rel=1e-12)
    assert r["residual"]["vanishes"]
    first = next(s for s in r["summary"] if s["quantity"] == "sum_PI")
    assert first["remedy"] == "counterweights+left_backward"
    # the counterweights are those of the default (a shaft for the other half): Q = F + C
    default = shared_run("petrol-1cyl").outputs["balancing"].results
    assert [c["mass_radius_kg_m"] for c in r["counterweights"]] == pytest.approx(
        [c["mass_radius_kg_m"] for c in default["counterweights"]], rel=1e-12
    )
    text = _unit_text(
        shared_html("petrol-1cyl", {"balancing": {"first_order_backward": "left"}}, "uk")
    )
    half = f"{round(c_i / 2)} Н"
    assert (
        f"незрівноваженими залишаються половина сили першого порядку, що обертається назустріч валу, {half}"
        in text
    )
    assert "за завданням її залишено незрівноваженою" in text
    assert "З ними зрівноважено відцентрову силу і половину сили інерції першого порядку" in text
    assert "немає (складову залишено незрівноваженою)" in text


def test_a_three_leaves_the_counter_rotating_half_of_its_first_order_couple():
    """The in-line three's first-order couple √3·C_I·a pulsates in the cylinders' plane: its
    counter-rotating half, √3/2·C_I·a, is what ``first_order_backward = "left"`` leaves."""
    import math

    from conftest import shared_run

    run = shared_run("inline3-petrol", {"balancing": {"first_order_backward": "left"}})
    r = run.outputs["balancing"].results
    a = run.scene.engine.cylinder_spacing
    (part,) = r["parts_left_chosen"]
    assert part["moment_Nm"] == pytest.approx(math.sqrt(3) / 2 * r["first_order_N"] * a, rel=1e-9)
    assert part["force_N"] == pytest.approx(0.0, abs=1e-9 * r["first_order_N"])
    assert all(shaft["order"] == 2 for shaft in r["balance_shafts"])
    text = _unit_text(
        shared_html("inline3-petrol", {"balancing": {"first_order_backward": "left"}}, "en")
    )
    # with the negligible rest named after it: not "only"
    assert "the part of the first-order moments turning against the shaft" in text


def test_the_summary_table_marks_an_order_left_unbalanced_but_negligible():
    """P_IV and P_VI of the single cylinder are under 1 % of C_I (|A_4|, |A_6| of the example's
    λ): left unbalanced, and marked negligible in the table as the conclusions call them; P_II
    (|A_2| ≈ λ) is not."""
    import re

    from conftest import shared_html, shared_run

    r = shared_run("petrol-1cyl", None, ("balancing",)).outputs["balancing"].results
    shares = r["first_order_shares"]
    assert shares["sum_PIV"] < 0.01 and shares["sum_PVI"] < 0.01 < shares["sum_PII"]
    html = shared_html("petrol-1cyl", None, "en", ("balancing",)).linked_html
    rows = {
        m.group(1): m.group(2)
        for m in re.finditer(
            r"<tr><td[^>]*><i>P</i><sub>(\w+)</sub></td>(?:<td[^>]*>[^<]*</td>)*?"
            r"<td[^>]*>(left unbalanced[^<]*)</td></tr>",
            html,
        )
    }
    assert rows["IV"] == rows["VI"] == "left unbalanced (negligible)"
    assert rows["II"] == "left unbalanced"


#: The flat four, its rod ratio 1/4: of its free moments only ΣM_II is over 1 % of C_I·a.
LONG_ROD_FLAT_FOUR = {
    "engine": {**FLYING_FLAT_FOUR["engine"], "rod_ratio": 0.25},
    "balancing": None,
}


@pytest.mark.parametrize(
    ("changes", "free_moments"),
    [(LONG_ROD_FLAT_FOUR, ["PII"]), (FLYING_FLAT_FOUR, ["PII", "PIV"]), (None, [])],
)
def test_one_free_moment_is_said_in_the_singular(changes, free_moments):
    """The free moments' sentence agrees with how many there are (those over 1 % of C_I·a):
    "The free moment ΣMII pulsates …" for one, "The free moments act as follows: ΣMII and ΣMIV
    pulsate …" for two, nothing where there is none (the in-line 4)."""
    import re

    from conftest import shared_html, shared_run

    r = shared_run("inline4-petrol", changes, ("balancing",)).outputs["balancing"].results
    free = [
        o["name"]
        for o in r["orders"]
        if o["moment_coefficient"] * o["amplitude_N"] >= 0.01 * r["first_order_N"]
    ]
    assert free == free_moments
    text = re.sub(r"<[^>]+>", "", shared_html("inline4-petrol", changes, "en").linked_html)
    assert ("The free moment ΣMII pulsates" in text) == (len(free) == 1)
    assert ("The free moments act as follows: ΣMII and ΣMIV pulsate" in text) == (len(free) == 2)
    if not free:
        assert "The free moment" not in text


def test_a_short_vectors_name_stands_clear_of_its_head():
    """A vector's name stands 5 pt off the middle of its arrow, square to it; an arrow under 0.3
    of the panel's half-width is mostly its head, and its name stands 9 pt off instead."""
    from crankdyn_builtin.balancing.figures import _name_arrow

    class Axes:
        def annotate(self, name, xy, xytext, **kwargs):
            self.placed = (name, xy, xytext)

    ax = Axes()
    _name_arrow(ax, "f", 0j, 1 + 0j, side=1.0, half_width=1.25)  # up the panel, 0.8 of it
    assert ax.placed[1] == (0.0, 0.5) and ax.placed[2] == pytest.approx((-5.0, 0.0))
    _name_arrow(ax, "b", 0j, 0.2 + 0j, side=-1.0, half_width=1.25)  # 0.16 of the panel
    assert ax.placed[2] == pytest.approx((9.0, 0.0))


def test_a_counter_rotating_vector_turned_back_over_the_other_is_named_on_the_other_side():
    """b drawn from f's tip back over f (an offset single's third order: b ≈ −f) has its middle
    where f's is; named on its right, as usual, it stood on f's name ("bf"). Named on its left
    it stands across the arrows from f; a b going on past f keeps its right."""
    from crankdyn_builtin.balancing.figures import _models_drawing

    def offsets(f, b):
        fig = _models_drawing([(3, "PIII", 3, [("force", f, b, 1.0)])], False, 1, "balanced")
        names = {a.get_text(): a.xyann for a in fig.axes[0].texts if a.get_text() in "fb"}
        return np.array(names["f"]), np.array(names["b"])

    f_at, b_at = offsets(0.5 + 0.02j, -0.49 + 0.01j)
    assert np.dot(f_at, b_at) < 0  # on opposite sides of the common line
    f_at, b_at = offsets(0.5 + 0.0j, 0.4 + 0.0j)
    assert np.dot(f_at, b_at) < 0  # f on the left of the line, b on the right


def test_an_order_tables_roman_numeral_one_is_upright_as_its_others():
    """The resultants' table names its rows C, I, II …: the Roman numeral I stays upright, as II
    and IV do (a cell of one letter is otherwise a symbol, set in italics: the criteria z, t)."""
    from crankdyn.report.typeset import typeset_html

    html = typeset_html(
        '<table><tr><td class="text">I</td><td class="text">II</td><td class="text">z</td></tr></table>',
        "uk",
        [],
    )
    assert '<td class="text">I</td><td class="text">II</td><td class="text"><i>z</i></td>' in html
    page = shared_html("inline4-petrol", None, "uk", ("balancing",)).linked_html
    assert '<td class="text">I</td>' in page and '<td class="text"><i>I</i></td>' not in page


def test_a_means_table_of_counterweights_alone_gives_no_speed_column():
    """Counterweights turn with the shaft: with no balance shaft the means table's speed column
    would read +1 in every row; it is left out, and kept where shafts turn at other speeds."""
    import re

    from conftest import shared_run

    def means_table(name, changes=None):
        html = shared_html(name, changes, "en", ("balancing",)).linked_html
        caption = re.search(
            r"<caption>Table \d+\.\d+ . (?:Counterweights|Balance shafts?)[^<]*</caption>", html
        )
        return html[caption.start() : html.index("</table>", caption.start())]

    r = shared_run("v8-petrol", None, ("balancing",)).outputs["balancing"].results
    assert r["counterweights"] and not r["balance_shafts"]
    assert "multiples of ω" not in means_table("v8-petrol")
    assert "multiples of ω" in means_table("inline4-petrol")  # Lanchester's shafts at 2ω


def test_counterweights_that_change_no_free_force_are_no_means_of_the_abstract():
    """An in-line six with counterweights on every crank: they relieve the main bearings and
    change no free force, so the abstract says what the crank arrangement balances, not what
    stays "after the balancing means are fitted"."""
    import html as markup

    from conftest import shared_html

    every = {"balancing": {"counterweights": "every_crank"}}
    page = markup.unescape(shared_html("inline6-diesel-trace", every, "en").linked_html)
    abstract = " ".join(
        re.sub(
            r"<[^>]+>",
            "",
            re.search(r'<section class="abstract".*?</section>', page, re.S).group(0),
        ).split()
    )
    assert "the arrangement of the cranks balances ΣC" in abstract
    assert "balancing means fitted" not in abstract
