"""A small unbalanced moment printed with the same digits in the table of orders and in the
conclusions: to 0.1 N·m, two significant digits under 1 N·m."""

from __future__ import annotations

import pytest
from test_plausibility_in_report import REGISTRY, Note

from crankdyn.report.i18n import translator
from crankdyn_builtin.balancing.notation import newton_metres


@pytest.mark.parametrize(
    "moment, printed",
    [(1809.64, "1809,6"), (3.349, "3,3"), (1.0, "1,0"), (0.07512, "0,075"), (0.0456, "0,046")],
)
def test_a_moment_is_printed_to_a_tenth_or_with_two_significant_digits_under_one(moment, printed):
    t = translator("ru", REGISTRY.catalogs)
    assert newton_metres(t, moment) == printed


def test_the_sixth_order_moment_has_the_same_digits_in_the_table_and_the_conclusions():
    note = Note(
        "inline4-petrol", {"engine": {"cylinders": 5, "firing_order": None}}, ("balancing",), "ru"
    )
    moment = note.result.outputs["balancing"].results["absolute"]["M_PVI_Nm"]
    assert 0.01 < moment < 1  # tenths would print it as 0,0 or 0,1
    printed = f"{moment:.2g}".replace(".", ",")
    section = note.section("balancing")
    row = section[section.index("P VI 0,0000") :]
    assert row.split()[8] == printed  # the moment column of the row of order VI
    assert f"Σ M VI = {printed} Н·м" in note.conclusions
