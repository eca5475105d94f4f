"""What a stage's ``render`` receives: translation, numbering, tables, figures, templates."""

from __future__ import annotations

import base64
from importlib import resources
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from markupsafe import Markup, escape

from .i18n import Translator


@dataclass
class FigureFile:
    name: str
    svg: bytes


@dataclass
class RenderContext:
    """Per-report rendering state shared by all sections.

    Equations, tables and figures are numbered per section ("2.3"), as course
    projects number them. Section templates are rendered with autoescape on.
    """

    t: Translator
    env: Any  # jinja2.Environment
    section_number: int = 0
    figures: list[FigureFile] = field(default_factory=list)
    _equation: int = 0
    _table: int = 0
    _figure: int = 0
    stage_name: str = ""
    table_step_deg: float = 10.0
    cycle_deg: float = 720.0
    conclusions: list[str] = field(default_factory=list)
    scene: Any = None

    def start_section(self, number: int, stage_name: str) -> None:
        self.section_number = number
        self.stage_name = stage_name
        self._equation = self._table = self._figure = 0

    # ----------------------------------------------------------------- numbering
    def equation(self, formula_html: str, label: str = "") -> Markup:
        """A displayed, numbered equation. ``formula_html`` is template-authored markup."""
        self._equation += 1
        number = f"{self.section_number}.{self._equation}"
        anchor = f' id="eq-{escape(label)}"' if label else ""
        return Markup(f'<div class="equation"{anchor}><span class="formula">{formula_html}</span>'
                      f'<span class="eqno">({number})</span></div>')

    def table(self, columns: Sequence[tuple[str, Sequence[float] | Sequence[str], int | None]],
              caption: str, header_html: bool = True, css_class: str = "data") -> Markup:
        """A numbered table. ``columns`` are (header markup, values, decimals or None for text)."""
        self._table += 1
        number = f"{self.section_number}.{self._table}"
        head = "".join(f"<th>{Markup(h) if header_html else escape(h)}</th>" for h, _, _ in columns)
        n_rows = len(columns[0][1]) if columns else 0
        rows = []
        for i in range(n_rows):
            cells = []
            for _, values, decimals in columns:
                v = values[i]
                text = escape(v) if decimals is None else escape(self.t.fixed(v, decimals))
                cells.append(f"<td>{text}</td>")
            rows.append("<tr>" + "".join(cells) + "</tr>")
        caption_text = escape(self.t("report.table_caption", number=number, caption=caption))
        return Markup(f'<table class="{css_class}"><caption>{caption_text}</caption>'
                      f"<thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>")

    def figure(self, fig, caption: str, name: str) -> Markup:
        """Render a matplotlib figure to SVG, number it and return its markup."""
        from .figures import to_svg  # lazy: heavy optional import (matplotlib)

        self._figure += 1
        number = f"{self.section_number}.{self._figure}"
        svg = to_svg(fig)
        file_name = f"fig_{number.replace('.', '_')}_{name}.svg"
        self.figures.append(FigureFile(file_name, svg))
        data = base64.b64encode(svg).decode("ascii")
        caption_text = escape(self.t("report.figure_caption", number=number, caption=caption))
        return Markup(f'<figure><img alt="{escape(caption)}" src="data:image/svg+xml;base64,{data}">'
                      f"<figcaption>{caption_text}</figcaption></figure>")

    # ----------------------------------------------------------------- text
    def conclude(self, sentence: str) -> str:
        """Add a sentence to the report's conclusions (returns "" for use in templates)."""
        self.conclusions.append(sentence)
        return ""

    def num(self, value: float, significant: int = 4) -> str:
        return self.t.number(value, significant)

    def render_template(self, name: str, **values: Any) -> str:
        template = self.env.get_template(name)
        return template.render(ctx=self, _=self.t, num=self.num, eq=self.equation, **values)


def sample_rows(crank_angle_deg: np.ndarray, table_step_deg: float,
                span_deg: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Rows shown in printed tables: grid indices and their angle labels.

    Every ``table_step_deg`` from 0 up to and including ``span_deg`` (default: the
    whole cycle). The grid is periodic without its end point, so the closing row
    (e.g. 720°) reuses the first grid point, as the textbook's tables show it.
    """
    n = len(crank_angle_deg)
    step = crank_angle_deg[1] - crank_angle_deg[0] if n > 1 else table_step_deg
    cycle = step * n
    span = cycle if span_deg is None else min(span_deg, cycle)
    every = max(int(round(table_step_deg / step)), 1)
    last = int(round(span / step))
    positions = np.arange(0, last + 1, every)
    return positions % n, positions * step


def template_search_path(extra: Sequence[Path]) -> list[str]:
    core = Path(str(resources.files("crankdyn.templates")))
    return [str(core)] + [str(p) for p in extra if p is not None]
