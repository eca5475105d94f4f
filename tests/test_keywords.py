"""The abstract's key words name what the report holds (the balancing, the bearings and the
flywheel when they are calculated)."""

from __future__ import annotations

import re

import pytest
from conftest import shared_html

from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import KEYWORDS_MAX, keywords
from crankdyn.report.i18n import translator


def _keywords(html: str) -> list[str]:
    return re.search(r'<p class="keywords">(.*?)</p>', html, flags=re.S).group(1).split(", ")


def test_the_key_words_follow_the_sections():
    full = _keywords(shared_html("inline4-petrol", language="uk").linked_html)
    alone = _keywords(shared_html("kinematics-only", language="uk").linked_html)
    assert full[:3] == [
        "ДИНАМІЧНИЙ РОЗРАХУНОК",
        "ДВИГУН ВНУТРІШНЬОГО ЗГОРЯННЯ",
        "ЦЕНТРАЛЬНИЙ КРИВОШИПНО-ШАТУННИЙ МЕХАНІЗМ",
    ]
    for word in (
        "КІНЕМАТИКА",
        "ІНДИКАТОРНА ДІАГРАМА",
        "КРУТНИЙ МОМЕНТ",
        "ЗРІВНОВАЖЕННЯ",
        "МАХОВИК",
    ):
        assert word in full, (word, full)
    assert "КІНЕМАТИКА" in alone and "МАХОВИК" not in alone and "ЗРІВНОВАЖЕННЯ" not in alone
    # a mechanism without a working cycle is analysed, not an engine calculated
    assert alone[:2] == ["КІНЕМАТИЧНИЙ АНАЛІЗ", "ТЕОРІЯ МЕХАНІЗМІВ І МАШИН"], alone
    assert "ДИНАМІЧНИЙ РОЗРАХУНОК" not in alone and "ДВИГУН ВНУТРІШНЬОГО ЗГОРЯННЯ" not in alone
    # DSTU 3008: five to fifteen, also for the smallest reports; the vane engine's scheme is drawn by
    # drawing_linkage, which writes with the drawing stage's catalog
    vane = _keywords(shared_html("vane-engine-kinematics", language="uk").linked_html)
    assert "КІНЕМАТИЧНА СХЕМА" in vane, vane
    assert len(alone) >= 5 and len(vane) >= 5, (alone, vane)
    assert 5 <= len(full) <= KEYWORDS_MAX and len(set(full)) == len(full)
    assert all(w == w.upper() for w in full)


def test_key_words_in_every_language_come_from_the_catalogs():
    registry = default_registry()
    stages = ["kinematics", "indicator", "forces", "torque", "balancing", "bearings", "flywheel"]
    for language, general in (("en", "DYNAMIC CALCULATION"), ("ru", "ДИНАМИЧЕСКИЙ РАСЧЁТ")):
        t = translator(language, registry.catalogs)
        words = keywords(t, "crank_slider", stages).split(", ")
        assert words[0] == general and len(words) >= 8, words
        assert not t.missing
    # a stage without key words of its own (a third party's) adds none; a mechanism without a
    # description in the catalog none either
    t = translator("uk", registry.catalogs)
    assert (
        keywords(t, "no_such_mechanism", ["no_such_stage"])
        == "ДИНАМІЧНИЙ РОЗРАХУНОК, ДВИГУН ВНУТРІШНЬОГО ЗГОРЯННЯ"
    )


def test_the_abstract_names_the_balancing_and_the_flywheel():
    """The abstract gives the balancing and the flywheel results."""
    import html as html_lib

    from conftest import as_read, shared_run

    from crankdyn.report.i18n import translator

    rendered = shared_html("inline4-petrol", language="uk").linked_html
    abstract = html_lib.unescape(
        re.sub(
            r"<[^>]+>",
            "",
            as_read(
                re.search(r'<section class="abstract">(.*?)</section>', rendered, flags=re.S).group(
                    1
                )
            ),
        )
    )
    results = shared_run("inline4-petrol").outputs
    t = translator("uk", default_registry().catalogs)
    flywheel = t.number(results["flywheel"].results["flywheel_inertia_kg_m2"], 4)
    assert f"момент інерції маховика {flywheel}\u202fкг·м²" in abstract, abstract
    balancing = results["balancing"].results
    unbalanced = [s["quantity"] for s in balancing["summary"] if not s["balanced"]]
    assert unbalanced == ["sum_PII", "sum_PIV", "sum_PVI"]
    # the example fits Lanchester's shafts (second order): the abstract says what they leave (a
    # supervisor: "C and P_I unbalanced" in the abstract of an engine the section balances)
    assert 2 in balancing["residual"]["balanced_orders"] and balancing["balance_shafts"]
    # and what the conclusions call negligible (ΣP_VI = 4,4 Н, under 1 % of C_I) only as small:
    # the table leaves it, so the abstract may not call the engine balanced without it
    plain = " ".join(abstract.replace("\u202f", " ").replace("\u00a0", " ").split())
    share = 100 * balancing["first_order_shares"]["sum_PVI"]
    assert share < 1
    # one sentence: each residual with its value and its share of C_I, the negligible one last
    found = re.search(
        r"після встановлення засобів зрівноваження з сил інерції та їхніх моментів незрівноваженою "
        r"залишається ΣPIV = ([\d,]+) Н \(([\d,]+) % від CI\), а також ΣPVI = ([\d,]+) Н – "
        r"нехтовно мала величина \(([\d,]+) % від CI\)",
        plain,
    )
    assert found, abstract
    iv, iv_share, vi, vi_share = (float(g.replace(",", ".")) for g in found.groups())
    values = [iv, vi, iv_share, vi_share]
    absolute = balancing["absolute"]
    assert values[0] == pytest.approx(abs(absolute["sum_PIV_N"]), abs=0.5)
    assert values[1] == pytest.approx(abs(absolute["sum_PVI_N"]), rel=0.02)
    shares = balancing["first_order_shares"]
    assert values[2] == pytest.approx(100 * shares["sum_PIV"], rel=0.03)
    assert values[3] == pytest.approx(share, rel=0.03)
    assert "лише малі" not in plain and "залишається величина" not in plain


def test_the_abstract_aim_lists_the_sections_the_note_holds():
    """The aim spoke of gas forces and torques in a note of the kinematics alone: it now lists the
    note's own sections (the input data aside), each title as it heads its section."""
    full = shared_html("inline4-petrol", language="uk").linked_html
    alone = shared_html("kinematics-only", language="uk").linked_html
    for html, present, absent, kind in (
        (full, ("маховик", "аналіз зрівноваженості двигуна"), (), "динамічний розрахунок двигуна"),
        (
            alone,
            ("кінематика кривошипно-шатунного механізму",),
            ("маховик", "сили тиску"),
            "кінематичний аналіз механізму",
        ),
    ):
        aim = re.search(rf"Мета роботи – {kind}: (.*?)\.</p>", html).group(1)
        titles = re.findall(r"<h2>\d+ ([^<]+)</h2>", html)
        assert aim.split("; ") == [t[0].lower() + t[1:] for t in titles[1:]], (aim, titles)
        assert all(p in aim for p in present) and not any(a in aim for a in absent), aim


def test_the_key_words_name_the_kind_of_engine():
    """A radial aircraft engine's key words say so ("ЗВЕЗДООБРАЗНЫЙ ДВИГАТЕЛЬ, АВИАЦИОННЫЙ
    ПОРШНЕВОЙ ДВИГАТЕЛЬ") after the mechanism; an in-line engine's add no layout."""
    import re

    from conftest import shared_html

    def key_words(name, language):
        html = shared_html(name, None, language).linked_html
        abstract = re.search(r'<section class="abstract">(.*?)</section>', html, flags=re.S).group(
            1
        )
        return re.sub(r"<[^>]+>", "", abstract).replace("\u2060", "")  # the joiner of "V-"

    radial = key_words("radial9-aircraft", "ru")
    assert "ЗВЕЗДООБРАЗНЫЙ ДВИГАТЕЛЬ, АВИАЦИОННЫЙ ПОРШНЕВОЙ ДВИГАТЕЛЬ" in radial
    assert "V-ПОДІБНИЙ ДВИГУН" in key_words("v8-petrol", "uk")
    inline = key_words("inline4-petrol", "en")
    assert (
        "RADIAL ENGINE" not in inline
        and " ENGINE, " not in inline.split("INTERNAL COMBUSTION ENGINE")[-1]
    )
