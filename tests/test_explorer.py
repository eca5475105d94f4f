"""Firing-order and crank-arrangement explorer."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from crankdyn.cli import main
from crankdyn.physics import balancing as bal
from crankdyn.physics import firing_explorer as fe
from crankdyn.physics.layout import build_layout


@pytest.mark.parametrize(
    "cylinders, strokes, arrangements, orders",
    [
        (3, 4, 2, 2),
        (4, 4, 3, 6),
        (5, 4, 24, 24),
        (6, 4, 30, 120),
        (8, 4, 630, 5040),
        (4, 2, 6, 6),
        (6, 2, 120, 120),
    ],
)
def test_inline_counts(cylinders, strokes, arrangements, orders):
    """(i-1)! firing orders; for an even four-stroke count, (i-1)!/2^(i/2-1) crank arrangements."""
    result = fe.explore(cylinders, "inline", strokes, top=3)
    assert result.arrangements == arrangements and result.firing_orders == orders
    assert orders == fe.count_firing_orders(cylinders)


@pytest.mark.parametrize(
    "cylinders, layout, strokes, gamma",
    [
        (6, "inline", 4, None),
        (5, "inline", 4, None),
        (4, "inline", 2, None),
        (8, "V", 4, 90.0),
        (6, "V", 4, 120.0),
        (12, "W", 4, 60.0),
        (8, "X", 4, 90.0),
        (4, "boxer", 4, None),
        (3, "Y", 2, 120.0),
    ],
)
def test_every_listed_order_fires_evenly_with_its_cranks(cylinders, layout, strokes, gamma):
    """Independent check through the layout builder: each row's firing order, given as the scene would give
    it, yields exactly the row's crank arrangement and even firing; rows are distinct."""
    result = fe.explore(cylinders, layout, strokes, gamma, top=None)
    assert len(result.rows) == result.firing_orders > 0
    seen = set()
    for row in result.rows:
        built = build_layout(layout, strokes, cylinders, gamma, list(row.firing_order), None)
        assert built.even_firing
        np.testing.assert_allclose(
            np.array(built.crank_lag_deg) % 360, np.array(row.crank_angles_deg) % 360, atol=1e-9
        )
        seen.add(row.firing_order)
    assert len(seen) == len(result.rows)


def test_inline8_full_ranking_is_sorted_and_its_coefficients_are_right():
    result = fe.explore(8, "inline", 4, top=None)
    assert len(result.rows) == 5040 == result.scored_firing_orders
    assert [r.rank for r in result.rows] == list(range(1, 5041))
    rng = np.random.default_rng(5)
    for row in [result.rows[i] for i in rng.choice(5040, 25, replace=False)]:
        layout = build_layout("inline", 4, 8, None, list(row.firing_order), None)
        g = bal.geometry_from_layout(layout)
        rot, first, second = (
            bal.rotating_model(g),
            bal.reciprocating_model(g, 1),
            bal.reciprocating_model(g, 2),
        )
        expected = {
            "sum_C": abs(rot.force_forward),
            "M_C": abs(rot.moment_forward),
            "sum_PI": first.force_max,
            "M_PI": first.moment_max,
            "sum_PII": second.force_max,
            "M_PII": second.moment_max,
        }
        for key, value in expected.items():
            assert row.coefficients[key] == pytest.approx(value, abs=1e-12)
    # keys never decrease down the table: in-line first key = sum_PI + M_PI, then the second order
    first = [r.coefficients["sum_PI"] + r.coefficients["M_PI"] for r in result.rows]
    assert all(b >= a - 1e-7 for a, b in zip(first, first[1:], strict=False))
    best = result.rows[0]
    assert all(
        v == 0.0 for v in best.coefficients.values()
    )  # the mirror-symmetric (cross) crankshaft
    assert best.neighbours == 0
    # the classic 1-6-2-5-8-3-7-4 is among the fully balanced orders with no neighbours firing in turn
    classic = next(r for r in result.rows if "-".join(r.firing_order) == "1-6-2-5-8-3-7-4")
    assert classic.neighbours == 0 and all(v == 0.0 for v in classic.coefficients.values())


def test_tiered_ranking_equals_the_full_ranking():
    full = fe.explore(8, "inline", 4, top=None).rows
    for top in (1, 10, 60):
        part = fe.explore(8, "inline", 4, top=top)
        assert [(r.firing_order, r.rank) for r in part.rows] == [
            (r.firing_order, r.rank) for r in full[:top]
        ]
        assert part.scored_firing_orders < 5040


def test_textbook_choices_rank_first():
    four = fe.explore(4, "inline", 4, top=2).rows
    assert all(
        r.crank_angles_deg == (0.0, 180.0, 180.0, 0.0) for r in four
    )  # flat crank, only 4 C_II left
    assert four[0].coefficients["sum_PII"] == pytest.approx(4.0)
    six = fe.explore(6, "inline", 4, top=2).rows
    assert {"-".join(r.firing_order) for r in six} == {"1-5-3-6-2-4", "1-4-2-6-3-5"}
    assert all(max(r.coefficients.values()) == 0.0 and r.neighbours == 0 for r in six)
    # 90-degree V8: the cross-plane crank (a rotating couple that counterweights cure) before the flat one
    v8 = fe.explore(8, "V", 4, 90.0, top=None).rows
    assert v8[0].coefficients["sum_PII"] == 0.0 and v8[0].coefficients["M_PI"] == pytest.approx(
        math.sqrt(10)
    )
    flat = [r for r in v8 if r.crank_angles_deg == (0.0, 180.0, 180.0, 0.0)]
    assert flat and all(r.coefficients["sum_PII"] == pytest.approx(4 * math.sqrt(2)) for r in flat)
    cross = [r for r in v8 if r.coefficients == pytest.approx(v8[0].coefficients)]
    assert len(cross) >= 8 and min(r.rank for r in flat) > max(r.rank for r in cross)


def test_locating_the_scene_order():
    order = ("1L", "1R", "4L", "3L", "3R", "2L", "2R", "4R")
    full = fe.explore(8, "V", 4, 90.0, top=None).rows
    expected = next(r.rank for r in full if r.firing_order == order)
    located = fe.explore(8, "V", 4, 90.0, top=3, locate=((0, 90, 270, 180), order))
    assert located.located_rank == expected and located.located.firing_order == order
    # a scene order outside the top rows of an in-line 8 is ranked without scoring everything
    row = fe.explore(8, "inline", 4, top=None).rows[3000]
    hit = fe.explore(8, "inline", 4, top=5, locate=(row.crank_angles_deg, row.firing_order))
    assert hit.located_rank == 3001


def test_no_even_firing_and_single_crank_engines():
    v6 = fe.explore(6, "V", 4, 60.0).reason  # a 60-degree V6 needs split pins
    assert v6.code == "bank_grid" and v6.values == {"unit_deg": 120.0, "interval_deg": 120.0}
    assert "multiples of 120" in str(v6)
    assert "split pins, one per cylinder, are not modelled" in str(v6)  # not promised
    radial = fe.explore(9, "radial", 4, top=5)
    assert radial.arrangements == 1 and radial.firing_orders == 1
    assert radial.rows[0].firing_order == ("1", "3", "5", "7", "9", "2", "4", "6", "8")
    assert radial.rows[0].coefficients["sum_PI"] == pytest.approx(4.5)
    assert fe.explore(1, "inline", 4).firing_orders == 1
    too_many = fe.enumerate_arrangements(14, "inline", 4, limit=100_000)
    assert too_many[-1].code == "too_many" and "beyond an exhaustive search" in str(too_many[-1])


@pytest.mark.parametrize(
    "language, said",
    [
        ("ru", "вспышки через каждые 180° возможны лишь при угле развала, кратном 180°"),
        ("uk", "спалахи через кожні 180° можливі лише за кута розвалу, кратного 180°"),
        ("en", "firings every 180° need a bank angle that is a multiple of 180°"),
    ],
)
def test_a_note_says_in_its_language_why_no_arrangement_fires_evenly(language, said):
    """A 90° V4 on shared pins: no even-firing arrangement exists; the note gives the reason in
    its own words and does not announce an enumeration of none."""
    from conftest import shared_html

    v4 = {
        "engine": {
            "cylinders": 4,
            "layout": "V",
            "bank_angle_deg": 90,
            "crank_angles_deg": [0, 180],
            "uneven_firing": True,
            "firing_order": ["1L", "2L", "1R", "2R"],
        },
        "balancing": {"explore": True},
    }
    html = shared_html("v8-petrol", v4, language, ("balancing",)).linked_html
    text = re.sub(r"[\u00a0\u202f]", " ", re.sub(r"<[^>]+>", "", html))
    assert said in text
    assert "must be multiples" not in text and "Порядки работы и схемы колен" not in text


def test_cli_explore(capsys):
    assert main(["explore", "--cylinders", "4", "--top", "2"]) == 0
    out = capsys.readouterr().out
    assert (
        "3 crank arrangements, 6 firing orders" in out and "1-3-4-2" in out and "0,180,180,0" in out
    )
    assert (
        main(
            [
                "explore",
                "--cylinders",
                "8",
                "--layout",
                "V",
                "--bank-angle",
                "90",
                "--json",
                "--top",
                "1",
            ]
        )
        == 0
    )
    data = json.loads(capsys.readouterr().out)
    assert data["firing_orders"] == 72 and len(data["rows"]) == 1
    assert main(["explore", "--cylinders", "8", "--layout", "V"]) == 2
    assert "--bank-angle" in capsys.readouterr().err
    assert main(["explore", "--cylinders", "7", "--layout", "V", "--bank-angle", "90"]) == 2
    assert "multiple of 2" in capsys.readouterr().err


def test_an_uneven_crank_is_not_located_among_the_even_firing_arrangements():
    """A 270° twin's crank lies off the 360° grid of even firing: rounding it onto the grid
    called it the 360° twin and the note said "the given firing order ranks 1 of 1"."""
    for lags, found in [
        ((0.0, 0.0), 1),
        ((0.0, 360.0), 1),
        ((0.0, 270.0), None),
        ((0.0, 180.0), None),
    ]:
        assert (
            fe.explore(2, "inline", 4, None, top=5, locate=(lags, ("1", "2"))).located_rank == found
        )


def test_the_note_of_an_uneven_twin_says_its_cranks_are_not_in_the_search():
    import html as html_lib
    import re

    from conftest import TWIN_270_ENGINE, shared_html

    twin = {
        "engine": TWIN_270_ENGINE,
        "report": {"language": "ru"},
    }
    page = shared_html("inline3-petrol", twin).linked_html
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", " ", page)).split())
    assert "Порядок работы из задания" not in text
    assert "Схема колен из задания даёт неравномерное чередование вспышек" in text


def test_an_uneven_twins_torque_conclusion_says_why_its_period_is_the_whole_cycle():
    """A 270° twin's torque repeats every 720°: the conclusion says it is the uneven firing,
    not the 360° an even twin's torque repeats in; an even engine says nothing of it."""
    import html as html_lib
    import re

    from conftest import TWIN_270_ENGINE, shared_html, shared_run

    twin = {
        "engine": TWIN_270_ENGINE,
        "report": {"language": "ru"},
    }
    assert shared_run("inline3-petrol", twin).outputs["torque"].results["period_deg"] == 720.0
    page = html_lib.unescape(
        re.sub(r"<[^>]+>", "", shared_html("inline3-petrol", twin).linked_html)
    )
    text = " ".join(page.replace("\u2060", "").replace("\u202f", " ").split())
    assert (
        "Чередование вспышек неравномерное, поэтому крутящий момент повторяется через 720°, "
        "а не через 360° (720°/2), как при равномерном чередовании." in text
    )
    even = shared_html("inline3-petrol", {"report": {"language": "ru"}}).linked_html
    assert "повторяется через" not in even


def test_a_given_order_tied_with_the_first_is_said_to_balance_as_well():
    """The in-line three's given 1-3-2 ranks second of two behind its mirror 1-2-3, with every
    coefficient the same: "2-й із 2" alone read as the worse order."""
    import re

    from conftest import shared_html, shared_run

    explorer = shared_run("inline3-petrol").outputs["balancing"].results["explorer"]
    assert explorer["scene_rank"] == 2
    assert explorer["scene"]["coefficients"] == pytest.approx(explorer["rows"][0]["coefficients"])
    text = re.sub(
        r"\s+", " ", re.sub(r"<[^>]+>", "", shared_html("inline3-petrol", None, "uk").linked_html)
    )
    assert "Порядок роботи із завдання – 2-й із 2, проте зрівноважений так само, як перший" in text


def test_a_boxers_neighbours_in_one_bank_are_a_crank_apart():
    """A flat four's banks hold cylinders 1, 3 and 2, 4 (a crank pin each, the banks on
    alternate cranks): 1→3 and 2→4 fire neighbours of one bank in turn in 1–3–2–4, though
    their cranks are two apart; 1–2–3–4 fires no two of one bank in turn."""
    ranked = {r.firing_order: r for r in fe.explore(4, "boxer", 4, None, top=None).rows}
    assert ranked[("1", "3", "2", "4")].neighbours == 2
    assert ranked[("1", "2", "3", "4")].neighbours == 0


def test_the_explorers_rule_columns_are_explained_before_its_table():
    """ "Neighbours", "Same pin", "Same half": the sentence announcing the ranked table says what
    the numbers in them count."""
    from conftest import EXPLORED_BOXER, shared_html

    html = shared_html("inline4-petrol", EXPLORED_BOXER, "en", ("balancing",)).linked_html
    text = re.sub(r"<[^>]+>", "", html)
    said = text.index("how many consecutive firings each rule names")
    assert said < text.index("Firing orders and crank arrangements ranked")


def test_a_given_crank_arrangement_gets_a_firing_order_that_fits_it():
    """Cranks given, no firing order: the explorer's best order for these cranks is taken (a
    flat-plane V8's 0-180-180-0, whose best order overall is a cross-plane one's)."""
    from conftest import shared_run

    flat = {"engine": {"firing_order": None, "crank_angles_deg": [0, 180, 180, 0]}}
    scene = shared_run("v8-petrol", flat, ("kinematics",)).scene
    assert scene.firing_order_chosen and scene.engine.crank_angles_deg == [0, 180, 180, 0]
    order = scene.engine.firing_order
    assert sorted(order) == sorted(f"{k}{b}" for k in range(1, 5) for b in "LR")
