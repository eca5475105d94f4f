"""Assemble the whole report from a run: sections in plan order, notes, conclusions."""

from __future__ import annotations

import datetime
import functools
from dataclasses import dataclass, field
from pathlib import Path

import jinja2
from markupsafe import Markup

from .. import __version__
from ..physics.extrema import EXTREMUM_RTOL
from ..orchestrator import RunResult
from ..plugins import Registry
from .context import FigureFile, RenderContext, inline_figures, template_search_path
from .i18n import translator


@dataclass
class SectionView:
    number: int
    key: str
    title: str
    html: Markup
    conclusions: list[str] = field(default_factory=list)


@dataclass
class RenderedReport:
    """A rendered report: the page referring to ``figures/NAME.svg``, and the figures once each."""

    linked_html: str
    figures: list[FigureFile]
    language: str
    missing_translations: set[str]

    @functools.cached_property
    def html(self) -> str:
        """The self-contained page: every figure inlined as a data: URI (preview, ``--self-contained``)."""
        return inline_figures(self.linked_html, self.figures)


def _environment(registry: Registry, result: RunResult) -> jinja2.Environment:
    extra = [s.template_dir for s in result.plan.order if s.template_dir is not None]
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(template_search_path(extra)),
        autoescape=True,  # every value is escaped unless a helper marks it as markup
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
    )


def render_html(result: RunResult, registry: Registry, language: str | None = None) -> RenderedReport:
    scene = result.scene
    language = language or scene.report.language
    t = translator(language, registry.catalogs)
    env = _environment(registry, result)
    ctx = RenderContext(t=t, env=env, table_step_deg=scene.analysis.table_step_deg, cycle_deg=scene.engine.cycle_deg, scene=scene)

    sections: list[SectionView] = []
    ctx.start_section(1, "input")
    sections.append(SectionView(1, "input", t("report.input_title"),
                                Markup(ctx.render_template("sections/input.html.j2", scene=scene,
                                                           mechanism=registry.mechanisms.get(scene.engine.mechanism)))))
    references: list[str] = []
    notes: list[str] = []
    for stage in result.plan.order:
        number = len(sections) + 1
        ctx.start_section(number, stage.name)
        ctx.conclusions = []
        output = result.outputs[stage.name]
        body = stage.render(output, ctx)
        if body is None:  # the stage ran for its data but has nothing to show for this scene
            continue
        sections.append(SectionView(number, stage.name, t(stage.title_key), Markup(body), list(ctx.conclusions)))
        for ref in stage.references:
            if ref not in references:
                references.append(ref)
        for key, params in output.notes:
            notes.append(t(key, **{k: (ctx.num(v) if isinstance(v, float) else v) for k, v in params.items()}))

    numerics_number = len(sections) + 1
    skipped = [(name, reason) for name, reason in result.plan.skipped.items()]
    css = "\n".join((Path(p) / "report.css").read_text(encoding="utf-8")
                    for p in template_search_path([])[:1])
    html = env.get_template("report.html.j2").render(
        _=t, num=ctx.num, scene=scene, meta=scene.report, sections=sections, notes=notes,
        timing=[(s.name, result.timing_s[s.name]) for s in result.plan.order], skipped=skipped,
        numerics_number=numerics_number, references=references, css=Markup(css),
        extremum_rtol=ctx.num(EXTREMUM_RTOL, 1),
        version=__version__, generated=datetime.date.today().isoformat(), language=language,
    )
    return RenderedReport(linked_html=html, figures=ctx.figures, language=language, missing_translations=set(t.missing))
