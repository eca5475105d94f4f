"""Worked substitutions: every stage's worked result equals its table row.

For each worked step the report shows, three checks, in uk, ru and en:
* the result as printed is a cell of the row it names (the row at the worked angle of the table the
  intro cites, or a row of the stage's table of results);
* the formula re-evaluated here, independently, from the numbers as substituted (as printed) gives
  the result to the precision of those numbers;
* the same formula from the unrounded inputs gives the stage's own float to 1e-12.

The sections are rendered without their figures (tested elsewhere); the whole typeset report, at
an angle the scene chooses, is checked the same way in tests/test_note.py.
"""

from __future__ import annotations

import functools
import math
import re

import pytest
from conftest import as_read, formula_as_read
from markupsafe import Markup

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.registry import default_registry
from crankdyn.report.context import RenderContext
from crankdyn.report.document import _environment
from crankdyn.report.i18n import translator
from crankdyn.scene.model import load_scene

REGISTRY = default_registry()


def _polytrope(x):
    return x["p0"] * (x["V_a"] / x["V"]) ** x["n"]


def _rad(x, key):
    return math.radians(x[key])


def _chi(x):
    """χ = √(1 − λ² sin² α) of the vane mechanism."""
    return math.sqrt(1 - x["lambda"] ** 2 * math.sin(_rad(x, "alpha_deg")) ** 2)


def _offset_displacement(x):
    return (
        math.sqrt((x["L_mm"] + x["R_mm"]) ** 2 - x["e_mm"] ** 2)
        - x["R_mm"] * math.cos(_rad(x, "phi_deg"))
        - x["L_mm"] * math.cos(_rad(x, "beta_deg"))
    )


def _planet_theta(x):
    return math.radians(x["psi0_deg"] + x["k"] * x["phi_deg"])


#: quantity -> the formula a supervisor would type into a calculator, over the substituted numbers
FORMULAS = {
    "polytrope_pressure": _polytrope,
    "journal_torque_sum": lambda x: math.fsum(v for k, v in x.items() if re.fullmatch(r"t\d+", k)),
    "output_torque": lambda x: x["t_k"] * 1e6 * x["R"] * x["F_p"],
    "crank_torque": lambda x: x["t_k"] * 1e6 * x["R"] * x["F_p"],
    "speed_irregularity": lambda x: x["omega_range"] / x["omega_mid"],
    "centrifugal_amplitude": lambda x: x["m_R"] * x["R"] * x["omega"] ** 2,
    "first_order_amplitude": lambda x: x["m_s"] * x["R"] * x["omega"] ** 2,
    "second_order_amplitude": lambda x: x["lambda"] * x["C_I"],
    "required_total_inertia": lambda x: x["dL"] / (x["delta_req"] * x["omega"] ** 2),
    "required_flywheel_inertia": lambda x: x["J_0"] - x["J_m"] - x["J_e"],
    "irregularity": lambda x: x["dL"] / (x["J"] * x["omega"] ** 2),
    "pin_pressure_max": lambda x: x["Q"] * 1e3 / (x["d_mm"] * x["B_mm"]),
    "journal_pressure_max": lambda x: x["Q"] * 1e3 / (x["d_mm"] * x["B_mm"]),
    "rod_cm_acceleration_x": lambda x: (
        x["arm_mm"]
        * 1e-3
        * (
            x["epsilon_r"] * math.cos(math.radians(x["beta_deg"]))
            - x["omega_r"] ** 2 * math.sin(math.radians(x["beta_deg"]))
        )
    ),
    "rod_inertia_couple": lambda x: -x["I_G"] * x["epsilon_r"],
    "offset_rod_angle": lambda x: math.degrees(
        math.asin(x["lambda"] * math.sin(_rad(x, "phi_deg")) - x["k"])
    ),
    "offset_piston_displacement": _offset_displacement,
    "offset_piston_velocity": lambda x: (
        x["R_mm"]
        * 1e-3
        * x["omega"]
        * math.sin(_rad(x, "phi_deg") + _rad(x, "beta_deg"))
        / math.cos(_rad(x, "beta_deg"))
    ),
    "offset_rod_angular_velocity": lambda x: (
        x["omega"] * x["lambda"] * math.cos(_rad(x, "phi_deg")) / math.cos(_rad(x, "beta_deg"))
    ),
    "planetary_big_end_x": lambda x: (
        x["a_mm"] * math.sin(_rad(x, "phi_deg")) + x["e_mm"] * math.sin(_planet_theta(x))
    ),
    "planetary_big_end_z": lambda x: (
        x["a_mm"] * math.cos(_rad(x, "phi_deg")) + x["e_mm"] * math.cos(_planet_theta(x))
    ),
    "planetary_rod_angle": lambda x: math.degrees(math.asin(x["x_B"] / x["L_mm"])),
    "vane_core_angle": lambda x: (
        -math.degrees(math.asin(x["lambda"] * math.sin(_rad(x, "alpha_deg"))))
    ),
    "vane_core_angular_velocity": lambda x: (
        -x["lambda"] * x["omega"] * math.cos(_rad(x, "alpha_deg")) / _chi(x)
    ),
    "vane_slider_height": lambda x: x["l_mm"] * _chi(x),
    "vane_slider_velocity": lambda x: (
        -x["omega"]
        * x["r_mm"]
        * 1e-3
        * x["lambda"]
        * math.sin(_rad(x, "alpha_deg"))
        * math.cos(_rad(x, "alpha_deg"))
        / _chi(x)
    ),
}


def _no_figure(
    fig, caption: str, name: str, see: str | None = None, see_params: dict | None = None
) -> Markup:
    if callable(fig):  # the function that would build it: nothing to release
        return Markup("")
    import matplotlib.pyplot as plt  # lazy: heavy optional import

    plt.close(fig)
    return Markup("")


@functools.cache
def _stages_run(example: str, stages: tuple[str, ...]):
    return run_scene(load_scene(examples_dir() / f"{example}.toml"), REGISTRY, list(stages))


def _sections(example: str, stages: tuple[str, ...], language: str):
    """Only the stages' own sections (the whole report: the in-line 4 test): HTML and worked blocks."""
    result = _stages_run(example, stages)
    t = translator(language, REGISTRY.catalogs)
    ctx = RenderContext(
        t=t,
        env=_environment(REGISTRY, result),
        table_step_deg=result.scene.analysis.table_step_deg,
        cycle_deg=result.scene.engine.cycle_deg,
        scene=result.scene,
    )
    ctx.figure = (
        _no_figure  # the figures are tested elsewhere; here only tables and worked lines count
    )
    html = []
    for number, stage in enumerate(stages, start=2):
        ctx.start_section(number, stage)
        html.append(
            next(s for s in result.plan.order if s.name == stage).presentation.render(
                result.outputs[stage], ctx
            )
        )
    assert not t.missing, t.missing
    return "".join(html), ctx.worked


def _table_rows(html: str, number: str) -> list[list[str]]:
    """Every row of table ``number`` (all its continued parts), as lists of cell texts."""
    block = re.search(
        rf'<table class="[^"]*" data-number="{re.escape(number)}">(.*?)</div>', html, flags=re.S
    )
    assert block, number
    return [
        re.findall(r"<td(?:\s[^>]*)?>(.*?)</td>", row)
        for row in re.findall(r"<tr(?:\s[^>]*)?>(.*?)</tr>", block.group(1), flags=re.S)
    ]


def worked_html(html: str, block) -> str:
    """The markup of ``block`` in the report."""
    blocks = re.findall(r'<div class="worked">.*?</div>', html, flags=re.S)
    from crankdyn.report.worked import groups_unbroken

    # the line as printed: its short bracketed groups held together (groups_unbroken)
    mine = [
        b
        for b in blocks
        if all(
            # (the word joiner after a slash and the no-break spaces that bind a short line read away)
            _as_text(f"= {groups_unbroken(s.substituted_html)} =") in _as_text(formula_as_read(b))
            for s in block.steps
        )
    ]
    assert len(mine) == 1, block.stage
    return mine[0]


def _as_text(html: str) -> str:
    """``html`` without the binders of a line: word joiners and no-break spaces."""
    return html.replace("\u2060", "").replace("\u00a0", " ")


def _shows(cell: str, text: str) -> bool:
    """The cell is the number ``text``, alone or followed by its unit ("17 235 Н", not "17 2350")."""
    return cell == text or (
        cell.startswith(text)
        and cell[len(text)] in "\u202f\u00a0 "
        and not cell[len(text) + 1 :][:1].isdigit()
    )


def _tolerance(step) -> float:
    """What rounding the substituted numbers (4–5 significant digits) can move the result by."""
    terms = sum(1 for k in step.inputs if re.fullmatch(r"t\d+", k))
    printed = 10.0**-step.decimals if step.significant is None else 0.0
    return 2e-3 * abs(step.value) + (terms + 1) * 0.5 * printed


def check_worked(html: str, worked, language: str) -> set[str]:
    """All three checks for every worked step of a rendered report; the stages checked."""
    t = translator(language, REGISTRY.catalogs)
    checked = set()
    for block in worked:
        if (
            not block.table_number
        ):  # results the text states: each stated outside the worked block too
            outside = html.replace(worked_html(html, block), "")
            for step in block.steps:
                assert re.search(rf"= {re.escape(step.result_text(t))}\b", outside), step.quantity
            rows = []
        else:
            rows = _table_rows(html, block.table_number)
        if block.angle_deg is not None:
            rows = [r for r in rows if r and r[0] == t.fixed(block.angle_deg, 0)]
            assert len(rows) == 1, (block.stage, block.angle_deg)
        for step in block.steps:
            if step.quantity not in FORMULAS:
                continue  # kinematics and forces: tests/test_note.py
            checked.add(block.stage)
            text = step.result_text(t)
            shown = [row for row in rows if any(_shows(cell, text) for cell in row)]
            assert shown or not block.table_number, (block.stage, step.quantity, text, rows)
            if step.row_key:  # a table of results, one row per crank or journal: that one's row
                assert any(row[0] == step.row_key for row in shown), (
                    step.quantity,
                    step.row_key,
                    shown,
                )
            elif (
                block.table_number and block.angle_deg is None
            ):  # a table of results: the row of its symbol
                assert any(cell.startswith(step.lhs_html) for row in shown for cell in row), (
                    step.quantity,
                    shown,
                )
            # the result is written in the worked line itself
            assert f"= {text}" in as_read(html)
            formula = FORMULAS[step.quantity]
            assert formula(step.inputs) == pytest.approx(step.value, abs=_tolerance(step)), (
                step.quantity
            )
            assert step.exact, step.quantity
            assert formula(step.exact) == pytest.approx(step.value, rel=1e-12, abs=1e-12), (
                step.quantity
            )
    return checked


INLINE4_STAGES = (
    "indicator",
    "forces",
    "torque",
    "balancing",
    "bearings",
    "flywheel",
    "speed_fluctuation",
)


@pytest.mark.parametrize("language", ["uk", "ru", "en"])
def test_inline4_worked_results_equal_their_tables(language):
    html, worked = _sections("inline4-petrol", INLINE4_STAGES, language)
    assert check_worked(html, worked, language) == set(INLINE4_STAGES) - {"forces"} | {
        "forces_torque"
    }


@pytest.mark.parametrize("language", ["uk", "ru", "en"])
@pytest.mark.parametrize(
    "example, stages",
    [
        ("offset-crank-engine", ("offset_crank", "indicator", "forces", "rod_dynamics")),
        ("planetary-kinematics", ("planetary", "rod_dynamics")),
        ("vane-engine-kinematics", ("vane",)),
        (
            "inline6-diesel-trace",
            ("forces", "torque"),
        ),  # a measured trace: small tangential forces at 30°
    ],
)
def test_other_mechanisms_worked_results_equal_their_tables(example, stages, language):
    html, worked = _sections(example, stages, language)
    assert check_worked(html, worked, language) == set(stages) - {"forces"} | (
        {"forces_torque"} if "forces" in stages else set()
    )


def test_a_worked_line_keeps_its_short_innermost_brackets_on_one_line():
    """The PDF does not break "(1 − cos | 8,048°)" and "(589,260 + | 583,396)" at a line's end:
    each short innermost group is kept whole, longer ones and
    groups that would cut a sub- or superscript's tag are left to break."""
    from crankdyn.report.worked import GROUP_CHARS, groups_unbroken

    line = "<i>s</i> = <i>R</i>[(1 − cos <i>α</i>) + (1 − cos <i>β</i>)/<i>λ</i>] = 0,039·[(1 − cos 8,048°)/0,28]"
    out = groups_unbroken(line)
    assert out.count('<span class="group">') == 3
    assert '<span class="group">(1 − cos\u00a08,048°)</span>' in out
    # nothing else changed but the function bound to its argument
    assert re.sub(r"</?span[^>]*>", "", out).replace("cos\u00a0", "cos ") == line
    long_group = "(" + "1 + " * GROUP_CHARS + "1)"
    assert groups_unbroken(long_group) == long_group
    across = "<sub>k(<i>i</i></sub>−1)"
    assert groups_unbroken(across) == across


def test_a_function_stays_with_its_argument_and_a_slash_with_its_bracket():
    """Not "…/cos | 8,048°" nor "…583,396)/ | (589,260 + …" broken at a line's end in the uk PDF."""
    from crankdyn.report.worked import groups_unbroken

    out = groups_unbroken(
        "cos(30° + 8,048°)/cos 8,048° + 0,2800·cos<sup>2</sup> 30°/cos<sup>3</sup> 8,048°"
    )
    assert (
        "/cos\u00a08,048°" in out
        and "cos<sup>2</sup>\u00a030°" in out
        and "cos<sup>3</sup>\u00a08,048°" in out
    )
    assert ')</span>/\u2060<span class="group">(589,260' in groups_unbroken(
        "2·(589,260 − 583,396)/(589,260 + 583,396)"
    )
    assert groups_unbroken("cosine 3") == "cosine 3"  # a word, not the function
