"""One scene to its output files: the code path shared by ``crankdyn report``, ``batch`` and ``serve``.

Everything is rendered in memory first (:func:`render_files`); only when all of it
succeeded are the files written, each atomically (:func:`write_report`). A bad scene
therefore raises before anything reaches the disk.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

from ..engine.frozen_heap import collector_paused, frozen_heap
from ..engine.orchestrator import RunResult, check_scene, plan, run_scene
from ..engine.studies import ForkedRun, start_studies
from ..parallel.fork import spare_core
from ..plugin.registry import Registry
from ..scene.model import Scene
from . import writers as outputs
from .manifest import write_outputs


@dataclass
class ReportRun:
    """A computed scene and the files written for it."""

    result: RunResult
    written: list[Path]
    #: catalog keys the rendered report (HTML, PDF, DOCX) has no text for in its language
    missing_translations: set[str] = field(default_factory=set)


def _run_aside(
    scene: Scene,
    registry: Registry,
    stages: Iterable[str] | None,
    languages: Iterable[str],
    printed: bool = False,
) -> RunResult | None:
    """The scene computed by a forked child (studies included, as they come) while this process
    imports and prepares what rendering needs (``printed``: the figures' PDF pages too); None if
    no child could (then run it here).
    A bad scene is refused here, before anything is forked."""
    scene = scene.with_plugin_defaults(registry)
    check_scene(scene, registry, languages)
    forked = ForkedRun.start(scene, plan(scene, registry, stages))
    if forked is None:
        return None
    try:
        with collector_paused():  # imports: nothing to collect
            from ..report import (
                document,  # noqa: F401  # lazy: heavy optional import (jinja2, babel, as for the figures)
            )
            from ..report.figures import (
                prepare,  # lazy: heavy optional import (matplotlib, while the child computes)
            )

            prepare(printed=printed)
    except BaseException:
        forked.close()
        raise
    return forked.result()


def render_files(
    result: RunResult,
    registry: Registry,
    formats: Iterable[str],
    self_contained: bool = False,
    figure_workers: int | None = None,
    missing: set[str] | None = None,
) -> dict[str, bytes]:
    """The output files of ``result`` in ``formats`` as relative name -> bytes (nothing written).

    report.html refers to the figures in ``figures/``, each stored once; with ``self_contained``
    they are inlined in the page instead (and no figures/ folder is written). The figures are
    drawn by ``figure_workers`` processes (default: one per CPU; a batch, which runs its
    variants in parallel, passes 1). The catalog keys the report has no text for are added to
    ``missing``, if given (``crankdyn report`` warns about them).
    """
    with frozen_heap():  # the collector skips the imported modules (crankdyn.engine.frozen_heap)
        return _render_files(
            result, registry, list(formats), self_contained, figure_workers, missing
        )


def _render_files(
    result: RunResult,
    registry: Registry,
    formats: list[str],
    self_contained: bool,
    figure_workers: int | None,
    missing: set[str] | None = None,
) -> dict[str, bytes]:
    files: dict[str, bytes] = {}
    if "html" in formats or "pdf" in formats or "docx" in formats:
        from ..report import mathtext_store  # lazy: heavy optional import (with the figures)
        from ..report.context import (
            draw_figures,  # lazy: heavy optional import (jinja2, babel, matplotlib)
        )

        # A printed report places each figure's PDF page (report.figure_forms); the page's files
        # and the Word file's pictures come from the figures' SVG.
        svg_needed = "html" in formats or "docx" in formats
        rendered = _rendered_and_printed(
            result, registry, formats, svg_needed, figure_workers, files
        )
        if svg_needed:
            draw_figures(rendered.figures, 1)  # none left, unless a section drew its figure again
        if missing is not None:
            missing.update(rendered.missing_translations)
        mathtext_store.save()  # the labels typeset here, for the next run
        if "html" in formats and self_contained:
            files["report.html"] = rendered.html.encode("utf-8")
        elif "html" in formats:
            files["report.html"] = rendered.linked_html.encode("utf-8")
            files.update({f"figures/{f.name}": f.svg for f in rendered.figures})
        if "docx" in formats:
            from ..report.docx import (
                report_docx,  # lazy: heavy optional import (pandoc, matplotlib)
            )

            files["report.docx"] = report_docx(rendered.html, rendered.figures, rendered.language)
    # after the report, which takes each study's output when its section comes (engine.studies)
    result.complete()
    if "json" in formats:
        files["results.json"] = outputs.json_bytes(outputs.results_document(result))
    if "csv" in formats:
        files.update(outputs.csv_tables(result))
    if "xlsx" in formats:
        files.update(outputs.xlsx_tables(result))
    return files


def _rendered_and_printed(
    result: RunResult,
    registry: Registry,
    formats: list[str],
    svg_needed: bool,
    figure_workers: int | None,
    files: dict[str, bytes],
):
    """The rendered report, its figures drawn (as SVG where ``svg_needed``, as PDF pages for the
    printed report) by forked children meanwhile; ``report.pdf`` added to ``files`` if asked."""
    from ..report import figure_forms  # lazy: heavy optional import (with the figures)
    from ..report.document import (
        render_html,  # lazy: heavy optional import (jinja2, babel, matplotlib)
    )
    from ..report.figures import (  # lazy: heavy optional import
        IncrementalDrawing,
        can_fork,
        default_workers,
    )

    workers = default_workers() if figure_workers is None else figure_workers
    forking = workers > 1 and can_fork()
    forms = "pdf" in formats and figure_forms.available()
    drawings = []
    if forking:
        drawings.append(IncrementalDrawing(workers, "svg" if svg_needed or not forms else "pdf"))
    try:
        # the figures are drawn by forked children while the next sections are rendered
        rendered = render_html(result, registry, figure_sink=drawings[0].add if drawings else None)
        if "pdf" in formats:
            if forking and forms and svg_needed:  # their PDF pages too
                drawings.append(IncrementalDrawing(workers, "pdf"))
                drawings[-1].add(rendered.figures)
            for drawing in drawings:
                # and, for the PDF, while WeasyPrint lays out the text: each figure is waited
                # for (or, without children, drawn) when the layout reaches it
                drawing.hand_out()
            files["report.pdf"] = _pdf(rendered)
        for drawing in drawings:
            drawing.finish()
    except BaseException:
        for drawing in drawings:
            drawing.abandon()
        raise
    return rendered


def _pdf(rendered) -> bytes:
    from ..report import printer  # lazy: heavy optional import (only a PDF has a printer)
    from ..report.pdf import html_to_pdf  # lazy: heavy optional import (weasyprint)

    # made by the printer process the command line started (WeasyPrint loaded meanwhile), if any
    pdf = printer.print_pdf(rendered.linked_html, rendered.figures)
    return pdf if pdf is not None else html_to_pdf(rendered.linked_html, rendered.figures)


def write_report(
    scene: Scene,
    registry: Registry,
    out_dir: Path,
    formats: Iterable[str],
    stages: Iterable[str] | None = None,
    languages: Iterable[str] = (),
    self_contained: bool = False,
    force: bool = False,
) -> ReportRun:
    """Compute ``scene`` and write its outputs below ``out_dir``, as ``crankdyn report`` does.

    Files of an earlier run into ``out_dir`` that this one does not write again are removed (only
    those crankdyn wrote and nobody changed since). Raises :class:`crankdyn.errors.SceneError` (and
    writes nothing) for a bad scene, :class:`crankdyn.errors.OutputError` (and writes nothing) when a
    file in ``out_dir`` is in the way and ``force`` is false.
    """
    missing: set[str] = set()
    result, files = run_and_render(
        scene, registry, formats, stages, languages, self_contained=self_contained, missing=missing
    )
    return ReportRun(
        result=result,
        written=write_outputs(Path(out_dir), files, force=force),
        missing_translations=missing,
    )


def run_and_render(
    scene: Scene,
    registry: Registry,
    formats: Iterable[str],
    stages: Iterable[str] | None = None,
    languages: Iterable[str] = (),
    *,
    self_contained: bool = False,
    cache=None,
    figure_workers: int | None = None,
    missing: set[str] | None = None,
) -> tuple[RunResult, dict[str, bytes]]:
    """Compute ``scene`` and render its files in memory: the one path of ``report``, ``batch`` and ``serve``.

    ``crankdyn report`` and ``batch`` write the files (:func:`write_report`); ``serve`` shows
    ``report.html`` in the browser and passes its stage ``cache`` (re-running only the stages whose
    inputs changed). ``missing``: see :func:`render_files`. Raises
    :class:`crankdyn.errors.SceneError` for a bad scene.
    """
    formats = list(formats)
    scene = scene.with_plugin_defaults(registry)
    # One report on its own (not a batch's variant, which shares the cores with the other
    # variants, nor the preview's cached run): the studies are computed in a forked child while
    # the report is rendered (crankdyn.engine.studies).
    alone = cache is None and figure_workers is None
    renders = any(f in formats for f in ("html", "pdf", "docx"))
    aside = alone and (os.cpu_count() or 1) > 1 and renders
    # Nothing to render (JSON, CSV, XLSX): the second core is spare while the stages run, and a
    # study computes its independent parts there (crankdyn.parallel.fork).
    with frozen_heap(), spare_core(alone and not renders):
        printed = "pdf" in formats
        result = _run_aside(scene, registry, stages, languages, printed) if aside else None
        if result is None:
            result = run_scene(scene, registry, stages, languages, cache=cache, defer_studies=aside)
            if aside:
                start_studies(result)
        try:
            return result, render_files(
                result, registry, formats, self_contained, figure_workers, missing
            )
        finally:
            result.close_background()  # also when rendering failed: no child is left behind


def _build_figures(figures) -> None:
    """Build the figures given as the functions that build them (``FigureFile.figure``)."""
    for figure in figures:
        if not figure.drawn:
            figure.figure  # noqa: B018 - built for its side effect


def run_for_preview(
    scene: Scene,
    registry: Registry,
    stages: Iterable[str] | None,
    languages: Iterable[str],
    stage_cache,
    sections_cache,
    defer_studies: bool = False,
    studies: RunResult | None = None,
    worker=None,
    inline_studies: bool = False,
    figure_sink=None,
):
    """The live preview's step of the same path: compute ``scene`` (re-running only the stages whose
    inputs changed) and render the report (re-rendering only the sections whose stage output or
    scene reads changed); the figures are left undrawn, so that the page can be shown first. With
    ``defer_studies`` a study that has to run again (the error against run time) is left for the
    next call and its section says so (``RunResult.pending``); the preview's study ``worker``
    (:class:`crankdyn.engine.studies.StudyWorker`) computes it meanwhile, and the next call, given
    the returned ``studies``, takes it from there (or computes it, if the scene changed since).
    With ``inline_studies`` as well (a study the worker computes quickly), this rendering waits
    for the worker's study when its section comes, so that the page is shown once, whole.
    ``figure_sink(figures)`` receives each section's new figures as the section is rendered
    (default: each is built, for its size).
    Returns (run result, :class:`crankdyn.report.document.RenderedReport`, the deferred studies
    as a :class:`RunResult` to pass as ``studies``, or None)."""
    from ..report.document import (
        render_html,  # lazy: heavy optional import (jinja2, babel, matplotlib)
    )

    scene = scene.with_plugin_defaults(registry)
    check_scene(scene, registry, languages)
    with frozen_heap():  # the collector skips the imported modules and cached results
        result = stage_cache.run_plan(
            scene, plan(scene, registry, stages), defer_studies=defer_studies, deferred=studies
        )
        deferred = None
        if result.deferred:  # computed by the worker meanwhile, if there is one
            job = (
                None
                if worker is None
                else worker.submit(
                    scene,
                    None if stages is None else list(stages),
                    [s.name for s in result.plan.order if s.name in result.deferred],
                )
            )
            if inline_studies and job is not None:  # taken when their sections come
                result.background = job
            else:  # shown as pending in this rendering, taken (or computed) by the next
                deferred = RunResult(
                    scene=scene,
                    plan=result.plan,
                    outputs={},
                    deferred=result.deferred,
                    background=job,
                )
                result.deferred = {}
        try:
            # each section's figures built as it comes (the page's placeholders need their sizes):
            # meanwhile the worker computes the study whose section comes last
            rendered = render_html(
                result,
                registry,
                sections_cache=sections_cache,
                figure_sink=figure_sink or _build_figures,
            )
        finally:
            result.close_background()
        for name in [name for name in result.outputs if stage_cache.deferred_study(name)]:
            stage_cache.adopt(name, result.outputs[name])  # the worker's study, kept as if run here
        return result, rendered, deferred
