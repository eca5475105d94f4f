"""Multi-cylinder engines: layouts, firing order, articulated rods, crankshaft torques."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import FLAT_FOUR_ENGINE, modified, shared_html, shared_run, write_scene
from scipy.optimize import brentq

from crankdyn.cli import examples_dir, main
from crankdyn.engine.orchestrator import run_scene
from crankdyn.physics import articulated as art
from crankdyn.physics.layout import LayoutError, build_layout
from crankdyn.plugin.registry import default_registry
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()
MULTI = ["inline4-petrol", "inline6-diesel-trace", "v8-petrol", "radial9-aircraft"]


def run(name, changes=None):
    """One computation per scene and worker, shared by the tests (they only read the results) and
    with the other test files (conftest.shared_run)."""
    return shared_run(name, changes)


# ----------------------------------------------------------------------------- layouts


def test_inline_crank_arrangements_from_firing_order():
    assert build_layout("inline", 4, 4, None, [1, 3, 4, 2], None).crank_lag_deg == (0, 180, 180, 0)
    assert build_layout("inline", 4, 6, None, [1, 5, 3, 6, 2, 4], None).crank_lag_deg == (
        0,
        120,
        240,
        240,
        120,
        0,
    )
    assert build_layout("inline", 2, 3, None, [1, 3, 2], None).crank_lag_deg == (0, 240, 120)


def test_radial_default_firing_order_every_other_cylinder():
    layout = build_layout("radial", 4, 9, None, None, None)
    assert layout.firing_order == ("1", "3", "5", "7", "9", "2", "4", "6", "8")
    assert np.allclose(layout.firing_intervals_deg(), 80.0)


def test_a_firing_order_written_from_another_cylinder_is_the_same_cycle():
    # the right bank's first cylinder written first, as a Russian handbook numbers a V8
    v8 = ["1L", "1R", "4L", "2L", "2R", "3L", "3R", "4R"]
    from_right = v8[1:] + v8[:1]
    ref = build_layout("V", 4, 8, 90, v8, None)
    other = build_layout("V", 4, 8, 90, from_right, None)
    assert other.firing_order == ref.firing_order == tuple(v8)
    assert other.crank_lag_deg == ref.crank_lag_deg
    assert np.allclose(other.firing_intervals_deg(), 90.0)


@pytest.mark.parametrize(
    "args, field, text",
    [
        (("inline", 4, 4, None, [1, 3, 3, 2], None), "engine.firing_order", "repeated: 3"),
        (("inline", 4, 4, None, [1, 3, 2], None), "engine.firing_order", "missing: 4"),
        (("inline", 4, 4, None, [1, 3, 4, 5], None), "engine.firing_order", "do not exist"),
        (("V", 4, 8, 90, [1, 2, 3, 4, 5, 6, 7, 8], None), "engine.firing_order", "do not exist"),
        (
            ("V", 4, 6, 90, ["1L", "1R", "2L", "2R", "3L", "3R"], None),
            "engine.firing_order",
            "share a crank",
        ),
        # 120 deg intervals and a 60 deg bank: no order fires evenly on shared pins
        (
            ("V", 4, 6, 60, ["1L", "2R", "3L", "1R", "2L", "3R"], None),
            "engine.firing_order",
            "no firing order fires evenly with this bank angle",
        ),
        # the refusal says split pins fire evenly but are not modelled (no field offers them)
        (
            ("V", 4, 6, 60, ["1L", "2R", "3L", "1R", "2L", "3R"], None),
            "engine.firing_order",
            "crankdyn models the banks on shared pins only",
        ),
        # 90 deg intervals and a 90 deg bank: another order does (the V8's)
        (
            ("V", 4, 8, 90, ["1L", "2L", "1R", "2R", "3L", "4L", "3R", "4R"], None),
            "engine.firing_order",
            "choose another firing order",
        ),
        (
            ("inline", 4, 4, None, [1, 3, 4, 2], [0, 180, 180]),
            "engine.crank_angles_deg",
            "one angle per crank",
        ),
        (("inline", 4, 2, None, [1, 2], [0, 180]), "engine.crank_angles_deg", "uneven"),
        (("V", 4, 8, None, ["1L"], None), "engine.bank_angle_deg", "required"),
        (("inline", 4, 4, 60, [1, 3, 4, 2], None), "engine.bank_angle_deg", "does not apply"),
        (("V", 4, 7, 90, None, None), "engine.cylinders", "multiple of 2"),
    ],
)
def test_layout_errors_name_the_field(args, field, text):
    with pytest.raises(LayoutError) as info:
        build_layout(*args)
    assert info.value.field == field and text in str(info.value)


def test_uneven_firing_allowed_when_declared():
    layout = build_layout("inline", 4, 2, None, [1, 2], [0, 180], uneven_firing=True)
    assert not layout.even_firing
    assert list(layout.firing_intervals_deg()) == [180.0, 540.0]


@pytest.mark.parametrize(
    "changes, field",
    [
        ({"engine": {"firing_order": [1, 3, 3, 2]}}, "engine.firing_order"),
        ({"engine": {"firing_order": ["1L", "2L", "3L", "4L"]}}, "engine.firing_order"),
        ({"engine": {"crank_angles_deg": [0, 180]}}, "engine.crank_angles_deg"),
        ({"engine": {"layout": "V", "bank_angle_deg": 90}}, "engine.firing_order"),
        ({"analysis": {"angle_step_deg": 0.7, "table_step_deg": 2.1}}, "analysis.angle_step_deg"),
    ],
)
def test_bad_multicylinder_scenes_exit_2(tmp_path, capsys, changes, field):
    scene = write_scene(tmp_path / "s.toml", modified("inline4-petrol", changes))
    out = tmp_path / "out"
    assert main(["report", str(scene), "-o", str(out), "--format", "json"]) == 2
    err = capsys.readouterr().err
    assert field in err and "Traceback" not in err
    assert not out.exists()


def test_articulated_slave_that_cannot_reach(tmp_path, capsys):
    scene = write_scene(
        tmp_path / "s.toml",
        modified("radial9-aircraft", {"articulated": {"slave_rod_length": "20 mm"}}),
    )
    assert main(["report", str(scene), "-o", str(tmp_path / "o"), "--format", "json"]) == 2
    assert "articulated.slave_rod_length" in capsys.readouterr().err


# ----------------------------------------------------------------------------- articulated rods

GEOMETRY = art.SlaveGeometry(
    crank_radius_m=0.0625,
    rod_length_m=0.25,
    pin_radius_m=0.06,
    pin_angle_rad=math.radians(64.0),
    bank_angle_rad=math.radians(60.0),
    slave_rod_length_m=0.19,
)


def _linkage_by_root_finding(alpha, g: art.SlaveGeometry):
    """Independent solution: master piston from |A - B| = L, pin from the rigid master rod,
    slave piston from |A_s - C| = l, each by a numerical root finder (global x-y frame)."""
    B = np.array(
        [g.crank_radius_m * math.sin(alpha), g.crank_radius_m * math.cos(alpha)]
    )  # x lateral, y = master axis
    y_a = brentq(
        lambda y: B[0] ** 2 + (y - B[1]) ** 2 - g.rod_length_m**2,
        B[1],
        B[1] + g.rod_length_m * 1.01,
        xtol=1e-15,
    )
    A = np.array([0.0, y_a])
    rod = (A - B) / g.rod_length_m
    c, s = math.cos(g.pin_angle_rad), math.sin(g.pin_angle_rad)
    # Rotate the rod direction by gamma_1 towards the slave bank (clockwise in x-y: rotation direction).
    pin_dir = np.array([rod[0] * c + rod[1] * s, -rod[0] * s + rod[1] * c])
    C = B + g.pin_radius_m * pin_dir
    axis = np.array([math.sin(g.bank_angle_rad), math.cos(g.bank_angle_rad)])
    return brentq(
        lambda x: np.sum((x * axis - C) ** 2) - g.slave_rod_length_m**2,
        float(C @ axis),
        float(C @ axis) + 2 * g.slave_rod_length_m,
        xtol=1e-15,
    )


def test_slave_piston_position_against_numerical_linkage():
    alphas = np.radians(np.arange(0, 360, 7.5))
    exact = art.slave_motion(alphas, GEOMETRY).piston_position_m
    independent = np.array([_linkage_by_root_finding(a, GEOMETRY) for a in alphas])
    assert np.max(np.abs(exact - independent)) < 1e-9


def test_slave_velocity_and_acceleration_by_finite_differences():
    w = 250.0
    a = np.radians(np.arange(0, 360, 5.0))
    m = art.slave_motion(a, GEOMETRY, w)
    h = 1e-6
    plus = art.slave_motion(a + w * h, GEOMETRY, w).piston_position_m
    minus = art.slave_motion(a - w * h, GEOMETRY, w).piston_position_m
    scale_v, scale_j = (
        np.max(np.abs(m.piston_velocity_m_s)),
        np.max(np.abs(m.piston_acceleration_m_s2)),
    )
    assert np.max(np.abs((plus - minus) / (2 * h) - m.piston_velocity_m_s)) < 1e-6 * scale_v
    assert (
        np.max(np.abs((plus - 2 * m.piston_position_m + minus) / h**2 - m.piston_acceleration_m_s2))
        < 1e-4 * scale_j
    )


def test_slave_stroke_is_longer_with_textbook_pin_angle():
    """Textbook §1.1: with l = L - r and gamma_1 from eq. (5), the slave stroke is 3-4 % longer."""
    g = art.SlaveGeometry(
        0.05,
        0.2,
        0.05,
        art.pin_angle_textbook_rad(9.5, 0.25, math.radians(60)),
        math.radians(60),
        0.15,
    )
    x_tdc, _, x_bdc, _ = art.slave_dead_centres(g)
    assert 1.03 < (x_tdc - x_bdc) / 0.1 < 1.04


def test_equal_compression_slave_rod_length():
    eps = 9.5
    g = art.SlaveGeometry(0.05, 0.2, 0.05, math.radians(60), math.radians(60), 0.15)
    length = art.slave_rod_length_equal_compression_m(g, eps)
    g = art.SlaveGeometry(0.05, 0.2, 0.05, math.radians(60), math.radians(60), length)
    x_tdc, _, x_bdc, _ = art.slave_dead_centres(g)
    deck = 0.05 + 0.2 + 0.1 / (eps - 1)
    assert (deck - x_bdc) / (deck - x_tdc) == pytest.approx(eps, rel=1e-10)
    # The textbook's closed form (eq. 3) is a close approximation of it.
    assert art.slave_rod_length_textbook_m(0.2, 0.05, 0.25, math.radians(60)) == pytest.approx(
        length, rel=1e-3
    )


def test_bay_statics_reproduce_textbook_equations_27_to_30():
    g = GEOMETRY
    alpha = np.radians(np.arange(0, 360, 3.0))
    lam = g.crank_radius_m / g.rod_length_m
    beta = np.arcsin(lam * np.sin(alpha))
    rng = np.random.default_rng(1)
    p1, p1_l = rng.normal(0, 3e6, alpha.size), rng.normal(0, 3e6, alpha.size)
    sm = art.slave_motion(alpha, g)
    t, z, n_sum = art.bay_crank_pin_forces(
        alpha,
        beta,
        p1,
        g.crank_radius_m,
        g.rod_length_m,
        [(sm.pin_a_m, sm.pin_n_m, sm.slave_rod_angle_rad, p1_l, g.bank_angle_rad)],
    )
    beta_l = sm.slave_rod_angle_rad
    phi = g.pin_angle_rad - g.bank_angle_rad
    alpha_l = alpha - g.bank_angle_rad
    k_l = p1_l / np.cos(beta_l)
    n_l = (
        p1_l
        * (g.pin_radius_m / g.rod_length_m)
        * np.sin(beta - beta_l - phi)
        / (np.cos(beta) * np.cos(beta_l))
    )  # (27)
    t_l = k_l * np.sin(alpha_l + beta_l) + n_l * np.cos(alpha_l + g.bank_angle_rad)  # (29)
    z_l = k_l * np.cos(alpha_l + beta_l) - n_l * np.sin(alpha_l + g.bank_angle_rad)  # (30)
    t_master = p1 * np.sin(alpha + beta) / np.cos(beta)  # (24)
    z_master = p1 * np.cos(alpha + beta) / np.cos(beta)  # (25)
    scale = 3e6
    assert np.max(np.abs(t - (t_master + t_l))) < 1e-9 * scale
    assert np.max(np.abs(z - (z_master + z_l))) < 1e-9 * scale
    assert np.max(np.abs(n_sum - (p1 * np.tan(beta) + n_l))) < 1e-9 * scale  # (22) + (28)


# ----------------------------------------------------------------------------- torques


@pytest.mark.parametrize("name", MULTI)
def test_mean_output_torque_equals_indicated_work(name):
    """Virtual work: mean output torque = indicated work of all cylinders / (2 pi strokes/2).

    For articulated rods this checks the whole bay statics: the torque comes from forces on
    the crank pin, the work from each piston's own pressure-volume loop.
    """
    torque = run(name).outputs["torque"].results
    assert torque["mean_Nm"] == pytest.approx(torque["mean_from_work_Nm"], rel=2e-4)


def test_diesel_rk_six_cylinder_acceptance():
    result = run("inline6-diesel-trace")
    work_one = result.outputs["indicator"].results["indicated_work_J"]
    torque = result.outputs["torque"].results
    assert torque["mean_from_work_Nm"] == pytest.approx(work_one * 6 / (4 * math.pi), rel=1e-12)
    assert abs(torque["mean_Nm"] / (work_one * 6 / (4 * math.pi)) - 1) < 0.002
    assert torque["period_deg"] == 120.0
    html = shared_html("inline6-diesel-trace", language="en").linked_html
    assert "Mean indicated torque" in html and 'data-stage="torque"' in html


@pytest.mark.parametrize("name", MULTI)
def test_last_journal_carries_the_output_torque(name):
    result = run(name)
    loads = result.outputs["torque"].data["crank_loads"]
    engine = result.outputs["torque"].data["engine_torque"]
    np.testing.assert_allclose(
        loads.journal_torque_Pa[-1] * loads.crank_radius_m * loads.piston_area_m2,
        engine.torque_Nm,
        rtol=0,
        atol=1e-9 * np.max(np.abs(engine.torque_Nm)),
    )
    # and it is the sum of all crank torques
    np.testing.assert_allclose(
        loads.journal_torque_Pa[-1], loads.tangential_Pa.sum(axis=0), rtol=1e-12
    )


@pytest.mark.parametrize(
    "name, pattern",
    [
        (
            "inline4-petrol",
            {2: 180, 3: 540, 4: 360},
        ),  # textbook table B.3: z_180, z_540, z_360 at alpha = 0
        (
            "inline6-diesel-trace",
            {5: 600, 3: 480, 6: 360, 2: 240, 4: 120},
        ),  # 1-5-3-6-2-4: crank i is 720 - delay_i into its cycle
    ],
)
def test_b3_phase_pattern(name, pattern):
    result = run(name)
    single = result.outputs["forces"].tables["forces"]["tangential_Pa"].to_numpy()
    loads = result.outputs["torque"].data["crank_loads"]
    step = result.scene.analysis.angle_step_deg
    for crank, cycle_angle in pattern.items():
        assert loads.tangential_Pa[crank - 1][0] == pytest.approx(
            single[int(cycle_angle / step)], abs=1e-6
        )
    # the pin torque of crank 1 is half its own tangential force (free end), eq. (44)
    np.testing.assert_allclose(loads.pin_torque_Pa[0], 0.5 * loads.tangential_Pa[0])


def test_torque_period_and_symmetric_v8():
    result = run("v8-petrol")
    torque = result.outputs["torque"].data["engine_torque"].torque_Nm
    assert result.outputs["torque"].results["period_deg"] == 90.0
    np.testing.assert_allclose(
        torque, np.roll(torque, 90), rtol=1e-9, atol=1e-9 * np.max(np.abs(torque))
    )


@pytest.mark.parametrize(("name", "language"), [("v8-petrol", "en"), ("radial9-aircraft", "uk")])
def test_multibank_reports_render(name, language):
    rendered = shared_html(name, language=language)  # the text only: its figures are not drawn here
    assert not rendered.missing_translations
    assert (
        'data-stage="bays"' in rendered.linked_html
        and 'data-stage="torque"' in rendered.linked_html
    )
    if name.startswith("radial"):
        assert ("B.2" in rendered.linked_html) or ("Б.2" in rendered.linked_html)


# ----------------------------------------------------------------------------- every layout


def _even_firing_order(layout, strokes, cylinders, bank_angle, lags):
    """A firing order for the given crank lags, built from the geometry (delay = psi + lag mod 360)."""
    from crankdyn.physics.layout import bank_axes_deg, cylinder_labels

    axes = bank_axes_deg(layout, bank_angle, cylinders)
    residues = sorted(
        ((axes[bank] + lags[bay]) % 360.0, label)
        for label, bank, bay in cylinder_labels(layout, cylinders)
    )
    base = residues[[r[1] for r in residues].index(cylinder_labels(layout, cylinders)[0][0])][0]
    delays, used = {}, set()
    for residue, label in residues:
        delay = (residue - base) % 360.0
        while strokes == 4 and round(delay, 6) in used:
            delay += 360.0
        used.add(round(delay, 6))
        delays[label] = delay
    return [label for label, _ in sorted(delays.items(), key=lambda kv: kv[1])]


@pytest.mark.parametrize(
    "layout, strokes, cylinders, bank, lags, rod",
    [
        ("X", 4, 8, 90, [0, 0], "central"),
        ("Y", 2, 6, 120, [0, 60], "central"),
        ("W", 2, 6, 60, [0, 180], "fork"),
        ("boxer", 4, 4, None, [0, 180, 180, 0], "central"),
        ("V", 4, 6, 120, [0, 240, 120], "articulated"),
        ("inline", 2, 3, None, [0, 120, 240], "central"),
    ],
)
def test_every_layout_keeps_the_invariants(layout, strokes, cylinders, bank, lags, rod):
    order = _even_firing_order(layout, strokes, cylinders, bank, lags)
    changes = {
        "engine": {
            "layout": layout,
            "strokes": strokes,
            "cylinders": cylinders,
            "bank_angle_deg": bank,
            "firing_order": order,
            "crank_angles_deg": lags,
            "rod_type": rod,
        }
    }
    if strokes == 2:
        changes["cycle"] = {
            "exhaust_pressure": None,
            "rounding": {
                "exhaust_closes_after_tdc_deg": None,
                "intake_opens_before_tdc_deg": None,
                "intake_closes_after_bdc_deg": None,
            },
        }
    if rod == "articulated":
        changes["articulated"] = {"pin_radius": "40 mm"}
    data = modified("inline4-petrol", changes)
    if bank is None:
        data["engine"].pop("bank_angle_deg", None)
    result = run_scene(scene_from_dict(data, base_dir=examples_dir()), REGISTRY)
    torque = result.outputs["torque"].results
    assert result.outputs["bays"].results["even_firing"]
    assert torque["mean_Nm"] == pytest.approx(torque["mean_from_work_Nm"], rel=3e-4)
    # articulated master and slave cylinders differ: the torque repeats per crank only
    cranks = result.outputs["bays"].results["cranks"]
    expected = 180.0 * strokes / (cranks if rod == "articulated" else cylinders)
    assert torque["period_deg"] == pytest.approx(expected)
    for entry in result.outputs["bearings"].results["main_journals"]:
        assert np.isfinite(entry["max_N"]) and entry["max_N"] > 0


@pytest.mark.slow  # the multi-cylinder crankshaft chapter in a Ukrainian PDF: tests/test_frame.py's in-line four
def test_v8_pdf_in_ukrainian(tmp_path):
    import shutil
    import subprocess

    out = tmp_path / "v8"
    # The crankshaft chapter and what it needs (the full Ukrainian note is tests/test_note.py's PDF)
    assert (
        main(
            [
                "report",
                str(examples_dir() / "v8-petrol.toml"),
                "-o",
                str(out),
                "--lang",
                "uk",
                "--format",
                "pdf",
                "--stages",
                "torque",
                "-q",
            ]
        )
        == 0
    )
    if shutil.which("pdftotext"):
        text = subprocess.run(
            ["pdftotext", str(out / "report.pdf"), "-"], capture_output=True, text=True
        ).stdout
        assert "Навантаження на колінчастий вал" in text and "Б.3" in text and "Б.4" in text


@pytest.mark.parametrize(
    "cylinders, layout, bank", [(4, "inline", None), (6, "inline", None), (8, "V", 90)]
)
def test_missing_firing_order_gets_the_explorers_best(cylinders, layout, bank):
    """No firing_order -> the explorer's top-ranked order and crank arrangement, said in the report.
    Checked against invariants: even firing, and the free first-order forces and moments of an in-line 4,
    in-line 6 vanish (both orders up to the second for the in-line 6); the cross-plane V8 keeps only a
    co-rotating first-order couple, which counterweights cure (no balance shaft)."""
    from crankdyn.physics import firing_explorer as fe

    data = modified(
        "v8-petrol" if layout == "V" else "inline4-petrol",
        {
            "flywheel": None,
            "analysis": {"stages": ["bays", "balancing"]},
            "engine": {"cylinders": cylinders, "firing_order": None, "crank_angles_deg": None},
        },
    )
    result = run_scene(scene_from_dict(data, base_dir=examples_dir()), default_registry())
    assert result.scene.firing_order_chosen
    best = fe.explore(cylinders, layout, 4, bank, top=1).rows[0]
    bays = result.outputs["bays"].results
    assert bays["firing_order"] == list(best.firing_order) and bays["firing_order_chosen"]
    assert bays["firing_intervals_deg"] == pytest.approx([720 / cylinders] * cylinders, abs=1e-9)
    # an in-line engine's cylinders have pins of their own: its rule says nothing of shared pins
    chosen = "bays.note_firing_chosen" + ("_own_pins" if layout == "inline" else "")
    assert chosen in [key for key, _ in result.outputs["bays"].notes]
    balancing = result.outputs["balancing"].results
    coefficients = balancing["coefficients"]
    first = next(o for o in balancing["orders"] if o["order"] == 1)
    assert coefficients["sum_PI"] == 0 and first["force_backward"]["magnitude"] == 0
    assert first["moment_backward"]["magnitude"] == 0 and (
        layout == "V" or coefficients["M_PI"] == 0
    )
    if cylinders == 6:
        assert coefficients["sum_PII"] == 0 and coefficients["M_PII"] == 0


def _printed_number(text: str) -> float:
    return float(text.replace("\u2009", "").replace("\u202f", "").replace(",", "."))


@pytest.mark.parametrize("language", ["uk", "en"])
def test_an_articulated_bays_rotating_mass_is_given_from_its_terms_in_the_text(language):
    """m_R of a radial with articulated rods: the task sheet lists the slave rods' data the scene
    gives, and the printed substitution of the bay's formula multiplies out to the printed m_R,
    the mass of the balancing section's C = m_R R ω²."""
    import re

    html = shared_html("radial9-aircraft", language=language).linked_html
    result = shared_run("radial9-aircraft")
    scene = result.scene
    task = re.search(r'<table class="data[^"]*" data-number="1.1">(.*?)</table>', html, flags=re.S)
    cells = [re.sub(r"<[^>]+>", "", c).strip() for c in re.findall(r"<td[^>]*>(.*?)</td>", task[1])]
    point = "." if language == "en" else ","
    for value in ("68", f"1{point}2", f"0{point}47"):  # r, the slave rod's mass, its share
        assert value in cells, value
    text = re.sub(r"<[^>]+>", "", html).replace("\u00a0", " ")
    found = re.search(
        r"= ([\d.,]+) \+ 2·([\d.,]+) \+ ([\d.,]+) \+ \(([\d.,]+)·\(1 − ([\d.,]+)\) \+ ([\d.,]+)\)·"
        r"([\d.,]+) = ([\d.,]+)",
        text,
    )
    assert found, "the bay's m_R with its substitution"
    pin, web, rod, slave, share, slave_pin, levers, total = map(_printed_number, found.groups())
    assert pin + 2 * web + rod + (slave * (1 - share) + slave_pin) * levers == pytest.approx(
        total, rel=1e-3
    )
    m_R = result.outputs["balancing"].results["rotating_mass_kg"]
    assert total == pytest.approx(m_R, rel=1e-3)
    assert slave == pytest.approx(1.2) and pin == pytest.approx(scene.masses.crank_pin)


def test_a_cylinders_bank_letter_is_printed_in_the_reports_letters():
    """1L, 1R of a V engine are 1Л, 1П in a Cyrillic note (лівий/правий, левый/правый) and stay
    1L, 1R in English: in the task sheet, the bays' text and tables and the scheme's
    firing order."""
    import re

    from crankdyn.report.i18n import translator

    assert translator("uk").cylinders(["1L", "1R", "4L", "3"]) == "1Л–1П–4Л–3"
    assert translator("ru").cylinder("2R") == "2П"
    assert translator("en").cylinders(["1L", "1R"]) == "1L–1R"
    for language, left, right in (("ru", "Л", "П"), ("uk", "Л", "П"), ("en", "L", "R")):
        html = shared_html("v8-petrol", language=language).linked_html
        for stage in ("input", "bays"):
            found = re.search(rf'data-stage="{stage}">(.*?)</section>', html, flags=re.S)
            text = re.sub(r"<(svg|script)\b.*?</\1>|<[^>]+>", " ", found[1], flags=re.S)
            labels = re.findall(r"(?<![\w.,])\d(L|R|Л|П)\b", text)
            assert labels, stage
            assert set(labels) <= {left, right}, (language, stage, set(labels))
    # the letters are explained where the bays' section first uses them
    assert "Л – левый ряд, П – правый ряд" in shared_html("v8-petrol", language="ru").linked_html
    # the scheme's liners, crank star and firing order (drawn, not in the text)
    from crankdyn_builtin.drawing.section import _labelled

    positions = shared_run("v8-petrol").outputs["drawing"].artifacts["positions"]
    drawn = _labelled(positions, translator("uk"))
    assert drawn.firing_order[:2] == ("1Л", "1П")
    assert {g.label for g in drawn.guides if g.label} >= {"1Л", "1П", "4П"}
    assert all("L" not in c and "R" not in c for _, _, cs in drawn.cranks for c in cs)


def test_a_bay_of_central_rods_is_not_also_said_to_have_fork_rods():
    page = shared_html("v8-petrol")
    html = page.linked_html if hasattr(page, "linked_html") else page
    assert "common crank pin through central rods;" in html
    assert "fork-and-blade" not in html


def test_the_rods_on_one_crank_pin_are_the_centrifugal_terms_mass():
    """c_r = −m_rR·Rω²/F_p with m_rR of every rod on the pin: the radial's is the bays' sum of the
    master's rotating part and the articulated rods' shares (10,29 kg), not one rod's."""
    result = shared_run("radial9-aircraft")
    rods_kg = result.outputs["bays"].results["rotating_mass_terms"]["rods_kg"]
    engine = result.scene.engine
    area = math.pi * engine.bore**2 / 4
    c_r = -rods_kg * engine.crank_radius_m * engine.angular_velocity_rad_s**2 / area
    assert result.outputs["bearings"].results["centrifugal_rod_Pa"] == pytest.approx(c_r, rel=1e-9)
    page = shared_html("radial9-aircraft")
    html = page.linked_html if hasattr(page, "linked_html") else page
    # the master rod's rotating part with the slaves' shares has its own letter (m_rR is one rod's)
    assert "Only the master rod bears on the crank pin: the rotating part of the master rod" in html
    assert (
        f"with the shares of the slave rods and their pins is <i>m</i><sub>rR.m</sub>\xa0=\xa0"
        f"{rods_kg:.4g}\u202fkg"
    ) in html


def test_a_vs_crank_columns_are_said_to_be_its_cylinders_sums():
    """The symbols call t_i a cylinder's force; a V's torque table gives each crank's sum."""
    page = shared_html("v8-petrol")
    html = page.linked_html if hasattr(page, "linked_html") else page
    assert html.count("A crank here carries two cylinders") == 1
    page = shared_html("inline4-petrol")
    html = page.linked_html if hasattr(page, "linked_html") else page
    assert "A crank here carries" not in html


def _boxer_data(**engine) -> dict:
    """A four-cylinder boxer built on the V8 example's masses and cycle (uk note)."""
    changes = {**FLAT_FOUR_ENGINE, **engine}
    return modified("v8-petrol", {"engine": changes, "report": {"language": "uk"}})


def test_a_boxer_gives_every_cylinder_its_own_crank_and_balances_as_a_flat_four():
    """A boxer has a crank pin per cylinder, opposed cylinders in neighbouring bays: with the
    cranks 0-180-180-0 every force and the first-order and centrifugal couples cancel, and only
    the second-order couple 2 A_2 C_I b is left (A_2 the exact second harmonic of the piston's
    acceleration, here found by a discrete Fourier transform of the exact kinematics)."""
    import re as _re

    from crankdyn.report.document import render_html as _render

    registry = default_registry()
    scene = scene_from_dict(_boxer_data())
    result = run_scene(scene, registry)
    bays = result.outputs["bays"].results
    assert bays["cranks"] == 4
    assert [c % 360 for c in bays["crank_angles_deg"]] == [0.0, 180.0, 180.0, 0.0]
    assert list(bays["firing_order"]) == ["1", "3", "2", "4"]
    balancing = result.outputs["balancing"].results
    absolute = balancing["absolute"]
    e = scene.engine
    lam = e.rod_ratio_value
    theta = np.linspace(0.0, 2 * np.pi, 4096, endpoint=False)
    # the piston's displacement from TDC over R (exact) and its acceleration over R omega^2
    x = 1 - np.cos(theta) + (1 - np.sqrt(1 - (lam * np.sin(theta)) ** 2)) / lam
    spectrum = np.fft.rfft(x)
    harmonic_2 = 4 * 2 * np.abs(spectrum[2]) / len(theta)  # (2 omega)^2 times x's 2nd harmonic
    c_one = balancing["reciprocating_mass_kg"] * e.crank_radius_m * e.angular_velocity_rad_s**2
    assert balancing["first_order_N"] == pytest.approx(c_one, rel=1e-12)
    for key in ("sum_C_N", "sum_PI_N", "sum_PII_N", "M_C_Nm", "M_PI_Nm"):
        assert abs(absolute[key]) < 1e-9 * c_one
    assert absolute["M_PII_Nm"] == pytest.approx(2 * harmonic_2 * c_one * 0.1, rel=1e-9)
    text = _re.sub(r"<[^>]+>", "", _render(result, registry, "uk").linked_html)
    assert "Кожен циліндр має власну шатунну шийку" in text
    assert "спільній шатунній шийці" not in text
    # the crank diagrams' vertical is across the flat banks, not a bay's axis of symmetry
    assert "Циліндри лежать горизонтально один проти одного" in text
    assert "вісь симетрії відсіку" not in text


def test_a_boxer_refuses_articulated_rods():
    """Articulated rods need cylinders sharing a crank pin; a boxer's have a pin each."""
    with pytest.raises(LayoutError, match="articulated rods"):
        build_layout("boxer", 4, 4, None, ["1", "3", "2", "4"], None, rod_type="articulated")


def test_a_boxer_scheme_lies_flat_and_marks_each_cylinders_crank_pin():
    """The scheme of a boxer lays its opposed banks horizontal, the first bank on the left, and
    marks the crank pin B and the piston pin A of each drawn cylinder with its number: the two
    cylinders in front have crank pins of their own, 180° apart."""
    import re
    from dataclasses import replace

    from crankdyn.report import mechanism_drawing as md
    from crankdyn.report.document import render_html as _render

    registry = default_registry()
    result = run_scene(scene_from_dict(_boxer_data()), registry)
    positions = result.outputs["drawing"].artifacts["positions"]
    front = md.upright(md.front_view(positions))
    directions = [np.asarray(g.direction, dtype=float) for g in front.guides]
    assert [g.label for g in front.guides] == ["1", "2"]
    np.testing.assert_allclose(directions, [[-1.0, 0.0], [1.0, 0.0]], atol=1e-12)
    crank, pairs = md.bank_mark_parts(md.front_view(positions))
    pins = [rod[1] for _, rod in pairs]
    assert crank[2] == pins[0] and len(set(pins)) == 2
    drawing_only = replace(
        result.plan, order=[s for s in result.plan.order if s.name.startswith("drawing")]
    )
    page = _render(replace(result, plan=drawing_only), registry, "uk")
    svg = next(f for f in page.figures if f.key == "scheme").svg.decode("utf-8")
    assert svg.count(">U<") == 2 and svg.count(">A<") == 2 and svg.count(">O<") == 1
    text = re.sub(r"<[^>]+>", "", page.linked_html)
    assert "U – вісь шатунної шийки і A – вісь поршневого пальця" in text
    assert "з номером циліндра в індексі (1, 2)" in text
    # its cranks balance one another: no counterweight is fitted, and none is drawn
    assert not len(result.outputs["balancing"].data["counterweights"].crank)
    assert "противага кривошипа" not in text


def test_a_flat_six_leaves_only_negligible_moments_and_says_moments():
    """A flat six's cranks cancel every force and the couples of orders 1, 2 and 4: what is left
    (orders 6 and up) are couples only, and the conclusion names moments, not forces."""
    import re

    from crankdyn.report.document import render_html as _render

    registry = default_registry()
    data = _boxer_data(cylinders=6, firing_order=[1, 6, 3, 2, 5, 4])
    result = run_scene(scene_from_dict(data), registry)
    absolute = result.outputs["balancing"].results["absolute"]
    c_one = result.outputs["balancing"].results["first_order_N"]
    for key in ("sum_C_N", "M_C_Nm", "sum_PI_N", "M_PI_Nm", "sum_PII_N", "M_PII_Nm"):
        assert abs(absolute[key]) < 1e-9 * c_one, key
    text = re.sub(r"<[^>]+>", "", _render(result, registry, "uk").linked_html)
    # one moment is said in the singular, several in the plural
    assert re.search(r"незрівноважен(і лише моменти|ий лише момент) [^(]*порядк(у|ів) \(ΣM", text)


def test_the_engine_section_is_titled_for_what_it_holds():
    """A V8's rods side by side leave the section the cylinders' order and phases (the crank
    section sums the pin's forces): no "forces on the crank pins" in its title; a radial's master
    rod sums them in the section itself, which keeps that title, on its one crank pin."""
    import re

    for name, forces in (("v8-petrol", False), ("radial9-aircraft", True)):
        html = shared_html(name)
        html = html.linked_html if hasattr(html, "linked_html") else html
        titles = re.findall(r"<h2[^>]*>\s*6\s+([^<]*)</h2>", html)
        assert titles, name
        assert ("crank pin" in titles[0]) is forces, (name, titles[0])
    assert titles[0].rstrip().endswith("on the crank pin"), titles[0]  # the radial's one pin


@pytest.mark.parametrize("bank, intervals", [(45, [405, 315]), (90, [450, 270]), (60, [420, 300])])
def test_a_v_twin_on_one_pin_fires_as_evenly_as_its_bank_angle_allows(bank, intervals):
    """Each cylinder of a four-stroke passes its TDC twice a cycle: the right bank's fires a turn
    plus the bank angle after the left's (720° - that after it), not the bank angle after it,
    which would leave 720° - γ between the left's firings and the next."""
    layout = build_layout("V", 4, 2, bank, ["1L", "1R"], [0], uneven_firing=True)
    np.testing.assert_allclose(layout.firing_intervals_deg(), intervals, atol=1e-9)


def test_a_radials_star_not_a_crank_arrangement_balances_and_no_moments_are_named():
    """All the cylinders of a radial work on one crank, in one plane across the shaft: what its
    cylinders' arrangement would balance with equal masses is said of the arrangement, not of a
    crank arrangement, and no moment is named."""
    import re

    html = shared_html("radial9-aircraft", None, "uk")
    html = html.linked_html if hasattr(html, "linked_html") else html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html))
    found = re.search(r"їхнє розташування зрівноважило б ([^;]*);", text)
    assert found and "ΣM" not in found.group(1).replace(" ", ""), found
    assert "Схема колін сама зрівноважує" not in text


def test_a_v_twins_note_speaks_of_one_crank_and_its_side_by_side_rods():
    """A 45° V-twin with its two rods side by side on one pin: no crank arrangement among its
    firing data, its balance said to come from the cylinders' arrangement, and the rods' offset
    along the pin given its couples rather than said to leave no moments."""
    import re

    from conftest import V_TWIN_ENGINE

    changes = {"engine": V_TWIN_ENGINE, "report": {"language": "uk"}}
    html = shared_html("v8-petrol", changes, "uk")
    html = html.linked_html if hasattr(html, "linked_html") else html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html))
    assert "Порядок роботи циліндрів 1Л–1П; інтервали між спалахами: 405° і 315°." in text
    assert "схема колін (відставання" not in text
    assert "зсув шатунів уздовж шийки і його моменти розглянуто після таблиці сил" in text
    assert "Від цього зміщення сили інерції дають поздовжні моменти" in text
    assert "поздовжніх моментів цих сил немає" not in text
    assert "зрівноважено схемою колін" not in text
    assert "Циліндри пронумеровано по колу зірки" not in text


@pytest.mark.parametrize(
    "language, sentence",
    [
        (
            "ru",
            "начиная с цилиндра 1, в направлении вращения вала. Главный шатун работает в "
            "цилиндре 1, прицепные – в остальных цилиндрах.",
        ),
        (
            "uk",
            "починаючи з циліндра 1, у напрямку обертання вала. Головний шатун працює в "
            "циліндрі 1, причіпні – в решті циліндрів.",
        ),
        (
            "en",
            "from cylinder 1 in the direction of the shaft's rotation. The master rod works in "
            "cylinder 1, the slave rods in the other cylinders.",
        ),
    ],
)
def test_a_radials_note_names_the_master_rods_cylinder(language, sentence):
    """The tables of a radial give the slave cylinders by number; the note says which cylinder
    the master rod works in (the one no slave rod is in), once; a V's note has no such sentence."""
    import re

    slaves = shared_run("radial9-aircraft", None, ("bays",)).outputs["bays"].results["slaves"]
    assert "1" not in {s["cylinder"] for s in slaves} and len(slaves) == 8
    # cylinder k + 1 reaches its TDC about 40°·k of the shaft's turn after cylinder 1: the
    # numbers run round the star in the direction of rotation, as the note says
    tdc = [s["tdc_master_angle_deg"] for s in sorted(slaves, key=lambda s: int(s["cylinder"]))]
    assert np.all(np.diff(tdc) > 0) and np.allclose(tdc, np.arange(1, 9) * 40.0, atol=5.0)
    html = shared_html("radial9-aircraft", None, language, ("bays",)).linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", html).replace("&#39;", "'").split())
    assert text.count(sentence) == 1
    v8 = shared_html("v8-petrol", None, language, ("bays",)).linked_html
    assert sentence.split(". ")[1].split(" 1")[0] not in " ".join(
        re.sub(r"<[^>]+>", "", v8).split()
    )


@pytest.mark.parametrize("example", ["radial9-aircraft", "v8-petrol", "inline3-petrol"])
def test_the_torque_table_has_a_row_at_each_extreme_the_conclusions_quote(example):
    """The conclusions give the engine torque's largest and least values to 0.1 N·m with their
    angles; table B.3 has a row at each (one the 30° step misses is added), so that no
    conclusion quotes a value the table does not show."""
    import re

    r = shared_run(example, None, ("torque",)).outputs["torque"].results
    html = shared_html(example, None, "en", ("torque",)).linked_html
    section = html[html.index('data-stage="torque"') :]
    table = section[: section.index("</table>")]
    rows = {}
    for row in re.findall(r"<tr[^>]*>(.*?)</tr>", table, flags=re.S)[1:]:
        cells = [re.sub(r"<[^>]+>", "", c).strip() for c in re.findall(r"<td[^>]*>(.*?)</td>", row)]
        rows[cells[0]] = cells[-1]
    for kind in ("max", "min"):
        angle = f"{r[f'{kind}_crank_angle_deg']:.0f}"
        assert angle in rows, (kind, angle, sorted(rows))
        assert rows[angle] == f"{r[f'{kind}_Nm']:.1f}".replace("-", "\u2212"), (kind, rows[angle])


def test_the_given_datas_firing_order_parts_once_after_its_middle_dash():
    """A narrow cell broke a V6's order as "1Л–1П–3Л–3П–2Л–" over a lone "2П": the order keeps
    its halves whole and may part only after its middle dash; a short order stays whole."""
    from crankdyn.report.i18n import translator

    t = translator("uk")
    six = t.firing_order_cell(["1L", "1R", "3L", "3R", "2L", "2R"])
    assert six == "1Л–\u20601П–\u20603Л–\u200b3П–\u20602Л–\u20602П"
    assert t.firing_order_cell(["1", "3", "4", "2"]) == "1–\u20603–\u20604–\u20602"
    assert t.firing_order_cell(["1", "2", "4", "5", "3"]).split("\u200b") == [
        "1–\u20602–\u20604–",
        "5–\u20603",
    ]
    from conftest import shared_html

    page = shared_html("v8-petrol", language="uk").linked_html
    cell = page.split(t("input.firing_order"), 1)[1].split("</tr>", 1)[0]
    assert cell.count("\u200b") == 1 and cell.count("–") == 7


def test_the_phase_tables_axis_angles_count_from_the_first_cylinder_by_its_label():
    """A V engine has no cylinder "1": the column counts from "1Л" (it said "від осі циліндра 1")."""
    from conftest import shared_html

    page = shared_html("v8-petrol", language="uk").linked_html
    assert "Кут осі циліндра від осі циліндра 1Л, °" in page
