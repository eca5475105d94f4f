"""A small unbalanced moment printed with the same digits in the table of orders and in the
conclusions: to 0.1 N·m, two significant digits under 1 N·m."""

from __future__ import annotations

import pytest
from test_plausibility_in_report import REGISTRY, Note

from crankdyn.report.i18n import translator
from crankdyn_builtin.balancing.notation import newton_metres, newtons


@pytest.mark.parametrize(
    "moment, printed",
    [(1809.64, "1809,6"), (3.349, "3,3"), (1.0, "1,0"), (0.07512, "0,075"), (0.0456, "0,046")],
)
def test_a_moment_is_printed_to_a_tenth_or_with_two_significant_digits_under_one(moment, printed):
    t = translator("ru", REGISTRY.catalogs)
    assert newton_metres(t, moment) == printed


@pytest.mark.parametrize(
    "value, moment, force",
    [
        # a low-speed marine engine's ΣM_II: five significant digits, not to the tenth of a N·m
        (1249297.6, "1\u202f249\u202f300", "1\u202f249\u202f300"),
        (68635.5, "68\u202f636", "68\u202f636"),
        (9999.96, "10\u202f000", "10\u202f000"),
        (17235.4, "17\u202f235", "17\u202f235"),  # a car engine's: whole newtons
        (-972434.0, "−972\u202f430", "−972\u202f430"),
    ],
)
def test_a_large_force_or_moment_has_five_significant_digits(value, moment, force):
    t = translator("uk", REGISTRY.catalogs)
    assert (newton_metres(t, value), newtons(t, value)) == (moment, force)


def test_the_sixth_order_moment_has_the_same_digits_in_the_table_and_the_conclusions():
    note = Note(
        "inline4-petrol", {"engine": {"cylinders": 5, "firing_order": None}}, ("balancing",), "ru"
    )
    moment = note.result.outputs["balancing"].results["absolute"]["M_PVI_Nm"]
    assert 0.01 < moment < 1  # tenths would print it as 0,0 or 0,1
    printed = f"{moment:.2g}".replace(".", ",")
    section = note.section("balancing")
    # the resultants' table: its rows named by the order, "VI", then the force's ratio and value
    row = section[section.index(" II 0,0000") :]
    row = row[row.index(" VI 0,0000") :]
    assert row.split()[4] == printed  # the moment column of the row of order VI
    assert f"Σ M VI = {printed} Н·м" in note.conclusions
