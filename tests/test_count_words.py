"""A count without a unit from one to nine is written in words (ДСТУ 3008, ГОСТ 2.105): a catalog
text's ``{n#form}`` gives the word in the grammatical form its noun asks for, a larger count or
a fraction in digits, and the noun still agrees by the CLDR plural rules."""

from __future__ import annotations

import re

import pytest

from crankdyn.report.i18n import Translator, translator


def test_counts_of_one_to_nine_are_words_in_the_form_asked_for():
    uk, ru, en = translator("uk"), translator("ru"), translator("en")
    assert [uk.count_words(n, "m_nom") for n in (1, 2, 5, 9)] == ["один", "два", "п’ять", "дев’ять"]
    assert [uk.count_words(n, "f_nom") for n in (1, 2)] == ["одна", "дві"]
    assert [uk.count_words(n, "f_acc") for n in (1, 4)] == ["одну", "чотири"]
    assert [uk.count_words(n, "n_loc") for n in (1, 3, 8)] == ["одному", "трьох", "восьми"]
    assert [ru.count_words(n, "n_loc") for n in (1, 3)] == ["одном", "трёх"]
    assert en.count_words(6, "m_nom") == "six"
    assert uk.count_words(4.0, "m_nom") == "чотири"  # a whole number given as a float


@pytest.mark.parametrize("value", [0, 10, 12, 2.5, -3, "—", float("nan")])
def test_other_values_stay_as_written(value):
    assert translator("uk").count_words(value, "m_nom") == str(value)


def test_a_catalog_text_puts_the_word_and_the_agreeing_noun():
    t = Translator(
        "uk",
        {
            "numerals.m_nom": "один|два|три|чотири|п’ять|шість|сім|вісім|дев’ять",
            "intro": "{n#m_nom} {n@циліндр|циліндри|циліндрів|циліндра}, разом {n}",
        },
        {},
    )
    assert t("intro", n=4) == "чотири циліндри, разом 4"
    assert t("intro", n=12) == "12 циліндрів, разом 12"


def test_a_v_engines_layout_is_said_in_words():
    from conftest import shared_html

    text = shared_html("v8-petrol", None, "uk", ("bays",)).linked_html
    assert "вісім циліндрів на чотирьох колінах" in text
    assert "Колінчастий вал прийнято повноопорним: п’ять корінних опор" in text


def test_the_firing_order_explorer_counts_in_words_and_captions_without_a_leading_digit():
    from conftest import EXPLORED_BOXER, shared_html

    html = shared_html("inline4-petrol", EXPLORED_BOXER, "uk", ("balancing",)).linked_html
    text = re.sub(r"<[^>]+>", "", html)
    assert "три схеми колін, шість порядків роботи" in text
    # every order listed: the caption says what the table ranks, not "6 найкращих із 6"
    assert "Порядки роботи і схеми колін, упорядковані за зрівноваженістю" in text
    assert "найкращих із" not in text


def test_an_own_pin_engines_explorer_leaves_out_the_shared_pin_rule():
    """A boxer's cylinders have crank pins of their own: the explorer ranks no order by two
    cylinders firing in turn on one pin (a column of zeros, a rule that cannot apply)."""
    from conftest import EXPLORED_BOXER, shared_html

    html = shared_html("inline4-petrol", EXPLORED_BOXER, "uk", ("balancing",)).linked_html
    assert "Одна шийка" not in html and "на одній шатунній шийці" not in html
    v8 = shared_html(
        "v8-petrol", {"balancing": {"explore": True}}, "uk", ("balancing",)
    ).linked_html
    assert "Одна шийка" in v8 and "двох циліндрів на одній шатунній шийці" in v8


def test_a_variant_key_is_said_for_an_engine_of_that_variant():
    """An aircraft engine's texts: ``<key>_propeller`` where a catalog gives one, in the report's
    language or in English; the plain key elsewhere and for other engines."""
    texts = {"fw.aim": "select the flywheel", "fw.aim_propeller": "account for the propeller"}
    english = {"fw.row": "flywheel", "fw.row_propeller": "propeller"}
    plain = Translator("uk", texts, english)
    aircraft = Translator("uk", texts, english, variant="propeller")
    assert plain("fw.aim") == "select the flywheel" and plain("fw.row") == "flywheel"
    assert aircraft("fw.aim") == "account for the propeller"
    assert aircraft("fw.row") == "propeller"  # only the English catalog has it
    assert aircraft("fw.aim_propeller") == "account for the propeller"  # chosen by hand: kept
    assert aircraft("fw.other") == "fw.other" and "fw.other" in aircraft.missing


def test_a_term_in_a_text_is_said_as_the_engines_variant_words_it():
    """``{=key}`` in a text is that key's text, of the first of the engine's variants a catalog
    gives: a boxer's forces are balanced by the engine's scheme, an in-line engine's by its cranks'."""
    texts = {
        "b.remedy": "зрівноважено схемою {=b.of} ({n@коліно|коліна|колін|коліна})",
        "b.of": "колін",
        "b.of_banked": "двигуна",
        "b.row_propeller": "гвинт",
    }
    inline = Translator("uk", texts, {})
    boxer = Translator("uk", texts, {}, variant=("propeller", "banked"))
    assert inline("b.remedy", n=2) == "зрівноважено схемою колін (коліна)"
    assert boxer("b.remedy", n=5) == "зрівноважено схемою двигуна (колін)"
    assert boxer("b.row") == "гвинт" and boxer("b.of") == "двигуна"
    assert not boxer.missing - {"b.row"}


def test_a_boxer_v_and_radial_are_banked_and_an_in_line_engine_is_not():
    from types import SimpleNamespace

    from crankdyn.report.document import text_variant

    def variants(layout, cylinders=2, application="automotive"):
        engine = SimpleNamespace(layout=layout, cylinders=cylinders, application=application)
        return text_variant(SimpleNamespace(engine=engine))

    assert variants("inline", 6) == () and variants("inline", 1) == ()
    assert variants("boxer") == variants("V", 8) == variants("radial", 9) == ("banked",)
    assert variants("radial", 9, "aircraft") == ("propeller", "banked")
    assert variants("inline", 4, "aircraft") == ("propeller",)
