"""What a stage's ``render`` receives: translation, numbering, tables, figures, templates."""

from __future__ import annotations

import base64
import html as html_lib
import os
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from markupsafe import Markup, escape

from ..errors import PluginError
from ..physics.extrema import first_extremum_index
from ..plugin.types import declared
from . import figure_memo, names
from .assets import FIGURE_DIR, templates_dir
from .formula_lines import unbroken_parts
from .i18n import Translator
from .typeset import SYMBOLS, SymbolTable, typeset_figure
from .worked import whole_digits


class FigureFile:
    """One figure of the report: its file name, the matplotlib figure and its SVG.

    The SVG is drawn when first asked for, or for all figures at once by :func:`draw_figures`
    (in parallel): a section's markup needs only the file name, so no figure holds up the text.
    ``figure`` may be given as a ``build`` function instead, which makes the matplotlib figure
    where it is first needed: in the forked child that draws it, so that the report's process
    only writes text (creating a figure's axes costs as much as a third of drawing it).
    """

    def __init__(
        self,
        name: str,
        svg: bytes | None = None,
        figure: Any = None,
        t: Translator | None = None,
        number: str = "",
        key: str = "",
        build: Callable[[], Any] | None = None,
        symbols: SymbolTable = SYMBOLS,
    ):
        self.name = name
        self.number = (
            number  # as printed ("3.1", "Б.2"); "" for a figure made outside a numbered section
        )
        self.key = key  # the name its stage declares (``StagePresentation.figures``)
        # a figure of its inputs alone (figure_memo.MemoFigure): its SVG may be one drawn before
        self._inputs = getattr(build, "digest", None)
        self._figure = figure if figure is not None else getattr(build, "built", None)
        self._build = build
        self._svg = svg
        self._pdf: bytes | None = None  # the figure as a one-page PDF, for the printed report
        self._t = t  # the report's translator: the figure's text is typeset on drawing
        self._symbols = symbols  # the report's symbol table (its subscripts per language)
        self._typeset_in = (
            None  # the process that typeset the figure (a forked drawer's is not this one)
        )
        # Set while a forked child draws this figure, per what it draws ("svg", "pdf"): called
        # (once) to wait for that child's drawing instead of drawing the figure a second time here.
        self.awaiting: dict[str, Callable[[FigureFile], None]] = {}

    @property
    def drawn(self) -> bool:
        return self._svg is not None

    def has(self, kind: str) -> bool:
        """Whether the figure's ``"svg"`` or ``"pdf"`` drawing is there."""
        return (self._svg if kind == "svg" else self._pdf) is not None

    def keep(self, kind: str, drawing: bytes) -> None:
        """Keep the ``"svg"`` or ``"pdf"`` drawing a forked child made; nothing waits for it now."""
        if kind == "svg":
            self._svg = drawing
        else:
            self._pdf = drawing
        self.awaiting.pop(kind, None)

    @property
    def figure(self):
        """The matplotlib figure (built now if it was given as a function; the Word export draws
        it again as PNG)."""
        if self._figure is None and self._build is not None:
            self._figure = self._build()
        return self._figure

    def made_from(self, fig) -> bool:
        """Whether this is ``fig`` (a Figure, or the function that builds one), without building it."""
        return fig is self._figure or fig is self._build

    def typeset(self):
        """The matplotlib figure with its text typeset for the report's language, in this process
        (once; a figure drawn by a forked process was typeset there, not here)."""
        if self._t is not None and self._typeset_in != os.getpid():
            typeset_figure(self.figure, self._t, self._symbols)
            self._typeset_in = os.getpid()
        return self.figure

    def draw(self) -> bytes:
        """The SVG bytes, drawn now (labels typeset for the report's language, laid out), or
        the SVG this process drew of the same inputs (:mod:`crankdyn.report.figure_memo`)."""
        from .figures import to_svg  # lazy: heavy optional import (matplotlib)

        drawn = figure_memo.svg(self._inputs, self._t, self._symbols)
        if drawn is None:
            drawn = to_svg(self.typeset())
            figure_memo.keep(self._inputs, self._t, self._symbols, drawn)
        return drawn

    def draw_pdf(self) -> bytes:
        """The figure as a one-page PDF, drawn now (labels typeset, laid out as for its SVG)."""
        from .figures import to_pdf  # lazy: heavy optional import (matplotlib)

        return to_pdf(self.typeset())

    def _await_child(self, kind: str) -> None:
        awaiting = self.awaiting.pop(kind, None)
        if awaiting is not None:
            awaiting(self)

    @property
    def svg(self) -> bytes:
        if self._svg is None:
            self._await_child("svg")
        if self._svg is None:
            self._svg = self.draw()
        return self._svg

    @property
    def pdf(self) -> bytes | None:
        """The figure as a one-page PDF (the printed report places it as it is), or None for a
        figure given only as its SVG."""
        if self._pdf is None:
            self._await_child("pdf")
        if self._pdf is None and (self._figure is not None or self._build is not None):
            self._pdf = self.draw_pdf()
        return self._pdf

    def __repr__(self) -> str:
        return f"FigureFile({self.name!r}, drawn={self.drawn})"


def start_drawing(figures: Sequence[FigureFile], workers: int | None = None):
    """Start drawing the figures not drawn yet in forked children (one per CPU), leaving this
    process free; returns a callable that waits for them and stores the SVGs (drawing here what
    a child did not deliver), or None when there is nothing to draw or forking is not possible."""
    from .figures import (  # lazy: heavy optional import (matplotlib)
        ForkedDrawing,
        can_fork,
        default_workers,
    )

    pending = [f for f in figures if not f.drawn]
    workers = default_workers() if workers is None else workers
    if not pending or workers <= 1 or not can_fork(allow_threads=True):
        return None
    drawing = ForkedDrawing(
        [f.draw for f in pending], [list(range(k, len(pending), workers)) for k in range(workers)]
    )

    def finish() -> None:
        for figure, svg in zip(pending, drawing.finish(), strict=True):
            figure._svg = svg

    return finish


def draw_figures(
    figures: Sequence[FigureFile], workers: int | None = None, allow_threads: bool = False
) -> None:
    """Draw every figure not drawn yet, shared by ``workers`` processes (default: the CPUs;
    see :func:`crankdyn.report.figures.draw_jobs` for when it stays serial)."""
    from .figures import default_workers, draw_jobs  # lazy: heavy optional import (matplotlib)

    pending = [f for f in figures if not f.drawn]
    drawn = draw_jobs(
        [f.draw for f in pending], default_workers() if workers is None else workers, allow_threads
    )
    for figure, svg in zip(pending, drawn, strict=True):
        figure._svg = svg


def inline_figures(html: str, figures: Sequence[FigureFile]) -> str:
    """``html`` with every ``src="figures/NAME.svg"`` replaced by the figure as a data: URI."""
    for figure in figures:
        data = base64.b64encode(figure.svg).decode("ascii")
        html = html.replace(
            f'src="{FIGURE_DIR}/{figure.name}"', f'src="data:image/svg+xml;base64,{data}"'
        )
    return html


def exact_decimals(values: Sequence[float], most: int = 3) -> int:
    """The fewest decimals (at most ``most``) that print every one of ``values`` as it is: 0 for
    whole degrees, 1 for a V16 two-stroke's 22.5° (whole degrees would print it as 22)."""
    for decimals in range(most + 1):
        if all(abs(round(v, decimals) - v) <= 1e-9 * max(1.0, abs(v)) for v in values):
            return decimals
    return most


def bound_number(sentence: str, number: str) -> str:
    """``sentence`` with the table's or figure's ``number`` bound to the word before it by a
    no-break space ("рис. 7.1", "табл. 2.1": never parted at a line's end)."""
    return sentence.replace(f" {number}", f"\u00a0{number}")


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
    _subsection: int = 0
    stage_name: str = ""
    table_step_deg: float = 10.0
    cycle_deg: float = 720.0
    conclusions: list[str] = field(default_factory=list)
    #: the main results the abstract names (:meth:`find`), over the whole report
    findings: list[str] = field(default_factory=list)
    scene: Any = None
    worked: list = field(default_factory=list)  # WorkedBlock of every worked substitution shown
    #: a section's title for what this scene's section contains, when it differs from the
    #: stage's title (honest headings: a part left out is not announced); reset per section
    title: str | None = None
    #: the figure names the section's stage declares (``StagePresentation.figures``); None: not checked
    #: (the input section, a context built by hand)
    declared_figures: tuple[str, ...] | None = None
    #: the report's symbol table (the core's and the registry's stages', ``typeset.symbol_table``)
    symbols: SymbolTable = SYMBOLS
    #: the data every stage of the run provided, by contract (``StageOutput.data``): a section
    #: may show what a later stage made of its subject (:meth:`data`)
    run_data: dict[str, Any] = field(default_factory=dict)
    #: the contracts the section being rendered read through :meth:`data` (the preview's
    #: section cache renders it again when one of them changes)
    data_reads: set[str] = field(default_factory=set)

    def data(self, contract: str) -> Any:
        """What a stage of the run provided under ``contract``; None when no stage did."""
        self.data_reads.add(contract)
        return self.run_data.get(contract)

    def __post_init__(self) -> None:
        # Templates print angles and other plain numbers through ``|numg`` in the report's locale,
        # whoever built the environment (the report, the API's single sections, the tests).
        self.env.filters["numg"] = lambda value, significant=4: self.t.number_g(value, significant)
        self.env.filters["cyl"] = self.t.cylinder  # "1L" as this language prints it
        self.env.filters["firing_order_cell"] = self.t.firing_order_cell
        self.env.filters["angle"] = self.angle_text  # a crank angle: "372°", "75,4°"
        self.env.filters["degrees_and"] = self.t.degrees_and  # "450° і 270°"
        # the assignment's engine name within a sentence ("Об’єкт розрахунку – трициліндровий …")
        self.env.filters["inside_sentence"] = lambda name: names.inside_sentence(
            name, self.t.language
        )

    @property
    def worked_angle_deg(self) -> float:
        """The crank angle of the worked substitutions ([report] worked_angle_deg, default 30°)."""
        return float(getattr(getattr(self.scene, "report", None), "worked_angle_deg", 30.0))

    @property
    def last_table_number(self) -> str:
        return f"{self.section_number}.{self._table}"

    @property
    def last_figure_number(self) -> str:
        return f"{self.section_number}.{self._figure}"

    def start_section(
        self, number: int, stage_name: str, figures: tuple[str, ...] | None = None
    ) -> None:
        """Start numbering a section; ``figures``: the names its stage declares (``StagePresentation.figures``)."""
        self.section_number = number
        self.stage_name = stage_name
        self._equation = self._table = self._figure = self._subsection = 0
        self.title = None
        self.declared_figures = figures

    def check_figure_declared(self, name: str) -> None:
        """A stage draws only the figures it declares: a :class:`PluginError` naming the stage and
        the figure otherwise (the report's figure files are what ``StagePresentation.figures``
        announces)."""
        if self.declared_figures is not None and not declared(name, self.declared_figures):
            raise PluginError(
                f"stage {self.stage_name!r} drew the figure {name!r}, which it does not declare in "
                f"StagePresentation.figures (declared: {list(self.declared_figures)})"
            )

    # ----------------------------------------------------------------- numbering
    def equation(self, formula_html: str, label: str = "") -> Markup:
        """A displayed, numbered equation. ``formula_html`` is template-authored markup."""
        self._equation += 1
        number = f"{self.section_number}.{self._equation}"
        anchor = f' id="eq-{escape(label)}"' if label else ""
        return Markup(
            f'<div class="equation"{anchor}><span class="formula">{unbroken_parts(formula_html)}</span>'
            f'<span class="eqno">({number})</span></div>'
        )

    #: Body rows of a table that fit one page at the report's table type size (9.5 pt), after
    #: the caption and the header: a shorter table is kept on one page; a longer one breaks
    #: between rows and continues under "Table N continued" and the header (:func:`table_markup`).
    ROWS_PER_PAGE = 32
    ROWS_PER_LANDSCAPE_PAGE = 20
    #: A portrait table with more body rows than this may also break between rows where the page
    #: ends (at least three rows on either side, templates/report.css), rather than leave the rest
    #: of the page empty: a 29-row table kept whole left page 24 of the in-line four's note 72 % blank.
    BREAKABLE_ROWS = 12

    def table(
        self,
        columns: Sequence[tuple[str, Sequence[float] | Sequence[str], int | None]],
        caption: str,
        header_html: bool = True,
        css_class: str = "data",
        extremes: Sequence[TableExtreme] = (),
        see: bool | str = True,
    ) -> Markup:
        """A numbered table, referred to in a sentence before it. ``columns`` are (header
        markup, values, decimals or None for text). A long table continues on the next pages
        with the continuation label and the repeated header; a wide one goes on landscape pages.
        ``extremes``: rows added between the table step's rows (:func:`add_extreme_rows`), set in
        bold and named in a note under the table. ``see``: as :func:`table_markup`'s."""
        self._table += 1
        number = f"{self.section_number}.{self._table}"
        head = "".join(f"<th>{Markup(h) if header_html else escape(h)}</th>" for h, _, _ in columns)
        n_rows = len(columns[0][1]) if columns else 0
        marked = {e.position for e in extremes}
        # a column of words is centred as a text column, not set flush right as numbers are
        wordy = [
            decimals is None
            and not all(_NUMBER_TEXT.fullmatch(str(v)) or str(v) == "" for v in values)
            for _, values, decimals in columns
        ]
        # a column of large values keeps at most TABLE_SIGNIFICANT digits (877 306 N·m, not 877 306,3)
        columns = [(h, values, table_decimals(values, d)) for h, values, d in columns]
        rows = []
        for i in range(n_rows):
            cells = []
            for (_, values, decimals), words in zip(columns, wordy, strict=True):
                v = values[i]
                text = escape(v) if decimals is None else escape(self.t.fixed(v, decimals))
                text = text or "—"  # an empty cell gets a dash, as the standard asks
                css = ' class="text"' if words else ""
                # bold in the cells, not by a class: the Word export keeps it
                cells.append(
                    f"<td{css}><b>{text}</b></td>" if i in marked else f"<td{css}>{text}</td>"
                )
            rows.append(
                ('<tr class="extremum">' if i in marked else "<tr>") + "".join(cells) + "</tr>"
            )
        caption_text = escape(self.t("report.table_caption", number=number, caption=caption))
        return table_markup(
            self.t,
            number,
            caption_text,
            head,
            rows,
            css_class,
            see=see,
            note=self.extremes_note(extremes),
        )

    def angle_labels(self, labels: Sequence[float]) -> list[str]:
        """Crank angles as a table's first column: whole degrees without a decimal, an added
        extremum's angle with the digits the angle step resolves (372,5), in the report's locale."""
        return [self.angle_text(float(a)) for a in labels]

    def angle_text(self, angle_deg: float) -> str:
        """A crank angle as printed: whole degrees as they are; an angle between whole degrees with
        one decimal per decade the computation step is finer than 1 deg (at least one), since the
        step is the resolution an angle read off the grid has."""
        return self.t.angle(
            angle_deg, self.scene.analysis.angle_step_deg if self.scene is not None else None
        )

    def extremes_note(self, extremes: Sequence[TableExtreme]) -> str:
        """The note under a table that names its added extremum rows ("" without any)."""
        if not extremes:
            return ""
        items = self.t("doc.table_extremes_separator").join(
            self.t("doc.table_extreme_item", angle=self.angle_text(e.crank_angle_deg), what=e.what)
            for e in extremes
        )
        return self.t(
            "doc.table_extremes_note", step=self.t.number_g(self.table_step_deg, 6), items=items
        )

    def table_html(
        self,
        headers: Sequence[str],
        rows: Sequence[Sequence[str]],
        caption: str,
        css_class: str = "data",
        markup_columns: Sequence[int] = (),
        text_columns: Sequence[int] = (),
        see: bool | str = True,
    ) -> Markup:
        """A numbered table from text cells; ``markup_columns`` hold template-authored markup
        (symbols), every other cell is escaped; ``text_columns`` are set as text, not numbers. A
        cell given as (text, n) spans n columns (a stroke over several intervals); the column
        indices of ``markup_columns`` and ``text_columns`` count the cells of a row as given."""
        self._table += 1
        number = f"{self.section_number}.{self._table}"
        head = "".join(f"<th>{escape(h)}</th>" for h in headers)
        body = []
        for row in rows:
            cells = []
            for i, cell in enumerate(row):
                cell, span = cell if isinstance(cell, tuple) else (cell, 1)
                content = Markup(cell) if i in markup_columns else escape(cell)
                css = (' class="text"' if i in text_columns else "") + (
                    f' colspan="{span}"' if span > 1 else ""
                )
                cells.append(f"<td{css}>{content}</td>")
            body.append("<tr>" + "".join(cells) + "</tr>")
        caption_text = escape(self.t("report.table_caption", number=number, caption=caption))
        return table_markup(self.t, number, caption_text, head, body, css_class, see=see)

    def figure(
        self, fig, caption: str, name: str, see: str | None = None, see_params: dict | None = None
    ) -> Markup:
        """Number a matplotlib figure and return its markup (with the sentence that refers to it
        before it); its SVG is drawn afterwards (:func:`draw_figures`, or on first use).

        ``fig``: the figure, or better a function of no arguments that builds and returns it
        (called once, by the process that draws the figure: a forked child while this one goes
        on with the text). It is called after ``render`` has returned, so it must take what it
        draws as arguments (``functools.partial``) or from variables not changed afterwards.

        ``see``: the catalog key of that sentence, with ``{number}`` (default ``doc.see_figure``,
        which speaks of curves): a scheme or a vector diagram is announced as what it is;
        ``see_params``: its other placeholders ("the load on crank pin {k}")."""
        self.check_figure_declared(name)
        for (
            earlier
        ) in self.figures:  # the same Figure again (changed since?): draw the earlier state now
            if earlier.made_from(fig) and not earlier.drawn:
                earlier.svg  # noqa: B018 - drawn for its side effect
        self._figure += 1
        number = f"{self.section_number}.{self._figure}"
        # ASCII file names (an appendix figure "Б.1" -> fig_u411_1_...): safe in every file system and URL
        ascii_number = "".join(c if c.isascii() else f"u{ord(c):x}" for c in number)
        file_name = f"fig_{ascii_number.replace('.', '_')}_{name}.svg"
        built = None if callable(fig) else fig
        self.figures.append(
            FigureFile(
                file_name,
                figure=built,
                t=self.t,
                number=number,
                key=name,
                symbols=self.symbols,
                build=fig if built is None else None,
            )
        )
        caption_text = escape(self.t("report.figure_caption", number=number, caption=caption))
        # the number bound to the word before it ("рис. 7.1" never parted at a line's end)
        see = escape(
            bound_number(
                self.t(see or "doc.see_figure", number=number, **(see_params or {})), number
            )
        )
        # Referenced, not inlined: the SVG is stored once, as figures/<name>; a self-contained
        # page (RenderedReport.html) swaps the reference for a data: URI afterwards.
        # one block, so that the sentence never ends a page without the figure it announces
        return Markup(
            f'<div class="figure-block"><p class="see">{see}</p>'
            f'<figure data-number="{number}"><img alt="{escape(caption)}" src="{FIGURE_DIR}/{file_name}">'
            f"<figcaption>{caption_text}</figcaption></figure></div>"
        )

    def subsection(self, title: str) -> Markup:
        """A numbered subsection's heading ("4.2 Title", DSTU 3008:2015, 6.2: subsections are numbered
        within their section), listed in the table of contents."""
        self._subsection += 1
        number = f"{self.section_number}.{self._subsection}"
        return Markup(
            f'<h3 class="subsection" id="sec-{escape(number)}">{escape(number)} {escape(title)}</h3>'
        )

    def figure_number(self, key: str) -> str | None:
        """The printed number of a figure an earlier section drew under ``key`` (a stage's declared
        figure name, e.g. the drawing's "scheme"), for a reference from a later section; None if none."""
        return next((f.number for f in self.figures if f.key == key and f.number), None)

    # ----------------------------------------------------------------- text
    def conclude(self, sentence: str) -> str:
        """Add a sentence to the report's conclusions (returns "" for use in templates)."""
        self.conclusions.append(sentence)
        return ""

    def find(self, phrase: str) -> str:
        """Add one of the main results to the abstract ("the largest gas pressure 5,1 MPa at
        α = 372°": a phrase, joined with the others into one sentence); returns ""."""
        self.findings.append(phrase)
        return ""

    def num(self, value: float, significant: int = 4) -> str:
        return self.t.number(value, significant)

    #: Relative differences below this are rounding: said in words ("practically zero"), not
    #: printed as 3,9·10⁻¹⁶ or as a bound such as "< 10⁻¹²".
    ROUNDING_LEVEL = 1e-12

    def deviation(self, relative: float, significant: int = 2) -> str:
        """A relative difference of a check: "practically zero" at the level of rounding (a number
        such as 3,9·10⁻¹⁶, or a bound on it, reads as a program's precision where it only says
        that two calculations agree)."""
        if abs(relative) < self.ROUNDING_LEVEL:
            return self.t("doc.rounding_difference")
        return self.t.number(relative, significant)

    def render_template(self, name: str, **values: Any) -> str:
        if "numg" not in self.env.filters:  # "372°", "7,5°": a number without padding zeros
            self.env.filters["numg"] = lambda value, significant=4: self.t.number_g(
                value, significant
            )
        if "cyl" not in self.env.filters:
            self.env.filters["cyl"] = self.t.cylinder
        self.env.filters["angle"] = self.angle_text  # this report's step
        self.env.filters["degrees_and"] = self.t.degrees_and
        template = self.env.get_template(name)
        return template.render(ctx=self, _=self.t, num=self.num, eq=self.equation, **values)


def table_markup(
    t,
    number: str,
    caption_html: str,
    head_html: str,
    rows: Sequence[str],
    css_class: str = "data",
    see: bool | str = True,
    note: str = "",
) -> Markup:
    """A numbered table's markup: the sentence referring to it, the caption, the header and the rows.

    ``see``: the catalog key of the sentence referring to the table, with ``{number}`` (True: the
    general ``doc.see_table``, "the results are given in table N"; False: none, the stage's text
    refers to the table itself).

    A table of more rows than :attr:`RenderContext.BREAKABLE_ROWS` (landscape: a page's) may break between rows
    where the page ends, wherever it starts; the printed page repeats the header
    (``thead``) and heads each page it continues on with "Table N continued": every row carries
    that label, and the page's top margin shows the label of the row the page starts with
    (``string-set`` in templates/report.css)."""
    wide = "wide" in css_class.split() and not fits_portrait(head_html, rows)
    limit = RenderContext.ROWS_PER_LANDSCAPE_PAGE if wide else RenderContext.BREAKABLE_ROWS
    long = len(rows) > limit
    if long:
        label = escape(t("doc.continued", number=number))
        rows = [
            f'<tr data-continued="{label}"' + r[len("<tr") :] if r.startswith("<tr") else r
            for r in rows
        ]
    head = f"<thead><tr>{head_html}</tr></thead>"
    see_key = see if isinstance(see, str) else "doc.see_table"
    return Markup(
        f'<div class="table-block{" long" if long else ""}{" landscape" if wide else ""}">'
        + (
            f'<p class="see">{escape(bound_number(t(see_key, number=number), number))}</p>'
            if see
            else ""
        )
        + f'<table class="{css_class}" data-number="{number}"><caption>{caption_html}</caption>'
        f"{head}<tbody>{''.join(rows)}</tbody></table>"
        + (f'<p class="table-note">{escape(note)}</p>' if note else "")
        + "</div>"
    )


@dataclass(frozen=True)
class TableExtreme:
    """A row added to a printed table at the grid point of an extremum that the table step misses."""

    position: int  # the row's place in the table
    crank_angle_deg: float
    what: str  # what is largest or least there, in the report's language


def add_extreme_rows(
    crank_angle_deg: np.ndarray,
    rows: np.ndarray,
    labels: np.ndarray,
    extremes: Sequence[tuple[np.ndarray, str, str]],
    resolution: float = 0.01,
) -> tuple[np.ndarray, np.ndarray, list[TableExtreme]]:
    """A printed table's rows (:func:`sample_rows`) with a row added at each extremum that the
    table step misses: a 30° table would otherwise miss the peak combustion pressure and the
    largest forces, which are what a strength calculation takes.

    ``extremes``: (values on the angle grid, ``"max"`` or ``"min"``, what it is). A row is added
    at the grid point of the largest (least) value unless a row of the table already shows a
    value within ``resolution`` of the values' range of it; extremes at one point share a row.
    Returns the grid indices, the angle labels (deg) and the added rows, in angle order.
    """
    present = set(int(r) for r in rows)
    added: dict[int, list[str]] = {}
    for values, kind, what in extremes:
        values = np.asarray(values, dtype=float)
        sign = 1.0 if kind == "max" else -1.0
        # the first in the cycle of equal extremes (a periodic torque's), as the conclusions say
        index = first_extremum_index(values, kind)
        shown = float(np.max(sign * values[np.asarray(rows, dtype=int)]))
        span = float(np.ptp(values))
        if index not in present and sign * values[index] - shown > resolution * span:
            added.setdefault(index, []).append(what)
    rows_list, labels_list = [int(r) for r in rows], [float(a) for a in labels]
    for index in sorted(added, key=lambda k: float(crank_angle_deg[k])):
        angle = float(crank_angle_deg[index])
        at = int(np.searchsorted(np.asarray(labels_list), angle, side="right"))
        rows_list.insert(at, index)
        labels_list.insert(at, angle)
    # an added index is not on the table step's grid, so it is in the table once
    marks = [
        TableExtreme(position=i, crank_angle_deg=labels_list[i], what=", ".join(added[r]))
        for i, r in enumerate(rows_list)
        if r in added
    ]
    return np.asarray(rows_list, dtype=int), np.asarray(labels_list), marks


#: Portrait text width (A4 less the 30 mm and 15 mm margins: 165 mm) left for a table, with room
#: to spare for the estimate's error, in mm; a character of the 9.5 pt table type is about 1.55 mm
#: wide (Liberation Serif: digits 0.5 em, lower-case letters 0.45 em on average), a cell's padding
#: and rules about 2.7 mm. The page-layout test checks that nothing reaches into the margin.
PORTRAIT_TABLE_MM, CHAR_MM, CELL_PADDING_MM = 158.0, 1.55, 2.7
#: A text cell wraps at spaces; it is given at most this many characters of width.
WRAP_CHARS = 20

_CELL = re.compile(r"<t[hd][^>]*>(.*?)</t[hd]>", re.S)
#: A cell that is a number as printed ("−1 234,5", "372,5", "1,2·10⁻³", "0,6150 кг"), not words.
#: The most significant digits a table column's largest value is given with: a big engine's
#: torque of 877 306 N·m to a tenth (seven digits) claims more than its inputs hold.
TABLE_SIGNIFICANT = 6


def table_decimals(values, decimals: int | None) -> int | None:
    """The decimals a numeric column is printed with: ``decimals``, fewer where its largest value
    would otherwise show more than :data:`TABLE_SIGNIFICANT` digits (None: a text column)."""
    if decimals is None:
        return None
    whole = whole_digits([v for v in values if isinstance(v, (int, float, np.floating))])
    if whole is None or whole < 1:  # below 1: nothing to cap
        return decimals
    return max(0, min(decimals, TABLE_SIGNIFICANT - whole))


_NUMBER_TEXT = re.compile(
    r"[−\-+]?[\d\s\u00a0\u202f,.]*\d(?:·10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)?"
    r"(?:[\s\u00a0\u202f][^\d\s]{1,8})?(?:\s\([^()]*\))?"
)


def _text(markup: str) -> str:
    return html_lib.unescape(re.sub(r"<[^>]+>", "", markup))


def fits_portrait(head_html: str, rows: Sequence[str]) -> bool:
    """Whether a table asked to be wide still fits a portrait page at the table type size: the
    widest cell of each column (a header wraps at its words, a text cell at its spaces) summed.
    A landscape page is kept for tables that need one, because each starts a page of its own
    and would leave the page before it short."""
    headers = [_text(h) for h in _CELL.findall(head_html)]
    widths = [max((len(w) for w in h.split()), default=1) for h in headers]
    for row in rows:
        for i, cell in enumerate(_CELL.findall(row)[: len(widths)]):
            text = _text(cell).strip()
            widths[i] = max(widths[i], len(text) if len(text) <= WRAP_CHARS else WRAP_CHARS)
    return sum(widths) * CHAR_MM + len(widths) * CELL_PADDING_MM <= PORTRAIT_TABLE_MM


def sample_rows(
    crank_angle_deg: np.ndarray, table_step_deg: float, span_deg: float | None = None
) -> tuple[np.ndarray, np.ndarray]:
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
    return [str(templates_dir())] + [str(p) for p in extra if p is not None]
