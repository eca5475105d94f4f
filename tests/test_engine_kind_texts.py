"""A note says what holds for its engine's kind: a two-stroke's gas exchange is the scavenging near
BDC (no pumping strokes, no intake and exhaust lines), a single crank has no running torque, an
articulated-rod radial's rods are not all central; its letters mean one thing each; its numbers
are printed to the digits the data justify and one value is printed alike wherever it appears."""

from __future__ import annotations

import re

import pytest
from conftest import as_read, shared_html

#: A two-stroke's gas exchange, per language.
SCAVENGING = {"en": "scavenging", "uk": "продування", "ru": "продувк"}
PUMPING_ALREADY = {
    "en": "of which the pumping strokes make",
    "uk": "з неї насосні ходи дають",
    "ru": "из неё насосные ходы дают",
}


def _text(html: str) -> str:
    body = html.split("<body", 1)[1]
    body = re.sub(r"<(script|style|svg)\b.*?</\1>", " ", body, flags=re.S)
    return " ".join(as_read(re.sub(r"<[^>]+>", " ", body)).split())


@pytest.mark.parametrize("language", ["en", "uk", "ru"])
def test_a_two_strokes_mechanical_losses_are_its_scavenging_not_pumping_strokes(language):
    two = _text(
        shared_html(
            "two-stroke-1cyl", {"engine": {"effective_power": "5 kW"}}, language
        ).linked_html
    )
    four = _text(shared_html("petrol-1cyl-uk", None, language).linked_html)
    effective = re.search(r"N\s*e\s*= 5 \S+, .{0,300}", two).group(0)
    assert PUMPING_ALREADY[language] not in effective, effective
    assert SCAVENGING[language] in effective, effective
    assert PUMPING_ALREADY[language] in four


@pytest.mark.parametrize(
    "two_stroke, title",
    [(True, "продування поблизу НМТ (збільшено)"), (False, "впуск і випуск (збільшено)")],
)
def test_the_low_pressure_inset_of_a_two_stroke_shows_its_scavenging(two_stroke, title):
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    from crankdyn.plugins import default_registry
    from crankdyn.report.i18n import translator
    from crankdyn_builtin.indicator.figures import _pv_figure

    volume = np.linspace(0.05, 0.5, 50)
    pressure = 0.1 + 4.0 * (0.05 / volume) ** 1.3
    t = translator("uk", default_registry().catalogs)
    fig = _pv_figure(volume, pressure, pressure * 0.98, [], t, two_stroke=two_stroke)
    titles = [ax.get_title() for ax in fig.axes[0].child_axes]
    assert titles == [title]


def _legend_texts(rendered, key: str) -> list[str]:
    figure = next(f for f in rendered.figures if f.key == key).figure
    return [
        text.get_text()
        for ax in figure.axes
        if ax.get_legend()
        for text in ax.get_legend().get_texts()
    ]


@pytest.mark.parametrize(
    "detail, expected, absent",
    [("course", "енергетичний метод", "RK45"), ("full", "RK45", "чисельне інтегрування")],
)
def test_a_course_notes_speed_figure_names_no_solver(detail, expected, absent):
    """A course note names no solver: its speed figure has no solver's curve (nor a nameless
    "numerical integration" one); a full note's names the solver."""
    legend = " | ".join(
        _legend_texts(shared_html("inline4-petrol", {"report": {"detail": detail}}, "uk"), "speed")
    )
    assert expected in legend and absent not in legend, legend
    assert "чисельне інтегрування" not in legend


def _symbol_rows(html: str) -> list[str]:
    return re.findall(r'<p class="symbol-row"><span class="symbol">(.*?)</span> – ', html)


def test_the_torque_non_uniformity_is_a_formula_and_listed_among_the_symbols():
    html = shared_html("v8-petrol", None, "ru").linked_html
    assert "<i>μ</i>" in _symbol_rows(html)
    assert re.search(
        r"<i>μ</i> = \(<i>M</i><sub>max</sub> − <i>M</i><sub>min</sub>\)/"
        r"<i>M</i><sub>ср</sub>\s=\s\d",
        html,
    )


def test_the_ignition_delay_time_is_not_the_number_of_strokes():
    html = shared_html("diesel-1cyl", None, "uk").linked_html
    rows = _symbol_rows(html)
    assert "<i>τ</i>" in rows and "<i>τ</i><sub>з</sub>" in rows, rows
    # the example gives τ_з: "6·n·τ_з = 6·…·0,0012 = …° [1, …] за заданого τ_з = 1,2 мс"
    assert re.search(
        r"6·<i>n</i>·<i>τ</i><sub>з</sub>\s=\s6·[\d\s\u202f]+·0,0012\s=\s[\d,]+° "
        r"[^<]* за заданого <i>τ</i><sub>з</sub>\s=\s\d",
        html,
    )
    assert not re.search(r"<i>τ</i>\s=\s\d", html)


def test_the_number_of_cylinders_takes_no_letter_of_the_running_index():
    html = shared_html("v8-petrol", None, "uk").linked_html
    row = re.search(r"<tr[^>]*><td[^>]*>Кількість циліндрів</td>(.*?)</tr>", html).group(1)
    assert "<i>i</i>" not in row, row


def test_the_counterweights_force_is_listed_among_the_symbols():
    """A 270° twin's cranks leave a centrifugal resultant, which its counterweights' forces add
    up to with F."""
    from conftest import TWIN_270_ENGINE

    html = shared_html("inline3-petrol", {"engine": TWIN_270_ENGINE}, "uk").linked_html
    assert re.search(r"<i>Q</i> = <i>F</i> \+ Σ<i>C</i>", html)
    assert "<i>Q</i>" in _symbol_rows(html)


@pytest.mark.parametrize(
    "language, word, central",
    [
        ("uk", "ГОЛОВНИМ І ПРИЧІПНИМИ ШАТУНАМИ", "ЦЕНТРАЛЬНИЙ КРИВОШИПНО-ШАТУННИЙ"),
        ("ru", "ГЛАВНЫМ И ПРИЦЕПНЫМИ ШАТУНАМИ", "ЦЕНТРАЛЬНЫЙ КРИВОШИПНО-ШАТУННЫЙ"),
    ],
)
def test_an_articulated_rod_radial_is_not_called_a_central_crank_slider(language, word, central):
    radial = _text(shared_html("radial9-aircraft", None, language).linked_html)
    inline = _text(shared_html("inline4-petrol", None, language).linked_html)
    assert word in radial and central not in radial
    assert central in inline and word not in inline
    assert "проходить через вісь колінчастого вала" not in radial.replace("осі циліндрів", "")


def _pin_area_needed_mm2(changes) -> float:
    """d·B at which the most loaded pin's mean and largest pressures are allowable, from the run's
    loads and the petrol engines' 12 and 20 MPa."""
    from conftest import shared_run

    pins = shared_run("radial9-aircraft", changes).outputs["bearings"].results["crank_pins"]
    return max(max(p["mean_N"] for p in pins) / 12.0, max(p["max_N"] for p in pins) / 20.0)


@pytest.mark.parametrize(
    "changes, assumed",
    [
        (None, True),
        ({"bearings": {"crank_pin_diameter": "60 mm", "crank_pin_width": "30 mm"}}, False),
    ],
)
def test_a_too_small_crank_pin_is_given_the_size_it_needs(changes, assumed):
    text = _text(shared_html("radial9-aircraft", changes, "uk").linked_html)
    needed = _pin_area_needed_mm2(changes)
    sentences = re.findall(r"d · B ≥ (\d+) мм²", text)  # as printed: three significant digits
    assert len(sentences) == 2, sentences  # the section's and the conclusion's
    assert all(abs(int(v) - needed) <= 0.005 * needed for v in sentences), (sentences, needed)
    assert ("ґрунтується на прийнятих розмірах" in text) is assumed
    assert ("прийнятих за типовими співвідношеннями" in text) is assumed


def test_a_range_whose_ends_print_alike_is_said_as_one_value():
    import sys

    sys.path.insert(0, str(__import__("pathlib").Path(__file__).parent))
    from test_scene_corpus import check_ranges

    # a flywheel so heavy that the mechanism's own variable inertia changes no printed digit
    heavy = {"flywheel": {"required_irregularity": 0.00003, "rim_mean_diameter": "500 mm"}}
    html = shared_html("inline4-petrol", heavy, "uk").linked_html
    note = type("Note", (), {"text": _text(html)})()
    assert not check_ranges(note), check_ranges(note)
    assert re.search(r"<i>J</i>\s≈\s\d", html)


def test_assumed_journal_sizes_are_printed_to_a_tenth_of_a_millimetre():
    html = shared_html("radial9-aircraft", None, "uk").linked_html
    text = _text(html)
    sizes = re.search(r"Розміри шийок: (.*?)\. У завданні", text).group(1)
    values = re.findall(r"= (\d+(?:,\d+)?) мм", sizes)
    assert len(values) == 4 and all(len(v.partition(",")[2]) <= 1 for v in values), sizes
    # the worked substitution takes the sizes as printed
    assert re.search(rf"\({values[0]}·10\s*−\s*3\s*·\s*{values[1]}·10", text), values


def test_a_diesels_ignition_delay_time_is_among_the_given_data():
    """The indicator section uses τ_з = 1,2 мс (6·n·τ_з); table 1.1 gives it."""
    import re

    from conftest import shared_html

    page = shared_html("diesel-1cyl", language="uk").linked_html
    row = next(
        r for r in re.findall(r"<tr[^>]*>.*?</tr>", page, flags=re.S) if "затримки займання" in r
    )
    cells = [re.sub(r"<[^>]+>", "", c) for c in re.findall(r"<td[^>]*>(.*?)</td>", row)]
    assert cells[0] == "Період затримки займання" and cells[1] == "τз", cells
    assert cells[2] == "1,2" and cells[3] == "мс", cells


def test_a_two_strokes_scavenging_names_its_transfer_ports_and_the_crankcase_assumption():
    """The exhaust ports' interval is not itself the scavenging: the transfer ports open and close
    within it; and a constant crankcase pressure is an assumption a crankcase-scavenged engine
    departs from, which the note says (a four-stroke's note keeps its one sentence)."""
    two = _text(shared_html("two-stroke-1cyl", None, "uk").linked_html)
    four = _text(shared_html("petrol-1cyl-uk", None, "uk").linked_html)
    assert "відкриваються й закриваються продувні вікна" in two
    assert "поки вони відкриті, циліндр продувається" not in two
    assert "Тиск у картері прийнято сталим" in two and "кривошипно-камерним продуванням" in two
    assert "кривошипно-камерним продуванням" not in four
    assert "сталий тиск p 0 роботи за цикл не виконує" in four


@pytest.mark.parametrize("language, tangent", [("en", "tan"), ("uk", "tg"), ("ru", "tg")])
def test_the_tangent_is_written_as_the_language_writes_it(language, tangent):
    """The side force N = p₁ tan β in English, N = p₁ tg β in Ukrainian and Russian."""
    text = _text(shared_html("petrol-1cyl", None, language).linked_html)
    assert f"N = p 1 {tangent} β" in text
    other = "tg" if tangent == "tan" else "tan"
    assert f"N = p 1 {other} β" not in text


def test_an_english_note_writes_angles_with_the_degree_sign():
    """ "intervals between firings: 405° and 315°", not "… 315 deg": the English note's angles carry the
    sign the Ukrainian and Russian ones do."""
    from conftest import V_TWIN_ENGINE

    text = _text(shared_html("v8-petrol", {"engine": V_TWIN_ENGINE}, "en").linked_html)
    assert not re.search(r"\d deg\b", text)
    assert "405° and 315°" in text


def test_the_english_negligible_orders_read_as_a_sentence():
    """ "Besides them, the unbalanced force of the sixth order (…)", not "the unbalanced the force
    of the sixth order"."""
    text = _text(shared_html("inline4-petrol", None, "en").linked_html)
    assert (
        "Besides them, the unbalanced force of the sixth order" in text
    )  # the one force: singular
    assert "unbalanced the " not in text


def test_a_boosted_engines_mechanical_efficiency_names_the_pumping_gain():
    """p_a > p_r: the pumping strokes gain work (N_p > 0), which the indicated power includes and
    the thermal calculation's leaves out; the note does not call them mechanical losses there, as
    it does for a naturally aspirated engine (N_p < 0)."""
    import re

    from conftest import shared_html

    boosted = {
        "cycle": {"intake_pressure": "0.19 MPa", "exhaust_pressure": "0.16 MPa"},
        "engine": {"effective_power": "60 kW"},
    }
    page = shared_html("inline4-petrol", boosted, "en", ("torque",)).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", page)).replace("&#39;", "'")
    assert re.search(
        r"of which the pumping strokes make N ?p = \d+\.\d+ kW \(the boosted engine's gain", text
    ), text
    plain = {"engine": {"effective_power": "60 kW"}}
    page = shared_html("inline4-petrol", plain, "en", ("torque",)).linked_html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", page))
    assert re.search(
        r"of which the pumping strokes make N ?p = −\d\.\d+ kW \(the thermal calculation counts them"
        r" among the mechanical losses",
        text,
    ), text


def test_a_twin_on_one_crank_lists_its_intervals_and_counterweights_as_prose():
    """ "450° і 270°", not "450; 270°"; "противаги на щоках коліна", not "коліна 1" when there
    is one crank."""
    from conftest import V_TWIN_ENGINE

    text = _text(shared_html("v8-petrol", {"engine": V_TWIN_ENGINE}, "uk").linked_html)
    assert "інтервали між спалахами: 405° і 315°." in text
    assert "становлять 405° і 315° замість рівних 360°" in text
    assert "на щоках коліна 1" not in text
    assert "дві противаги на щоках коліна і один зрівноважувальний вал" in text


@pytest.mark.parametrize("example", ["v8-petrol", "inline3-petrol"])
def test_counterweights_of_a_force_balanced_shaft_are_said_to_form_a_couple(example):
    """Cranks whose centrifugal and first-order resultants are zero (a cross-plane V8, an in-line
    three): the counterweights' forces add up to zero and form a couple, not "Q = F + ΣC"."""
    text = _text(shared_html(example, None, "en").linked_html)
    assert "forces add up to zero too and form a couple that cancels the moments" in text
    assert "add up to Q = F + ΣC" not in text


def test_a_single_cylinders_counterweights_still_add_up_to_f_plus_c():
    """One crank: its counterweight balances the co-rotating first-order half and C."""
    text = _text(shared_html("petrol-1cyl", None, "en").linked_html)
    assert "inertia force Q = F + C, F being that half of the first-order force" in text
    assert "form a couple that cancels" not in text


@pytest.mark.parametrize(
    ("example", "said"),
    [
        ("petrol-1cyl-uk", "вісь циліндра проходить через вісь колінчастого вала"),
        ("inline4-petrol", "the cylinder axes pass through the crankshaft axis"),
    ],
)
def test_the_mechanism_is_described_with_as_many_cylinder_axes_as_there_are(example, said):
    assert said in _text(shared_html(example).linked_html)


@pytest.mark.parametrize(("stages", "fitted"), [(None, True), (("torque",), False)])
def test_the_crank_load_conclusion_says_it_leaves_out_the_counterweights(stages, fitted):
    """The torque section's crank loads are the cranks' own: where the balancing fits
    counterweights (a V8's), the conclusion says they are not in it; without the balancing
    there are none to leave out."""
    text = _text(shared_html("v8-petrol", None, "en", stages).linked_html)
    assert ("without the crankshaft's counterweights" in text.replace("&#39;", "'")) is fitted
    assert "The largest specific resultant load on the crank from all its cylinders" in text


@pytest.mark.parametrize(
    ("example", "language", "said"),
    [
        ("inline4-petrol", "en", "The cylinders fire every 180°."),
        ("v8-petrol", "uk", "Інтервал між спалахами – 90°."),
        ("inline3-petrol", "ru", "Интервал между вспышками – 240°."),
    ],
)
def test_an_even_firing_engine_names_its_one_interval(example, language, said):
    assert said in _text(shared_html(example, None, language).linked_html)


def test_a_singles_abstract_names_the_couple_its_side_balance_shaft_leaves():
    """The balance shaft beside a single's crankshaft balances its force but leaves a couple: the
    abstract, which lists what stays unbalanced, names it as the balancing section does."""
    run_text = _text(shared_html("two-stroke-1cyl", None, "en").linked_html)
    said = "the balance shaft beside the crankshaft leaves a first-order couple of"
    assert said in run_text
    assert run_text.index(said) < run_text.index("The counter-rotating shaft lies beside")


@pytest.mark.parametrize(("stages", "fitted"), [(None, True), (("forces",), False)])
def test_a_singles_crank_load_conclusion_says_it_leaves_out_the_counterweights(stages, fitted):
    """A single's largest crank load q is the crank's own: with the balancing's counterweights
    fitted the conclusion says they are not in it."""
    text = _text(shared_html("petrol-1cyl", None, "en", stages).linked_html)
    assert "The largest specific resultant load on the crank" in text
    assert ("rotating masses, without the counterweights;" in text) is fitted
