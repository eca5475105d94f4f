"""Leave out what a scene does not need: which sections appear, in HTML and results.json.

A matrix of scenes — kinematics only, one cylinder, two-stroke, in-line (with and without a flywheel
request), articulated rods, a pressure trace — each with the report sections and results.json keys
that must be there and those that must not. Only the in-line example asks for a flywheel
(its [flywheel] table); in every other scene the flywheel stages must stay out.
"""

from __future__ import annotations

import dataclasses
import re

import pytest
from conftest import shared_run
from markupsafe import escape

from crankdyn.output.writers import results_document
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import UNLISTED_SKIPS, _skip_key, render_html, skipped_reason
from crankdyn.report.i18n import translator

REGISTRY = default_registry()
ENGINE = {"kinematics", "indicator", "forces", "numerics"}
FLYWHEEL = {"flywheel", "speed_fluctuation"}  # only with a [flywheel] table

MATRIX = {
    # name: (example, changes, sections present, sections absent, json present, json absent,
    #        numerics parts present, numerics parts absent)
    "kinematics-only": (
        "kinematics-only",
        {},
        {"kinematics", "numerics_kinematics"},
        {"indicator", "forces", "bays", "torque", "numerics"},
        {"kinematics", "numerics_kinematics"},
        {"indicator", "forces", "bays", "torque", "numerics"},
        {"kinematics-forms"},
        {"steps", "solvers"},
    ),
    "single-cylinder": (
        "petrol-1cyl",
        {},
        ENGINE,
        {"bays", "torque", "numerics_kinematics"},  # bays/torque run for data only
        ENGINE | {"bays", "torque"},
        {"numerics_kinematics"},
        {"steps", "kinematics-forms", "theoretical"},
        {"solvers"},
    ),
    "two-stroke": (
        "two-stroke-1cyl",
        {},
        ENGINE,
        {"bays", "torque", "numerics_kinematics"},
        ENGINE | {"torque"},
        {"numerics_kinematics"},
        {"steps", "kinematics-forms", "theoretical"},
        set(),
    ),
    "in-line-with-flywheel": (
        "inline4-petrol",
        {},
        ENGINE | {"bays", "torque"} | FLYWHEEL,
        {"numerics_kinematics"},
        ENGINE | {"bays", "torque"} | FLYWHEEL,
        {"numerics_kinematics"},
        {"steps", "kinematics-forms", "theoretical"},
        {"refused-steps"},
    ),
    "in-line-no-flywheel-request": (
        "inline4-petrol",
        {"flywheel": None},
        ENGINE | {"bays", "torque"},
        {"numerics_kinematics"} | FLYWHEEL,
        ENGINE | {"bays", "torque"},
        {"numerics_kinematics"} | FLYWHEEL,
        {"steps", "kinematics-forms", "theoretical"},
        {"refused-steps"},
    ),
    "articulated": (
        "radial9-aircraft",
        {},
        ENGINE | {"bays", "torque"},
        {"numerics_kinematics"},
        ENGINE | {"bays", "torque"},
        {"numerics_kinematics"},
        # its numerics study moves every step onto the engine's grid: nothing refused
        {"steps", "kinematics-forms", "theoretical"},
        {"refused-steps"},
    ),
    # A balancing exercise: geometry, masses and layout, no working cycle.
    "balancing-only": (
        "v8-petrol",
        {"cycle": None},
        {"kinematics", "balancing", "numerics_kinematics"},
        {"indicator", "forces", "bays", "torque", "bearings", "numerics"},
        {"kinematics", "balancing", "numerics_kinematics"},
        {"indicator", "forces", "bays", "torque", "bearings", "numerics"},
        {"kinematics-forms"},
        {"steps", "solvers"},
    ),
    "pressure-trace": (
        "diesel-rk-trace",
        {},
        ENGINE,
        {"bays", "torque", "numerics_kinematics"},
        ENGINE,
        {"numerics_kinematics"},
        {"steps", "kinematics-forms"},
        {"theoretical", "refused-steps"},
    ),
}
_CACHE: dict = {}


def absent_sections(name):
    absent = MATRIX[name][3]
    return absent if MATRIX[name][2] & FLYWHEEL else absent | FLYWHEEL


def absent_keys(name):
    absent = MATRIX[name][5]
    return absent if MATRIX[name][4] & FLYWHEEL else absent | FLYWHEEL


def full_detail(result):
    """``result`` as a ``[report] detail = "full"`` scene's (the same run: the detail changes
    only what the report shows): every section and the studies' parts in the body."""
    report = result.scene.report.model_copy(update={"detail": "full"})
    return dataclasses.replace(result, scene=result.scene.model_copy(update={"report": report}))


def build(name):
    if name not in _CACHE:
        example, changes = MATRIX[name][:2]
        result = shared_run(example, changes)  # shared with the other test files (read only)
        html = render_html(full_detail(result), REGISTRY, "en").linked_html
        _CACHE[name] = (result, results_document(result), html)
    return _CACHE[name]


def numbered_sections(html: str) -> list[str]:
    """The stage sections of the report, in order (the fixed closing sections are not numbered by stage)."""
    # numbered chapters, and the stages' appendices (lettered) that detail = "course" moves there
    return re.findall(
        r'<section class="chapter(?: appendix)?" id="sec-(?:\d+|[A-ZА-Я])" data-stage="([^"]+)"',
        html,
    )


def numerics_parts(html: str) -> set[str]:
    parts = set(re.findall(r'data-part="([^"]+)"', html))
    if "<i>L</i><sub>i</sub> (theor.), %" in html:  # the closed-form indicated work's column
        parts.add("theoretical")
    return parts


@pytest.mark.parametrize("name", list(MATRIX))
def test_leave_out_matrix(name):
    """One run per scene (shared by the three checks: separate tests would run it once per xdist
    worker): its sections in the HTML, its keys in results.json, the parts of its numerics section."""
    result, document, html = build(name)
    check_sections_in_html(name, result, html)
    check_keys_in_results_json(name, document)
    check_parts_of_the_numerics_section(name, document, html)


def check_sections_in_html(name, result, html):
    present, absent = MATRIX[name][2], absent_sections(name)
    sections = numbered_sections(html)
    assert len(sections) == len(set(sections)), sections  # each section once
    assert present <= set(sections), (present - set(sections), sections)
    assert not absent & set(sections), sections
    # every stage left out for what the scene lacks is listed with its reason in the method notes;
    # one for another mechanism, or whose content another section gives, is not (results.json has it)
    from crankdyn.report.document import text_variant

    t = translator("en", REGISTRY.catalogs, text_variant(result.scene))  # as the report's
    for stage, reason in result.plan.skipped.items():
        title = t(REGISTRY.stages[stage].presentation.title_key)
        line = escape(t("doc.skipped_stage", stage=title, reason=skipped_reason(t, reason)))
        assert (line in html) == (_skip_key(reason) not in UNLISTED_SKIPS), (stage, reason)
    # the error-against-run-time section follows every section whose numbers it judges
    if "numerics" in sections:
        assert all(
            sections.index(s) < sections.index("numerics")
            for s in ("kinematics", "indicator", "forces", "bays", "torque")
            if s in sections
        )


def check_keys_in_results_json(name, document):
    present, absent = MATRIX[name][4], absent_keys(name)
    assert present <= set(document), present - set(document)
    assert not absent & set(document)
    assert set(document["stages_run"]) | set(document["stages_skipped"]) == set(REGISTRY.stages)
    for stage in absent & set(REGISTRY.stages):
        assert stage in document["stages_skipped"] and document["stages_skipped"][stage]


def check_parts_of_the_numerics_section(name, document, html):
    parts_present, parts_absent = MATRIX[name][6], MATRIX[name][7]
    parts = numerics_parts(html)
    assert parts_present <= parts, parts_present - parts
    assert not parts_absent & parts, parts & parts_absent
    numerics = document.get("numerics") or document.get("numerics_kinematics")
    assert ("steps" in numerics) == ("steps" in parts_present)
    assert ("solvers" in numerics) == ("solvers" in parts)
    if "steps" in numerics:
        has_theory = any("theoretical_work_error_relative" in s for s in numerics["steps"])
        assert has_theory == ("theoretical" in parts_present)
        assert bool(numerics["steps_refused"]) == ("refused-steps" in parts_present)


def test_balancing_needs_no_cycle():
    """Without [cycle] the balancing section is the full one (the same numbers as with the cycle, which
    computes them through the bay loads), only the torque reaction is left out, and every stage left out
    names what it lacks."""
    result, document, html = build("balancing-only")
    skipped = document["stages_skipped"]
    assert "[cycle]" in skipped["indicator"]
    for stage in ("forces", "bays", "torque", "bearings"):
        assert "gas_pressure" in skipped[stage] and "[cycle]" in skipped[stage], (
            stage,
            skipped[stage],
        )
    assert "[cycle]" in skipped["numerics"] and "[masses]" not in skipped["numerics"]
    with_cycle = shared_run("v8-petrol")
    full = with_cycle.outputs["balancing"].results
    alone = result.outputs["balancing"].results
    assert full["reaction_torque_range_Nm"] > 0 and alone["reaction_torque_range_Nm"] is None
    assert set(alone) == set(full)
    for key in ("rotating_mass_kg", "reciprocating_mass_kg", "centrifugal_N", "first_order_N"):
        assert alone[key] == pytest.approx(full[key], rel=1e-13)
    assert alone["summary"] == full["summary"] and alone["absolute"] == pytest.approx(
        full["absolute"], rel=1e-12
    )
    assert [c["mass_kg"] for c in alone["counterweights"]] == pytest.approx(
        [c["mass_kg"] for c in full["counterweights"]], rel=1e-12
    )
    assert ("balancing.note_no_torque", {}) in result.outputs["balancing"].notes
    assert "no indicated torque" in html


def course_html(name: str) -> str:
    """The course note (``detail = "course"``, the default) of a matrix scene, in English."""
    result = build(name)[0]
    report = result.scene.report.model_copy(update={"detail": "course"})
    course = dataclasses.replace(result, scene=result.scene.model_copy(update={"report": report}))
    return render_html(course, REGISTRY, "en").linked_html


def test_a_course_note_says_in_one_sentence_what_the_assignment_gives_no_data_for():
    """A course note names the calculations left out for want of data in one sentence, titles in
    it and each reason once, not as a list of sections; a mechanism studied for its kinematics
    (no working cycle) says nothing of flywheels or forces left out."""
    result = build("single-cylinder")[0]
    html = course_html("single-cylinder")
    t = translator("en", REGISTRY.catalogs)
    assert t("report.skipped_intro") not in html and '<ul class="skipped' not in html
    left_out = {
        stage: skipped_reason(t, reason)
        for stage, reason in result.plan.skipped.items()
        if _skip_key(reason) not in (*UNLISTED_SKIPS, "skip.not_applicable")
    }
    assert {"flywheel", "speed_fluctuation"} <= set(left_out), left_out
    sentence = re.search(r'<p class="skipped">(.*?)</p>', html).group(1)
    # with the tasks the introduction lists, where a reader looks for what the note does
    introduction = html[html.index('id="sec-introduction"') :]
    introduction = introduction[: introduction.index("</section>")]
    assert '<p class="skipped">' in introduction
    first = t(REGISTRY.stages[next(iter(left_out))].presentation.title_key)
    assert sentence.startswith(first) and " are not calculated in this note: " in sentence
    for stage, reason in left_out.items():
        title = t(REGISTRY.stages[stage].presentation.title_key)
        assert title[1:] in sentence and sentence.count(str(escape(reason))) == 1, (stage, reason)
    # what the note takes instead of the rod's dynamics, not only what it lacks
    assert "rod_dynamics" in left_out
    assert "the rod is taken as two masses at the axes of its eyes" in sentence
    assert '<p class="skipped">' not in course_html("kinematics-only")
