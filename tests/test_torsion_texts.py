"""The torsional vibration section's words: what a run that did not settle shows, how orders
print."""

from __future__ import annotations

import pytest


# a torsional exact solution run to tightened tolerances: in the slow tier, which CI runs
@pytest.mark.slow
def test_a_torsional_run_that_did_not_settle_is_not_called_the_steady_state():
    """A torsional model that did not settle within its cycles shows its last cycle: its figure
    was captioned "в установившемся режиме" and the conclusions quoted its twist and torque as
    results; they are said to be the last cycle's estimates."""
    import re

    from conftest import shared_html, shared_run

    changes = {"torsion": {"max_cycles": 1}}
    torsion = shared_run("inline4-torsion", changes).outputs["speed_fluctuation"].results
    assert not torsion["torsion"]["steady_state"]["converged"]
    page = shared_html("inline4-torsion", changes, "ru")
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", page.linked_html))
    assert "Крутильная модель в установившемся режиме" not in text
    assert (
        "Крутильная модель за последний рассчитанный цикл (установившийся режим не достигнут)"
        in text
    )
    assert (
        "Интегрирование не вышло на установившийся режим, поэтому наибольшее закручивание" in text
    )


def test_harmonic_orders_are_printed_as_the_halves_and_wholes_they_are():
    """A four-stroke crank's torque has orders 0,5, 1, 1,5 …: the table printed "0,500", "1,00",
    "10,0" and the text "above order 15,5" as "15,5" only by chance of its digits."""
    import re

    from conftest import shared_html

    html = shared_html("inline4-torsion", None, "ru").linked_html
    head = html.index("Порядки гармоник момента колена, критические частоты")
    table = html[head : html.index("</table>", head)]
    orders = re.findall(r"<tr[^>]*><td[^>]*>([^<]+)</td>", table)
    assert orders[:4] == ["0,5", "1", "1,5", "2"], orders[:6]
    assert "1,00" not in orders and "0,500" not in orders


def test_the_torsional_models_given_data_are_in_the_table_of_the_tasks_data():
    """The spans' stiffnesses, the end discs and the damping of [torsion] first appeared in the
    last chapter; the table of the task's data gives them with the rest."""
    import re

    from conftest import shared_html

    html = shared_html("inline4-torsion", None, "uk").linked_html
    head = html.index("Таблиця 1.1")
    table = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html[head : html.index("</table>", head)]))
    assert re.search(
        r"Крутильна жорсткість ділянок вала між колінами c i [\d ,·⁰-⁹;]+ Н·м/⁠рад", table
    )
    assert "Відносне демпфування ζ 0,05" in table
    assert "3,000·10⁶" not in table


def test_a_given_rod_inertia_is_in_the_table_of_the_tasks_data():
    import re

    from conftest import shared_html

    changes = {"masses": {"rod_moment_of_inertia": "0.0011 kg m^2"}}
    html = shared_html("petrol-1cyl", changes, "uk").linked_html
    head = html.index("Таблиця 1.1")
    table = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html[head : html.index("</table>", head)]))
    assert "Момент інерції шатуна відносно його центра мас I G 0,0011 кг·м²" in table


#: The V8 example made a flat-four aircraft engine with its propeller on a soft flange: a stiff
#: shaft whose twist scale is small, so that at rtol = 10⁻⁴ the solver's own error keeps the cycles
#: from repeating one another within the steady tolerance.
STIFF_FLAT_FOUR = {
    "engine": {
        "layout": "boxer",
        "bank_angle_deg": None,
        "cylinders": 4,
        "firing_order": [1, 3, 2, 4],
        "crank_angles_deg": [0, 180, 180, 0],
        "rpm": 2700,
        "application": "aircraft",
        "cylinder_spacing": "65 mm",
    },
    "flywheel": {"inertia": "0.75 kg*m^2", "engine_inertia": "0.012 kg*m^2"},
    "torsion": {
        "span_stiffness": "9e5 N*m/rad",
        "flywheel_stiffness": "4e5 N*m/rad",
        "free_end_inertia": "0.004 kg*m^2",
        "free_end_stiffness": "3e5 N*m/rad",
        "damping_ratio": 0.02,
        "max_cycles": 5,
        "compare_solvers": False,
    },
}


# a torsional exact solution run to tightened tolerances: in the slow tier, which CI runs
@pytest.mark.slow
def test_a_default_rtol_is_tightened_until_the_cycles_repeat():
    """The given rtol = 10⁻⁴ leaves the stiff flat four unsettled after 5 cycles; left to the
    default, the search tightens it and settles within a few cycles, and says at which rtol."""
    from conftest import shared_run

    def steady(extra: dict) -> dict:
        changes = {**STIFF_FLAT_FOUR, "torsion": {**STIFF_FLAT_FOUR["torsion"], **extra}}
        run = shared_run("v8-petrol", changes, ["speed_fluctuation"])
        return run.outputs["speed_fluctuation"].results["torsion"]

    given = steady({"rtol": 1e-4})
    assert not given["steady_state"]["converged"] and given["solver"]["rtol"] == 1e-4
    default = steady({})
    assert default["steady_state"]["converged"] and default["steady_state"]["cycles"] <= 10
    assert default["solver"]["rtol"] < 1e-4


def test_a_torsional_model_without_a_flywheel_names_its_reference_crank():
    """A loose [δ] the engine's own inertia meets needs no flywheel: the torsional chain then
    ends at the last crank, its reference disc, and the section says so instead of naming a
    flywheel the model does not have."""
    import re

    from conftest import shared_html, shared_run

    changes = {"flywheel": {"required_irregularity": 0.2, "engine_inertia": "0.2 kg*m^2"}}
    run = shared_run("inline4-torsion", changes, ("speed_fluctuation",))
    torsion = run.outputs["speed_fluctuation"].results["torsion"]
    assert [node["name"] for node in torsion["nodes"]][-1] == "crank 4"
    assert run.outputs["flywheel"].results["own_inertia_sufficient"]
    page = shared_html("inline4-torsion", changes, "en", ("speed_fluctuation",))
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", page.linked_html))
    assert (
        "the flywheel section found no flywheel needed at this speed, so the chain ends at "
        "crank 4" in text
    )
    assert "The first natural frequency of the crankshaft without a flywheel is" in text
    assert "speeds of crank 4 (the reference disc) and of crank 1" in text
    assert "with the flywheel is" not in text and "The flywheel's irregularity" not in text
