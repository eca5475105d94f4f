"""Sections kept between renderings of (versions of) one scene: the live preview's second cache.

The stage cache (:mod:`crankdyn.engine.stage_cache`) hands back the *same* ``StageOutput`` object
for a
stage whose inputs did not change. A section rendered from that same object, at the same
number, in the same language, from the same values of the scene fields its ``render`` read
(recorded while it ran, through the read-tracking scene copy) is the same section: its HTML,
conclusions, abstract findings, title, worked substitutions and figures — already drawn — are reused, and only
the sections of re-run stages are built and drawn again. A save that changes ``masses.rod``
thus leaves the kinematics and indicator sections, and their figures, as they were.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..engine.stage_cache import field_digests, reads_of, tracked_copy
from ..plugin.types import Stage, StageOutput
from .context import FigureFile, RenderContext


@dataclass
class _Section:
    stage: Stage
    output: StageOutput
    key: tuple
    reads: frozenset[str]
    fields: tuple
    body: str | None
    title: str | None
    conclusions: list[str]
    findings: list[str]
    worked: list
    figures: list[FigureFile]
    #: the run's data the section read (``RenderContext.data``), by contract: kept while the
    #: same objects are the run's
    data: dict = field(default_factory=dict)


class SectionCache:
    """Rendered sections by stage name; :attr:`renders` counts the real renders per stage."""

    def __init__(self) -> None:
        self._sections: dict[str, _Section] = {}
        self.renders: dict[str, int] = {}

    def render(self, stage: Stage, output: StageOutput, ctx: RenderContext) -> str | None:
        """``stage.presentation.render(output, ctx)``, or the kept section when nothing it depends on changed
        (then its figures, conclusions, title and worked substitutions are put into ``ctx`` too)."""
        if stage.presentation is None:  # a stage without a section
            return None
        key = (ctx.section_number, ctx.t.language, ctx.table_step_deg, ctx.cycle_deg)
        kept = self._sections.get(stage.name)
        scene = ctx.scene
        if (
            kept is not None
            and kept.stage is stage
            and kept.output is output
            and kept.key == key
            and scene is not None
            and kept.fields == field_digests(scene, kept.reads)
            and all(ctx.run_data.get(c) is kept.data.get(c) for c in kept.data)
        ):
            ctx.figures.extend(kept.figures)
            ctx.worked.extend(kept.worked)
            ctx.conclusions.extend(kept.conclusions)
            ctx.findings.extend(kept.findings)
            ctx.title = kept.title
            return kept.body
        figures_before, worked_before, findings_before = (
            len(ctx.figures),
            len(ctx.worked),
            len(ctx.findings),
        )
        tracked = tracked_copy(scene) if scene is not None else None
        ctx.scene = tracked
        ctx.data_reads = set()
        try:
            body = stage.presentation.render(output, ctx)
        finally:
            ctx.scene = scene
            reads = reads_of(tracked) if tracked is not None else frozenset()
        self.renders[stage.name] = self.renders.get(stage.name, 0) + 1
        if scene is not None:
            self._sections[stage.name] = _Section(
                stage,
                output,
                key,
                reads,
                field_digests(scene, reads, as_read=True),
                body,
                ctx.title,
                list(ctx.conclusions),
                ctx.findings[findings_before:],
                ctx.worked[worked_before:],
                ctx.figures[figures_before:],
                {c: ctx.run_data.get(c) for c in ctx.data_reads},
            )
        return body

    def forget(self) -> None:
        self._sections.clear()
