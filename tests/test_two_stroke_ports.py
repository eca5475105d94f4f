"""A port-scavenged two-stroke's indicator diagram: the lost stroke fraction ψ of its exhaust
ports, compression from the port closing a′, expansion to the port opening b, the scavenging
pressure between them, the theoretical mean indicated pressure and the note's words.

The independent values come from the crank-slider's geometry written out here (the law of
cosines in the crank triangle), not from crankdyn's kinematics."""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest
from scipy.integrate import quad
from tests.conftest import shared_html

from crankdyn import api
from crankdyn.errors import SceneError
from crankdyn.physics import indicator as ind

BORE, STROKE, ROD = 0.070, 0.066, 0.122  # m, the outboard motor's cylinder
RADIUS = STROKE / 2
AREA = math.pi * BORE**2 / 4
EPS, P_A, N1, P_Z, N2 = 6.8, 0.098e6, 1.32, 5.0e6, 1.27
OPENS = 78.0  # exhaust ports open before BDC, deg


def piston_travel_m(alpha_deg, radius=RADIUS, rod=ROD):
    """s = R + L − (R cos α + √(L² − R² sin² α)): the pin's distance from the crank centre."""
    a = np.radians(alpha_deg)
    return radius + rod - (radius * np.cos(a) + np.sqrt(rod**2 - (radius * np.sin(a)) ** 2))


def volume_m3(alpha_deg):
    clearance = AREA * STROKE / (EPS - 1.0)
    return clearance + AREA * piston_travel_m(alpha_deg)


def volume_slope_m3_per_deg(alpha_deg):
    a = np.radians(alpha_deg)
    root = np.sqrt(ROD**2 - (RADIUS * np.sin(a)) ** 2)
    ds = RADIUS * np.sin(a) + RADIUS**2 * np.sin(a) * np.cos(a) / root
    return AREA * ds * math.pi / 180.0


def port_params(ignition="spark", rho=1.0, opens=OPENS):
    psi = 1.0 - piston_travel_m(180.0 - opens) / STROKE
    return ind.CycleParameters(
        strokes=2,
        ignition=ignition,
        compression_ratio=EPS,
        intake_pressure_Pa=P_A,
        compression_index=N1,
        max_pressure_Pa=P_Z,
        pre_expansion_ratio=rho,
        expansion_index=N2,
        lost_stroke_fraction=float(psi),
    )


@pytest.mark.parametrize(
    "opens, rod_ratio", [(78.0, 0.2705), (60.0, 0.25), (95.0, 0.3), (0.0, 0.28)]
)
def test_the_lost_stroke_fraction_is_the_ports_share_of_the_stroke(opens, rod_ratio):
    radius = 0.04
    rod = radius / rod_ratio
    expected = 1.0 - piston_travel_m(180.0 - opens, radius, rod) / (2 * radius)
    assert ind.lost_stroke_fraction(opens, rod_ratio) == pytest.approx(expected, abs=1e-12)


def test_the_outboard_motors_ports_take_a_third_of_the_stroke():
    # s_b = 44.21 mm of 66 mm: ψ = 0.330 (the supervisor's own figure)
    assert port_params().lost_stroke_fraction == pytest.approx(1 - 44.21 / 66.0, abs=2e-4)


def test_compression_starts_at_the_port_closing():
    params = port_params()
    clearance = AREA * STROKE / (EPS - 1.0)
    start = clearance + AREA * piston_travel_m(180.0 - OPENS)  # V_a′ = V_b, symmetric ports
    actual = start / clearance
    assert ind.actual_compression_ratio(params) == pytest.approx(actual, rel=1e-12)
    assert ind.port_closing_volume_m3(clearance, params) == pytest.approx(start, rel=1e-12)
    assert ind.compression_end_pressure_Pa(params) == pytest.approx(P_A * actual**N1, rel=1e-12)
    assert ind.expansion_end_pressure_Pa(params) == pytest.approx(P_Z / actual**N2, rel=1e-12)
    # p_c ≈ 0.80 MPa from the port closing, against 1.23 MPa over the whole stroke
    assert 0.79e6 < ind.compression_end_pressure_Pa(params) < 0.80e6


def independent_pressure_Pa(alpha_deg, rho=1.0):
    """The theoretical diagram piece by piece: expansion to b, p_a with the ports open,
    compression from a′ (spark ignition: p_z at firing TDC)."""
    clearance = AREA * STROKE / (EPS - 1.0)
    v_port = clearance + AREA * piston_travel_m(180.0 - OPENS)
    v = volume_m3(alpha_deg)
    if alpha_deg <= 180.0 - OPENS:
        return P_Z * min(1.0, rho * clearance / v) ** N2
    if alpha_deg < 180.0 + OPENS:
        return P_A
    return P_A * (v_port / v) ** N1


@pytest.mark.parametrize(
    "alpha", [5.0, 30.0, 90.0, 101.5, 102.5, 150.0, 180.0, 210.0, 257.5, 258.5, 300.0, 355.0]
)
def test_the_theoretical_pressure_follows_the_ports(alpha):
    params = port_params()
    clearance = AREA * STROKE / (EPS - 1.0)
    got = ind.theoretical_pressure_Pa(
        np.array([alpha]), np.array([volume_m3(alpha)]), clearance, params
    )[0]
    assert got == pytest.approx(independent_pressure_Pa(alpha), rel=1e-12)


def test_the_pressure_is_the_scavenging_one_while_the_ports_are_open():
    params = port_params()
    clearance = AREA * STROKE / (EPS - 1.0)
    alpha = np.linspace(180.0 - OPENS + 0.01, 180.0 + OPENS - 0.01, 2001)
    theory = ind.theoretical_pressure_Pa(alpha, volume_m3(alpha), clearance, params)
    assert np.all(theory == P_A)


@pytest.mark.parametrize("ignition, rho", [("spark", 1.0), ("diesel", 1.4)])
def test_the_closed_form_mean_pressure_is_the_diagrams_work_over_the_swept_volume(ignition, rho):
    params = port_params(ignition, rho)
    clearance = AREA * STROKE / (EPS - 1.0)

    def integrand(alpha):
        p = ind.theoretical_pressure_Pa(
            np.array([alpha]), np.array([volume_m3(alpha)]), clearance, params
        )[0]
        return p * volume_slope_m3_per_deg(alpha)

    # the isobar's end ρV_c, the port opening b, BDC, the port closing a′
    v_z = rho * clearance
    isobar_end = 0.0
    if rho > 1.0:  # bisection on the volume
        lo, hi = 0.0, 90.0
        for _ in range(100):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if volume_m3(mid) < v_z else (lo, mid)
        isobar_end = 0.5 * (lo + hi)
    edges = sorted({0.0, isobar_end, 180.0 - OPENS, 180.0, 180.0 + OPENS, 360.0})
    work = sum(
        quad(integrand, a, b, epsabs=0.0, epsrel=1e-12, limit=200)[0]
        for a, b in zip(edges[:-1], edges[1:], strict=False)
    )
    swept = AREA * STROKE
    assert ind.theoretical_mean_indicated_pressure_Pa(params) == pytest.approx(
        work / swept, rel=1e-6
    )


def _outboard_scene(**cycle):
    return {
        "report": {"title": "Two-stroke outboard motor", "language": "uk"},
        "engine": {
            "strokes": 2,
            "cylinders": 1,
            "rpm": 5500,
            "bore": "70 mm",
            "stroke": "66 mm",
            "rod_length": "122 mm",
        },
        "masses": {"piston_group": "0.34 kg", "rod": "0.31 kg", "rod_cm_fraction": 0.29},
        "cycle": {
            "ignition": "spark",
            "compression_ratio": EPS,
            "intake_pressure": "0.098 MPa",
            "compression_index": N1,
            "max_pressure": "5.0 MPa",
            "expansion_index": N2,
            "rounding": {"ignition_advance_deg": 22, "exhaust_opens_before_bdc_deg": OPENS},
            **cycle,
        },
        "analysis": {"angle_step_deg": 0.5},
    }


@pytest.fixture(scope="module")
def outboard():
    return api.run(_outboard_scene(), stages=("indicator",))


def test_the_stage_takes_the_ports_from_the_scene(outboard):
    v = outboard.values
    psi = 1.0 - piston_travel_m(180.0 - OPENS) / STROKE
    clearance = AREA * STROKE / (EPS - 1.0)
    assert v["indicator.lost_stroke_fraction"] == pytest.approx(psi, rel=1e-9)
    assert v["indicator.actual_compression_ratio"] == pytest.approx(
        1.0 + (1.0 - psi) * (EPS - 1.0), rel=1e-9
    )
    assert v["indicator.port_closing_volume_m3"] == pytest.approx(
        clearance + (1.0 - psi) * AREA * STROKE, rel=1e-9
    )
    assert v["indicator.exhaust_ports_open_deg"] == pytest.approx(180.0 - OPENS)
    assert v["indicator.exhaust_ports_close_deg"] == pytest.approx(180.0 + OPENS, abs=1e-6)


def test_the_rounded_diagram_is_continuous_and_scavenged_near_p_a(outboard):
    table = outboard.tables["indicator"]
    angle = np.asarray(table["crank_angle_deg"])
    pressure = np.asarray(table["pressure_Pa"])
    open_ = (angle >= 180.0 - OPENS) & (angle <= 180.0 + OPENS)
    assert P_A * (1 - 1e-9) <= pressure[open_].min() <= 1.05 * P_A
    # at BDC the cylinder is down at the scavenging pressure, below p_b
    assert pressure[angle == 180.0][0] == pytest.approx(P_A, rel=1e-9)
    # continuous: on a 0.5° grid no step exceeds the steepest slope of the lines times the step
    # (the combustion's rise is the steepest, ~0.3 MPa per degree); the theoretical diagram's
    # drop at b (0.57 MPa) is gone
    steps = np.abs(np.diff(np.append(pressure, pressure[0])))
    near_b = np.abs(angle - (180.0 - OPENS)) < 2.0
    assert steps[near_b].max() < 0.02e6
    assert steps.max() < 0.2e6


def test_the_rounded_pressure_is_smooth_at_the_ports_points():
    params = port_params()
    clearance = AREA * STROKE / (EPS - 1.0)
    rounding = ind.RoundingParameters(
        ignition_advance_deg=22.0,
        combustion_delay_deg=2.42,
        pressure_rise_to_tdc_Pa=0.5e6,
        peak_pressure_fraction=0.85,
        peak_angle_after_tdc_deg=12.0,
        exhaust_opens_before_bdc_deg=OPENS,
    )
    joints = [180.0 - OPENS, 180.0 - 0.75 * OPENS, 180.0 + OPENS, 180.0 + 1.25 * OPENS]
    for joint in joints:
        alpha = np.array([joint - 1e-6, joint + 1e-6])
        p = ind.rounded_pressure_Pa(
            alpha, volume_m3(alpha), clearance, params, rounding, volume_function=volume_m3
        )
        assert abs(p[1] - p[0]) < 1e-3 * P_A, joint


def test_a_four_stroke_cycle_keeps_the_whole_stroke():
    params = ind.CycleParameters(
        strokes=4,
        ignition="spark",
        compression_ratio=EPS,
        intake_pressure_Pa=P_A,
        compression_index=N1,
        max_pressure_Pa=P_Z,
        pre_expansion_ratio=1.0,
        expansion_index=N2,
        exhaust_pressure_Pa=0.11e6,
    )
    assert params.lost_stroke_fraction == 0.0
    assert ind.actual_compression_ratio(params) == EPS
    assert ind.compression_end_pressure_Pa(params) == P_A * EPS**N1
    assert ind.expansion_end_pressure_Pa(params) == P_Z * (1.0 / EPS) ** N2
    with pytest.raises(ValueError, match="lost_stroke_fraction"):
        dataclasses.replace(params, lost_stroke_fraction=0.3)
    four = api.run("examples/petrol-1cyl.toml", stages=("indicator",)).values
    assert "indicator.lost_stroke_fraction" not in four


@pytest.mark.parametrize(
    "language, ports, valve",
    [("uk", "вікон", "клапан"), ("ru", "окон", "клапан"), ("en", "ports", "valve")],
)
def test_a_two_strokes_note_speaks_of_ports_and_the_actual_compression_ratio(
    language, ports, valve
):
    html = shared_html("two-stroke-1cyl", language=language, stages=("indicator",)).linked_html
    assert valve not in html.lower()
    assert html.count(ports) >= 5
    sub = "t" if language == "en" else "д"
    # the example: S = 54 mm, λ = 0.25, ports open 80° before BDC, ε = 7
    radius = 0.027
    psi = 1.0 - piston_travel_m(100.0, radius, radius / 0.25) / (2 * radius)
    actual = 1.0 + (1.0 - psi) * (7.0 - 1.0)
    shown = re.search(
        f"<i>ε</i><sub>{sub}</sub> = <i>V</i><sub>a′</sub>/<i>V</i><sub>c</sub>\xa0=\xa0([0-9.,]+)",
        html,
    )
    assert shown is not None
    assert float(shown.group(1).replace(",", ".")) == pytest.approx(actual, abs=6e-4)
    assert "Blair" in html


def test_a_diesel_whose_pre_expansion_outgrows_the_actual_compression_is_refused():
    # ε = 7 with the ports open 80° before BDC (λ = 0.25): ε_д = 4.38 < ρ = 4.9
    scene = _outboard_scene(
        ignition="diesel", pre_expansion_ratio=4.9, compression_ratio=7.0, max_pressure="9 MPa"
    )
    scene["cycle"]["rounding"]["exhaust_opens_before_bdc_deg"] = 90.0
    with pytest.raises(SceneError) as refused:
        api.run(scene, stages=("indicator",))
    assert "cycle.pre_expansion_ratio = 4.9" in str(refused.value)
    assert "actual compression ratio from the exhaust ports' closing" in str(refused.value)


def test_a_thermal_p_i_check_still_explains_a_fullness_above_one():
    """The ported two-stroke's rounded diagram has more area than p_i′ counts (its blowdown after
    b): with a thermal p_i to check against, the note still states φ = p_i/p_i′ and why it
    exceeds 1."""
    import re

    from conftest import shared_html, shared_run

    given = {"cycle": {"mean_indicated_pressure": "0.55 MPa"}}
    r = shared_run("two-stroke-1cyl", given, ("indicator",)).outputs["indicator"].results
    phi = r["gross_mean_indicated_pressure_Pa"] / r["theoretical_mean_indicated_pressure_Pa"]
    assert r["diagram_fullness"] == pytest.approx(phi, rel=1e-12) and phi > 1
    html = shared_html("two-stroke-1cyl", given, "en", ("indicator",)).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html))
    assert "Check: the thermal calculation gives a mean indicated pressure of 0.5500 MPa" in text
    assert f"the diagram fullness: φf = pi/pi′ = {phi:.4g}" in text.replace("\u2060", "")
    assert "whereas the actual blowdown lasts" in text


def test_only_a_spark_ignition_two_stroke_is_said_to_be_scavenged_by_its_crankcase():
    """The forces' note on p_0: a crankcase-scavenged (spark-ignition) two-stroke's crankcase
    is its scavenging pump, whose work the note leaves out; a diesel two-stroke is scavenged by
    a blower or a turbocharger, and its note says what a four-stroke's does."""
    from tests.conftest import shared_run

    spark = shared_run("two-stroke-1cyl").outputs["forces"].notes
    diesel = {"engine": {"rpm": 2000}, "cycle": {"ignition": "diesel", "pre_expansion_ratio": 1.3}}
    compression = shared_run("two-stroke-1cyl", diesel).outputs["forces"].notes
    assert [key for key, _ in spark if key.startswith("forces.note_gauge")] == [
        "forces.note_gauge_two_stroke"
    ]
    assert [key for key, _ in compression if key.startswith("forces.note_gauge")] == [
        "forces.note_gauge"
    ]


def test_the_scavenging_pressures_sources_are_cited_in_one_bracket():
    """The ports' gas exchange cites the textbook and Blair together: "[6, 10]", not "[6], [10]"."""
    import re

    from conftest import shared_html

    text = " ".join(
        re.sub(r"<[^>]+>", "", shared_html("two-stroke-1cyl", None, "ru").linked_html).split()
    )
    assert re.search(r"давлению продувки pa \[\d+, \d+\]\.", text)
    assert not re.search(r"pa \[\d+\], \[\d+\]", text)
