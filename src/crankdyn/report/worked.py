"""Worked substitutions: one calculation with the numbers put in, as a supervisor checks first.

A stage's ``render`` picks the printed table row nearest the scene's ``[report]
worked_angle_deg`` and lists, for its main formulas, the formula, the same formula with that
row's numbers substituted, and the result — the value of the table row itself, so the worked
line and the table can never disagree. Each step is also kept as data (:class:`WorkedStep`,
``RenderContext.worked``) so a test can re-evaluate the substituted numbers independently.
Nothing here computes physics.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from markupsafe import Markup, escape

from .formula_lines import unbroken_parts
from .i18n import MINUS, NARROW_NBSP


@dataclass
class WorkedStep:
    """One worked formula: ``lhs = formula = substituted = result unit``."""

    quantity: str  # a stable name, e.g. "piston_displacement"
    lhs_html: str
    formula_html: str
    substituted_html: str
    value: float  # the table row's value, in the table's unit
    decimals: int  # as the table prints it
    unit: str
    inputs: dict[str, float] = field(default_factory=dict)  # the substituted numbers, as printed
    significant: int | None = None  # a result table printing significant digits, not decimals
    exact: dict[str, float] = field(
        default_factory=dict
    )  # the same inputs unrounded (tests: to 1e-12)
    row_key: str = (
        ""  # in a table of results: the first cell of the row holding this result ("1", a journal)
    )

    def result_text(self, t) -> str:
        """The result as its table prints it."""
        if self.significant is not None:
            return t.number(self.value, self.significant)
        return t.fixed(self.value, self.decimals)


@dataclass
class WorkedBlock:
    """The worked steps of one stage. ``angle_deg`` None: results that hold for the whole cycle
    (amplitudes, a flywheel), taken from a table of results rather than a row at one angle;
    ``table_number`` "" as well: results the section's text states (no table holds them)."""

    stage: str
    table_number: str
    angle_deg: float | None
    steps: list[WorkedStep]
    note: str = ""  # a translated sentence after the intro (e.g. which stroke the angle lies on)


def worked_row(labels: Sequence[float], wanted_deg: float) -> int:
    """Index of the printed table row nearest ``wanted_deg`` (the first of equals). An angle
    beyond the table's span is taken at the same point of its period, whole turns (360° for a
    table of one turn, 720° for a four-stroke cycle's): 390° in a table of 0…360° is its 30°,
    not its nearest row, 360°."""
    angles = np.asarray(labels, dtype=float)
    low, high = float(angles.min()), float(angles.max())
    if not low <= wanted_deg <= high:
        period = 360.0 * max(1.0, np.ceil((high - low) / 360.0 - 1e-9))
        wanted_deg = low + (wanted_deg - low) % period
    return int(np.argmin(np.abs(angles - wanted_deg)))


def snapped(value: float, scale: float) -> float:
    """``value``, or 0 where it is rounding noise next to ``scale`` (below 10⁻⁹ of it): a rod
    angle of 10⁻¹⁵° at a dead centre is substituted as the 0° it is, not as "−3,852·10⁻¹⁵"."""
    return 0.0 if abs(value) < 1e-9 * abs(scale) else value


def printed(t, value: float, significant: int = 4) -> tuple[str, float]:
    """A number as substituted into a formula, and the value the reader sees."""
    text = t.number(value, significant)
    return text, _parse(text)


def printed_g(t, value: float, significant: int = 6) -> tuple[str, float]:
    """A scene input as the reader wrote it ("0,09", "1,37"): no padding zeros."""
    text = t.number_g(value, significant)
    return text, _parse(text)


#: The significant digits a table column's largest value is printed with at least, where its
#: decimals would give fewer (:func:`column_decimals`).
COLUMN_SIGNIFICANT = 4


def column_decimals(values, decimals: int, significant: int = COLUMN_SIGNIFICANT) -> int:
    """``decimals``, or more where the column's largest value would show fewer than
    ``significant`` digits with them: a slow marine engine's piston acceleration of 158 m/s² is
    printed 157,9, its rod's ε_r of 22 rad/s² 22,14, so that a worked line substituting the
    table's numbers gives back the table's result (at most three decimals more)."""
    whole = whole_digits(values)
    if whole is None:
        return decimals
    return min(decimals + 3, max(decimals, significant - whole))


def whole_digits(values) -> int | None:
    """The digits before the decimal point of the largest finite magnitude in ``values`` (0 for
    0,05, 3 for −157,9), or None when there is none above zero."""
    finite = np.abs(np.asarray(values, dtype=float))
    finite = finite[np.isfinite(finite)]
    largest = float(finite.max()) if finite.size else 0.0
    return int(np.floor(np.log10(largest))) + 1 if largest > 0.0 else None


def printed_fixed(t, value: float, decimals: int) -> tuple[str, float]:
    """A table value as printed with ``decimals`` decimals, and the value the reader sees."""
    text = t.fixed(value, decimals)
    return text, _parse(text)


def bracketed(text: str, value: float) -> str:
    """A negative factor in brackets: "·(−1,5)", never "·−1,5"."""
    return text if value >= 0 else f"({text})"


_FROM_SUPERSCRIPT = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")


def _parse(text: str) -> float:
    """The value of a number as printed: "−1,2·10⁻³", "12 345,6"."""
    text = text.replace(NARROW_NBSP, "").replace("\u00a0", "").replace(MINUS, "-").replace(",", ".")
    mantissa, _, exponent = text.partition("·10")
    return float(
        f"{mantissa}e{int(exponent.translate(_FROM_SUPERSCRIPT))}" if exponent else mantissa
    )


#: The longest innermost bracketed group of a worked line (visible characters) kept on one line: the
#: PDF broke "(1 − cos | 8,048°)" and "(589,260 + | 583,396)" at the line's end; a longer group may break.
GROUP_CHARS = 40
#: The printed characters of a worked line (the text's width less its indent; an equation's line,
#: beside its number, holds fewer).
WORKED_LINE_CHARS = 84
_INNERMOST_GROUP = re.compile(r"\([^()]*\)")
_TAG_RE = re.compile(r"<[^>]+>")


def _tags_balanced(html: str) -> bool:
    """Whether every tag opened in ``html`` is closed in it, and none closed that it did not open."""
    depth: list[str] = []
    for closing, name in re.findall(r"<(/?)(\w+)", html):
        if not closing:
            depth.append(name)
        elif not depth or depth.pop() != name:
            return False
    return not depth


#: A function's name and its argument ("cos 8,048°", "cos<sup>3</sup> 8,048°"): bound by a no-break space.
_FUNCTION_ARGUMENT = re.compile(
    r"\b(cos|sin|tg|ctg|arcsin|arccos|arctg|ln|exp)((?:<sup>[^<]*</sup>)?) (?=\S)"
)
#: A slash before a bracket ("…)/(589,260 + …"): a word joiner after it, as the equations have.
_SLASH_BRACKET = re.compile(r"/(?=[(\[])")


def groups_unbroken(line_html: str) -> str:
    """``line_html`` with each short innermost "( … )" group in a span that the page does not
    break, a function bound to its argument and no break after a slash before a bracket (not
    "…/cos | 8,048°", "…583,396)/ | (589,260 + …" across a line's end)."""

    def keep(match: re.Match) -> str:
        group = match.group(0)
        if len(_TAG_RE.sub("", group)) > GROUP_CHARS or not _tags_balanced(group):
            return group
        return f'<span class="group">{group}</span>'

    line_html = _FUNCTION_ARGUMENT.sub(lambda m: f"{m.group(1)}{m.group(2)}\u00a0", line_html)
    line_html = _SLASH_BRACKET.sub("/\u2060", line_html)
    return _INNERMOST_GROUP.sub(keep, line_html)


def worked_markup(ctx, block: WorkedBlock) -> Markup:
    """The worked example's sentence and one displayed line per step.

    No heading of its own: an unnumbered heading inside a section is not a structural element
    of the note (ДСТУ 3008), and the sentence already says what follows and for which row."""
    t = ctx.t
    if block.angle_deg is None:
        intro = (
            t("doc.worked_intro_results", table=block.table_number)
            if block.table_number
            else t("doc.worked_intro_text")
        )
    else:
        angle = ctx.angle_text(block.angle_deg)
        intro = t("doc.worked_intro", angle=angle, table=block.table_number)
    parts = ['<div class="worked">', f"<p>{escape(intro)}</p>"]
    if block.note:
        parts.append(f"<p>{escape(block.note)}</p>")
    for step in block.steps:
        result = step.result_text(t)
        unit = "°" if step.unit == "°" else f" {escape(step.unit)}" if step.unit else ""
        line = f"{step.lhs_html} = {step.formula_html} = {step.substituted_html} = {escape(result)}{unit}"
        # carried over as an equation is: after "=" or at a sign outside brackets, the sign repeated
        parts.append(
            f'<p class="worked-line">{unbroken_parts(groups_unbroken(line), WORKED_LINE_CHARS)}</p>'
        )
    parts.append("</div>")
    ctx.worked.append(block)
    return Markup("".join(parts))
