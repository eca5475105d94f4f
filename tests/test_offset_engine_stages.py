"""The offset crank-slider through the torque, bearing and balancing stages: each result against
an independent value (virtual work, the rod's direction from the linkage, a quadrature of the
exact acceleration, the central mechanism at e = 0)."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from conftest import modified
from scipy import integrate

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.physics import balancing as bal
from crankdyn.physics import offset_crank as oc
from crankdyn.plugin.contracts import COUNTERWEIGHTS, ENGINE_TORQUE, KINEMATICS
from crankdyn.plugin.registry import default_registry
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()
R, L, E = 0.039, 0.14, 0.008  # examples/offset-crank-engine.toml
LAM, K = R / L, E / L
#: a coarser grid than the example's keeps each run cheap; the checks hold at any step
COARSE = {"analysis": {"angle_step_deg": 2, "table_step_deg": 30}}


def _run(changes=None):
    data = modified("offset-crank-engine", {**COARSE, **(changes or {})})
    return run_scene(scene_from_dict(data, base_dir=examples_dir()), REGISTRY)


@pytest.fixture(scope="module")
def offset_run():
    return _run()


def test_offset_engine_gets_torque_bearings_and_balancing(offset_run):
    for stage in ("bays", "torque", "bearings", "balancing"):
        assert stage in offset_run.stages_run, offset_run.plan.skipped.get(stage)


def test_torque_by_virtual_work(offset_run):
    """T omega = F_piston v_piston, with v from a central difference of the displacement."""
    motion = offset_run.outputs["offset_crank"].data[KINEMATICS]
    forces = offset_run.outputs["forces"].tables["forces"]
    torque = offset_run.outputs["torque"].data[ENGINE_TORQUE]
    area = np.pi * 0.082**2 / 4
    h = 1e-3  # deg
    ds = (
        motion.displacement_at(motion.crank_angle_deg + h)
        - motion.displacement_at(motion.crank_angle_deg - h)
    ) / np.radians(2 * h)
    piston_force = forces["total_Pa"].to_numpy() * area
    np.testing.assert_allclose(
        torque.torque_Nm, piston_force * ds, atol=1e-6 * np.max(np.abs(piston_force)) * R
    )


def test_rod_bearing_is_loaded_along_the_rod(offset_run):
    """The two-mass rod carries its force along its axis: across the rod the bearing sees only the
    rod's rotating part, c_rod sin(phi + beta), phi the crank's angle from the cylinder axis."""
    table = offset_run.outputs["bearings"].tables["bearings"]
    c_rod = offset_run.outputs["bearings"].results["centrifugal_rod_Pa"]
    alpha = np.radians(table["crank_angle_deg"].to_numpy())
    phi = alpha + oc.dead_centres(R, L, E).tdc_angle_rad
    beta = oc.rod_angle_rad(phi, LAM, K)
    np.testing.assert_allclose(
        table["rod_bearing1_t_Pa"], c_rod * np.sin(phi + beta), atol=1e-9 * abs(c_rod)
    )


def test_main_bearings_carry_the_rod_force_and_the_rotating_masses(offset_run):
    """Both main bearings together carry the rod's push along its own axis, (p1 tan beta, p1) in
    engine axes (t lateral, z along the cylinder axis towards the shaft), and the rotating masses'
    and counterweights' force, fixed in the crank's axes and turned with it by phi = alpha + phi_TDC."""
    table = offset_run.outputs["bearings"].tables["bearings"]
    p1 = offset_run.outputs["forces"].tables["forces"]["total_Pa"].to_numpy()
    forces = offset_run.outputs["forces"].data["forces"]
    alpha = np.radians(table["crank_angle_deg"].to_numpy())
    phi = alpha + oc.dead_centres(R, L, E).tdc_angle_rad
    beta = oc.rod_angle_rad(phi, LAM, K)
    # in crank axes: z towards the shaft (the centrifugal force, outward, is negative), t across
    cw = offset_run.outputs["balancing"].data[COUNTERWEIGHTS]
    pull = cw.centrifugal_N / forces.piston_area_m2  # each counterweight pulls outward at psi
    crank_z = forces.centrifugal_Pa - np.sum(pull * np.cos(cw.angle_from_crank_rad))
    crank_t = np.sum(pull * np.sin(cw.angle_from_crank_rad))
    lateral = p1 * np.tan(beta) + crank_t * np.cos(phi) - crank_z * np.sin(phi)
    axial = p1 + crank_t * np.sin(phi) + crank_z * np.cos(phi)
    total_t = table["main_bearing0_t_Pa"].to_numpy() + table["main_bearing1_t_Pa"].to_numpy()
    total_z = table["main_bearing0_z_Pa"].to_numpy() + table["main_bearing1_z_Pa"].to_numpy()
    scale = np.max(np.abs(p1))
    np.testing.assert_allclose(total_t, lateral, atol=1e-9 * scale)
    np.testing.assert_allclose(total_z, axial, atol=1e-9 * scale)


def test_offset_harmonics_by_quadrature():
    """A_n = a_n - i b_n with a_n, b_n the Fourier integrals of the exact offset acceleration."""
    harmonics = bal.harmonics_for(LAM, 12, K)
    for n in (1, 2, 3, 4):

        def j(a):
            return oc.piston_acceleration_m_s2(a, 1.0, LAM, K, 1.0)

        a_n = integrate.quad(lambda a: j(a) * np.cos(n * a), 0, 2 * np.pi, limit=200)[0] / np.pi  # noqa: B023 - called within this iteration
        b_n = integrate.quad(lambda a: j(a) * np.sin(n * a), 0, 2 * np.pi, limit=200)[0] / np.pi  # noqa: B023 - called within this iteration
        assert harmonics[n] == pytest.approx(complex(a_n, -b_n), abs=1e-12)
    assert abs(harmonics[3]) > 1e-3  # an odd order the central mechanism does not have


def test_offset_harmonics_become_the_central_ones():
    central = bal.harmonics_for(LAM, 12)
    tiny = bal.harmonics_for(LAM, 12, 1e-9)
    np.testing.assert_allclose(tiny.real, central, atol=1e-8)
    np.testing.assert_allclose(tiny.imag, 0.0, atol=1e-8)


def test_offset_balancing_checks_against_the_exact_force(offset_run):
    r = offset_run.outputs["balancing"].results
    assert r["offset_ratio"] == pytest.approx(K)
    assert r["time_domain_check"]["agrees"] and r["residual"]["vanishes"]
    assert 3 in r["time_domain_check"]["orders"]
    # one cylinder: every order pulses along the axis with its amplitude |A_n| C_I
    harmonics = bal.harmonics_for(LAM, 12, K)
    for o in r["orders"]:
        if o["order"]:
            assert o["force_max_N"] == pytest.approx(
                abs(harmonics[o["order"]]) * r["first_order_N"], rel=1e-9
            )


def test_zero_offset_balancing_is_the_central_one():
    offset = _run({"mechanism": {"offset": "0 mm"}})
    central = _run({"engine": {"mechanism": "crank_slider"}, "mechanism": None})
    a, b = offset.outputs["balancing"].results, central.outputs["balancing"].results
    assert a["counterweights"][0]["mass_kg"] == pytest.approx(
        b["counterweights"][0]["mass_kg"], rel=1e-12
    )
    assert a["absolute"]["sum_PII_N"] == pytest.approx(b["absolute"]["sum_PII_N"], rel=1e-12)
    ta, tb = (
        offset.outputs["bearings"].tables["bearings"],
        central.outputs["bearings"].tables["bearings"],
    )
    for column in (
        "rod_bearing1_t_Pa",
        "rod_bearing1_z_Pa",
        "main_bearing0_t_Pa",
        "main_bearing1_z_Pa",
    ):
        np.testing.assert_allclose(ta[column], tb[column], atol=1e-6 * np.max(np.abs(tb[column])))


@pytest.mark.parametrize(
    "engine",
    [
        {"cylinders": 4, "firing_order": [1, 3, 4, 2], "cylinder_spacing": "90 mm"},
        {"cylinders": 8, "layout": "V", "bank_angle_deg": 90, "cylinder_spacing": "90 mm"},
    ],
)
def test_multi_cylinder_offset_engine(engine):
    """Every cylinder an offset crank-slider at its own phase: the vector models reproduce the sum of
    the cylinders' exact inertia forces, and the torque's mean is the indicated work per cycle."""
    result = _run({"engine": engine, "analysis": {"angle_step_deg": 3, "table_step_deg": 30}})
    for stage in ("bays", "torque", "bearings", "balancing"):
        assert stage in result.stages_run, result.plan.skipped.get(stage)
    balancing = result.outputs["balancing"].results
    assert balancing["time_domain_check"]["agrees"] and balancing["residual"]["vanishes"]
    harmonics = bal.harmonics_for(LAM, 12, K)
    if engine["cylinders"] == 4:  # in line: the first orders cancel, the second add up
        assert balancing["coefficients"]["sum_PI"] == 0.0
        assert balancing["absolute"]["sum_PII_N"] == pytest.approx(
            4 * abs(harmonics[2]) * balancing["first_order_N"], rel=1e-9
        )
    torque = result.outputs["torque"].data[ENGINE_TORQUE]
    work = result.outputs["bays"].results["indicated_work_J"]
    assert torque.mean_torque_Nm == pytest.approx(work / (4 * np.pi), rel=2e-3)


def test_a_plugin_mechanism_with_a_piston_motion_gets_torque_and_bearings():
    """The Scotch yoke (the example plugin) provides `kinematics` only: with masses and a cycle it
    gets the bays, torque and bearings, and its torque is T = F_piston R sin(alpha) (ds/dalpha of
    a yoke), by virtual work."""
    from test_scene_corpus import _plugin_registry  # the example plugin, registered once

    data = tomllib.loads(
        (examples_dir() / "plugin-example" / "scotch-yoke.toml").read_text(encoding="utf-8")
    )
    data["analysis"] = {"angle_step_deg": 2}
    # [masses] gives a connecting rod's mass, split by a rod's length: with masses a scene gives
    # one, whatever the mechanism (the yoke's torque below does not depend on it)
    data["engine"]["rod_ratio"] = 0.25
    data["masses"] = {
        "piston_group": "0.4 kg",
        "rod": "0.3 kg",
        "rod_cm_fraction": 0.3,
        "crank_pin": "0.2 kg",
        "crank_web": "0.1 kg",
    }
    data["cycle"] = {
        "source": "theoretical",
        "ignition": "spark",
        "compression_ratio": 9,
        "intake_pressure": "0.09 MPa",
        "compression_index": 1.36,
        "max_pressure": "5 MPa",
        "expansion_index": 1.25,
    }
    result = run_scene(
        scene_from_dict(data, base_dir=examples_dir() / "plugin-example"), _plugin_registry()
    )
    for stage in ("bays", "torque", "bearings"):
        assert stage in result.stages_run, result.plan.skipped.get(stage)
    forces = result.outputs["forces"].tables["forces"]
    alpha = np.radians(forces["crank_angle_deg"].to_numpy())
    piston_force = forces["total_Pa"].to_numpy() * np.pi * 0.06**2 / 4
    torque = result.outputs["torque"].data[ENGINE_TORQUE].torque_Nm
    np.testing.assert_allclose(
        torque, piston_force * 0.04 * np.sin(alpha), atol=1e-9 * np.max(np.abs(piston_force))
    )


@pytest.mark.parametrize(
    "example, listed",
    [("offset-crank-engine", "1, 2, 3, … "), ("petrol-1cyl", "1, 2, 4, … ")],
)
def test_the_balancing_note_lists_the_orders_the_vector_method_sums(example, listed):
    """An offset crank-slider's series has odd orders (the note said "1, 2, 4, …" for it too)."""
    from conftest import shared_run

    notes = dict(shared_run(example).outputs["balancing"].notes)
    (orders,) = [p["orders"] for key, p in notes.items() if key.startswith("balancing.note_check")]
    assert orders.startswith(listed), orders


def test_the_abstract_names_every_force_the_balancing_table_leaves_unbalanced():
    """The abstract said only P_II stays unbalanced while the table leaves P_III, P_IV and P_VI
    too (small ones, under 1 % of the first order's, are named as such)."""
    import html as html_lib
    import re

    from conftest import shared_html, shared_run

    r = shared_run("offset-crank-engine").outputs["balancing"].results
    balanced = set(r["residual"]["balanced_orders"]) | ({0} if r["counterweights"] else set())
    left = [s["order"] for s in r["summary"] if not s["balanced"] and s["order"] not in balanced]
    assert left, "the example leaves some orders unbalanced"
    page = shared_html("offset-crank-engine").linked_html
    abstract = page[page.index('class="abstract"') :]
    abstract = abstract[: abstract.index("</section>")]
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", " ", abstract)).split())
    roman = {1: "I", 2: "II", 3: "III", 4: "IV", 5: "V", 6: "VI"}
    for order in left:
        assert f"P {roman[order]} " in text or f"P {roman[order]}," in text, (order, text)


def test_the_indicator_refers_to_the_section_that_computed_the_offset_pistons_motion():
    """The indicator's volume comes "from the piston displacement computed in section N": for an
    offset crank-slider that is its own stage's section, not the central kinematics' title."""
    import re

    from conftest import shared_html

    page = shared_html("offset-crank-engine").linked_html
    found = re.search(r"piston displacement computed in section (\S+?)\.", page)
    assert found is not None and found.group(1).isdigit(), found
    assert "Kinematics of the crank-slider" not in found.group(0)


def test_the_offset_kinematics_gives_the_mean_piston_speed_of_its_true_stroke():
    """v_mean = S n / 30 with the offset mechanism's own stroke S (longer than 2R)."""
    from conftest import shared_html, shared_run

    result = shared_run("offset-crank-engine")
    r = result.outputs["offset_crank"].results
    rpm = r["angular_velocity_rad_s"] * 30 / np.pi
    assert r["mean_piston_speed_m_s"] == pytest.approx(r["stroke_m"] * rpm / 30, rel=1e-12)
    assert r["stroke_m"] > 2 * r["crank_radius_m"]
    shown = f"{r['mean_piston_speed_m_s']:.2f}"
    page = shared_html("offset-crank-engine").linked_html
    plain = page.replace("/\u2060", "/").replace("\u00a0", " ")
    assert f"<i>v</i><sub>mean</sub> = <i>Sn</i>/30 = {shown}" in plain


@pytest.mark.parametrize("offset_mm", [8.0, -8.0, 95.0, -100.9])  # |e| < L - R = 101 mm
def test_the_indicator_diagram_takes_the_pistons_own_stroke_and_dead_centres(offset_mm):
    """V_h = F S with the piston's stroke S = √((L+R)² − e²) − √((L−R)² − e²) (not 2R), so
    V(BDC) = V_a at the real BDC α = 180° + arcsin(e/(L−R)) − arcsin(e/(L+R)), where the intake
    line ends at p_a; the diagram's work equals the mean torque × 4π (virtual work)."""
    e = offset_mm * 1e-3
    result = _run({"mechanism": {"offset": f"{offset_mm} mm"}})
    motion = result.outputs["offset_crank"].data[KINEMATICS]
    indicator = result.outputs["indicator"]
    r = indicator.results
    stroke = np.sqrt((L + R) ** 2 - e**2) - np.sqrt((L - R) ** 2 - e**2)
    bdc = 180.0 + np.degrees(np.arcsin(e / (L - R)) - np.arcsin(e / (L + R)))
    area = np.pi * 0.082**2 / 4
    assert r["swept_volume_m3"] == pytest.approx(area * stroke, rel=1e-12)
    assert r["bdc_crank_angle_deg"] == pytest.approx(bdc, rel=1e-12)
    clearance = r["clearance_volume_m3"]
    v_a = 9.5 * clearance  # epsilon V_c
    for at in (bdc, 360.0 + bdc):
        volume = clearance + area * float(motion.displacement_at(np.array([at]))[0])
        assert volume == pytest.approx(v_a, rel=1e-12), at
    # the intake line runs at p_a up to the real BDC, past the nominal 180°
    table = indicator.tables["indicator"]
    angle = np.asarray(table["crank_angle_deg"])
    theory = np.asarray(table["pressure_theoretical_Pa"])
    before_bdc = (angle > 90.0) & (angle <= bdc)
    assert np.all(theory[before_bdc] == 0.085e6)
    torque = result.outputs["forces"].tables["forces"]["torque_Nm"].to_numpy()
    assert np.mean(torque) * 4 * np.pi == pytest.approx(r["indicated_work_J"], rel=2e-3)


def test_the_inertia_remainder_is_split_into_its_lambda_cubed_and_offset_terms(offset_run):
    """p_j - (p_jI + p_jII) of an offset crank-slider = (the central crank-slider's p_j of the
    same R, lambda - p_jI - p_jII: the terms of order lambda^3 and up) + (the offset mechanism's
    p_j - the central one's: the offset's terms); both parts against the central closed form."""
    forces = offset_run.outputs["forces"]
    r, f = forces.results, forces.tables["forces"]
    omega = 5600 * np.pi / 30
    alpha = np.radians(f["crank_angle_deg"].to_numpy())
    sin_beta = LAM * np.sin(alpha)
    cos_beta = np.sqrt(1 - sin_beta**2)
    j_central = (
        R
        * omega**2
        * (np.cos(alpha + np.arcsin(sin_beta)) / cos_beta + LAM * np.cos(alpha) ** 2 / cos_beta**3)
    )
    area = np.pi * 0.082**2 / 4
    p_central = -r["reciprocating_mass_kg"] * j_central / area
    harmonics = f["inertia_first_order_Pa"].to_numpy() + f["inertia_second_order_Pa"].to_numpy()
    central_part = np.max(np.abs(p_central - harmonics))
    offset_part = np.max(np.abs(f["inertia_Pa"].to_numpy() - p_central))
    assert r["inertia_higher_orders_central_max_Pa"] == pytest.approx(central_part, rel=1e-9)
    assert r["inertia_offset_terms_max_Pa"] == pytest.approx(offset_part, rel=1e-9)
    assert offset_part > 0.1 * central_part  # the offset's share is no round-off
    assert r["inertia_higher_orders_max_Pa"] <= central_part + offset_part
    assert r["crank_angle_at_tdc_deg"] == pytest.approx(np.degrees(np.arcsin(E / (L + R))))


def test_the_printed_rod_force_formula_is_the_one_computed():
    """t = p1 sin(φ + β)/cos β with φ = α + φ_TDC, the crank's angle from the cylinder axis:
    the forces section prints φ, and the table's t is that formula (t = 0 at TDC)."""
    import re

    from conftest import shared_html, shared_run

    page = shared_html("offset-crank-engine").html.replace("/\u2060", "/")
    assert "<i>t</i> = <i>p</i><sub>1</sub> sin(<i>φ</i> + <i>β</i>)/cos <i>β</i>" in page
    assert not re.search(r"<i>t</i> = <i>p</i><sub>1</sub> sin\(<i>α</i>", page)
    result = shared_run("offset-crank-engine")
    f = result.outputs["forces"].tables["forces"]
    phi = np.radians(f["crank_angle_deg"].to_numpy()) + np.arcsin(E / (L + R))
    beta = np.arcsin(LAM * np.sin(phi) - K)
    p1 = f["total_Pa"].to_numpy()
    np.testing.assert_allclose(
        f["tangential_Pa"].to_numpy(),
        p1 * np.sin(phi + beta) / np.cos(beta),
        atol=1e-9 * np.max(np.abs(p1)),
    )
    assert f["tangential_Pa"].to_numpy()[0] == pytest.approx(0.0, abs=1e-9 * np.max(np.abs(p1)))


#: The example made a twin with its cranks at 0°/180° (uneven firing), on a coarse grid, and the
#: stages its tests read (the run and the report shared by them).
TWIN = {
    **COARSE,
    "engine": {
        "cylinders": 2,
        "crank_angles_deg": [0, 180],
        "firing_order": [1, 2],
        "uneven_firing": True,
        "cylinder_spacing": "100 mm",
    },
}
TWIN_STAGES = ("offset_crank", "bays", "balancing")


def _plain(html: str) -> str:
    import html as html_lib
    import re

    text = html_lib.unescape(re.sub(r"<[^>]+>", " ", html)).replace("\u2060", "")
    return " ".join(text.split())


def test_the_given_data_name_the_throw_the_offset_and_the_crank_angles():
    """Table 1.1 and the assignment call the scene's stroke what it is for an offset crank-slider,
    the crank throw 2R, and give the offset e; Table 1.1 adds the piston's own stroke S (the
    closed form) and the cranks' angles the scene gives."""
    from conftest import shared_html

    page = shared_html("offset-crank-engine", TWIN, stages=TWIN_STAGES).linked_html
    start = page.index('class="assignment"')
    assignment = _plain(page[start : page.index("</section>", start)])
    assert "2R = 78 mm" in assignment and "e = 8 mm" in assignment
    assert "S = 78 mm" not in assignment
    text = _plain(page)
    stroke = np.sqrt((L + R) ** 2 - E**2) - np.sqrt((L - R) ** 2 - E**2)
    assert "Crank throw (twice the crank radius) 2 R 78 mm" in text  # 2<i>R</i>
    assert "Pin offset (of the cylinder axis from the crankshaft axis) e 8 mm" in text
    assert f"Piston stroke (computed in section 2) S {stroke * 1e3:.5g} mm" in text
    assert "Angles of the cranks (lag behind crank 1) 0; 180 °" in text


def test_a_small_offset_is_not_called_a_quick_return_mechanism():
    """K = 1.022 for e = 8 mm: the strokes differ by 2.2 %, below the 5 % of a quick return;
    e = 95 mm (K = 1.46) is one."""
    from conftest import shared_html

    small = _plain(shared_html("offset-crank-engine", COARSE, stages=["offset_crank"]).linked_html)
    k = (180 + np.degrees(np.arcsin(E / (L - R)) - np.arcsin(E / (L + R)))) / (
        180 - np.degrees(np.arcsin(E / (L - R)) - np.arcsin(E / (L + R)))
    )
    assert f"differ by only {100 * (k - 1):.1f} %" in small
    assert "practically no quick return" in small and "(a quick-return mechanism)" not in small
    wide = {**COARSE, "mechanism": {"offset": "95 mm"}}
    large = _plain(shared_html("offset-crank-engine", wide, stages=["offset_crank"]).linked_html)
    assert "(a quick-return mechanism)" in large


def test_the_twins_scheme_has_its_crank_star_and_the_balancing_figure_its_odd_orders():
    """The bays section refers to the scheme's crank star: the offset twin's scheme has one (both
    cranks); the balancing figure draws the third order an offset leaves unbalanced."""
    from conftest import shared_run

    from crankdyn_builtin.balancing.figures import _models_shown, models_left_out
    from crankdyn_builtin.offset_crank.geometry import offset_geometry

    result = shared_run("offset-crank-engine", TWIN, stages=TWIN_STAGES)
    geometry = offset_geometry(result.scene, np.zeros(1))
    assert [lag for _, lag, _ in geometry.cranks] == [0.0, 180.0]
    r = result.outputs["balancing"].results
    third = next(o for o in r["orders"] if o["order"] == 3)
    assert third["moment_coefficient"] > 1e-6  # unbalanced: the offset's odd order
    assert 3 in [o["order"] for o in _models_shown(r)[0]]
    assert 3 not in models_left_out(r)


def test_the_crank_pins_warning_stands_with_their_table_not_after_the_journals():
    """A crank pin too narrow for its load (10 mm): the sentence judging its pressure follows the
    crank pins' table and comes before the main journals' table."""
    from conftest import shared_html

    narrow = {**TWIN, "bearings": {"crank_pin_width": "10 mm"}}
    page = _plain(shared_html("offset-crank-engine", narrow, stages=["bearings"]).linked_html)
    start = page.index("Loads on the crank pins: largest and mean force")
    warning = page.index("The crank pin's sizes are not given in the assignment", start)
    journals = page.index("Loads on the main journals: largest and mean force", start)
    assert start < warning < journals


def test_the_orders_the_vector_figure_leaves_out_are_named_in_number_and_agreement():
    """An offset single leaves P_V and P_VI unbalanced beside four other orders: the figure has
    room for five, so one order is left out, and the note names it in the singular (it said
    "Неуравновешенные порядки VI ... не показаны")."""
    import html as html_lib
    import re

    from conftest import shared_html, shared_run

    from crankdyn_builtin.balancing.figures import models_left_out

    r = shared_run("offset-crank-engine").outputs["balancing"].results
    assert {5, 6} <= {o["order"] for o in r["orders"]}
    (left_out,) = models_left_out(r)
    page = shared_html("offset-crank-engine", language="ru").linked_html
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", " ", page)).split())
    assert (
        f"Неуравновешенный порядок {left_out} на рисунке не показан: рисунок вмещает 6 панелей"
        in text
    )
    # the table of the forces of every order, by its number
    number = re.search(r"Таблица (7\.\d+) – Центробежная сила и силы инерции каждого порядка", text)
    assert f"его коэффициенты приведены в табл. {number.group(1)}." in text


@pytest.mark.parametrize("language", ["uk", "ru", "en"])
def test_the_offsets_stroke_and_tdc_angle_read_the_same_wherever_printed(language):
    """The note gave φ_TDC as 2,6°, 2,562° and 2,5620° and S as 78,14, 78,138 and 78,1385 mm in
    different sentences; each is now one number throughout (S to the micrometre: 2R + 0,138 mm)."""
    import html as html_lib
    import re

    from conftest import shared_html, shared_run

    r = shared_run("offset-crank-engine").outputs["offset_crank"].results
    page = shared_html("offset-crank-engine", language=language).linked_html
    page = re.sub(r"<(script|style|svg)\b.*?</\1>", " ", page, flags=re.S)
    text = html_lib.unescape(re.sub(r"<[^>]+>", "", page)).replace("\u2060", "")
    comma = "." if language == "en" else ","
    tdc = f"{r['tdc_crank_angle_from_axis_deg']:.3f}".replace(".", comma)  # 2.562 deg
    stroke = f"{r['stroke_m'] * 1e3:.3f}".replace(".", comma)  # 78.138 mm
    tdc_prints = re.findall(rf"(?<![\d{comma}])(2{comma}[56]\d*)°", text)  # 2.5… or 2.6 deg
    assert tdc_prints and set(tdc_prints) == {tdc}, tdc_prints
    stroke_prints = re.findall(rf"(?<![\d{comma}])(78{comma}\d+)\s*(?:mm|мм)", text)
    assert len(stroke_prints) >= 3 and set(stroke_prints) == {stroke}, stroke_prints
    # the BDC's angles too, to the thousandth (a compressor's "174°" beside "174,011°")
    for key, whole in (("bdc_crank_angle_from_axis_deg", "184"), ("bdc_crank_angle_deg", "181")):
        bdc = f"{r[key]:.3f}".replace(".", comma)
        bdc_prints = re.findall(rf"(?<![\d{comma}])({whole}(?:{comma}\d+)?)°", text)
        assert bdc_prints and set(bdc_prints) == {bdc}, (key, bdc_prints)


def test_a_negative_offsets_tdc_is_said_to_lie_before_the_axis():
    """An offset to the other side (e < 0, as a compressor's) puts TDC before the cylinder axis:
    the conclusion said "ВМТ розташована на −2,562° за віссю циліндра" (a double negative)."""
    import re

    from conftest import shared_html

    page = shared_html("offset-crank-engine", {"mechanism": {"offset": "-8 mm"}}, "uk")
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", page.linked_html))
    assert "ВМТ розташована на 2,562° перед віссю циліндра (проти напрямку обертання)" in text
    assert "−2,562° за віссю" not in text
    assert "відхиленої від осі циліндра на φВМТ = −2,562° у напрямку обертання" in text


def test_the_masses_table_gives_the_harmonic_of_every_order_analysed():
    """An offset crank-slider's table of masses gives |A_ν| and ψ_ν for each order the section
    analyses (its figure and its tables of forces go on to the sixth), not for the first four only;
    the phase's column reads "Phase ψ_ν, °"."""
    import re

    from conftest import shared_html, shared_run

    r = shared_run("offset-crank-engine").outputs["balancing"].results
    analysed = [o["order"] for o in r["orders"] if o["order"] >= 1]
    html = shared_html("offset-crank-engine", None, "en").linked_html
    table = html[html.index("Masses, amplitudes of the forces") :]
    table = table[: table.index("</table>")]
    listed = [int(n) for n in re.findall(r"\|\u2060?<i>A</i><sub>(\d+)</sub>\|", table)]
    assert max(analysed) > 4 and listed == analysed
    assert "Phase <i>ψ</i><sub><i>ν</i></sub>, °" in table


@pytest.mark.parametrize("language", ["uk", "ru", "en"])
def test_the_replaced_formulas_set_their_letters_as_the_note_does(language):
    """The list of the textbook's formulas an offset replaces sets p_1 and the stroke's S = 2·R in
    italics with a true subscript, as every other formula of the note, not as "p₁" or "2R"."""
    from conftest import shared_html

    html = shared_html("offset-crank-engine", None, language).linked_html.replace("\u00a0", " ")
    assert "p₁" not in html and "πD²" not in html and "= 2R" not in html
    assert "<i>t</i> = <i>p</i><sub>1</sub> sin(" in html
    if language != "en":  # lone letters of Cyrillic prose in italics (the English prose's upright)
        assert "<i>S</i> = 2·<i>R</i>" in html
