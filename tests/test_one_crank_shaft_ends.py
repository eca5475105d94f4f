"""The shaft's ends as a one-crank engine's note names them, and its torque check at one angle.

"The free end" is the in-line engine's name for the end opposite the power take-off. An engine of
one crank (a radial, a V-twin on one pin) names its ends by what is there: an aircraft engine's
rear end, opposite the propeller; another engine's end opposite the power take-off. An in-line
engine of several cranks keeps the free end.

The torque check of a radial lists every cylinder's part of the crank's t_Σ, each cylinder at its
own cycle angle; the parts, as printed, sum to the printed t_Σ (to their rounding), and t_Σ is the
row of the torque table at that angle.
"""

from __future__ import annotations

import functools
import re
from html import unescape

import pytest
from test_one_crank_texts import RADIAL, V_TWIN

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.scene.model import load_scene, scene_from_dict

REGISTRY = default_registry()
STAGES = ["balancing", "bearings", "torque"]
FREE_END = {"uk": "вільного кінця", "ru": "свободного конца", "en": "free end"}


@functools.cache
def _text(name: str, language: str) -> str:
    if name in ("radial", "vtwin"):
        data = {"radial": RADIAL, "vtwin": V_TWIN}[name]
        data = {**data, "report": {**data["report"], "language": language}}
        run = run_scene(scene_from_dict(data, base_dir=examples_dir()), REGISTRY, STAGES)
    else:
        scene = load_scene(examples_dir() / f"{name}.toml")
        run = run_scene(scene, REGISTRY, STAGES)
    html = render_html(run, REGISTRY, language).linked_html
    text = re.sub(r"<[^>]+>", "", html)
    return " ".join(text.replace("\xa0", " ").replace("\u2060", "").split())


@pytest.mark.parametrize("language", ["uk", "ru", "en"])
@pytest.mark.parametrize(
    ("name", "ends"),
    [
        (
            "radial",
            {
                "uk": ("заднього кінця вала", "повітряного гвинта"),
                "ru": ("заднего конца вала", "воздушного винта"),
                "en": ("rear", "propeller end"),
            },
        ),
        (
            "vtwin",
            {
                "uk": ("протилежного відбору потужності", "з протилежного кінця вала"),
                "ru": ("противоположного отбору мощности", "с противоположного конца вала"),
                "en": ("opposite the power take-off", "at the opposite end of the shaft"),
            },
        ),
    ],
)
def test_a_one_crank_engine_names_its_shaft_ends_by_what_is_there(name, ends, language):
    text = _text(name, language)
    assert FREE_END[language] not in text.lower()
    for words in ends[language]:
        assert words in text, words


def test_an_inline_engine_of_several_cranks_keeps_the_free_end():
    assert FREE_END["en"] in _text("inline4-petrol", "en")


@pytest.mark.parametrize(
    ("language", "each_pin", "one_pin"),
    [
        ("ru", "на каждой шатунной шейке", "на шатунной шейке"),
        ("uk", "на кожній шатунній шийці", "на шатунній шийці"),
        ("en", "on each crank pin", "on the crank pin"),
    ],
)
def test_the_radials_torque_check_sums_its_cylinders_parts(language, each_pin, one_pin):
    text = _text("radial", language)
    assert each_pin not in text and one_pin in text
    # (a long line breaks after "=" or "+", which the break repeats on the next line)
    line = re.search(r"tΣ = ((?:t\w+ \+ )+t\w+) =+ ?(.*?) = (−?\d+[,.]\d+) ", text)
    assert line, "no sum over the cylinders"
    names = line.group(1).split(" + ")
    assert len(names) == 5  # the master and four slaves

    def number(s: str) -> float:
        return float(s.strip("() ").replace(",", ".").replace("−", "-"))

    terms = [number(s) for s in re.split(r" ?\+\+? ", line.group(2))]
    assert len(terms) == 5
    total = number(line.group(3))
    assert abs(sum(terms) - total) <= 5 * 0.5e-4 + 0.5e-3
    # the slaves' parts matter: the master's part alone is not the total
    assert abs(terms[0] - total) > 0.01


@pytest.mark.parametrize(
    ("language", "of_crank_i"), [("uk", "i-го коліна"), ("ru", "i-го колена"), ("en", "crank i's")]
)
def test_one_cranks_journal_loads_are_written_for_that_crank(language, of_crank_i):
    """R_0–1 = −(l″_1/l_1) F_1 and R_1–2 = −(l′_1/l_1) F_1: no crank i + 1, no list of crank i's
    spans; an in-line engine of several cranks keeps the general formula."""
    text = _text("radial", language)
    assert "R0–1 = −(l″1/l1) F1" in text and "R1–2 = −(l′1/l1) F1" in text
    assert of_crank_i not in text
    assert "Fi+1" not in text
    if language == "en":
        assert "Fi+1" in _text("inline4-petrol", "en")


@pytest.mark.parametrize(
    ("name", "language", "seen_from"),
    [
        ("radial", "uk", "вигляд із заднього кінця вала, протилежного повітряному гвинту"),
    ],
)
def test_a_one_crank_schemes_caption_names_the_end_it_is_seen_from(name, language, seen_from):
    data = {"radial": RADIAL, "vtwin": V_TWIN}[name]
    data = {**data, "report": {**data["report"], "language": language}}
    run = run_scene(scene_from_dict(data, base_dir=examples_dir()), REGISTRY, ["drawing"])
    html = render_html(run, REGISTRY, language).linked_html
    text = " ".join(unescape(re.sub(r"<[^>]+>", "", html)).split())
    assert seen_from in text
    assert FREE_END[language] not in text.lower()
