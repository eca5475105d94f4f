"""Exact rod loads: with ``[rod_dynamics] apply_to_loads = true`` the forces, and so the
bays, torque and bearings, use the rod as a rigid body.

Independent reference, written here: the Newton-Euler equations of the piston and of the rod solved as a
linear system at every angle (np.linalg.solve), in a frame of the test's own. Crank axis at the origin,
cylinder axis +y, crank pin B = R (sin a, cos a), rod angle b = arcsin(lambda sin a), piston pin
A = (0, R cos a + L cos b). The accelerations are second derivatives of these positions by a
central difference in a (8th order, h = 0.02 rad), times omega^2 — not the code's closed forms. Unknowns: the piston's
force on the rod at A (Ax, Ay), the crank pin's force on the rod at B (Bx, By), the wall force N:
  piston  x: 0 = -Ax + N;   y: m_p yA'' = -F_g - Ay
  rod     x: m aGx = Ax + Bx;   y: m aGy = Ay + By;   about G: I b'' = (A - G) x F_A + (B - G) x F_B.
The load on the crank pin is -F_B: T along (cos a, -sin a), Z along -(sin a, cos a).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import modified

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.errors import SceneError
from crankdyn.plugin.registry import default_registry
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()
I_G = "0.0035 kg m^2"


def _run(example, inertia=I_G, apply=True, **more):
    changes = {
        "masses": {"rod_moment_of_inertia": inertia},
        "rod_dynamics": {"apply_to_loads": apply},
        **more,
    }
    return run_scene(scene_from_dict(modified(example, changes), base_dir=examples_dir()), REGISTRY)


def newton_euler(alpha, R, L, lr, m, inertia, mp, w, gas_N):
    lam = R / L

    def positions(a):
        b = np.arcsin(lam * np.sin(a))
        B = np.array([R * np.sin(a), R * np.cos(a)])
        A = np.array([np.zeros_like(a), R * np.cos(a) + L * np.cos(b)])
        return A, B, B + (lr / L) * (A - B), b

    h = 2e-2  # 8th-order central difference: truncation ~h^8, round-off ~eps/h^2, both below 1e-11
    c = {1: 8 / 5, 2: -1 / 5, 3: 8 / 315, 4: -1 / 560}

    def second(fn):
        return (
            (
                sum(k * (fn(alpha + j * h) + fn(alpha - j * h)) for j, k in c.items())
                - 2 * sum(c.values()) * fn(alpha)
            )
            / h**2
            * w**2
        )

    A, B, G, b = positions(alpha)
    aA = second(lambda a: positions(a)[0])
    aG = second(lambda a: positions(a)[2])
    bdd = second(lambda a: positions(a)[3])
    out = {k: np.zeros_like(alpha) for k in ("T", "Z", "Ax", "Ay", "N")}
    for i, a in enumerate(alpha):
        ra, rb = A[:, i] - G[:, i], B[:, i] - G[:, i]
        #            Ax       Ay       Bx       By      N
        M = np.array(
            [
                [-1.0, 0.0, 0.0, 0.0, 1.0],
                [0.0, -1.0, 0.0, 0.0, 0.0],
                [1.0, 0.0, 1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0, 1.0, 0.0],
                [-ra[1], ra[0], -rb[1], rb[0], 0.0],
            ]
        )
        rhs = np.array(
            [0.0, mp * aA[1, i] + gas_N[i], m * aG[0, i], m * aG[1, i], inertia * bdd[i]]
        )
        ax, ay, bx, by, n = np.linalg.solve(M, rhs)
        out["T"][i] = -(bx * np.cos(a) - by * np.sin(a))
        out["Z"][i] = bx * np.sin(a) + by * np.cos(a)
        out["Ax"][i], out["Ay"][i], out["N"][i] = ax, ay, n
    return out


@pytest.fixture(scope="module")
def exact_run():
    return _run("petrol-1cyl")


def test_loads_match_a_newton_euler_solve(exact_run):
    scene = exact_run.scene
    e, m = scene.engine, scene.masses
    f = exact_run.outputs["forces"].tables["forces"]
    alpha = np.radians(f["crank_angle_deg"].to_numpy())
    area = exact_run.outputs["forces"].results["piston_area_m2"]
    ref = newton_euler(
        alpha,
        e.crank_radius_m,
        e.rod_length_m,
        scene.rod_cm_from_big_end_m,
        m.rod,
        m.rod_moment_of_inertia,
        m.piston_group,
        e.angular_velocity_rad_s,
        f["gas_Pa"].to_numpy() * area,
    )
    scale = np.max(np.hypot(ref["T"], ref["Z"]))
    for column, value in (
        ("crank_pin_tangential_N", ref["T"]),
        ("crank_pin_radial_N", ref["Z"]),
        ("wrist_pin_lateral_N", ref["Ax"]),
        ("wrist_pin_axial_N", -ref["Ay"]),
        ("side_N", ref["N"]),
    ):
        assert np.max(np.abs(f[column].to_numpy() - value)) < 1e-9 * scale, column
    # the torque and the bay loads handed on are the exact ones
    np.testing.assert_allclose(
        f["torque_Nm"], ref["T"] * e.crank_radius_m, rtol=0, atol=1e-9 * scale * e.crank_radius_m
    )
    c_rod = exact_run.outputs["forces"].results["centrifugal_rod_Pa"]
    np.testing.assert_allclose((f["radial_Pa"] + c_rod) * area, ref["Z"], rtol=0, atol=1e-9 * scale)
    # and the difference to the two-mass loads is reported, not zero
    r = exact_run.outputs["forces"].results["exact_rod"]
    two = np.hypot(f["crank_pin_tangential_two_mass_N"], f["crank_pin_radial_two_mass_N"])
    assert r["crank_pin_difference_max_N"] > 1e-3 * np.max(two)
    assert "forces.note_exact_rod" in [k for k, _ in exact_run.outputs["forces"].notes]


def test_two_mass_inertia_gives_the_textbook_loads():
    """With I_G = m l_R (L - l_R) the rigid rod is dynamically the two-mass rod: the loads agree."""
    only = {"analysis": {"stages": ["forces"]}}
    base = _run("petrol-1cyl", apply=False, inertia="1 kg m^2", **only)
    scene = base.scene
    m, L, lr = scene.masses.rod, scene.engine.rod_length_m, scene.rod_cm_from_big_end_m
    exact = _run("petrol-1cyl", inertia=f"{m * lr * (L - lr):.17g} kg m^2", **only)
    a, b = base.outputs["forces"].tables["forces"], exact.outputs["forces"].tables["forces"]
    for column in ("tangential_Pa", "radial_Pa", "side_Pa", "torque_Nm"):
        scale = np.max(np.abs(a[column]))
        np.testing.assert_allclose(b[column], a[column], rtol=0, atol=1e-9 * scale, err_msg=column)


def test_exact_loads_reach_the_bearings():
    only = {"analysis": {"stages": ["bearings"]}, "flywheel": None}
    plain, exact = _run("inline4-petrol", apply=False, **only), _run("inline4-petrol", **only)
    assert (
        "exact_rod" in exact.outputs["forces"].results
        and "exact_rod" not in plain.outputs["forces"].results
    )
    pins = [exact.outputs["bearings"].results, plain.outputs["bearings"].results]
    assert pins[0] != pins[1]


def test_apply_to_loads_needs_the_moment_of_inertia():
    data = modified("petrol-1cyl", {"rod_dynamics": {"apply_to_loads": True}})
    with pytest.raises(SceneError, match="rod_moment_of_inertia"):
        run_scene(scene_from_dict(data, base_dir=examples_dir()), REGISTRY)


def test_the_side_and_rod_forces_handed_on_are_the_reported_ones(exact_run):
    """A later stage (a plugin's) reads the side force N and the rod force K from CrankForces: the
    rigid rod's with apply_to_loads (against the Newton-Euler solve), the two-mass model's
    n = p_1 tg β without it (a plugin walkthrough had to recompute them, wrongly for the rigid rod)."""
    from crankdyn.plugin.contracts import FORCES, KINEMATICS

    scene, e, m = exact_run.scene, exact_run.scene.engine, exact_run.scene.masses
    data = exact_run.outputs["forces"].data[FORCES]
    area, alpha = data.piston_area_m2, np.radians(data.crank_angle_deg)
    ref = newton_euler(
        alpha,
        e.crank_radius_m,
        e.rod_length_m,
        scene.rod_cm_from_big_end_m,
        m.rod,
        m.rod_moment_of_inertia,
        m.piston_group,
        e.angular_velocity_rad_s,
        data.gas_Pa * area,
    )
    assert np.max(np.abs(data.side_Pa * area - ref["N"])) < 1e-9 * np.max(np.abs(ref["N"]))
    plain = _run("petrol-1cyl", apply=False)
    two = plain.outputs["forces"].data[FORCES]
    beta = plain.outputs["kinematics"].data[KINEMATICS].rod_angle_rad
    np.testing.assert_allclose(
        two.side_Pa, two.total_Pa * np.tan(beta), rtol=0, atol=1e-9 * np.max(np.abs(two.total_Pa))
    )
    np.testing.assert_allclose(
        two.rod_Pa, two.total_Pa / np.cos(beta), rtol=0, atol=1e-9 * np.max(np.abs(two.total_Pa))
    )


def test_the_step_study_of_rigid_rod_loads_measures_them_against_themselves():
    """With the rigid rod's loads the step study's reference is the same calculation at a fine
    step (the pointwise model gives the two-mass loads): the peaks' error at 1° is a step error,
    under the 0.1 % the calculation aims at, not the two models' difference of several per cent."""
    cheap = {"numerics": {"steps_deg": [10], "repeats": 1, "kinematics_forms": False}}
    result = _run("petrol-1cyl", **cheap)
    result.complete()
    r = result.outputs["numerics"].results
    assert r["reference_method"] == "fine_step"
    assert r["at_scene_step"]["peaks_error_relative"] < 1e-3, r["at_scene_step"]


def test_the_rigid_rods_loads_give_no_gas_only_excess_work():
    """The gas forces' torque is the output torque less the two-mass inertia torque; with the
    rigid rod's loads that leaves the rod's own inertia couple in it, so no gas-only ΔL is given
    (and the flywheel section says nothing of it)."""
    result = _run("inline4-petrol")
    assert result.outputs["flywheel"].results["excess_work_gas_J"] is None
    two_mass = _run("inline4-petrol", apply=False)
    assert two_mass.outputs["flywheel"].results["excess_work_gas_J"] > 0


def test_the_forces_section_says_its_table_takes_the_rigid_rod():
    """With the rigid rod's loads the forces section says that its table's k, N, t, z follow from
    the rod's equations of motion, by how much they differ from the two-mass values, and the
    rod-dynamics note no longer says the forces keep the two-mass model."""
    import re

    from crankdyn.report.document import render_html

    result = _run("petrol-1cyl")
    html = render_html(result, REGISTRY, "en").linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html))
    difference = result.outputs["forces"].results["exact_rod"]["crank_pin_difference_max_N"]
    assert "take the rod as a rigid body with its moment of inertia IG (section" in text
    assert re.search(
        r"differ from the two-mass values by up to ([\d ,.]+) N on the crank pin", text
    )
    said = re.search(r"by up to ([\d ,.\u202f]+) N on the crank pin", text).group(1)
    assert float(said.replace("\u202f", "").replace(" ", "")) == pytest.approx(difference, rel=1e-3)
    assert "keeps the textbook's two-mass split" not in text.replace("&#39;", "'")
    two = render_html(_run("petrol-1cyl", apply=False), REGISTRY, "en").linked_html
    assert "take the rod as a rigid body" not in two
