"""Worked substitutions: one calculation with the numbers put in, as a supervisor checks first.

A stage's ``render`` picks the printed table row nearest the scene's ``[report]
worked_angle_deg`` and lists, for its main formulas, the formula, the same formula with that
row's numbers substituted, and the result — the value of the table row itself, so the worked
line and the table can never disagree. Each step is also kept as data (:class:`WorkedStep`,
``RenderContext.worked``) so a test can re-evaluate the substituted numbers independently.
Nothing here computes physics.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
from markupsafe import Markup, escape
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


@dataclass
class WorkedBlock:
    stage: str
    table_number: str
    angle_deg: float
    steps: list[WorkedStep]


def worked_row(labels: Sequence[float], wanted_deg: float) -> int:
    """Index of the printed table row nearest ``wanted_deg`` (the first of equals)."""
    labels = np.asarray(labels, dtype=float)
    return int(np.argmin(np.abs(labels - wanted_deg)))


def printed(t, value: float, significant: int = 4) -> tuple[str, float]:
    """A number as substituted into a formula, and the value the reader sees."""
    text = t.number(value, significant)
    return text, _parse(text)


def printed_fixed(t, value: float, decimals: int) -> tuple[str, float]:
    """A table value as printed with ``decimals`` decimals, and the value the reader sees."""
    text = t.fixed(value, decimals)
    return text, _parse(text)


def _parse(text: str) -> float:

    return float(text.replace(NARROW_NBSP, "").replace(MINUS, "-").replace(",", "."))


def worked_markup(ctx, block: WorkedBlock) -> Markup:
    """The worked example's heading, its sentence and one displayed line per step."""
    t = ctx.t
    angle = t.number_g(block.angle_deg)
    parts = [f'<div class="worked"><h3>{escape(t("doc.worked_title", angle=angle))}</h3>',
             f'<p>{escape(t("doc.worked_intro", angle=angle, table=block.table_number))}</p>']
    for step in block.steps:
        result = t.fixed(step.value, step.decimals)
        unit = f" {escape(step.unit)}" if step.unit else ""
        parts.append(f'<p class="worked-line">{step.lhs_html} = {step.formula_html} = '
                     f'{step.substituted_html} = {escape(result)}{unit}</p>')
    parts.append("</div>")
    ctx.worked.append(block)
    return Markup("".join(parts))
