"""A chosen firing order's second-order moment set against every even-firing order's, checked by
an independent brute force over the firing orders, and the sentence the note says about it."""

from __future__ import annotations

import cmath
import itertools
import math

import pytest
from test_plausibility_in_report import Note

from crankdyn.physics.firing_explorer import second_order_moment_rank


def _inline_second_order_moments(cylinders: int) -> dict[tuple[int, ...], float]:
    """M_II/(C_II·a) of every firing order (cylinder 1 first) of an in-line four-stroke engine of
    an odd cylinder count: the k-th cylinder to fire lags k·720/i degrees of the cycle, its crank
    the same mod 360; cylinder n sits at n - (i + 1)/2 cylinder spacings from the middle, and
    with all axes vertical the moment's largest length is |Σ x_n e^(j·2ξ_n)|."""
    moments = {}
    for rest in itertools.permutations(range(2, cylinders + 1)):
        order = (1, *rest)
        lag = {n: (720.0 / cylinders * k) % 360.0 for k, n in enumerate(order)}
        total = sum(
            (n - (cylinders + 1) / 2) * cmath.exp(2j * math.radians(lag[n]))
            for n in range(1, cylinders + 1)
        )
        moments[order] = abs(total)
    return moments


def _cranks(order: tuple[int, ...], cylinders: int) -> list[float]:
    lag = {n: (720.0 / cylinders * k) % 360.0 for k, n in enumerate(order)}
    return [lag[n] for n in range(1, cylinders + 1)]


@pytest.mark.parametrize("cylinders", [3, 5])
def test_the_rank_of_each_arrangements_second_order_moment_matches_a_brute_force(cylinders):
    moments = _inline_second_order_moments(cylinders)
    for order, own in moments.items():
        rank = second_order_moment_rank(cylinders, "inline", 4, None, _cranks(order, cylinders))
        assert rank["orders"] == math.factorial(cylinders - 1) == len(moments)
        assert rank["coefficient"] == pytest.approx(own, abs=1e-9)
        assert rank["larger"] == sum(m > own + 1e-6 for m in moments.values())
        assert rank["smaller"] == sum(m < own - 1e-6 for m in moments.values())


def test_an_inline_fives_chosen_order_is_said_to_have_the_largest_second_order_moment():
    moments = _inline_second_order_moments(5)
    largest = max(moments.values())
    tied = sum(abs(m - largest) < 1e-6 for m in moments.values())
    changes = {"engine": {"cylinders": 5, "firing_order": None}}
    note = Note("inline4-petrol", changes, ("bays",), "ru")
    chosen = tuple(int(x) for x in note.result.outputs["bays"].results["firing_order"])
    assert moments[chosen] == pytest.approx(largest, abs=1e-9)
    section = note.section("bays")
    assert f"Σ M II = {largest:.4f}".replace(".", ",") in section
    phrase = "наибольший из 24 порядков работы с равномерным чередованием вспышек"
    assert f"{phrase} (такой же у {tied} из них)" in section
    assert "уравновешивающие валы второго порядка" in section


def test_no_sentence_where_the_chosen_order_has_no_second_order_moment_or_none_is_smaller():
    # an in-line six: no second-order moment; an in-line three: one arrangement, nothing smaller
    for cylinders in (6, 3):
        changes = {"engine": {"cylinders": cylinders, "firing_order": None}}
        section = Note("inline4-petrol", changes, ("bays",), "en").section("bays")
        assert "second-order moment" not in section
