"""The main bearings' largest mean and peak pressures compared with the allowable ones of the
engine's kind (Kolchin and Demidov: mean 12 and largest 20 MPa in petrol engines, 16 and 40 MPa
in diesels), in the bearings section and in the conclusions, with the digits of the table."""

from __future__ import annotations

from types import SimpleNamespace

import pytest
from test_plausibility_in_report import Note

from crankdyn_builtin.bearings.compute import main_pressure_verdict


def _scene(ignition):
    return SimpleNamespace(cycle=None if ignition is None else SimpleNamespace(ignition=ignition))


def _journals(*pressures):
    """Journals of hand-chosen (mean, largest) pressures, MPa, on a 1000 mm² projected area."""
    return {
        "main_journals": [
            {
                "journal": f"{j}-{j + 1}",
                "mean_MPa": m,
                "max_MPa": x,
                "mean_N": m * 1e3,
                "max_N": x * 1e3,
            }
            for j, (m, x) in enumerate(pressures)
        ]
    }


@pytest.mark.parametrize(
    "ignition, pressures, exceeded, area_mm2",
    [
        ("spark", [(11.9, 19.9), (5.0, 8.0)], "", 19.9e3 / 20),
        ("spark", [(3.0, 15.0), (12.5, 9.0)], "mean", 12.5e3 / 12),
        ("diesel", [(15.0, 41.0), (8.0, 20.0)], "max", 41.0e3 / 40),
        ("diesel", [(17.0, 20.0), (8.0, 44.0)], "both", 44.0e3 / 40),
        # an engine of unknown ignition (a measured trace) is judged as a diesel: 14 < 16
        (None, [(14.0, 39.0)], "", 39.0e3 / 40),
    ],
)
def test_the_main_bearings_pressures_are_classified_by_the_allowable_ones(
    ignition, pressures, exceeded, area_mm2
):
    verdict = main_pressure_verdict(_scene(ignition), _journals(*pressures))
    assert verdict["exceeded"] == exceeded
    assert verdict["kind"] == ("spark" if ignition == "spark" else "diesel")
    assert verdict["p_mean"] == max(m for m, _ in pressures)
    assert verdict["p_max"] == max(x for _, x in pressures)
    assert verdict["area_needed_m2"] * 1e6 == pytest.approx(area_mm2, rel=1e-12)


def test_the_journals_of_the_largest_mean_and_peak_are_named_the_first_of_equal_ones():
    verdict = main_pressure_verdict(
        _scene("spark"), _journals((3.0, 15.0), (12.5, 9.0), (3.0, 15.0))
    )
    assert verdict["mean_journal"]["journal"] == "1-2"
    assert verdict["max_journal"]["journal"] == "0-1"
    assert main_pressure_verdict(_scene("spark"), {}) is None


def test_an_unbalanced_inline_fours_centre_main_bearing_is_above_the_allowable_mean_pressure():
    # the example has no counterweights: the centre journal carries the centrifugal forces of
    # two cranks; its size is assumed, d = 0.7·82 = 57.4 mm, B = 0.45·57.4 = 25.8 mm
    note = Note("inline4-petrol", {}, ("bearings",), "ru")
    journals = note.result.outputs["bearings"].results["main_journals"]
    centre = journals[2]
    p_mean = centre["mean_N"] / (57.4e-3 * 25.8e-3) / 1e6
    assert p_mean == pytest.approx(centre["mean_MPa"], rel=1e-9) and p_mean > 12
    section = note.section("bearings")
    sentence = section[section.index("Наибольшее среднее давление на коренной подшипник") :]
    assert f"подшипник {p_mean:.2f} МПа".replace(".", ",") in sentence
    assert "(оба – на шейке 2–3)" in sentence
    assert "допустимы среднее давление до 12 МПа и наибольшее до 20 МПа [" in sentence
    assert "превышено допустимое среднее давление" in sentence
    assert note.cited(sentence).startswith("Колчин А. И., Демидов В. П.")
    # d·B at which the largest mean load gives 12 MPa
    area = max(j["mean_N"] for j in journals) / 12e6 * 1e6
    assert f"d · B ≥ {area:.0f} мм²" in sentence
    assert "Коренные подшипники: превышено допустимое среднее давление" in note.conclusions
    # the journal's sizes are not given: the verdict is said to rest on the assumed ones
    assumed = "приняты по типовым соотношениям ( d = 57,4 мм, B = 25,8 мм), поэтому следующий вывод"
    assert assumed in section
    # the big-end bearing is within its allowable pressures, as the conclusions say
    assert "Давление на шатунный подшипник в пределах допустимого" in note.conclusions


def test_wider_main_journals_bring_the_main_bearings_within_the_allowable_pressures():
    # 40 mm instead of 25.8 mm: the pressures fall by 25.8/40
    base = Note("inline4-petrol", {}, ("bearings",), "uk")
    wide = Note(
        "inline4-petrol", {"bearings": {"main_journal_width": "40 mm"}}, ("bearings",), "uk"
    )
    before = max(j["mean_MPa"] for j in base.result.outputs["bearings"].results["main_journals"])
    after = max(j["mean_MPa"] for j in wide.result.outputs["bearings"].results["main_journals"])
    assert after == pytest.approx(before * 25.8 / 40, rel=1e-9) and after < 12
    section = wide.section("bearings")
    assert f"корінний підшипник {after:.2f} МПа".replace(".", ",") in section
    assert "у межах допустимих для бензинових двигунів середнього 12 МПа" in section
    assert "Розміри корінної шийки в завданні не вказано" not in section
    concluded = "Тиск на корінні підшипники в межах допустимого для бензинових двигунів: "
    assert concluded + f"середній до {after:.2f} МПа".replace(".", ",") in wide.conclusions


def test_a_diesels_main_bearings_are_judged_by_the_diesels_allowable_pressures():
    note = Note("diesel-1cyl", {}, ("bearings",), "en")
    section = note.section("bearings")
    assert "allowable in diesels [" in section and "largest 40 MPa" in section
    assert "The main-bearing pressure is within the values allowable in diesels" in note.conclusions
    assert "against the allowable 16 and 40 MPa" in note.conclusions


def test_counterweights_on_other_cranks_leave_a_journal_loaded_by_its_neighbours():
    """An in-line five with counterweights on its end cranks only: journal 2–3 carries cranks 2
    and 3, which have none, so its load is chiefly their centrifugal forces, and the note names
    counterweights next to it as the remedy (it offered only a longer bearing)."""
    import re

    from conftest import shared_html, shared_run

    five = {"engine": {"cylinders": 5, "firing_order": [1, 2, 4, 5, 3]}}
    r = shared_run("inline3-petrol", five, ("balancing", "bearings")).outputs["bearings"].results
    assert r["counterweight_cranks"] == [1, 5]
    journal = max(r["main_journals"], key=lambda j: j["mean_N"])
    assert journal["journal"] in ("2-3", "3-4")
    assert journal["centrifugal_N"] > 0.5 * journal["mean_N"]
    page = shared_html("inline3-petrol", five, "en", ("balancing", "bearings")).linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", page).split())
    assert "carries chiefly the centrifugal forces of the cranks beside it" in text


@pytest.mark.parametrize(
    "ignition, pressures, key",
    [
        ("spark", [(11.9, 19.9), (5.0, 8.0)], None),
        ("spark", [(3.0, 15.0), (12.5, 9.0)], "bearings.plausibility_main_pressure_spark"),
        ("diesel", [(8.0, 44.0)], "bearings.plausibility_main_pressure_diesel"),
    ],
)
def test_main_bearings_above_the_allowable_pressures_are_warned_of_on_the_console(
    ignition, pressures, key
):
    """As a crank pin's: the console names the journal, its pressures, the allowable ones and the
    projected area needed; the report's section and conclusions word it themselves (their
    texts of the warning are empty)."""
    from crankdyn.report.i18n import translator
    from crankdyn_builtin.bearings.compute import _main_pressure

    found = _main_pressure(_scene(ignition), _journals(*pressures))
    if key is None:
        assert found == []
        return
    [(got, params)] = found
    assert got == key
    worst = max(pressures, key=lambda p: p[0])
    assert (params["p_mean"], params["journal"]) == (
        worst[0],
        f"{pressures.index(worst)}-{pressures.index(worst) + 1}",
    )
    assert params["area_needed"] == pytest.approx(
        main_pressure_verdict(_scene(ignition), _journals(*pressures))["area_needed_m2"] * 1e6
    )
    t = translator("en", default_catalogs())
    said = t(key, **params)
    assert said.startswith("Plausibility warning: main-bearing pressure")
    # each pressure beside its own limit: one of the two may be within it
    assert (
        f"(allowable {params['mean_limit']})" in said
        and f"(allowable {params['max_limit']})" in said
    )
    assert t(key + "_section", **params) == "" and t(key + "_conclusion", **params) == ""


def default_catalogs():
    from crankdyn.plugin.registry import default_registry

    return default_registry().catalogs
