"""The flywheel by the energy method: excess work, irregularity, inertia, rim."""

from __future__ import annotations

import html as html_lib
import math
import re

import numpy as np
import pytest
from conftest import shared_run

from crankdyn.errors import SceneError
from crankdyn.physics import flywheel as fw
from crankdyn.physics import speed_fluctuation as sf
from crankdyn.plugin.registry import default_registry

REGISTRY = default_registry()
FLYWHEEL_1CYL = {"flywheel": {"required_irregularity": 0.02}}


def run(name, changes=None):
    """One computation per scene and worker, shared with the other test files (read only)."""
    return shared_run(name, changes)


# ----------------------------------------------------------------------------- physics


def test_excess_work_of_a_sine_torque_is_twice_amplitude_over_order():
    # M = M0 + A sin(k a): W(a) = A (1 - cos k a)/k, so max W - min W = 2A/k exactly.
    n = 7200
    alpha = np.arange(n) * (4 * np.pi / n)
    for k in (1, 2, 3.5):
        result = fw.excess_work(alpha, 120.0 + 300.0 * np.sin(k * alpha))
        assert result.excess_work_J == pytest.approx(2 * 300.0 / k, rel=1e-5)
        assert result.mean_torque_Nm == pytest.approx(120.0, abs=1e-9)
        # W = A (1 - cos k a)/k: smallest where cos k a = 1, largest where it is -1
        assert math.cos(k * alpha[result.min_index]) == pytest.approx(1.0, abs=1e-6)
        assert math.cos(k * alpha[result.max_index]) == pytest.approx(-1.0, abs=1e-6)
        assert result.cumulative_J[result.min_index] == pytest.approx(0.0, abs=1e-6)


def test_irregularity_and_required_inertia_invert_each_other():
    excess, omega = 445.0, 586.43
    inertia = fw.required_inertia_kg_m2(excess, 0.01, omega)
    assert inertia == pytest.approx(excess / (0.01 * omega**2))
    assert fw.cyclic_irregularity(excess, inertia, omega) == pytest.approx(0.01)
    with pytest.raises(ValueError):
        fw.cyclic_irregularity(excess, 0.0, omega)


@pytest.mark.parametrize("width_m", [None, 0.02, 0.08])
def test_rim_carries_the_inertia_of_a_hollow_cylinder(width_m):
    rim = fw.rim_design(0.12, 0.26, 7200.0, width_m)
    ro, ri = rim.outer_diameter_m / 2, rim.inner_diameter_m / 2
    # independent: J = pi/2 rho b (ro^4 - ri^4), m = pi rho b (ro^2 - ri^2)
    assert math.pi / 2 * 7200.0 * rim.width_m * (ro**4 - ri**4) == pytest.approx(0.12, rel=1e-10)
    assert math.pi * 7200.0 * rim.width_m * (ro**2 - ri**2) == pytest.approx(rim.mass_kg, rel=1e-10)
    assert rim.thin_rim_mass_kg == pytest.approx(4 * 0.12 / 0.26**2)
    # the exact rim is lighter than the thin-rim estimate (its outer half is further out)
    assert rim.mass_kg < rim.thin_rim_mass_kg
    if width_m is None:
        assert rim.width_m == pytest.approx(rim.thickness_m)


def test_thin_rim_limit():
    # a very wide rim is very thin: its mass approaches 4 J / D_m^2
    rim = fw.rim_design(0.12, 0.30, 7800.0, width_m=2.0)
    assert rim.thickness_m < 1e-3
    assert rim.mass_kg == pytest.approx(rim.thin_rim_mass_kg, rel=1e-5)


def test_rim_that_cannot_reach_the_inertia_is_refused():
    with pytest.raises(ValueError, match="no rim"):
        fw.rim_design(50.0, 0.05, 7200.0)


def test_hoop_stress():
    assert fw.rim_hoop_stress_Pa(7800.0, 50.0) == pytest.approx(7800.0 * 2500.0)


@pytest.mark.parametrize("rod_ratio", [1e-4, 0.1, 0.28, 0.4])
def test_mean_square_torque_arm_against_two_term_closed_form(rod_ratio):
    # two-term kinematics: <s'^2> = R^2 (1/2 + lambda^2/8); the exact one differs by O(lambda^4)
    R = 0.039
    exact = sf.mean_arm_squared_m2(R, rod_ratio)
    two_term = R**2 * (0.5 + rod_ratio**2 / 8)
    assert abs(exact - two_term) <= 0.2 * rod_ratio**4 * R**2 + 1e-15


# ----------------------------------------------------------------------------- stage


def test_inline4_flywheel_by_the_energy_method():
    result = run("inline4-petrol")
    r = result.outputs["flywheel"].results
    torque = result.outputs["torque"].results
    omega = r["angular_velocity_rad_s"]
    assert r["mean_torque_Nm"] == pytest.approx(torque["mean_Nm"], rel=1e-12)
    assert r["required_total_inertia_kg_m2"] == pytest.approx(
        r["excess_work_J"] / (0.01 * omega**2)
    )
    assert r["required_flywheel_inertia_kg_m2"] == pytest.approx(
        r["required_total_inertia_kg_m2"]
        - r["mechanism_inertia_mean_kg_m2"]
        - r["engine_inertia_kg_m2"]
    )
    assert r["irregularity"] == pytest.approx(0.01)
    # the mean reduced inertia: 4 cylinders' m_s <s'^2> plus 4 cranks' m_R R^2, plus the
    # second-order balance shafts' masses at 2ω (Σ m ρ² ν², ν = 2)
    forces = result.outputs["forces"].results
    balancing = result.outputs["balancing"].results
    scene = result.scene
    R, lam = scene.engine.crank_radius_m, scene.engine.rod_ratio_value
    rho = balancing["balance_shaft_radius_m"]
    shafts = balancing["balance_shafts"]
    assert [shaft["order"] for shaft in shafts] == [2, 2] and not balancing["counterweights"]
    expected = (
        4 * forces["reciprocating_mass_kg"] * sf.mean_arm_squared_m2(R, lam)
        + 4 * forces["rotating_mass_kg"] * R**2
        + sum(m["mass_kg"] * rho**2 * 2**2 for shaft in shafts for m in shaft["masses"])
    )
    assert r["mechanism_inertia_mean_kg_m2"] == pytest.approx(expected, rel=1e-9)
    rim = r["rim"]
    assert rim["inertia_kg_m2"] == pytest.approx(r["flywheel_inertia_kg_m2"])
    assert rim["speed_m_s"] == pytest.approx(omega * rim["outer_diameter_m"] / 2)
    assert rim["speed_ok"] is True
    # The crankshaft is fastest where the cumulative excess work peaks
    sfr = result.outputs["speed_fluctuation"].results
    assert sfr["omega_max_crank_angle_deg"] == pytest.approx(
        r["excess_work_max_crank_angle_deg"], abs=2.0
    )
    assert sfr["omega_min_crank_angle_deg"] == pytest.approx(
        r["excess_work_min_crank_angle_deg"], abs=2.0
    )
    # An in-line 4 has four equal speed peaks per cycle: the reported one is the first (physics/extrema.py)
    assert 0.0 <= r["excess_work_max_crank_angle_deg"] < 180.0
    assert 0.0 <= sfr["omega_max_crank_angle_deg"] < 180.0


def test_no_flywheel_table_no_flywheel_section():
    result = run("petrol-1cyl")
    assert result.plan.skipped["flywheel"] == "the scene has no [flywheel] table"
    assert "speed_fluctuation" in result.plan.skipped


def test_chosen_flywheel_gives_its_irregularity():
    result = run(
        "inline4-petrol",
        {
            "flywheel": {
                "required_irregularity": None,
                "inertia": "0.2 kg*m^2",
                "rim_mean_diameter": None,
                "max_rim_speed": None,
            }
        },
    )
    r = result.outputs["flywheel"].results
    assert r["flywheel_given"] and r["flywheel_inertia_kg_m2"] == pytest.approx(0.2)
    assert r["irregularity"] == pytest.approx(
        r["excess_work_J"] / ((0.2 + r["own_inertia_kg_m2"]) * r["angular_velocity_rad_s"] ** 2)
    )
    assert r["required_flywheel_inertia_kg_m2"] is None and r["rim"] is None


def test_own_inertia_may_suffice():
    result = run(
        "inline4-petrol",
        {
            "flywheel": {
                "required_irregularity": 0.2,
                "rim_mean_diameter": None,
                "max_rim_speed": None,
            }
        },
    )
    r = result.outputs["flywheel"].results
    assert r["required_flywheel_inertia_kg_m2"] == 0.0 and r["flywheel_inertia_kg_m2"] == 0.0
    assert r["irregularity"] < 0.2
    assert any(key == "flywheel.note_no_flywheel" for key, _ in result.outputs["flywheel"].notes)


def test_very_small_flywheel_single_cylinder_is_refused_clearly():
    # at 1500 rpm: at the example's speed its counterweights' inertia alone keeps δ near 0,25
    changes = {"engine": {"rpm": 1500}, "flywheel": {"inertia": "1e-9 kg*m^2"}}
    with pytest.raises(SceneError) as info:
        run("petrol-1cyl", changes)
    problem = info.value.problems[0]
    assert problem.field == "flywheel.inertia" and "too small" in problem.allowed
    assert "kg*m^2 gives delta" in problem.allowed  # it says what would do


def test_very_small_flywheel_multi_cylinder_stays_finite():
    result = run(
        "inline4-petrol",
        {
            "flywheel": {
                "required_irregularity": None,
                "inertia": "1e-9 kg*m^2",
                "rim_mean_diameter": None,
                "max_rim_speed": None,
            }
        },
    )
    r = result.outputs["speed_fluctuation"].results
    assert 0.05 < r["irregularity"] < 0.5
    assert all(
        math.isfinite(x)
        for x in (r["omega_min_rad_s"], r["omega_max_rad_s"], r["solver"]["error_relative"])
    )
    assert r["omega_min_rad_s"] > 0.5 * r["omega_mean_rad_s"]


def test_flywheel_table_needs_something_to_do():
    with pytest.raises(SceneError) as info:
        run("petrol-1cyl", {"flywheel": {"engine_inertia": "0.01 kg*m^2"}})
    assert info.value.problems[0].field == "flywheel"
    with pytest.raises(SceneError) as info:
        run(
            "petrol-1cyl",
            {"flywheel": {"required_irregularity": 0.01, "engine_inertia": "0.01 kg"}},
        )
    assert info.value.problems[0].field == "flywheel.engine_inertia"


@pytest.mark.parametrize(
    "changes, shown",
    [
        ({}, False),  # sized for [δ]: its δ is [δ] again, no row of its own
        (
            {
                "flywheel": {
                    "required_irregularity": None,
                    "inertia": "0.2 kg*m^2",
                    "rim_mean_diameter": None,
                    "max_rim_speed": None,
                }
            },
            True,
        ),  # a given flywheel: its δ is a result
        (
            {
                "flywheel": {
                    "required_irregularity": 0.2,
                    "rim_mean_diameter": None,
                    "max_rim_speed": None,
                }
            },
            True,
        ),
    ],
)
def test_the_table_lists_delta_only_where_it_is_a_result(changes, shown):
    from crankdyn.report.document import render_html

    result = run("inline4-petrol", changes)
    html = render_html(result, REGISTRY, "en").linked_html
    section = html[
        html.index('data-stage="flywheel"') : html.index('data-stage="speed_fluctuation"')
    ]
    assert ("Cyclic irregularity (energy method)" in section) is shown


def test_an_engine_whose_own_inertia_meets_the_required_irregularity_gets_no_flywheel():
    """J_m + J_e > J_0: the engine meets [δ] by itself; the equation compares the two (a negative
    flywheel inertia is printed nowhere), the abstract and the conclusions design none, and a
    vehicle's note says it carries a flywheel all the same."""
    from crankdyn.report.document import render_html

    result = run(
        "v8-petrol", {"flywheel": {"required_irregularity": 0.2, "engine_inertia": "5 kg*m^2"}}
    )
    r = result.outputs["flywheel"].results
    difference = r["required_total_inertia_kg_m2"] - r["own_inertia_kg_m2"]
    assert difference < 0 and r["own_inertia_sufficient"]
    assert r["flywheel_inertia_difference_kg_m2"] == pytest.approx(difference)
    html = render_html(result, default_registry(), "en").linked_html
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", " ", html)).split())
    assert "flywheel moment of inertia 0 kg" not in text
    assert "a flywheel of 0 kg" not in text
    assert (
        "at the given speed no flywheel is needed: the engine's own inertia suffices" in text
    )  # the abstract
    assert (
        "within the required [δ] = 0.2: at the given speed no flywheel is needed" in text
    )  # the conclusions
    plain = re.sub(r"[\u2009\u202f\u00a0]", " ", html)
    printed = re.search(r" = ([\d.]+) kg·m² &gt; <i>J</i><sub>0</sub>", plain)  # J_m + J_e
    assert printed and float(printed.group(1)) == pytest.approx(r["own_inertia_kg_m2"], rel=1e-3)
    assert "&lt; 0" not in plain and "J_f is negative" not in text
    assert "A vehicle's engine carries a flywheel all the same" not in text  # no application
    from conftest import shared_html

    car = {
        "engine": {"application": "automotive"},
        "flywheel": {"required_irregularity": 0.2, "engine_inertia": "5 kg*m^2"},
    }
    html = shared_html("v8-petrol", car, "en", ("flywheel",)).linked_html
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", " ", html)).split())
    assert text.count("A vehicle's engine carries a flywheel all the same") == 2  # and concluded


def test_a_given_flywheel_beside_an_own_inertia_that_meets_the_required_one_is_not_a_zero():
    """[δ] and a flywheel both given, the engine's own inertia above J_0: the section compares
    J_m + J_e with J_0 and gives the required flywheel as not needed, not "J_f = J_0 − J_m − J_e
    = 0 kg·m² (0 % of J_0)" beside the given flywheel's row of the same symbol."""
    from conftest import shared_html, shared_run

    both = {"flywheel": {"inertia": "0.5 kg*m^2", "required_irregularity": 0.2}}
    r = shared_run("inline4-petrol", both, ("flywheel",)).outputs["flywheel"].results
    assert r["required_total_inertia_kg_m2"] < r["own_inertia_kg_m2"]
    assert r["required_flywheel_inertia_kg_m2"] == 0.0 and r["flywheel_given"]
    page = shared_html("inline4-petrol", both, "en", ("flywheel",)).linked_html
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", " ", page)).split())
    assert "(0 % of J 0 )" not in text and "= 0 kg·m²" not in text.replace("\u202f", " ")
    assert re.search(r"J m \+ J e = [\d.]+ \+ [\d.]+ = [\d.]+ kg·m² > J 0", text), text[:3000]


def test_a_vehicles_designed_flywheel_is_said_to_be_chosen_for_moving_off_too():
    """A flywheel designed for [δ] at the rated speed leaves a car's engine with a δ many times
    [δ] at a quarter of that speed, near idling: the section and the conclusions say a
    vehicle's flywheel is chosen for starting, idling and moving off as well (the conclusion with
    that δ, the lower speeds' last row); an engine of no stated use gets neither."""
    from conftest import shared_html, shared_run

    car = {"engine": {"application": "automotive"}}
    r = shared_run("inline4-petrol", car, ("flywheel",)).outputs["flywheel"].results
    quarter = r["lower_speeds"][-1]
    assert quarter["speed_fraction"] == 0.25 and quarter["irregularity"] > 3 * 0.01
    page = shared_html("inline4-petrol", car, "en", ("flywheel",)).linked_html
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", " ", page)).split())
    text = re.sub(r"[\u2009\u202f\u00a0]", " ", text)
    assert "A vehicle's flywheel is chosen for starting, idling and moving off as well" in text
    # said once: the given speed's caveat leaves the choice to this sentence
    assert "so the flywheel is also chosen for starting and idling" not in text
    conclusion = (
        f"At a quarter of the given speed ({quarter['rpm']:.0f} rpm) the same J would leave "
        f"δ = {quarter['irregularity']:.3g} with the full-load pressures"
    )
    assert conclusion in text[text.index("Conclusions") :]
    plain = shared_html("inline4-petrol", None, "en", ("flywheel",)).linked_html
    assert "moving off" not in plain


def test_a_rim_faster_than_allowed_fails_in_the_abstract_and_the_conclusions():
    """The section said the rim is too fast while the abstract and the conclusions presented the
    flywheel as adequate."""
    from conftest import shared_html, shared_run

    changes = {"flywheel": {"max_rim_speed": "20 m/s"}}
    rim = shared_run("inline4-petrol", changes).outputs["flywheel"].results["rim"]
    assert rim["speed_ok"] is False and rim["speed_m_s"] > 20
    page = shared_html("inline4-petrol", changes).linked_html
    abstract = page[page.index('class="abstract"') :]
    abstract = abstract[: abstract.index("</section>")]
    assert "above the allowed 20" in abstract
    assert "does not pass the speed check" in page[page.index('class="conclusions"') :]


def test_a_raised_flywheel_and_the_energy_methods_have_symbols_of_their_own():
    """Where the exact solution raises the energy method's flywheel, the table and the worked
    substitution name the energy method's J′_f and the adopted J_f, each explained in the list of
    symbols (one letter for two values in one table would be read as one quantity)."""
    from conftest import shared_html

    raised = {"flywheel": {"required_irregularity": 0.05, "rim_mean_diameter": "500 mm"}}
    html = shared_html("diesel-1cyl", raised, language="en").linked_html
    text = re.sub(r"\s+", " ", html_lib.unescape(re.sub(r"<[^>]+>", " ", html)))
    assert re.search(r"flywheel by the energy method J ′ f [\d.]+ kg", text), "its row"
    assert re.search(r"flywheel \(exact solution\) J f [\d.]+ kg", text), "the adopted one's row"
    assert re.search(r"J ′ f = J 0 − J m − J e = ", text)
    assert "J′f – flywheel moment of inertia by the energy method" in html_lib.unescape(
        re.sub(r"<[^>]+>", "", html)
    )


@pytest.mark.parametrize(
    "detail, curves",
    [
        ("course", ["exact periodic solution", "energy method (constant J)"]),
        ("full", ["exact periodic solution", "solver RK45", "energy method (constant J)"]),
    ],
)
def test_the_speed_figure_shows_the_curves_its_section_describes(detail, curves):
    """A course note's section describes the exact solution and the energy method, so its figure
    draws those two (the solver's curve, a check, is the appendix's); a full note names its solver
    and draws its curve too."""
    from conftest import shared_html

    rendered = shared_html(
        "inline4-petrol", {"report": {"detail": detail}}, "en", ("speed_fluctuation",)
    )
    (speed,) = [f for f in rendered.figures if f.name.endswith("_speed.svg")]
    assert [line.get_label() for line in speed.figure.axes[0].get_lines()] == curves


@pytest.mark.parametrize(
    "example, mean, variable",
    [
        # one cylinder on one crank: no sums over cylinders, no crank count
        ("petrol-1cyl", "= ms ⟨s′2⟩ + mRR2 =", "+ mRR2 + ms s′(α)2,"),
        # a star's cylinders on one crank: the sum over cylinders, no crank count
        # articulated rods: each cylinder's own reciprocating mass
        ("radial9-aircraft", "= Σi msi ⟨s′2⟩ + mRR2 =", "+ mRR2 + Σi msi s′(αi)2,"),
        ("inline4-petrol", "= ms Σi ⟨s′2⟩ + iк mRR2 =", "+ iкmRR2 + Σi ms s′(αi)2,"),
    ],
)
def test_the_reduced_inertia_is_written_for_the_engines_cylinders_and_cranks(
    example, mean, variable
):
    """J_m and J(α) sum over the cylinders and count the cranks only where the engine has
    several: a single cylinder's note writes m_s⟨s′²⟩ + m_R R², with no Σ_i, α_i or i_k (whose
    definitions would then stand in its list of symbols)."""
    import re

    from conftest import example_data, shared_html

    given = example_data("inline4-petrol")["flywheel"]
    # an aircraft engine's propeller has no rim to size
    flywheel = (
        None
        if example == "inline4-petrol"
        else {"flywheel": {k: v for k, v in given.items() if not k.startswith("rim_")}}
    )
    html = shared_html(example, flywheel, "ru", ("flywheel", "speed_fluctuation")).linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", html).replace("\u2060", "").split())
    assert mean in text and variable in text
    symbols = re.sub(r"<[^>]+>", "", html[html.index('<div class="symbol-list">') :])
    assert ("число колен" in symbols) is (example == "inline4-petrol")


@pytest.mark.parametrize(
    "language, engines, crank",
    [
        ("ru", "крутящий момент двигателя", ("одного колена составляет", "Суммарный индикаторный")),
        ("uk", "крутний момент двигуна", ("одного коліна становить", "Сумарний індикаторний")),
        ("en", "torque of the engine", ("torque of one crank", "The indicated torque varies")),
    ],
)
def test_a_single_cylinders_torque_is_the_engines(language, engines, crank):
    """One cylinder on one crank: the forces section's torque, its table, figure and conclusion,
    and the flywheel's are the engine's torque, not "one crank's" nor a "total" of several."""
    import re

    from conftest import example_data, shared_html

    flywheel = {"flywheel": example_data("inline4-petrol")["flywheel"]}
    html = shared_html("petrol-1cyl", flywheel, language, ("forces", "flywheel")).linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", html).split())
    assert text.count(engines) >= 3
    assert not any(words in text for words in crank), [w for w in crank if w in text]


def test_the_gas_forces_excess_work_is_the_gas_torques_own():
    """ΔL of the gas forces alone, against an independent gas torque of the single cylinder:
    M_g = (p − p₀)F_p·R·sin(α + β)/cos β from the forces stage's gas pressure and the exact rod
    angle sin β = λ sin α, its excess work by hand (cumulative sum of M_g − mean)."""
    changes = {"flywheel": {"required_irregularity": 0.01}}
    result = shared_run("petrol-1cyl", changes, ("forces", "flywheel"))
    r = result.outputs["flywheel"].results
    crank = result.outputs["forces"].data["forces"]
    e = result.scene.engine
    alpha = np.radians(crank.crank_angle_deg)
    beta = np.arcsin(e.rod_ratio_value * np.sin(alpha))
    gas = (
        crank.gas_Pa * crank.piston_area_m2 * e.crank_radius_m * np.sin(alpha + beta) / np.cos(beta)
    )
    step = alpha[1] - alpha[0]
    work = (
        np.concatenate([[0.0], np.cumsum(0.5 * ((gas - gas.mean())[1:] + (gas - gas.mean())[:-1]))])
        * step
    )
    assert r["excess_work_gas_J"] == pytest.approx(np.ptp(work), rel=2e-3)
    # the inertia forces of a single cylinder at 5600 rpm change ΔL by more than a few per cent,
    # and the section says by how much
    added = r["excess_work_J"] - r["excess_work_gas_J"]
    assert abs(added) > 0.05 * r["excess_work_J"]
    from conftest import shared_html

    page = shared_html("petrol-1cyl", changes, "en", ("flywheel",)).linked_html
    text = html_lib.unescape(re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", page)))
    said = re.search(r"would give an excess work of ([\d.]+) J[:;] ", text)
    assert said and float(said.group(1)) == pytest.approx(r["excess_work_gas_J"], rel=1e-3)
    # a difference, not a share of ΔL: the two torques' excess works do not add
    after = text[said.end() : said.end() + 90]
    assert (f"ΔL is {abs(added):.4g} J larger" if added > 0 else "lower it by") in after, after


def test_an_aircraft_engines_propeller_gets_no_rim_and_the_console_says_so():
    """Rim fields given for an aircraft engine are left out (its propeller takes the flywheel's
    part and has no rim), and the console names the field; a car engine's rim is sized."""
    from conftest import example_data

    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.plausibility import console_lines, warnings

    registry = default_registry()
    given = {"flywheel": example_data("inline4-petrol")["flywheel"]}
    assert "rim_mean_diameter" in given["flywheel"]
    flying = shared_run("radial9-aircraft", given, ("flywheel",))
    assert flying.outputs["flywheel"].results["rim"] is None
    lines = console_lines(warnings(flying.scene, registry, flying), registry)
    assert any("flywheel.rim_mean_diameter = 240 mm is left out" in line for line in lines), lines
    car = shared_run("inline4-petrol", None, ("flywheel",))
    assert car.outputs["flywheel"].results["rim"] is not None
    lines = console_lines(warnings(car.scene, registry, car), registry)
    assert not any("rim_mean_diameter" in line for line in lines)


def _square_rim_outer_m(inertia, density, mean_diameter):
    """Outer diameter of a square rim of J in closed form: J = π ρ h² D (D² + h²) / 4 is a
    quadratic in h², h² = (−D² + √(D⁴ + 16 J / (π ρ D))) / 2."""
    d = np.asarray(mean_diameter, dtype=float)
    h2 = (-(d**2) + np.sqrt(d**4 + 16.0 * inertia / (math.pi * density * d))) / 2.0
    return d + np.sqrt(h2)


@pytest.mark.parametrize("limit_m", [0.239, 0.30, 0.50])
def test_the_largest_rim_within_an_outer_diameter_is_the_closed_forms(limit_m):
    inertia, density = 0.1133, 7850.0
    found = fw.largest_rim_mean_diameter_m(inertia, density, limit_m)
    assert _square_rim_outer_m(inertia, density, found) == pytest.approx(limit_m, rel=1e-9)
    # the largest such diameter: a dense scan of the closed form finds none above it that fits
    scan = np.linspace(0.01, limit_m, 200_001)
    fits = scan[_square_rim_outer_m(inertia, density, scan) <= limit_m]
    assert found == pytest.approx(fits.max(), abs=2 * (scan[1] - scan[0]))


def test_no_rim_within_a_small_outer_diameter():
    """The outer diameter D + h(D) has a least value over D: a limit below it has no rim."""
    inertia, density, limit_m = 0.1133, 7850.0, 0.1365
    scan = np.linspace(0.005, 0.5, 100_001)
    assert _square_rim_outer_m(inertia, density, scan).min() > limit_m
    assert fw.largest_rim_mean_diameter_m(inertia, density, limit_m) is None


def test_a_too_fast_rim_gets_the_largest_passing_diameter_in_the_note():
    """The rim fails the allowed peripheral speed: the section and the conclusions give the
    largest mean diameter, in whole millimetres, whose rim carries the same inertia within it."""
    from conftest import shared_html, shared_run

    changes = {"flywheel": {"max_rim_speed": "70 m/s"}}
    run = shared_run("inline4-petrol", changes, stages=["flywheel"])
    rim = run.outputs["flywheel"].results["rim"]
    passing = rim["passing"]
    assert rim["speed_ok"] is False and passing["speed_m_s"] <= 70.0
    omega = run.scene.engine.rpm * math.pi / 30
    limit = 2 * 70.0 / omega
    largest = fw.largest_rim_mean_diameter_m(rim["inertia_kg_m2"], rim["density_kg_m3"], limit)
    assert passing["mean_diameter_m"] == math.floor(largest * 1e3) / 1e3
    assert passing["outer_diameter_m"] == pytest.approx(
        _square_rim_outer_m(rim["inertia_kg_m2"], rim["density_kg_m3"], passing["mean_diameter_m"])
    )
    text = re.sub(
        r"[\u00a0\u202f\u2009]",
        " ",
        html_lib.unescape(
            re.sub(
                r"<[^>]+>",
                "",
                shared_html("inline4-petrol", changes, None, ["flywheel"]).linked_html,
            )
        ),
    )
    diameter = f"{passing['mean_diameter_m'] * 1e3:g}"
    assert f"carried by a rim of mean diameter at most {diameter} mm" in text
    assert re.search(
        rf"a rim of mean diameter at most {diameter} mm \([\d.]+ × [\d.]+ mm, [\d.]+ kg\) "
        "carries the same inertia and passes it",
        text,
    )  # the conclusions
    slow = {"flywheel": {"max_rim_speed": "40 m/s"}}
    slow_run = shared_run("inline4-petrol", slow, stages=["flywheel"])
    assert slow_run.outputs["flywheel"].results["rim"]["passing"] is None
    assert "no rim of this material and section carries the same inertia" in re.sub(
        r"<[^>]+>", "", shared_html("inline4-petrol", slow, None, ["flywheel"]).linked_html
    )


@pytest.mark.parametrize(
    "example, changes, direction",
    [
        ("inline4-petrol", None, "more slowly"),  # the inertia torque adds to the gas torque's ΔL
        ("v8-petrol", {"flywheel": {"required_irregularity": 0.01}}, "faster"),  # it offsets it
    ],
)
def test_the_speed_regime_sentence_says_where_delta_l_tends_at_low_speed(
    example, changes, direction
):
    """δ = ΔL/(Jω²) at a lower speed: ΔL itself tends to the gas torque's alone as the inertia
    torque fades with ω², and δ at lower speeds is given with the same J (it may even fall at
    first, where ΔL falls faster than ω²)."""
    from conftest import shared_html, shared_run

    r = shared_run(example, changes, ("flywheel",)).outputs["flywheel"].results
    assert (r["excess_work_gas_J"] > r["excess_work_J"]) is (direction == "faster")
    page = shared_html(example, changes, "en", ("flywheel",)).linked_html
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", "", page)).replace("\u2060", "").split())
    gas = f"{r['excess_work_gas_J']:.4g}"
    assert f"at a lower speed ΔL itself tends to {gas} J" in text
    rows = r["lower_speeds"]
    values = ", ".join(f"{row['irregularity']:.3g} at {row['rpm']:.0f} rpm" for row in rows[:2])
    assert f"the irregularity would be δ = {values} and " in text
    # at a quarter of the speed ΔL is nearer the gas torque's own than at the given speed (not
    # on the way, necessarily: an in-line four's passes below it, 445 → 174 → 69 → 172 J)
    gas = r["excess_work_gas_J"]
    assert abs(rows[-1]["excess_work_J"] - gas) < abs(r["excess_work_J"] - gas)


def test_articulated_cylinders_enter_the_reduced_inertia_with_their_own_masses():
    """J_m took the plain m_s = m_pg + m_r l_R/L for every cylinder of a radial, while the
    balancing and the bays give the master cylinder the reduced master rod's mass and a slave its
    slave rod's share: J_m is now Σ m_si ⟨s′²⟩ + m_R R² with each cylinder's own mass (⟨s′²⟩ ≈
    R²(½ + λ²/8), the first terms of the exact mean)."""
    from conftest import example_data, shared_run

    given = example_data("inline4-petrol")["flywheel"]
    flywheel = {"flywheel": {k: v for k, v in given.items() if not k.startswith("rim_")}}
    run = shared_run("radial9-aircraft", flywheel)
    fw = run.outputs["flywheel"].results
    b = run.outputs["balancing"].results
    e = run.scene.engine
    R, lam = e.crank_radius_m, e.rod_ratio_value
    masses = b["reciprocating_mass_kg"] + (e.cylinders - 1) * b["slave_reciprocating_mass_kg"]
    expected = masses * R**2 * (0.5 + lam**2 / 8) + b["rotating_mass_kg"] * R**2
    own = (
        fw["mechanism_inertia_mean_kg_m2"]
        - fw["counterweight_inertia_kg_m2"]
        - fw["balance_shaft_inertia_kg_m2"]
    )
    assert own == pytest.approx(expected, rel=2e-3)


def test_a_stationary_engines_flywheel_holds_at_its_governed_speed():
    """A generator set's engine runs at its governed speed at every load: the note said the
    flywheel is also chosen for idling at a lower speed, as a vehicle's is."""
    from conftest import shared_html

    stationary = {"engine": {"application": "stationary"}}
    page = shared_html("inline4-petrol", stationary, "en", ("flywheel",)).linked_html
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", "", page)).replace("\u2060", "").split())
    assert "at which a stationary engine runs at every load, no load included" in text
    assert "starting and idling" not in text


def test_excess_work_at_another_speed_scales_the_inertia_torque_alone():
    """M = M_m + A sin 2α + k²·B sin 2α: W = −(A + k²B)/2·cos 2α, ΔL = |A + k²B| (per half-wave
    the same), so with A = 100 N·m and B = −300 N·m ΔL is 200 J at k = 1, 25 J at k = ½ and
    vanishes at k = 1/√3."""
    alpha = np.linspace(0.0, 4.0 * np.pi, 1441)
    gas, inertia = 50.0 + 100.0 * np.sin(2 * alpha), -300.0 * np.sin(2 * alpha)
    at = [fw.excess_work_at_speed_J(alpha, gas, inertia, k) for k in (1.0, 0.5, 3**-0.5)]
    assert at == pytest.approx([200.0, 25.0, 0.0], abs=0.01)  # the trapezoid's error
    # all the speeds at once: the same, each by excess_work's own trapezoid
    together = fw.excess_work_at_speed_J(alpha, gas, inertia, [1.0, 0.5, 3**-0.5])
    assert together == pytest.approx(at, abs=1e-9)


def test_the_irregularity_at_lower_speeds_is_that_of_the_engine_run_there():
    """A pressure trace gives the same cylinder pressures at every speed: the flywheel's ΔL at
    half the speed equals that of the same engine computed at half the speed (its inertia forces
    computed afresh there), and δ = ΔL/(J (ω/2)²) with the same J; at k = 1 it is the engine's."""
    # a flywheel given, so that J is the same at both speeds (the next test's, its runs shared)
    flywheel = {"flywheel": {"inertia": "4 kg*m^2", "required_irregularity": 0.01}}
    full = shared_run("inline6-diesel-trace", flywheel).outputs["flywheel"].results
    half = shared_run("inline6-diesel-trace", {**flywheel, "engine": {"rpm": 800}})
    half = half.outputs["flywheel"].results
    rows = {row["speed_fraction"]: row for row in full["lower_speeds"]}
    assert [row["rpm"] for row in full["lower_speeds"]] == [1200.0, 800.0, 400.0]
    assert rows[0.5]["excess_work_J"] == pytest.approx(half["excess_work_J"], rel=1e-9)
    omega = full["angular_velocity_rad_s"] / 2
    assert rows[0.5]["irregularity"] == pytest.approx(
        half["excess_work_J"] / (full["total_inertia_kg_m2"] * omega**2), rel=1e-9
    )


def test_the_speed_at_which_the_irregularity_reaches_the_required_one():
    """A pressure trace keeps its pressures at every speed: the engine run just below the speed
    the note names has δ ≥ [δ], and just above it δ < [δ] (each run computing its inertia forces
    afresh, with the same J); the section and the conclusions give that speed. A flywheel designed
    for [δ] at the given speed gets no such speed: any lower one exceeds [δ]."""
    from conftest import shared_html

    fly = {"flywheel": {"inertia": "4 kg*m^2", "required_irregularity": 0.01}}
    r = shared_run("inline6-diesel-trace", fly).outputs["flywheel"].results
    assert r["irregularity"] < 0.01
    reached = r["required_irregularity_reached_rpm"]
    assert 400 < reached < 1600

    def delta(rpm):
        run = shared_run("inline6-diesel-trace", {**fly, "engine": {"rpm": rpm}})
        return run.outputs["flywheel"].results["irregularity"]

    # interpolated between the scan's steps (1 %, 16 rpm), given to three digits (±5 rpm)
    assert delta(reached - 6) >= 0.01 > delta(reached + 6)
    page = shared_html("inline6-diesel-trace", fly, "en", ("flywheel",)).linked_html
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", " ", page)).split())
    from crankdyn.report.i18n import translator

    about = translator("en").number_g(reached, 4)  # rounded to three significant digits
    assert f"δ would reach [δ] = 0.01 at about {about} rpm" in text
    designed = {"flywheel": {"required_irregularity": 0.01}}
    r = shared_run("inline6-diesel-trace", designed).outputs["flywheel"].results
    assert r["irregularity"] == pytest.approx(0.01, rel=2e-2)
    assert r["required_irregularity_reached_rpm"] is None


def test_a_raised_flywheel_names_no_speed_at_which_the_irregularity_reaches_the_required_one():
    """A flywheel raised until the exact solution gives [δ] has, by the energy method, a δ below
    [δ] at the given speed (here by 1.5 %), yet any lower speed exceeds [δ]: no speed just below
    the given one is named as where δ reaches [δ]."""
    r = shared_run("diesel-1cyl", {"flywheel": {"required_irregularity": 0.05}}, ["flywheel"])
    r = r.outputs["flywheel"].results
    assert r["flywheel_raised"]
    assert r["irregularity"] < 0.99 * 0.05
    assert r["required_irregularity_reached_rpm"] is None
    assert r["lower_speeds"][0]["irregularity"] > 0.05  # three quarters of the speed exceed it
