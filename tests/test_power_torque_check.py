"""The torque check by the indicated power: M_i = N_i/ω = 3·10⁴ N_i/(π n), equal to the torque
from the work, W/(2π·revolutions), when N_i = W i n/(60 τ/2) is right."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from crankdyn.physics import crankshaft as cs


def test_indicated_power_of_a_four_stroke_four_cylinder():
    # 340 J per cylinder and cycle, 4 cylinders, a cycle every 2 revolutions at 6000 rpm: 50 cycles/s
    assert cs.indicated_power_kW(340.0, 4, 4, 6000.0) == pytest.approx(340.0 * 4 * 50 / 1000)


@pytest.mark.parametrize(
    ("work_J", "cylinders", "strokes", "rpm"), [(340.0, 1, 4, 5600.0), (1200.0, 6, 2, 1600.0)]
)
def test_the_power_torque_is_the_work_torque(work_J, cylinders, strokes, rpm):
    from_work = work_J * cylinders / (2 * math.pi * strokes / 2)
    from_power = cs.torque_from_power_Nm(work_J, cylinders, strokes, rpm)
    assert from_power == pytest.approx(from_work, rel=1e-12)


def test_torque_non_uniformity_is_the_swing_over_the_mean_magnitude():
    """μ = (M_max − M_min)/|M_m|: 10 + 40 sin α swings 80 N·m about 10 N·m, μ = 8; a driven
    machine's −10 + 40 sin α swings alike about −10 N·m, μ = 8 as well (not −8); a zero mean
    has no μ."""
    alpha = np.radians(np.arange(0.0, 720.0, 0.5))
    assert cs.torque_non_uniformity(10.0 + 40.0 * np.sin(alpha)) == pytest.approx(8.0, rel=1e-12)
    assert cs.torque_non_uniformity(-10.0 + 40.0 * np.sin(alpha)) == pytest.approx(8.0, rel=1e-12)
    assert cs.torque_non_uniformity(np.array([-40.0, 40.0])) == float("inf")


def test_effective_output_against_the_indicated_one():
    """η_m = N_e/(N_i − N_p) and M_e = N_e/ω: at 6000 rpm (ω = 200π) 50 kW effective of 62.5 kW
    indicated is η_m = 0.8 and M_e = 50 000/(200π) = 79.577 N·m; with pumping strokes that take
    1.25 kW of those 62.5 kW the thermal calculation's N_i is 63.75 kW and η_m = 50/63.75; a
    motored N_i ≤ 0 has no η_m."""
    out = cs.effective_output(62500.0, 50000.0, 200 * math.pi)
    assert out["mechanical_efficiency"] == pytest.approx(0.8, rel=1e-15)
    assert out["mean_effective_torque_Nm"] == pytest.approx(79.57747154594767, rel=1e-12)
    pumped = cs.effective_output(62500.0, 50000.0, 200 * math.pi, pumping_power_W=-1250.0)
    assert pumped["mechanical_efficiency"] == pytest.approx(50 / 63.75, rel=1e-15)
    assert pumped["mean_effective_torque_Nm"] == out["mean_effective_torque_Nm"]
    assert cs.effective_output(-1.0, 50000.0, 100.0)["mechanical_efficiency"] is None


@pytest.mark.parametrize(
    ("example", "stage", "n_e_W"),
    [("inline4-petrol", "torque", 55e3), ("petrol-1cyl-uk", "forces", 13.5e3)],
)
def test_a_scene_with_its_effective_power_gets_the_mechanical_efficiency(example, stage, n_e_W):
    """The scene's N_e (engine.effective_power) against N_i from the indicator work without its
    pumping strokes, as the thermal calculation's: η_m = N_e/(N_i − N_p) with
    N_i = W_i·i·n/(60·τ/2) and N_p = W_p·i·n/(60·τ/2) (W_p the diagram's gas-exchange work, the
    indicator stage's result), and M_e = N_e/ω; the report's sentence prints them."""
    from conftest import shared_html, shared_run

    result = shared_run(example)
    r = result.outputs[stage].results
    e = result.scene.engine
    work_all = result.outputs["torque"].results["mean_from_work_Nm"] * 2 * math.pi * e.strokes / 2
    n_i = work_all * e.rpm / 60 / (e.strokes / 2)
    pumping = result.outputs["indicator"].results["pumping_work_J"]
    assert pumping < 0  # a naturally aspirated four-stroke's strokes take work
    n_p = pumping * e.cylinders * e.rpm / 60 / (e.strokes / 2)
    assert r["effective_power_W"] == n_e_W
    assert r["mechanical_efficiency"] == pytest.approx(n_e_W / (n_i - n_p), rel=1e-12)
    assert r["mechanical_efficiency"] < n_e_W / n_i
    assert r["mean_effective_torque_Nm"] == pytest.approx(n_e_W / (math.pi * e.rpm / 30), rel=1e-12)
    html = shared_html(example, language="uk").linked_html
    assert "механічний ККД <i>η</i><sub>м</sub>" in html
    assert "<i>N</i><sub>e</sub></td>" in html  # the given data's row
    # the conclusion gives η_m by the same formula: M_e is not η_m times the mean torque here
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html))
    eta = f"{r['mechanical_efficiency']:.3f}".replace(".", ",")
    assert f"механічний ККД ηм = Ne/⁠(Ni − Nнх) = {eta}, насосні ходи віднесено" in text


def test_an_effective_power_above_the_indicated_one_is_pointed_out(tmp_path):
    """η_m ≥ 1 is no mechanical efficiency: the note says the given power should be checked, once
    (the example's report language, English)."""
    from crankdyn.cli import examples_dir
    from crankdyn.engine.orchestrator import run_scene
    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.document import render_html
    from crankdyn.scene.model import load_scene

    text = (examples_dir() / "inline4-petrol.toml").read_text(encoding="utf-8")
    scene_file = tmp_path / "scene.toml"
    scene_file.write_text(
        text.replace('effective_power = "55 kW"', 'effective_power = "0.08 MW"'), encoding="utf-8"
    )
    registry = default_registry()
    scene = load_scene(scene_file)
    assert scene.engine.effective_power == pytest.approx(80e3)
    result = run_scene(scene, registry, ["torque"])
    assert result.outputs["torque"].results["mechanical_efficiency"] > 1
    html = render_html(result, registry).linked_html
    # said once, in the section's plausibility sentence and its conclusion (not also in the
    # stage's own paragraph)
    assert html.count("is not below one, which no engine can have") == 1, html
    assert (
        html.count("The mechanical efficiency comes out at one or above, which is impossible") == 1
    )
    assert "is above 0.95, whereas a real engine" not in html


def test_each_main_journals_torque_range_and_amplitude():
    """A fatigue check needs the smallest running torques and the amplitude, not only the
    largest. Each journal k's torque is t_kk·R·F_p over the cycle (the
    table's running specific force): its max, min and (max − min)/2; the last journal carries the
    engine's output torque."""
    import numpy as np
    from conftest import shared_html, shared_run

    result = shared_run("inline4-petrol")
    out = result.outputs["torque"]
    f = out.tables.arrays("torque")
    area = math.pi * result.scene.engine.bore**2 / 4
    radius = result.scene.engine.stroke / 2
    for k, journal in enumerate(out.results["journals"], start=1):
        torque = np.asarray(f[f"journal{k}_torque_Pa"]) * radius * area
        assert journal["max_Nm"] == pytest.approx(torque.max(), rel=1e-12)
        assert journal["min_Nm"] == pytest.approx(torque.min(), rel=1e-12)
        assert journal["amplitude_Nm"] == pytest.approx(
            (torque.max() - torque.min()) / 2, rel=1e-12
        )
        assert journal["max_abs_Nm"] == pytest.approx(np.abs(torque).max(), rel=1e-12)
    last = out.results["journals"][-1]
    assert last["max_Nm"] == pytest.approx(out.results["max_Nm"], rel=1e-12)
    assert last["min_Nm"] == pytest.approx(out.results["min_Nm"], rel=1e-12)
    html = shared_html("inline4-petrol", language="uk").linked_html
    assert (
        "Набіжні крутні моменти на корінних шийках: найбільший і найменший за цикл та амплітуда"
        in html
    )
    # the journals' names explained where they first appear (the bearings section explained them
    # four pages later), and μ named where the section states it (the conclusions name it μ)
    assert (
        "(шийку названо номерами колін, між якими вона лежить: 1–2 – між колінами 1 і 2; 0 – вільний кінець вала, номер після останнього коліна – кінець з боку маховика)"
        in html
    )
    assert (
        "коефіцієнт нерівномірності крутного моменту <i>μ</i>" in html
        or "коефіцієнт нерівномірності крутного моменту μ" in html
    )


def test_the_worked_sum_says_where_its_angles_lie_between_the_forces_tables_rows():
    """A V8 fires every 90°: with the tables every 60° the worked row at 60° puts cylinders at
    angles between the forces table's rows (−30° + 720°), which the note says are computed as
    the rows are, not read off the table; every 30° they are the table's own rows."""
    from conftest import shared_html

    def note(step):
        page = shared_html("v8-petrol", {"analysis": {"table_step_deg": step}}, "en").linked_html
        return " ".join(re.sub(r"<[^>]+>", " ", page).split())

    between = note(60)
    assert "at these angles is computed as the rows of the forces table of section" in between
    assert "(that table gives every 60°, and some of these angles lie between its rows)" in between
    rows = note(30)
    assert "is taken from the forces table of section" in rows
    assert "lie between its rows" not in rows


def test_a_journal_torque_that_peaks_alike_twice_takes_the_crank_most_loaded_there():
    """Table B.4's |t_k| row: an in-line six's journal torque repeats every 240°, so |t_k| peaks
    alike at two angles; the row takes the one where the crank's own load q is larger (the
    combination its strength is checked for), not merely the first (where the crank may be
    unloaded)."""
    import numpy as np

    from crankdyn.physics.crankshaft import dangerous_combinations

    angle = np.radians(np.arange(0.0, 720.0, 1.0))
    journal = np.abs(np.sin(3 * angle / 2))[None, :]  # peaks alike at 60°, 180°, 300°, ...
    load = (1.0 + np.cos(angle - np.radians(300.0)))[None, :]  # the crank loaded near 300°
    row = dangerous_combinations(load, load, load, journal)[0]
    assert row["M"] == 300
    # unequal peaks: the largest, whatever the load there
    journal[0, 60] *= 1.01
    assert dangerous_combinations(load, load, load, journal)[0]["M"] == 60


def test_the_dangerous_combinations_include_the_least_radial_and_tangential_forces():
    """z and t at their least (most negative: the inertia forces pulling the crank outwards, the
    torque reversed) close the stress cycle the crank's fatigue check takes, beside the maxima."""
    import numpy as np

    from crankdyn.physics.crankshaft import dangerous_combinations

    angle = np.radians(np.arange(0.0, 720.0, 1.0))
    radial = np.cos(angle)[None, :]  # least at 180° (and again at 540°: the first is taken)
    tangential = np.sin(angle - np.radians(30.0))[None, :]  # least at 300°
    row = dangerous_combinations(radial, tangential, radial, tangential)[0]
    assert (row["Z"], row["Zmin"]) == (0, 180)
    assert (row["T"], row["Tmin"]) == (120, 300)


#: A 4Ч 9,2/8,6 four firing 1-2-4-3 at a high peak pressure: the running torque's amplitude is
#: largest on journal 3-4, its magnitude on the last journal.
_AMPLITUDE_BEFORE_THE_END = {
    "engine": {
        "firing_order": [1, 2, 4, 3],
        "rpm": 5200,
        "bore": "92 mm",
        "stroke": "86 mm",
        "rod_ratio": None,
        "rod_length": "145 mm",
    },
    "masses": {"piston_group": "0.66 kg", "rod": "0.84 kg"},
    "cycle": {"max_pressure": "8.5 MPa", "compression_ratio": 9.3},
}


def test_the_running_torque_is_said_to_grow_towards_the_flywheel_only_where_its_amplitude_does():
    """The journals' largest magnitudes may grow towards the flywheel while the amplitude
    (M_max − M_min)/2, which a fatigue check of a journal takes, is largest on journal 3–4: the
    section then names that journal and amplitude, and does not say the running torque grows."""
    import re

    from conftest import shared_html, shared_run

    changes = _AMPLITUDE_BEFORE_THE_END
    journals = shared_run("inline4-petrol", changes, ("torque",)).outputs["torque"].results
    journals = journals["journals"]
    widest = max(range(len(journals)), key=lambda k: journals[k]["amplitude_Nm"])
    largest = max(range(len(journals)), key=lambda k: journals[k]["max_abs_Nm"])
    assert widest == 2 and largest == 3  # journal 3–4 against 4–5
    page = shared_html("inline4-petrol", changes, "en", ("torque",)).linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", page).split())
    amplitude = f"{journals[widest]['amplitude_Nm']:.1f}"
    assert (
        f"smallest values), {amplitude} N·m, which a fatigue check of a journal takes, is on the journal"
        in text
    )
    assert "after crank 3." in text and "grows towards the flywheel" not in text
    # where both grow, it is said as before
    plain = shared_html("inline4-petrol", None, "en", ("torque",)).linked_html
    assert "grows towards the flywheel" in plain and "fatigue check of a journal" not in plain
