"""A given firing order that leaves a force or moment another even-firing order of the same
engine balances: the order written in another numbering of the cylinders (a flat four numbered
by banks) gives another crankshaft, and the report says which order balances it."""

from __future__ import annotations

import html as html_text
import re

import pytest
from conftest import shared_html, shared_run

from crankdyn.physics import firing_explorer as fe


@pytest.mark.parametrize(
    ("cylinders", "layout", "cranks", "order", "better", "better_cranks", "freed"),
    [
        # every throw of a flat four in line: the opposed pistons move together, so the
        # centrifugal and first-order forces add up (4 C, 4 C_I); cranks 0-180-180-0 cancel them
        (4, "boxer", (0, 0, 0, 0), "1432", "1324", (0, 180, 180, 0), ("sum_C", "sum_PI")),
        # an in-line four firing 1-2-3-4 (cranks 0-180-0-180): the forces cancel, their couples
        # do not; the mirror-symmetric shaft 0-180-180-0 cancels both
        (4, "inline", (0, 180, 0, 180), "1234", "1243", (0, 180, 180, 0), ("M_C", "M_PI")),
    ],
)
def test_an_order_that_leaves_what_another_balances_is_found(
    cylinders, layout, cranks, order, better, better_cranks, freed
):
    found = fe.better_balanced(cylinders, layout, 4, None, cranks, tuple(order))
    assert found is not None
    best, freed_keys = found
    assert "".join(best.firing_order) == better
    assert best.crank_angles_deg == better_cranks
    assert freed_keys == freed


@pytest.mark.parametrize(
    ("cylinders", "layout", "strokes", "cranks", "order"),
    [
        (4, "boxer", 4, (0, 180, 180, 0), "1324"),
        (4, "inline", 4, (0, 180, 180, 0), "1342"),
        # an in-line five or three: every even-firing order leaves the same free moments
        (5, "inline", 4, (0, 144, 216, 288, 72), "12453"),
        (3, "inline", 2, (0, 240, 120), "132"),
    ],
)
def test_a_best_balanced_order_is_let_be(cylinders, layout, strokes, cranks, order):
    assert fe.better_balanced(cylinders, layout, strokes, None, cranks, tuple(order)) is None


#: A flat four (the bundled in-line four's data) fired 1-4-3-2 in the calculation's numbering.
FLAT_FOUR_BY_BANKS = {"engine": {"layout": "boxer", "firing_order": [1, 4, 3, 2]}}


def test_the_report_names_the_order_that_balances_the_engine():
    run = shared_run("inline4-petrol", FLAT_FOUR_BY_BANKS, ("balancing",))
    r = run.outputs["balancing"].results
    assert r["better_firing"] == {
        "firing_order": ["1", "3", "2", "4"],
        "crank_angles_deg": [0.0, 180.0, 180.0, 0.0],
        "freed": ["sum_C", "sum_PI"],
    }
    # all four throws in line: the table's coefficients are the four cylinders' sum
    rows = {s["quantity"]: s for s in r["summary"]}
    assert rows["sum_C"]["coefficient"] == pytest.approx(4.0)
    html = shared_html("inline4-petrol", FLAT_FOUR_BY_BANKS, "en", ("balancing",)).linked_html
    text = " ".join(html_text.unescape(re.sub(r"<[^>]+>", " ", html)).replace("\xa0", " ").split())
    assert "The given firing order 1–4–3–2 puts the cranks at 0; 0; 0; 0°" in text
    assert "the order 1–3–2–4, with the cranks at 0; 180; 180; 0°, fires the cylinders" in text
    assert "The given firing order 1–4–3–2 leaves ΣC, Σ P I unbalanced" in text


def test_the_bundled_engines_orders_are_not_questioned():
    for name in ("inline4-petrol", "v8-petrol", "inline3-petrol"):
        r = shared_run(name, None, ("balancing",)).outputs["balancing"].results
        assert "better_firing" not in r, name
