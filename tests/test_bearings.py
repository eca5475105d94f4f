"""Vector load diagrams of crank pins, main journals and bearings."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from conftest import shared_html, shared_run

from crankdyn.engine.orchestrator import run_scene
from crankdyn.physics import bearings as brg
from crankdyn.plugin.registry import default_registry

REGISTRY = default_registry()


def run(name, changes=None):
    """One computation per scene and worker, shared by the tests (they only read the results) and
    with the other test files (conftest.shared_run)."""
    return shared_run(name, changes)


def test_single_cylinder_pin_diagram_is_t_and_z_plus_c_rod():
    result = run("petrol-1cyl")
    s = result.scene
    forces = result.outputs["forces"].tables["forces"]
    table = result.outputs["bearings"].tables["bearings"]
    # c of the rod's rotating part, computed here from the scene independently of the stages.
    area = np.pi * s.engine.bore**2 / 4
    c_rod = (
        -s.masses.rod
        * (1 - s.masses.rod_cm_fraction)
        * s.engine.crank_radius_m
        * s.engine.angular_velocity_rad_s**2
        / area
    )
    np.testing.assert_allclose(table["pin1_t_Pa"], forces["tangential_Pa"], rtol=0, atol=1e-6)
    np.testing.assert_allclose(table["pin1_z_Pa"], forces["radial_Pa"] + c_rod, rtol=0, atol=1e-6)


def test_single_cylinder_rod_bearing_is_the_rotated_reverse():
    result = run("petrol-1cyl")
    table = result.outputs["bearings"].tables["bearings"]
    alpha = np.radians(table["crank_angle_deg"].to_numpy())
    beta = np.arcsin(result.scene.engine.rod_ratio_value * np.sin(alpha))
    t, z = table["pin1_t_Pa"].to_numpy(), table["pin1_z_Pa"].to_numpy()
    angle = alpha + beta
    # Rotate (t, z) by (alpha + beta) as a complex number in the z-t plane and reverse it.
    rotated = -(z + 1j * t) * np.exp(-1j * angle)
    np.testing.assert_allclose(table["rod_bearing1_z_Pa"], rotated.real, atol=1e-6)
    np.testing.assert_allclose(table["rod_bearing1_t_Pa"], rotated.imag, atol=1e-6)
    np.testing.assert_allclose(
        np.hypot(table["rod_bearing1_t_Pa"], table["rod_bearing1_z_Pa"]), np.hypot(t, z), rtol=1e-12
    )


def test_inline4_journal_loads_mirror_symmetric_and_reactions_balance():
    result = run("inline4-petrol")
    r = result.outputs["bearings"].results
    journals = r["main_journals"]
    for a, b in ((0, 4), (1, 3)):
        assert journals[a]["max_N"] == pytest.approx(journals[b]["max_N"], rel=1e-9)
        assert journals[a]["mean_N"] == pytest.approx(journals[b]["mean_N"], rel=1e-9)
    # Sum of the loads on all journals = sum of the forces on all cranks, at every angle.
    loads = result.outputs["torque"].data["crank_loads"]
    layout = result.outputs["bays"].data["bay_loads"].layout
    theta = np.radians(loads.crank_angle_deg)
    positions = np.array([theta - np.radians(lag) for lag in layout.crank_lag_deg])
    fa, fn = brg.crank_force_engine_frame(
        loads.tangential_Pa, loads.radial_Pa, loads.centrifugal_Pa, positions
    )
    ja, jn = brg.journal_loads(fa, fn, np.full(4, 0.5), np.full(4, 0.5))
    np.testing.assert_allclose(ja.sum(axis=0), fa.sum(axis=0), atol=1e-6)
    np.testing.assert_allclose(jn.sum(axis=0), fn.sum(axis=0), atol=1e-6)
    # The stage's main-bearing loads are these journal loads in engine axes.
    table = result.outputs["bearings"].tables["bearings"]
    np.testing.assert_allclose(
        np.hypot(table["main_bearing2_t_Pa"], table["main_bearing2_z_Pa"]),
        np.hypot(ja[2], jn[2]),
        rtol=1e-12,
    )


def test_journal_loads_match_textbook_equations_50_to_53():
    """Eq. (48)-(53): journal between cranks i and i+1 in the axes of crank i."""
    rng = np.random.default_rng(3)
    n = 37
    t = rng.normal(size=(2, n))
    z = rng.normal(size=(2, n))
    c = -0.7
    theta = rng.uniform(0, 2 * np.pi, n)
    phi_k = np.radians(120.0)  # crank i+1 trails crank i by 120 deg
    positions = np.array([theta, theta - phi_k])
    fa, fn = brg.crank_force_engine_frame(t, z, c, positions)
    l1, l2 = 0.4, 0.55  # l'_i+1/l_i+1 and l''_i/l_i shares
    ja, jn = brg.journal_loads(fa, fn, np.array([1 - l2, l1]), np.array([l2, 1 - l1]))
    e_t, e_z = brg.crank_axes(positions[0])
    jt, jz = brg.to_frame(ja[1], jn[1], e_t, e_z)
    z2, t2, c2 = l2 * z[0], l2 * t[0], l2 * c  # z''_i, t''_i, c''_i
    z1, t1, c1 = l1 * z[1], l1 * t[1], l1 * c  # z'_(i+1), t'_(i+1), c'_(i+1)
    # Textbook (50)-(53): its angle between the cranks is the one by which crank i+1 leads
    # crank i, i.e. minus our lag; its c is the magnitude (ours is negative: c = -|c|).
    phi = -phi_k
    z_book = z2 + z1 * np.cos(phi) + t1 * np.sin(phi) - (-c2 - c1 * np.cos(phi))  # (50) + (51)
    t_book = t2 + t1 * np.cos(phi) - z1 * np.sin(phi) + (-c1) * np.sin(phi)  # (52) + (53)
    np.testing.assert_allclose(jz, z_book, atol=1e-12)
    np.testing.assert_allclose(jt, t_book, atol=1e-12)


def test_wear_diagram_and_oil_hole():
    # A load that always presses at +z: the least-loaded arc is centred opposite, at 180 deg.
    psi, wear = brg.wear_diagram(np.zeros(10), np.ones(10), np.ones(10))
    start, end, centre = brg.least_loaded_arc(psi, wear)
    assert centre == pytest.approx(180.0, abs=1.0)
    assert wear.max() == pytest.approx(10.0) and wear.min() == 0.0


def test_wear_diagram_counts_each_load_over_its_spread():
    # Loads pressing at 0.5, 90.5 and 200.5 deg (off the 1-deg surface grid, so no psi sits exactly
    # at the 60 deg edge) with weights 1, 2, 4: the wear at psi is the sum of the
    # weights whose contact is within 60 deg.
    angles = np.radians([0.5, 90.5, 200.5])
    psi, wear = brg.wear_diagram(np.sin(angles), np.cos(angles), [1.0, 2.0, 4.0])
    expected = [
        sum(
            w
            for a, w in zip((0.5, 90.5, 200.5), (1.0, 2.0, 4.0), strict=True)
            if abs((p - a + 180.0) % 360.0 - 180.0) <= 60.0
        )
        for p in psi
    ]
    np.testing.assert_allclose(wear, expected)


@pytest.mark.parametrize("spread, resolution", [(60.0, 1.0), (30.0, 0.5), (0.5, 1.0), (89.5, 2.0)])
def test_wear_diagram_equals_its_definition_on_and_off_the_surface_grid(spread, resolution):
    # The runs of surface points found per load must be those of the definition
    # |psi - contact| <= spread on the circle, also for contacts exactly on the grid (edges
    # included), next to 0/360 (runs that wrap) and a spread narrower than the grid (loads that
    # cover no point); where nothing presses the wear is exactly 0.
    rng = np.random.default_rng(7)
    degrees = np.concatenate(
        [rng.uniform(0, 360, 300), np.arange(0.0, 360.0, 7.0), [0.0, 359.9999999, 1e-9, 300.0]]
    )
    weight = rng.uniform(0.5, 3.0, degrees.size)
    a = np.radians(degrees)
    psi, wear = brg.wear_diagram(weight * np.sin(a), weight * np.cos(a), weight, spread, resolution)
    contact = np.degrees(np.arctan2(weight * np.sin(a), weight * np.cos(a))) % 360.0
    inside = np.abs((psi[:, None] - contact[None, :] + 180.0) % 360.0 - 180.0) <= spread
    np.testing.assert_allclose(wear, (inside * weight).sum(axis=1), rtol=1e-12, atol=0)
    assert np.array_equal(wear == 0, ~inside.any(axis=1))


def test_results_keys_per_pin_and_journal():
    r = run("v8-petrol").outputs["bearings"].results
    assert len(r["crank_pins"]) == 4 and len(r["main_journals"]) == 5
    for entry in r["crank_pins"] + r["main_journals"]:
        for key in ("max_N", "mean_N", "max_MPa", "mean_MPa", "oil_hole_deg"):
            assert np.isfinite(entry[key])
        assert entry["max_N"] >= entry["mean_N"] > 0


def test_main_journals_are_named_by_the_cranks_they_lie_between_each_name_once():
    """0 is the free end, the number after the last crank the other end: a single-throw shaft has
    journals 0-1 and 1-2 ("1-0" would read as 0-1 written backwards)."""
    assert [
        j["journal"] for j in run("petrol-1cyl").outputs["bearings"].results["main_journals"]
    ] == ["0-1", "1-2"]
    v8 = run("v8-petrol").outputs
    assert [j["journal"] for j in v8["bearings"].results["main_journals"]] == [
        "0-1",
        "1-2",
        "2-3",
        "3-4",
        "4-5",
    ]
    assert [j["journal"] for j in v8["torque"].results["journals"]] == ["1-2", "2-3", "3-4", "4-5"]


@pytest.mark.parametrize("language", ["en", "uk"])
def test_bearing_section_renders(language):
    html = shared_html(
        "inline4-petrol", language=language
    ).linked_html  # shared with other test files (read only)
    assert 'data-stage="bearings"' in html
    assert html.count('src="figures/') >= 10
    # a journal's name "2–3": an en dash between the cranks' numbers ("0-1" beside the pins' "1–4"
    # would read as two conventions; the pins' range is "1…4"); the results keep "0-1"
    section = html[html.index('data-stage="bearings"') :]
    section = section[: section.index("</section>")]
    text = re.sub(r"<[^>]+>", " ", re.sub(r"<svg.*?</svg>", "", section, flags=re.S))
    assert "2\u20133" in text and not re.search(r"\b\d-\d\b", text)


def test_load_diagram_labels_of_coinciding_points_are_merged():
    """alpha and alpha + 360 deg at (nearly) one point of a load diagram share one label."""
    from crankdyn_builtin.bearings.labels import _coinciding

    x = [0.0, 1.0, 0.001, 2.0, 1.02, 5.0]
    y = [0.0, 1.0, 0.0, 2.0, 1.0, 5.0]
    assert _coinciding(x, y, 0.05) == [(0, [0, 2]), (1, [1, 4]), (3, [3]), (5, [5])]
    assert _coinciding(x, y, 0.0) == [(0, [0]), (1, [1]), (2, [2]), (3, [3]), (4, [4]), (5, [5])]


def test_load_diagram_labels_move_to_a_free_corner():
    """A label whose place up and right of its point is taken goes to the first free corner."""
    from crankdyn_builtin.bearings.labels import _label_places

    points, texts = [(0.0, 0.0), (1.0, 0.0), (100.0, 100.0)], ["210", "570", "30"]
    places = _label_places(points, texts, per_pt=1.0)  # a 3-digit label is about 10 x 7 pt
    # up and right of the first point is nearer the second one: the first goes to the next corner,
    # and the second, its up-right corner free, takes it
    assert places[0] == (-2, 2, "right", "bottom")
    assert places[1] == (2, 2, "left", "bottom")
    assert places[2] == (2, 2, "left", "bottom")  # far from the others


def test_load_diagram_labels_side_by_side_keep_a_gap():
    """ "210, 570" ending 1 pt before "30" would read as "210, 57030": the second label moves."""
    from crankdyn_builtin.bearings.labels import _label_places

    width = len("210, 570") * 3.8
    points = [(0.0, 0.0), (width + 1.0, 0.0)]  # "30" would start 1 pt after "210, 570" ends
    places = _label_places(points, ["210, 570", "30"], per_pt=1.0)
    # up and right of the first point the long label would lie over the second point: it goes left
    assert places[0] == (-2, 2, "right", "bottom") and places[1] == (2, 2, "left", "bottom")


def test_load_diagram_label_without_room_is_left_out_and_the_important_ones_go_first():
    """Crowded labels printed over each other were unreadable ("300, 660" on a tick label): a
    label with no free corner, near or further out, inside the plotting area, is left out (the
    point keeps its mark, the table its numbers); labels are placed in the order asked for."""
    from crankdyn_builtin.bearings.labels import _label_places

    # a box just large enough for the point itself: no 10 pt label fits inside
    assert _label_places([(0.0, 0.0)], ["210"], per_pt=1.0, bounds=(-3.0, -3.0, 3.0, 3.0)) == [None]
    # two points 1 pt apart: the one placed first takes the first corner nearer itself than the
    # other point (up and right of the left point is nearer the right one: it goes left)
    points, texts = [(0.0, 0.0), (1.0, 0.0)], ["30", "60"]
    assert _label_places(points, texts, per_pt=1.0, order=[1, 0])[1] == (2, 2, "left", "bottom")
    assert _label_places(points, texts, per_pt=1.0)[0] == (-2, 2, "right", "bottom")


def test_load_diagram_label_is_nearer_its_own_point_than_any_other():
    """No "330" beside the 480° mark, no "120" beside the 330° one: whatever the
    crowding, a label's box is nearer its own point than any other point."""
    from crankdyn_builtin.bearings.labels import _label_places

    rng = np.random.default_rng(7)
    points = [tuple(p) for p in rng.uniform(0.0, 60.0, size=(25, 2))]
    texts = [str(30 * k) for k in range(25)]
    placed = 0
    for i, place in enumerate(_label_places(points, texts, per_pt=1.0)):
        if place is None:
            continue
        placed += 1
        dx, dy, ha, va = place
        width, height = len(texts[i]) * 0.64 * 7.0, 1.17 * 7.0
        x0 = points[i][0] + dx - (width if ha == "right" else 0.0)
        y0 = points[i][1] + dy - (height if va == "top" else 0.0)

        def distance(p):
            return math.hypot(
                max(x0 - p[0], 0.0, p[0] - x0 - width),  # noqa: B023 - called within this iteration
                max(y0 - p[1], 0.0, p[1] - y0 - height),  # noqa: B023 - called within this iteration
            )

        assert all(distance(points[i]) < distance(q) for j, q in enumerate(points) if j != i), (
            texts[i]
        )
    assert placed >= 10  # the rule leaves most labels a place


def test_load_diagram_labels_keep_clear_of_the_pole_and_the_oil_hole():
    """No "90, 330, 660" printed over the oil hole's line, no "180" over the pole's O:
    a label's box meets none of the obstacles (pole, letter O, points along the line)."""
    from crankdyn_builtin.bearings.labels import _label_places, _pole_and_oil_hole

    obstacles = _pole_and_oil_hole(
        pole_z=0.0, radius=20.0, oil_deg=0.0, per_pt=1.0
    )  # the line runs up to z = 20
    # screen y is −z: the line occupies y in [−20, 0] at x = 0
    points = [(0.0, -20.0), (0.0, 0.0), (-3.0, -10.0)]
    places = _label_places(points, ["90, 330, 660", "180", "540"], per_pt=1.0, obstacles=obstacles)
    for (x, y), text, place in zip(points, ["90, 330, 660", "180", "540"], places, strict=True):
        if place is None:
            continue
        dx, dy, ha, va = place
        width, height = len(text) * 3.8, 7.0
        x0 = x + dx - (width if ha == "right" else 0.0)
        y0 = y + dy - (height if va == "top" else 0.0)
        for box in obstacles:
            assert min(x0 + width, box[2]) <= max(x0, box[0]) or min(y0 + height, box[3]) <= max(
                y0, box[1]
            ), (text, place, box)
    # without the obstacles the first choice, up and right, would have been taken
    assert _label_places(points[1:2], ["180"], per_pt=1.0) == [(2, 2, "left", "bottom")]
    assert places[1] != (2, 2, "left", "bottom")


def test_load_diagram_labels_keep_off_the_curve_and_face_outwards():
    """No label on the curve ("90, 450" on the loop it labels) nor inside a loop.
    With the curve given, a label goes to a corner the curve does not cross, facing away from the
    curve's centre; where every free corner is crossed, to the one crossed least."""
    import numpy as np

    from crankdyn_builtin.bearings.labels import _curve_samples, _label_places

    angle = np.radians(np.arange(0.0, 360.0, 1.0))
    circle = _curve_samples(50 * np.cos(angle), 50 * np.sin(angle), 1.0)
    assert (
        np.max(np.abs(np.hypot(*circle) - 50.0)) < 0.1
        and np.max(np.hypot(*np.diff(circle, axis=1))) <= 1.0
    )
    # the circle's left and right edges: the labels outside it, left and right
    places = _label_places([(-50.0, 0.0), (50.0, 0.0)], ["210", "30"], per_pt=1.0, curve=circle)
    assert places[0][2] == "right" and places[1][2] == "left"
    assert _label_places([(-50.0, 0.0)], ["210"], per_pt=1.0)[0] == (
        2,
        2,
        "left",
        "bottom",
    )  # inside, without it

    # a straight line through the point, up and right: the first corner would sit on it
    line = _curve_samples(np.linspace(-30, 30, 61), np.linspace(-30, 30, 61), 1.0)
    place = _label_places([(0.0, 0.0)], ["90, 450"], per_pt=1.0, curve=line)[0]
    width, height = len("90, 450") * 0.64 * 7.0, 1.17 * 7.0
    x0 = place[0] - (width if place[2] == "right" else 0.0)
    y0 = place[1] - (height if place[3] == "top" else 0.0)
    assert not np.any(
        (line[0] > x0) & (line[0] < x0 + width) & (line[1] > y0) & (line[1] < y0 + height)
    ), place
    assert _label_places([(0.0, 0.0)], ["90, 450"], per_pt=1.0)[0] == (2, 2, "left", "bottom")


def test_counterweight_loads_in_crank_axes():
    """+t is the direction of rotation, +z from the pin to the shaft axis (crank_axes): a
    counterweight opposite the pin pulls along +z, one 90° ahead along +t."""
    from crankdyn.plugin.contracts import Counterweights
    from crankdyn_builtin.bearings.compute import _counterweight_loads_Pa as counterweight_loads_Pa

    fitted = Counterweights(
        crank=np.array([0, 1, 1]),
        centrifugal_N=np.array([2.0, 3.0, 1.0]),
        angle_from_crank_rad=np.radians([180.0, 90.0, 0.0]),
    )
    t, z = counterweight_loads_Pa(fitted, 3, area_m2=0.5)
    np.testing.assert_allclose(t, [0.0, 6.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(z, [4.0, -2.0, 0.0], atol=1e-12)
    assert not np.any(counterweight_loads_Pa(None, 2, 1.0)[0])


def test_main_journals_carry_half_the_counterweight_of_a_single_crank():
    """The counterweight the balancing section fits, Q = F + C (half the first-order force and the
    rotating masses' centrifugal force, opposite the pin), acts on the crank between two equal
    spans: each main journal's diagram (the reaction, in crank axes) moves by -Q/2 along z at
    every angle, t unchanged; the crank pin's load does not change. Q from the masses of the
    forces stage, not from the balancing stage's numbers."""
    from crankdyn.engine.orchestrator import plan

    with_cw = run("petrol-1cyl")
    scene = with_cw.scene
    names = [s.name for s in plan(scene, REGISTRY).order if s.name != "balancing"]
    without = run_scene(scene, REGISTRY, names)
    f = with_cw.outputs["forces"].results
    e = scene.engine
    q_Pa = (
        (f["rotating_mass_kg"] + 0.5 * f["reciprocating_mass_kg"])
        * e.crank_radius_m
        * e.angular_velocity_rad_s**2
        / f["piston_area_m2"]
    )
    a, b = (
        with_cw.outputs["bearings"].tables["bearings"],
        without.outputs["bearings"].tables["bearings"],
    )
    assert with_cw.outputs["bearings"].results["with_counterweights"]
    assert not without.outputs["bearings"].results["with_counterweights"]
    for j in (0, 1):
        np.testing.assert_allclose(
            a[f"journal{j}_z_Pa"] - b[f"journal{j}_z_Pa"], -0.5 * q_Pa, rtol=1e-9
        )
        np.testing.assert_allclose(a[f"journal{j}_t_Pa"], b[f"journal{j}_t_Pa"], atol=1e-6 * q_Pa)
    np.testing.assert_allclose(a["pin1_z_Pa"], b["pin1_z_Pa"], rtol=1e-12)


def test_polar_summary_range_and_the_angles_of_its_extremes():
    """|(t, z)| = 5, 1, 2, 5 (3-4-5 triangles): the largest at the first of its equal samples."""
    t, z = np.array([3.0, 1.0, 2.0, 4.0]), np.array([4.0, 0.0, 0.0, 3.0])
    s = brg.polar_summary(
        t,
        z,
        piston_area_m2=2.0,
        diameter_m=0.5,
        width_m=0.1,
        crank_angle_deg=[0.0, 90.0, 180.0, 270.0],
    )
    assert (s["max_N"], s["min_N"], s["mean_N"]) == (10.0, 2.0, pytest.approx(6.5))
    assert (s["max_crank_angle_deg"], s["min_crank_angle_deg"]) == (0.0, 90.0)
    assert s["max_MPa"] == pytest.approx(10.0 / 0.05 / 1e6)
    # the cube-law mean of a roller bearing: ((10^p + 2^p + 4^p + 10^p)/4)^(1/p), p = 10/3
    p = 10.0 / 3.0
    expected = ((2 * 10.0**p + 2.0**p + 4.0**p) / 4.0) ** (1.0 / p)
    assert s["rolling_equivalent_N"] == pytest.approx(expected, rel=1e-12)


def test_a_rolling_bearings_mean_equivalent_load():
    """P_m = (mean Q^p)^(1/p): a constant load is itself; half a cycle at Q₁, half at Q₂ is
    ((Q₁^p + Q₂^p)/2)^(1/p); |A sin α| with p = 3 is A (4/(3π))^(1/3) (the mean of |sin|³);
    a load too large for its power to be computed directly still gives its value."""
    assert brg.rolling_equivalent_load_N(np.full(720, 4.2e3)) == pytest.approx(4.2e3, rel=1e-14)
    two_levels = np.r_[np.full(360, 1.0e3), np.full(360, 3.0e3)]
    p = 10.0 / 3.0
    assert brg.rolling_equivalent_load_N(two_levels) == pytest.approx(
        ((1.0e3**p + 3.0e3**p) / 2.0) ** (1.0 / p), rel=1e-12
    )
    alpha = np.linspace(0.0, 2.0 * np.pi, 100_000, endpoint=False)
    assert brg.rolling_equivalent_load_N(-5.0e3 * np.sin(alpha), exponent=3.0) == pytest.approx(
        5.0e3 * (4.0 / (3.0 * np.pi)) ** (1.0 / 3.0), rel=1e-9
    )
    assert brg.rolling_equivalent_load_N(two_levels * 1e200) == pytest.approx(
        1e200 * ((1.0e3**p + 3.0e3**p) / 2.0) ** (1.0 / p), rel=1e-12
    )
    assert brg.rolling_equivalent_load_N(np.zeros(8)) == 0.0


def test_a_crank_loads_its_journals_by_the_lever_rule_as_the_printed_formula_says():
    # A beam on two supports l apart, loaded at l′ from the first: the second carries F l′/l, the
    # first F l″/l (l″ = l − l′). journal_loads with share_after = l′/l (the stage's span_ratio)
    # must do so, and equation (9.3) must print R_j = −[(l′_i/l_i) F_i + (l″_{i+1}/l_{i+1}) F_{i+1}]
    # (the journal after crank i, before crank i+1), not the primes the other way round.
    l, l_prime = 1.0, 0.3
    force = np.array([[2.0, -1.0]])  # one crank, two angles
    before, after = brg.journal_loads(
        force, 3 * force, np.array([(l - l_prime) / l]), np.array([l_prime / l])
    )
    np.testing.assert_allclose(before[0], (l - l_prime) / l * force[0])
    np.testing.assert_allclose(before[1], l_prime / l * force[0])
    np.testing.assert_allclose(after[1], l_prime / l * 3 * force[0])
    import crankdyn_builtin.bearings as plugin

    with open(f"{plugin.__path__[0]}/templates/sections/bearings.html.j2", encoding="utf-8") as fh:
        text = fh.read()
    assert (
        "(<i>l</i>′<sub><i>i</i></sub>/<i>l</i><sub><i>i</i></sub>) <b><i>F</i></b><sub><i>i</i></sub> + "
        "(<i>l</i>″<sub><i>i</i>+1</sub>/<i>l</i><sub><i>i</i>+1</sub>)"
    ) in text


def test_pins_that_print_alike_take_one_row():
    """Table 9.1 of the in-line four does not repeat one row four times."""
    from crankdyn_builtin.bearings.worked import pin_rows as _pin_rows

    pin = {
        "max_N": 16370.0,
        "mean_N": 9890.0,
        "max_MPa": 10.22,
        "mean_MPa": 6.17,
        "oil_hole_deg": 175.0,
    }
    same = [dict(pin, crank=k) for k in range(1, 5)]
    assert _pin_rows(same) == (same[:1], ["1…4"])
    other = same[:3] + [dict(pin, crank=4, max_N=17000.0)]
    assert _pin_rows(other) == (other, ["1", "2", "3", "4"])
    assert _pin_rows(same[:1]) == (same[:1], ["1"])
    # two alike: both named, a range of two would read as if there were more between them
    assert _pin_rows(same[:2]) == (same[:1], ["1, 2"])


def test_two_narrow_polar_diagrams_stand_side_by_side_each_announced_with_its_number_bound():
    """No tall, narrow polar diagram alone on a page, half of it empty. A crank
    pin's and its rod bearing's diagrams (a main journal's and its bearing's) share a row when both
    are at most HALF_WIDTH_CM wide; "рис. 7.1" is never parted at a line's end."""
    import re

    from crankdyn_builtin.bearings.figures import (
        HALF_WIDTH_CM,
        POLAR_HEIGHT_CM,
        POLAR_HEIGHT_MAX_CM,
        _polar_size,
    )

    html = shared_html("petrol-1cyl-uk").linked_html
    rows = re.findall(
        r'<div class="figure-row-block"><p class="see">([^<]*)</p><div class="figure-row">(.*?)</div></div></div>',
        html,
        flags=re.S,
    )
    assert len(rows) == 2 and all(
        row.count("<figure ") == 2 and 'class="see"' not in row for _, row in rows
    ), len(rows)
    # announced together above the row, each figure by its number, before the row
    assert all(
        all(f"рис.\u00a0{n}" in sentences for n in re.findall(r'data-number="([^"]+)"', row))
        for sentences, row in rows
    )
    assert "рис.\u00a07.1" in html and "рис.\u00a07.2" in html
    # a tall diagram is only as wide as its plot needs; a round one keeps its height, stands
    # alone and is no taller than a tall one may be
    t = np.cos(np.linspace(0, 2 * np.pi, 73))
    assert _polar_size(t, 3 * np.sin(np.linspace(0, 2 * np.pi, 73)), 0.0, 0.12)[0] <= HALF_WIDTH_CM
    width, height = _polar_size(t, np.sin(np.linspace(0, 2 * np.pi, 73)), 0.0, 0.12)
    assert height == POLAR_HEIGHT_CM <= POLAR_HEIGHT_MAX_CM and width > HALF_WIDTH_CM
    # a flat one (a boxer's main bearing: t up to 10, z to 2, a journal circle of 0.12·10)
    # takes the full width and only the height its plot needs at equal scales (1.1 × 14 cm ×
    # 4/20), with 2.2 cm of labels: 5.28 of the usual 12 cm
    width, height = _polar_size(10 * t, 2 * np.sin(np.linspace(0, 2 * np.pi, 73)), 0.0, 0.12)
    assert width == 16.0
    assert height == pytest.approx(1.1 * 14.0 * 4.0 / 20.0 + 2.2, rel=1e-9)


def test_the_wear_diagram_shows_the_crank_axes_its_angles_are_counted_in():
    """Without axes and a direction the wear diagram's 0° cannot be related to +z nor the oil
    hole checked. It draws the crank's z (towards the shaft axis, at 0°)
    and t (the direction of rotation, at 90°), inside the journal's circle."""
    import numpy as np

    from crankdyn_builtin.bearings.figures import _wear_drawing

    psi = np.arange(0.0, 360.0, 1.0)
    wear = {"surface_angle_deg": psi, "pin1_wear_N": 1.0 + np.cos(np.radians(psi))}
    fig = _wear_drawing(wear, {"crank_pins": [{"oil_hole_deg": 180.0}]}, 1)
    ax = fig.axes[0]
    names = {text.get_text(): text.get_position() for text in ax.texts}
    assert names["$z$"][0] == 0.0 and abs(names["$t$"][0] - np.pi / 2) < 1e-12
    assert all(
        radius < 0.4 for _, radius in names.values()
    )  # clear of the wear, laid from 0.4 inwards at most
    assert sum(1 for child in ax.get_children() if type(child).__name__ == "Annotation") == 2


#: The V8 example as one cylinder: the same bore, stroke, rod, masses, cycle and speed.
ONE_CYLINDER = {
    "engine": {
        "cylinders": 1,
        "layout": "inline",
        "bank_angle_deg": None,
        "firing_order": None,
        "crank_angles_deg": None,
        "cylinder_spacing": None,
    },
    "balancing": None,
}


def test_each_rod_side_by_side_bears_its_own_cylinders_load_as_a_one_cylinder_engine():
    """A V8's big-end bearing carries only its own rod: at shaft angle theta, the bearing of a
    cylinder whose cycle runs delta behind equals the one-cylinder engine's rod bearing (same
    masses, one rod's centrifugal force) at its own cycle angle theta - delta, in its own rod's
    axes; its pressure is over the pin's width shared by the two bearings."""
    v8 = run("v8-petrol")
    one = run("v8-petrol", ONE_CYLINDER).outputs["bearings"]
    single = one.tables["bearings"]
    table, results = v8.outputs["bearings"].tables["bearings"], v8.outputs["bearings"].results
    step = float(table["crank_angle_deg"][1] - table["crank_angle_deg"][0])
    delays = {
        p["cylinder"]: p["cycle_delay_deg"] for p in v8.outputs["bays"].results["cylinder_phases"]
    }
    rods = results["rod_bearings"]
    assert results["rod_bearings_per_pin"] == 2 and len(rods) == 8
    for place, rod in enumerate(rods):
        name = f"rod_bearing{rod['crank']}_{place % 2 + 1}"
        shift = int(round(delays[rod["cylinder"]] / step))
        for axis in ("t", "z"):
            np.testing.assert_allclose(
                table[f"{name}_{axis}_Pa"].to_numpy(),
                np.roll(single[f"rod_bearing1_{axis}_Pa"].to_numpy(), shift),
                rtol=0,
                atol=1e-9 * float(np.abs(single[f"rod_bearing1_{axis}_Pa"]).max()),
            )
        reference = one.results["rod_bearings"][0]
        assert rod["max_N"] == pytest.approx(reference["max_N"], rel=1e-9)
        # the pin's width shared by two bearings of 0.45·d each (0.6·d for the one rod of the
        # one-cylinder engine): the pressure of the same force over the narrower bearing
        sizes, one_sizes = results["dimensions"], one.results["dimensions"]
        assert rod["width_m"] == pytest.approx(sizes["crank_pin_width_m"] / 2, rel=1e-12)
        assert rod["width_m"] == pytest.approx(0.45 * sizes["crank_pin_diameter_m"], rel=2e-3)
        ratio = one_sizes["crank_pin_width_m"] / rod["width_m"]
        assert rod["max_MPa"] == pytest.approx(ratio * reference["max_MPa"], rel=1e-9)
    # across its own rod a bearing feels only its rod's centrifugal force c_r sin(alpha + beta):
    # |t_r| stays within one rod's |c_r| (the other bank's rod force would exceed it)
    one_rod = abs(results["centrifugal_rod_Pa"]) / 2
    assert np.abs(table["rod_bearing1_1_t_Pa"]).max() <= one_rod * (1 + 1e-12)


def test_a_shared_pin_carries_the_sum_of_its_rods_own_loads():
    """The crank pin keeps the load of both rods: the sum of its two one-cylinder loads, each at
    its own cycle angle."""
    v8 = run("v8-petrol")
    single = run("v8-petrol", ONE_CYLINDER).outputs["bearings"].tables["bearings"]
    table = v8.outputs["bearings"].tables["bearings"]
    step = float(table["crank_angle_deg"][1] - table["crank_angle_deg"][0])
    phases = v8.outputs["bays"].results["cylinder_phases"]
    for axis in ("t", "z"):
        expected = np.zeros((4, len(table)))
        for p in phases:
            shift = int(round(p["cycle_delay_deg"] / step))
            expected[p["crank"] - 1] += np.roll(single[f"pin1_{axis}_Pa"].to_numpy(), shift)
        for k in range(4):
            np.testing.assert_allclose(
                table[f"pin{k + 1}_{axis}_Pa"].to_numpy(), expected[k], rtol=1e-12, atol=1e-6
            )


def test_a_fork_rods_bearing_carries_the_whole_pin_load():
    """The blade rod runs on the outside of the fork rod's bearing shell: the fork rod's one
    bearing on the pin carries both rods' load over the pin's whole width."""
    assert brg.big_end_bearings_on_pin("central", 2) == 2
    assert (
        brg.big_end_bearings_on_pin("fork", 2) == brg.big_end_bearings_on_pin("articulated", 4) == 1
    )
    assert brg.big_end_bearing_width_m(0.036, 2) == 0.018
    out = run("v8-petrol", {"engine": {"rod_type": "fork"}}).outputs["bearings"]
    r, table = out.results, out.tables["bearings"]
    assert "rod_bearings_per_pin" not in r and len(r["rod_bearings"]) == 4
    np.testing.assert_allclose(
        np.hypot(table["rod_bearing1_t_Pa"], table["rod_bearing1_z_Pa"]),
        np.hypot(table["pin1_t_Pa"], table["pin1_z_Pa"]),
        rtol=1e-12,
    )
    assert r["rod_bearings"][0]["max_MPa"] == pytest.approx(
        r["crank_pins"][0]["max_MPa"], rel=1e-12
    )


def test_a_v_engines_note_gives_each_rod_bearings_pressure_and_what_c_holds():
    """The pins table of a V8 gives the pins' loads (both rods) without a bearing pressure; the rod
    bearings' table gives each rod's own, over one bearing's width; the forces section says its c
    holds one cylinder's rod, the crank section that its q holds all."""
    import html as markup

    html = markup.unescape(shared_html("v8-petrol").linked_html)
    section = html[html.index('data-stage="bearings"') :]
    section = re.sub(r"<[^>]+>", " ", re.sub(r"<svg.*?</svg>", "", section, flags=re.S))
    rod = run("v8-petrol").outputs["bearings"].results["rod_bearings"][0]
    assert "each from its own rod's force only" in section
    assert (
        f"{rod['max_MPa']:.2f}" in section
        and f"B\u00a0=\u00a0{rod['width_m'] * 1e3:.4g}\u202fmm" in section
    )
    assert "of this cylinder's rod only" in html and "with the rods of all its cylinders" in html


def test_a_russian_note_names_each_rod_bearing_by_its_cylinders_russian_label():
    """The rod bearings of a V8 are named as the note prints its cylinders: 4Л, not 4L, in the
    figure titles, captions, references and the table of rod bearings."""
    rendered = shared_html("v8-petrol", None, "ru", ("bearings",))
    text = re.sub(r"<[^>]+>", " ", rendered.linked_html)
    assert re.search(r"подшипник цилиндра \d[ЛП]\b", text)
    assert not re.search(r"\b\d[LR]\b", text)
    svgs = [f.svg.decode() for f in rendered.figures if "rod" in f.name]
    assert svgs and all(not re.search(r">\d[LR]<|цилиндра \d[LR]", s) for s in svgs)


#: A tractor diesel 4Ч 11/12,5 on the in-line four's layout, without counterweights: its gas
#: forces set the peaks, the in-phase cranks 2 and 3 a steady centrifugal load on journal 2–3.
_TRACTOR = {
    "engine": {
        "rpm": 2200,
        "bore": "110 mm",
        "stroke": "125 mm",
        "rod_length": "230 mm",
        "rod_ratio": None,
        "cylinder_spacing": "130 mm",
    },
    "masses": {
        "piston_group": "2.4 kg",
        "rod": "2.9 kg",
        "rod_cm_fraction": 0.26,
        "crank_pin": "1.3 kg",
        "crank_web": "1.1 kg",
    },
    "cycle": {
        "ignition": "diesel",
        "compression_ratio": 16.0,
        "intake_pressure": "0.09 MPa",
        "compression_index": 1.36,
        "max_pressure": "7.6 MPa",
        "pre_expansion_ratio": 1.5,
        "expansion_index": 1.23,
        "exhaust_pressure": "0.11 MPa",
        "rounding": None,
    },
}


def test_a_journal_of_the_largest_mean_load_is_named_when_the_peak_picks_others():
    """Journals 1–2 and 3–4 carry the largest peak, journal 2–3 the largest mean (its steady
    centrifugal load, no counterweights): the conclusions name both, and the centrifugal
    assessment is about the journal of the largest mean."""
    run = shared_run("inline4-petrol", _TRACTOR, ("bearings",))
    results = run.outputs["bearings"].results
    assert not results["with_counterweights"]
    journals = results["main_journals"]
    peak = max(j["max_N"] for j in journals)
    by_mean = max(journals, key=lambda j: j["mean_N"])
    assert by_mean["max_N"] < peak  # the mean picks a journal the peak does not
    html = shared_html("inline4-petrol", _TRACTOR, "uk", ("bearings",)).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html))
    label = by_mean["journal"].replace("-", "–")
    assert (
        f"За середнім за цикл тиском найбільш навантажений підшипник корінної шийки {label}" in text
    )
    assert f"Найбільше середнє навантаження має корінна шийка {label};" in text


def test_rods_side_by_side_say_how_far_their_planes_lie_off_the_pins_middle():
    """A V8's two rods on a pin: each plane half a big-end bearing's width off the middle, which
    over the example's crank spacing a = 112 mm shifts the journals' shares by that ratio (the
    loads: test_each_side_by_side_rod_loads_the_main_journals_by_its_own_plane)."""
    r = shared_run("v8-petrol", None, ("bearings",)).outputs["bearings"].results
    width = r["rod_bearings"][0]["width_m"]
    assert r["rod_plane_offset_m"] == pytest.approx(width / 2, rel=1e-12)
    assert r["rod_plane_share_shift"] == pytest.approx(width / 2 / 0.112, rel=1e-12)
    text = re.sub(
        r"\s+", " ", re.sub(r"<[^>]+>", " ", shared_html("v8-petrol", None, "en").linked_html)
    )
    text = text.replace("&#39;", "'")
    # two rods: each is an outermost one
    assert f"each rod's plane lies {width / 2 * 1e3:.3g} mm off the pin's middle" in text
    # one rod per pin: nothing to say
    assert (
        "rod_plane_offset_m"
        not in shared_run("inline4-petrol", None, ("bearings",)).outputs["bearings"].results
    )


@pytest.mark.parametrize(
    ("example", "said"),
    [
        ("radial9-aircraft", "The main supports of radial aircraft engines are usually rolling"),
        ("two-stroke-1cyl", "The supports of small two-stroke petrol engines with crankcase"),
    ],
)
def test_supports_usually_on_rolling_bearings_are_said_to_be(example, said):
    """A radial aircraft engine's and a small spark-ignition two-stroke's supports are usually
    rolling bearings: the plain bearings' pressures are said to be a guide only; a car engine's
    and a flat or in-line aircraft engine's (plain bearings, as a Lycoming's) are not."""
    rendered = shared_html(example, None, "en")
    assert said in rendered.linked_html
    # and what a rolling bearing is chosen by: its mean equivalent load, the results' largest
    results = shared_run(example).outputs["bearings"].results
    main = max(b["rolling_equivalent_N"] for b in results["main_bearings"]) / 1e3
    text = " ".join(rendered.linked_html.split())
    if example == "two-stroke-1cyl":
        rod = max(b["rolling_equivalent_N"] for b in results["rod_bearings"]) / 1e3
        # one cylinder: its one big end
        assert f"reaches {rod:.2f} kN at the big end and {main:.2f} kN at the main" in text
        assert f"{rod:.2f} kN at the big end and {main:.2f} kN at the main supports." in text
    else:
        assert f"reaches {main:.2f} kN at the main supports" in text
    car = shared_html("inline4-petrol", None, "en").linked_html
    assert "usually rolling" not in car and "crankcase scavenging" not in car
    flat = shared_html("inline4-petrol", {"engine": {"application": "aircraft"}}, "en")
    assert (
        "usually rolling" not in flat.linked_html
        and "rolling main bearings" not in flat.linked_html
    )


@pytest.mark.parametrize("pole_z", [0.0, 4.0, -6.0])
def test_load_diagram_labels_stand_at_points_inside_the_axes(pole_z):
    """A label is drawn without asking whether its point lies inside the axes: every point is one
    of the curve's, inside the limits autoscaled to the curve and the journal's circle, so what is
    drawn is what matplotlib's clipping of labels to the axes would draw."""
    from matplotlib.text import Annotation

    from crankdyn.report.i18n import translator
    from crankdyn_builtin.bearings.figures import _polar_drawing

    angle = np.arange(0.0, 720.0, 1.0)
    a = np.radians(angle)
    t_Pa = 1e6 * (3.0 * np.sin(a) + 1.5 * np.sin(2.0 * a))
    z_Pa = 1e6 * (2.0 + 5.0 * np.cos(a) - 2.0 * np.cos(3.0 * a))
    fig = _polar_drawing(
        translator("en"), t_Pa, z_Pa, angle, pole_z, "Pin", 45.0, 1.0, 30.0, ("T", "Z")
    )
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    labels = [
        artist
        for artist in fig.axes[0].get_children()
        if isinstance(artist, Annotation) and artist.get_text() != "O"
    ]
    assert len(labels) >= 6
    for label in labels:
        assert label.get_annotation_clip() is False
        label.set_annotation_clip(None)  # matplotlib's default: drawn only inside the axes
        assert label._check_xy(renderer), label.get_text()


#: An in-line five (the in-line four with a fifth cylinder, firing 1-2-4-5-3): its journals 2–3
#: and 3–4 carry the same loads, the largest peak and the largest mean.
INLINE_FIVE = {"engine": {"cylinders": 5, "firing_order": [1, 2, 4, 5, 3]}}


@pytest.mark.parametrize(
    "language, texts",
    [
        (
            "uk",
            (
                "корінна шийка 2–3 (так само навантажена шийка 3–4); вона сприймає",
                "корінної шийки 2–3 (так само навантажена шийка 3–4) –",
                "(обидва – на шийках 2–3 і 3–4)",
                "За найбільшою за цикл силою найбільш навантажені корінні шийки 2–3 і 3–4:",
                "Корінну шийку 2–3 (так само навантажена шийка 3–4) навантажують",
            ),
        ),
        (
            "en",
            (
                "2–3 (journal 3–4 carries the same load), carries chiefly",
                "main journal 2–3 (journal 3–4 carries the same load) is its largest load",
                "(both at journals 2–3 and 3–4)",
                "the most loaded main journals are 2–3 and 3–4:",
            ),
        ),
    ],
)
def test_journals_the_table_prints_alike_are_named_together(language, texts):
    """Where two main journals print the same loads, every sentence on "the most loaded" or "the
    largest mean" journal names both (one of them alone would contradict the table), and a single
    other journal is "шийка", "journal … carries", in the singular."""
    run = shared_run("inline4-petrol", INLINE_FIVE, ("bearings",))
    journals = {j["journal"]: j for j in run.outputs["bearings"].results["main_journals"]}
    for key in ("max_N", "mean_N"):
        assert journals["2-3"][key] == pytest.approx(journals["3-4"][key], rel=1e-9)
        assert journals["2-3"][key] == max(j[key] for j in journals.values())
    html = shared_html("inline4-petrol", INLINE_FIVE, language, ("bearings",)).linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", html).replace("\xa0", " ").split())
    for expected in texts:
        assert expected in text, expected


def test_the_within_limits_sentence_quotes_the_pressures_as_the_table_prints_them():
    """Table 7.1 gives p_max = 10,21 and p_mean = 6,17 MPa; the sentence below it said "6,2" and
    "10,2" (read as other values)."""
    import re

    from conftest import shared_html

    html = shared_html("petrol-1cyl-uk").linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html).replace("\u202f", " "))
    assert "шатунний підшипник сягає 6,17 МПа, а найбільший – 10,21 МПа" in text


@pytest.mark.parametrize(
    ("application", "said"),
    [("motorcycle", True), ("marine", True), ("outboard", True), ("automotive", False)],
)
def test_the_allowable_pressures_of_car_engines_are_only_a_guide_for_another_engine(
    application, said
):
    """The allowable bearing pressures of the method are those of car and tractor engines: a
    motorcycle or marine engine's note says that they only guide it; a car engine's does not."""
    import re

    from conftest import shared_html

    changes = {"engine": {"application": application}}
    kind = "an outboard engine" if application == "outboard" else f"a {application} engine"
    html = shared_html("petrol-1cyl", changes, "en", ("bearings",)).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html))
    # the journal sizes are taken from car proportions too: one sentence says both only guide
    guide = (
        "are likewise those of automotive and tractor engines [6]; here both serve only as a guide"
    )
    assert (guide in text) is said
    if said:
        assert f"The engine is {kind}, not a car or tractor engine" in text
        assert text.count(f"The engine is {kind}") == 2  # and the conclusions'
    # and the conclusions, which repeat the verdicts, say so too, before them
    concluded = f"The engine is {kind}, while the allowable bearing pressures its bearings are"
    assert (concluded in text) is said
    if said:  # before the verdicts it qualifies
        assert text.rindex(concluded) < text.rindex("The big-end bearing pressure is within")


@pytest.mark.parametrize(
    ("cylinders", "said"),
    [(1, "в подшипнике нижней головки шатуна"), (2, "в подшипниках нижних головок шатунов")],
)
def test_two_stroke_big_ends_are_counted(cylinders, said):
    """A crankcase-scavenged single's rolling-bearing note names its one big end; a twin's, both."""
    overrides = {"report": {"language": "ru"}}
    if cylinders == 2:
        overrides["engine"] = {"cylinders": 2}
    text = " ".join(shared_html("two-stroke-1cyl", overrides, "ru").linked_html.split())
    assert said in text
    other = "в подшипниках нижних головок шатунов" if cylinders == 1 else "нижней головки шатуна"
    assert other not in text


def test_journal_caption_numbers_the_crank_only_among_several():
    """A main journal's diagram is drawn in the axes of a crank: "the crank's" where there is one,
    "crank 1" where there are more."""
    single = " ".join(shared_html("petrol-1cyl", None, "en").linked_html.split())
    assert "main journal" in single and "(axes of the crank, oil hole marked)" in single
    assert "axes of crank 1" not in single
    four = " ".join(shared_html("inline4-petrol", None, "en").linked_html.split())
    assert re.search(r"\(axes of crank [1-4], oil hole marked\)", four)


def test_a_single_crank_with_rods_side_by_side_says_its_journals_share_unequally_in_fact():
    """A V-twin's two rods on its one pin: the rods' planes lie half a big-end bearing's width off
    the pin's middle, but a single crank's span between its journals is not given, so the note
    says the equal shares are the model's and leaves the difference out (no share is computed)."""
    from conftest import V_TWIN_ENGINE

    changes = {"engine": V_TWIN_ENGINE}
    r = shared_run("v8-petrol", changes, ("bearings",)).outputs["bearings"].results
    width = r["rod_bearings"][0]["width_m"]
    assert r["rod_plane_offset_m"] == pytest.approx(width / 2, rel=1e-12)
    assert r["rod_plane_share_shift"] is None
    html = shared_html("v8-petrol", changes, "uk").linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html))
    offset = f"{width / 2 * 1e3:.3g}".replace(".", ",")
    assert f"площина кожного шатуна зміщена від середньої на {offset} мм" in text
    assert "проліт у завданні не вказано" in text
    # one crank pin: its rod bearings' captions name no pin number
    assert "на шатунній шийці (лише сила цього шатуна" in text
    assert "на шатунній шийці 1 " not in text


def test_a_motorcycle_engine_with_its_own_journal_sizes_is_told_only_of_the_pressures():
    """Journal sizes given: only the allowable pressures are car engines', and the note says so
    of them alone."""
    import re

    from conftest import shared_html

    changes = {
        "engine": {"application": "motorcycle"},
        "bearings": {
            "crank_pin_diameter": "45 mm",
            "crank_pin_width": "26 mm",
            "main_journal_diameter": "50 mm",
            "main_journal_width": "24 mm",
        },
    }
    html = shared_html("petrol-1cyl", changes, "en", ("bearings",)).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html))
    assert "The engine is a motorcycle engine: the allowable bearing pressures" in text
    assert "not a car or tractor engine" not in text


def test_rolling_supports_are_said_before_the_plain_bearing_verdicts_they_qualify():
    """A crankcase-scavenged two-stroke's supports are usually rolling: the conclusions say so
    first, and the oil holes and pressures after it read as a guide."""
    html = shared_html("two-stroke-1cyl", None, "en").linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html))
    rolling = text.index("The supports are treated here as plain bearings")
    assert "so the following conclusions on the pressures and oil holes" in text
    assert rolling < text.index("its oil hole is best placed at")
    assert rolling < text.index("The big-end bearing pressure is within")


def test_a_single_cranks_journal_force_names_the_counterweights_force_it_includes():
    """A V-twin's one crank carries counterweights: formula F_1 is followed by their specific
    centrifugal force, m·r·ω²/F_p of the balancing section's counterweights."""
    from conftest import V_TWIN_ENGINE

    changes = {"engine": V_TWIN_ENGINE}
    run = shared_run("v8-petrol", changes, ("bearings", "balancing"))
    scene = run.scene
    (counterweight,) = run.outputs["balancing"].results["counterweights"]
    area = math.pi * scene.engine.bore**2 / 4
    expected = counterweight["mass_radius_kg_m"] * scene.engine.angular_velocity_rad_s**2 / area
    r = run.outputs["bearings"].results
    assert r["counterweight_specific_force_Pa"] == [pytest.approx(expected, rel=1e-9)]
    html = shared_html("v8-petrol", changes, "en", ("bearings", "balancing")).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html))
    printed = re.search(r"their specific centrifugal force, ([\d.]+) MPa", text)
    assert float(printed.group(1)) == pytest.approx(expected / 1e6, abs=5e-4)


def test_each_side_by_side_rod_loads_the_main_journals_by_its_own_plane():
    """A V8's rods on crank 1: 1L's plane lies p/2 towards the free end, 1R's p/2 away from it, so
    the free-end journal 0 takes 0.5 + (p/2)/a of 1L's force and 0.5 − (p/2)/a of 1R's
    (textbook eq. 48-49 for each rod). Doubling p changes journal 0's load by (f_1R − f_1L)·p/(2a)
    in crank 1's axes (the rods' centrifugal forces cancel), f of each cylinder at its own cycle
    angle from the forces table."""
    width = (
        shared_run("v8-petrol", None, ("bearings",))
        .outputs["bearings"]
        .results["rod_bearings"][0]["width_m"]
    )
    p = 1e3 * width  # mm: the default distance between the rods' planes, given explicitly
    runs = [
        shared_run("v8-petrol", {"balancing": {"rod_offset": f"{k * p} mm"}}, ("bearings",))
        for k in (1, 2)
    ]
    tables = [r.outputs["bearings"].tables["bearings"] for r in runs]
    forces = runs[0].outputs["forces"].tables["forces"]
    phases = {
        c["cylinder"]: c["cycle_delay_deg"]
        for c in runs[0].outputs["bays"].results["cylinder_phases"]
    }
    angle = np.asarray(forces["crank_angle_deg"])
    a = runs[0].scene.engine.cylinder_spacing

    def at(column, cylinder):
        values = np.asarray(forces[column])
        return np.interp((angle - phases[cylinder]) % 720.0, angle, values, period=720.0)

    for axis, column in (("t", "tangential_Pa"), ("z", "radial_Pa")):
        change = np.asarray(tables[1][f"journal0_{axis}_Pa"]) - np.asarray(
            tables[0][f"journal0_{axis}_Pa"]
        )
        expected = (at(column, "1R") - at(column, "1L")) * (p * 1e-3) / (2 * a)
        scale = np.max(np.abs(expected))
        assert scale > 1e4  # a change worth checking: well above round-off
        np.testing.assert_allclose(change, expected, rtol=0, atol=1e-9 * scale)


@pytest.mark.parametrize(("example", "frame_deg"), [("v8-petrol", 45.0), ("inline4-petrol", 0.0)])
def test_the_main_bearing_diagram_is_drawn_in_the_engines_vertical_axes(example, frame_deg):
    """A 90° V8's main-bearing load is drawn in axes along its banks' axis of symmetry, 45° from
    cylinder 1's (the balancing's vertical); an in-line engine's along cylinder 1's axis. The
    journal's own load (crank 1's axes) turned into those axes gives the bearing's, reversed."""
    run = shared_run(example, None, ("bearings",))
    r = run.outputs["bearings"].results
    f = run.outputs["bearings"].tables["bearings"]
    assert r["main_bearing_frame_deg"] == frame_deg
    theta = np.radians(np.asarray(f["crank_angle_deg"]))
    journal = np.asarray(f["journal0_t_Pa"]) + 1j * np.asarray(f["journal0_z_Pa"])
    bearing = np.asarray(f["main_bearing0_t_Pa"]) + 1j * np.asarray(f["main_bearing0_z_Pa"])
    # (t, z) axes turn with the crank: a vector's components in axes turned by φ are its
    # components in the frame's axes turned back by φ − frame (t = e_t·v, z = e_z·v)
    turn = np.exp(-1j * (theta - np.radians(frame_deg)))
    np.testing.assert_allclose(bearing, -journal / turn, atol=1e-6 * np.max(np.abs(journal)))
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", shared_html(example, None, "en").linked_html))
    assert ("y along the engine's vertical" in text.replace("&#39;", "'")) is (frame_deg != 0)


def test_a_narrow_polar_diagrams_short_tick_labels_stay_upright():
    """A tall, narrow diagram (a rod bearing's t within ±1.3 MPa, drawn at 19 pt per MPa) has
    ticks −1, 0, 1: labels of two characters fit 19 pt apart, so they stay upright; ticks
    −0.5, 0, 0.5 at 9.5 pt apart would not, and are turned."""
    from crankdyn.report.figures import new_figure
    from crankdyn_builtin.bearings.figures import _fitting_ticks

    def rotation(low, high, per_pt):
        fig, ax = new_figure(4, 10)
        _fitting_ticks(ax.xaxis, (low, high), per_pt)
        ax.set_xlim(low, high)
        ticks = [v for v in ax.get_xticks() if low <= v <= high]
        return ticks, ax.xaxis.get_major_ticks()[0].label1.get_rotation()

    ticks, turned = rotation(-1.3, 1.3, 1 / 19)
    assert [round(v, 6) for v in ticks] == [-1.0, 0.0, 1.0]
    assert turned == 0
    ticks, turned = rotation(-0.65, 0.65, 1 / 19)
    assert [round(v, 6) for v in ticks] == [-0.5, 0.0, 0.5]
    assert turned == 90


def test_the_typical_proportions_named_are_those_of_the_sizes_assumed():
    """A crank pin given and the main journals not: the note names the main journal's typical
    proportions (d = 0.70·D, B = 0.45·d) and not the crank pin's 0.63·D, which it did not take."""

    def text(changes, language):
        html = shared_html("inline4-petrol", changes, language, ("bearings",)).linked_html
        return " ".join(re.sub(r"<[^>]+>", "", html).split())

    given_pin = text(
        {"bearings": {"crank_pin_diameter": "50 mm", "crank_pin_width": "30 mm"}}, "uk"
    )
    assert (
        "(діаметр корінної шийки 0,70·D, ширина корінної шийки 0,45 її діаметра); для остаточного"
        in given_pin
    )
    assert "0,63·D" not in given_pin
    assert (
        "(crank pin diameter 0.63·D, crank pin width 0.60 of its diameter, main journal diameter "
        "0.70·D, main journal width 0.45 of its diameter)" in text(None, "en")
    )


def test_a_flat_engines_vertical_is_normal_to_its_cylinders_not_the_banks_axis_of_symmetry():
    """A boxer's main-bearing diagrams take y along the engine's vertical, which is normal to its
    opposed cylinders' axes: said so in the section and in the list of symbols, not in a V's
    words ("the banks' axis of symmetry")."""
    from conftest import FLAT_FOUR_ENGINE

    html = shared_html("v8-petrol", {"engine": FLAT_FOUR_ENGINE}, "ru").linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", html).split())
    assert "y – вдоль вертикали двигателя, перпендикулярно к осям цилиндров, сверху" in text
    assert (
        "y – ось диаграммы коренного подшипника вдоль вертикали двигателя (перпендикулярно к "
        "осям цилиндров)" in text
    )
    assert "симметрии рядов" not in text
    v8 = " ".join(re.sub(r"<[^>]+>", "", shared_html("v8-petrol", None, "ru").linked_html).split())
    assert "вдоль вертикали двигателя, оси симметрии рядов цилиндров" in v8


def test_rods_side_by_side_are_told_each_bearings_width_and_the_pins_length():
    """The pressure of a big-end bearing among two on a pin is its own: the note asks for each
    bearing's d·B and width and for the pin's length, which carries both (twice the width), not
    for "the crank pin's" area with one bearing's width."""
    from conftest import V_TWIN_ENGINE

    changes = {
        "engine": V_TWIN_ENGINE,
        "bearings": {"crank_pin_diameter": "36 mm", "crank_pin_width": "30 mm"},
    }
    r = shared_run("v8-petrol", changes, ("bearings",)).outputs["bearings"].results
    assert r["rod_bearings_per_pin"] == 2
    text = " ".join(
        re.sub(r"<[^>]+>", "", shared_html("v8-petrol", changes, "en").linked_html).split()
    )
    found = re.search(
        r"each big-end bearing needs a projected area d·B ≥ ([\d ]+) mm² \(a bearing width "
        r"B ≥ ([\d.]+) mm at d = 36 mm, a pin at least ([\d.]+) mm long\)",
        text,
    )
    assert found, "no side-by-side pressure conclusion"
    area, width, pin = (float(g.replace(" ", "")) for g in found.groups())
    assert width == pytest.approx(area / 36, rel=2e-3) and pin == pytest.approx(2 * width, rel=2e-3)
    assert "the crank pin needs a projected area" not in text


def test_the_rolling_bearings_life_check_names_its_letters_apart_from_the_notes_others():
    """The life check of a small two-stroke's rolling bearings: the mean over n_α angles (n is the
    speed, k the force along the rod), the dynamic load rating C_r (C is the centrifugal force),
    and P_m, n_α, L_10 and C_r in the list of symbols."""
    from conftest import shared_html

    html = shared_html("two-stroke-1cyl", None, "ru").linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", html).split())
    assert "/nα)3/10 по nα углам цикла" in text.replace("\u2060", "")
    assert "(Cr/Pm)" in text.replace("\u2060", "")
    from conftest import symbol_rows

    rows = symbol_rows(html)
    for start in (
        "Pm – средняя эквивалентная нагрузка",
        "Cr – динамическая грузоподъёмность",
        "L10 – номинальная долговечность",
    ):
        assert any(row.startswith(start) for row in rows), start


def test_the_unrolled_diagrams_axis_names_the_journal_drawn():
    """The unrolled diagrams' y axis names the journal drawn, |R_1–2|, as its legend does, not
    the general |R_i,i+1| (an in-line four)."""
    from conftest import shared_html

    figures = shared_html("inline4-petrol", None, "uk").figures
    svg = next(f for f in figures if "unrolled" in f.name).svg.decode()
    r = shared_run("inline4-petrol", None, ("bearings",)).outputs["bearings"].results
    name = r["main_journals"][r["drawn_journals"][0] - 1]["journal"].replace("-", "–")
    assert f"R_{{\\mathrm{{{name}}}}}" in svg and "i,i+1" not in svg


def test_the_abstract_gives_the_crank_pins_load_with_the_tables_digits():
    """ "найбільше навантаження на шатунну шийку 9,00 кН" in the abstract, as the crank pins'
    table and the conclusions print it (it gave 9,000)."""
    from conftest import shared_html, shared_run

    r = shared_run("two-stroke-1cyl", None, ("bearings",)).outputs["bearings"].results
    pin = r["crank_pins"][r["drawn_pins"][0] - 1]
    html = shared_html("two-stroke-1cyl", None, "ru").linked_html
    abstract = re.search(r'<section class="abstract".*?</section>', html, re.S).group(0)
    printed = f"{pin['max_N'] / 1e3:.2f}".replace(".", ",")
    assert printed == "4,72"
    assert f"наибольшая нагрузка на шатунную шейку {printed}" in abstract.replace("\u202f", " ")


def test_counterweights_asked_for_by_the_main_bearings_are_reconciled_with_the_balancing():
    """An in-line four needs no counterweights for its free forces, so its balancing section
    fits none; main journals too narrow for the cranks' centrifugal forces ask for them: the
    bearings section and its conclusion say why the balancing section has none, and only then."""
    import html as markup

    def text(changes) -> str:
        page = markup.unescape(shared_html("inline4-petrol", changes).linked_html)
        return " ".join(re.sub(r"<[^>]+>", "", page).split())

    narrow = {"bearings": {"main_journal_width": "10 mm"}}
    said = "fits no counterweights, since the engine's free forces and moments need none"
    found = text(narrow)
    assert found.count(said) == 2  # the section and the conclusions
    number = re.search(r"(\d+) Balancing of the engine", found).group(1)
    assert f"Section {number} {said}" in found
    assert said not in text({**narrow, "balancing": {"counterweights": "every_crank"}})


def test_an_english_note_names_a_single_crank_pin_with_its_article():
    """ "The polar diagram of the load on crank pin is shown": one crank's pin is "the crank pin",
    one of several is "crank pin 2"."""
    import html as markup

    def text(name) -> str:
        page = markup.unescape(shared_html(name, None, "en").linked_html)
        return " ".join(re.sub(r"<[^>]+>", "", page).split())

    single = text("petrol-1cyl")
    assert "The polar diagram of the load on the crank pin is shown" in single
    assert "Wear diagram of the crank pin:" in single and "on crank pin " not in single
    several = text("inline4-petrol")
    assert re.search(r"Polar diagram of the load on crank pin \d", several)
    assert not re.search(r"the crank pin \d", several)
