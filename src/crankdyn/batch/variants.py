"""``crankdyn batch VARIANTS.csv --base SCENE -o DIR``: one report per student variant.

Each CSV row overrides fields of the base scene (columns are dotted scene paths such
as ``engine.bore``; an optional ``variant`` column names the row's folder). Rows run
in parallel in worker processes through the same code path as ``crankdyn report``
(:func:`crankdyn.pipeline.write_report`); a row that fails is recorded with its error
and the others go on. At the end the batch writes an answer key of the main results
(``answer_key.csv`` and ``.xlsx``) and, if rows failed, ``failures.csv``.
"""

from __future__ import annotations

import contextlib
import csv
import hashlib
import io
import math
import os
import re
import signal
import sys
import time
import tomllib
import uuid
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any, TextIO

from ..errors import CrankdynError, Problem, SceneError, UsageError
from ..output import pipeline  # noqa: F401 - loaded here, so forked batch workers inherit them
from ..output import writers as outputs  # noqa: F401 - loaded here, so forked batch workers inherit them
from ..output.manifest import MANIFEST, check_outputs, write_outputs
from ..output.pipeline import run_and_render
from ..output.writers import xlsx_bytes
from ..parallel.pool import (
    DEFAULT_TIMEOUT_S,
    check_seconds,
    connect,
    run_all,
    run_all_dask,
    stop_signals,
)
from ..plugin.registry import Registry, default_registry
from ..report import i18n
from ..report.i18n import available_languages
from ..scene.model import merge, scene_from_dict
from . import answer_key  # noqa: F401 - loaded here, so forked batch workers inherit them

VARIANT_COLUMN = "variant"

#: Variants of one run: the rows of a batch CSV, the points of a sweep (``crankdyn sweep`` and
#: :func:`crankdyn.api.sweep` alike). Checked from the counts before any list of variants is built.
MAX_VARIANTS = 100_000

#: Fields of one run: the override columns of a batch CSV, the swept and fixed fields of a sweep,
#: the names of an API grid. A scene has a few dozen fields; this leaves room for all of them.
MAX_FIELDS = 200

#: Bytes of a batch's variants file, checked before it is read: 100 000 rows of a few dozen short
#: cells take a few MB; a file far larger is not a class's variants.
MAX_VARIANTS_FILE_BYTES = 64 * 1024 * 1024

#: Characters of a variant's folder name. A longer id is cut and ends in ``-`` and 8 hex digits of
#: the SHA-256 of the whole id, so the name stays stable between runs and distinct between ids.
MAX_VARIANT_NAME_CHARS = 80

#: UTF-8 bytes of a variant's folder name (file systems allow 255 bytes per name).
MAX_VARIANT_NAME_BYTES = 160

#: The batch's own files in its output folder (compared case-insensitively): no variant id may be
#: one of them, or its folder would take the place of the answer key, failure list or manifest.
KEY_FILE_NAMES = ("answer_key.csv", "answer_key.xlsx", "failures.csv")
"""The files a batch writes in its output folder besides one folder per variant."""
RESERVED_NAMES = frozenset(
    n.casefold()
    for n in ("answer_key.csv", "answer_key.xlsx", "answer_key.parquet", "failures.csv", MANIFEST)
)

# The answer key's columns are declared by the stages (``Stage.answer_columns``) and
# collected from the registry by :mod:`crankdyn.answer_key`; this module names no result key.


@dataclass
class Variant:
    row: int  # 1-based data row (the header is row 0)
    name: str  # folder name below DIR
    overrides: dict[str, Any]  # nested dict laid over the base scene
    cells: dict[str, str]  # the row's cells as written, for the answer key
    error: str | None = None  # a problem with the row itself (e.g. a duplicate variant id)


@dataclass
class Outcome:
    row: int
    name: str
    ok: bool
    seconds: float = 0.0
    error: str = ""
    answers: dict[str, Any] = field(default_factory=dict)
    stages_run: list[str] = field(default_factory=list)
    absent: list[str] = field(
        default_factory=list
    )  # answer-key columns whose key its stage's results lack
    files: int = 0
    rendered: dict[str, bytes] | None = None  # files rendered on a Dask worker, until written here


@dataclass
class BatchReport:
    out_dir: Path
    outcomes: list[Outcome]
    seconds: float
    written: list[Path]
    interrupted: bool = False  # Ctrl-C or SIGTERM ended the run; unfinished variants failed
    warnings: list[str] = field(
        default_factory=list
    )  # for the user, once per batch (answer_key.unanswered)
    stop_signal: int = 0  # the signal that ended it (signal.SIGINT, signal.SIGTERM), 0 if none

    @property
    def failures(self) -> list[Outcome]:
        return [o for o in self.outcomes if not o.ok]


# --------------------------------------------------------------------------- reading the CSV


def parse_cell(text: str) -> Any:
    """A CSV cell as a TOML value: ``82`` -> 82, ``0.28`` -> 0.28, ``true``, ``[1, 3, 4, 2]``;
    anything that is not a TOML value (``82 mm``, ``Ivanenko I.``) stays the string it is."""
    text = text.strip()
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except (tomllib.TOMLDecodeError, RecursionError):  # "[[[[…" nested beyond the parser's depth
        return text


def _nest(path: str, value: Any) -> dict:
    out: Any = value
    for part in reversed(path.split(".")):
        out = {part: out}
    return out


_DECIMAL_COMMA = re.compile(r"^([-+]?\d+),(\d+(?:[eE][-+]?\d+)?)(\s*[^\d,\s][^,]*)?$")


def _decimal_point(text: str) -> str:
    match = _DECIMAL_COMMA.match(text)
    return f"{match[1]}.{match[2]}{match[3] or ''}" if match else text


_SAFE = re.compile(r"[^\w.-]+", re.UNICODE)


def read_variants(csv_path: Path) -> tuple[list[str], list[Variant]]:
    """The override columns and the rows of ``csv_path``; a malformed file raises SceneError."""

    source = str(csv_path)
    rows, decimal_comma = _csv_rows(_read_variants_text(csv_path, source), source)
    # Blank rows are skipped but still counted, so row numbers match the spreadsheet's.
    numbered = [(k, r) for k, r in enumerate(rows) if any(c.strip() for c in r)]
    if not numbered:
        raise SceneError(
            Problem(
                "variants",
                source,
                "empty file; the first row names the scene fields, "
                "e.g. variant,report.student,engine.bore",
            ),
            source,
        )
    header = [h.strip() for h in numbered[0][1]]
    _check_size(source, sum(h != VARIANT_COLUMN for h in header), len(numbered) - 1)
    fields = _header_fields(source, header)
    return fields, _variants(numbered, header, fields, decimal_comma, source)


def _read_variants_text(csv_path: Path, source: str) -> str:
    """The text of the variants file; a missing, oversized or unreadable file raises SceneError."""
    try:
        if not csv_path.is_file():
            if csv_path.exists():
                raise SceneError(Problem("variants", source, "not a regular file"), source)
        elif csv_path.stat().st_size > MAX_VARIANTS_FILE_BYTES:
            raise SceneError(
                Problem(
                    "variants",
                    source,
                    f"a variants file may be at most "
                    f"{MAX_VARIANTS_FILE_BYTES} bytes (it has "
                    f"{csv_path.stat().st_size})",
                ),
                source,
            )
        return csv_path.read_text(encoding="utf-8-sig")  # Excel writes a BOM
    except FileNotFoundError:
        raise SceneError(Problem("variants", source, "file not found"), source) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(
            Problem(
                "variants", source, f"cannot read the file as UTF-8 CSV ({exc.__class__.__name__})"
            ),
            source,
        ) from None


def _csv_rows(text: str, source: str) -> tuple[list[list[str]], bool]:
    """The rows of the CSV text in its sniffed dialect, and whether its numbers take the decimal
    comma."""
    sample = text[:4096]
    try:
        dialect = csv.Sniffer().sniff(sample, delimiters=",;\t")
    except csv.Error:
        dialect = csv.excel
    try:
        rows = list(csv.reader(io.StringIO(text), dialect))
    except csv.Error as exc:  # a cell beyond the csv module's field size limit, a NUL byte
        raise SceneError(
            Problem("variants", source, f"not a readable CSV file: {exc}"), source
        ) from None
    # A semicolon- or tab-separated file usually comes from a spreadsheet in a locale with the
    # decimal comma: read "0,28" and "82,5 mm" as 0.28 and "82.5 mm" there.
    return rows, dialect.delimiter != ","


def _variants(numbered, header, fields, decimal_comma: bool, source: str) -> list[Variant]:
    """The variants of the file's non-blank rows after the header (``numbered``: (record, cells));
    a variant id that names one of the batch's own files raises SceneError."""
    variants: list[Variant] = []
    names: dict[str, int] = {}
    reserved: list[Problem] = []
    header_index = numbered[0][0]
    width = max(2, len(str(numbered[-1][0] - header_index)))
    for record, cells in numbered[1:]:
        row_number = record - header_index
        row, error = _row_cells(cells, header, decimal_comma)
        wanted = row.get(VARIANT_COLUMN, "") or f"{row_number:0{width}d}"
        name = folder_name(wanted, f"{row_number:0{width}d}")
        if wanted.casefold() in RESERVED_NAMES or name.casefold() in RESERVED_NAMES:
            reserved.append(_reserved_name_problem(row_number, wanted))
        if name in names:
            error = (
                error
                or f"variant id {wanted!r} is used by row {names[name]} too; ids must be unique"
            )
            name = f"{name}__row{row_number}"
        names.setdefault(name, row_number)
        variants.append(Variant(row_number, name, _row_overrides(row, fields), row, error))
    if reserved:
        raise SceneError(reserved, source)
    return variants


def _row_cells(cells: list[str], header: list[str], decimal_comma: bool) -> tuple[dict, str | None]:
    """A row's cells by column name (a short row padded with empty cells), and the error of a row
    with more filled cells than the header names."""
    error = None
    if len(cells) > len(header) and any(c.strip() for c in cells[len(header) :]):
        error = f"row has {len(cells)} cells but the header names {len(header)} columns"
    cells = (cells + [""] * len(header))[: len(header)]
    row = dict(
        zip(
            header,
            (_decimal_point(c.strip()) if decimal_comma else c.strip() for c in cells),
            strict=True,
        )
    )
    return row, error


def _row_overrides(row: dict, fields: list[str]) -> dict:
    """The scene overrides of a row's filled cells."""
    overrides: dict = {}
    for name in fields:
        if row[name] != "":  # an empty cell keeps the base scene's value
            overrides = merge(overrides, _nest(name, parse_cell(row[name])))
    return overrides


def _reserved_name_problem(row_number: int, wanted: str) -> Problem:
    """The problem of a variant id that names one of the batch's own files."""
    own = ", ".join(sorted(RESERVED_NAMES))
    return Problem(
        f"row {row_number}, column {VARIANT_COLUMN}",
        wanted,
        f"a name of the batch's own files ({own}); give the variant another id",
    )


def _header_fields(source: str, header: list[str]) -> list[str]:
    """The scene fields a variants file's header names; a malformed header raises SceneError."""
    problems = []
    seen: set[str] = set()
    for i, name in enumerate(header, start=1):
        if not name:
            problems.append(
                Problem(
                    f"column {i}", name, "empty column name; name a scene field such as engine.bore"
                )
            )
        elif name in seen:
            problems.append(Problem(f"column {i}", name, "named twice"))
        elif name != VARIANT_COLUMN and (
            any(not part for part in name.split(".")) or not re.fullmatch(r"[A-Za-z_][\w.]*", name)
        ):
            problems.append(
                Problem(
                    f"column {i}",
                    name,
                    "not a dotted scene path such as engine.bore or "
                    "cycle.rounding.ignition_advance_deg",
                )
            )
        seen.add(name)
    fields = [h for h in header if h != VARIANT_COLUMN]
    for a in fields:
        for b in fields:
            if b.startswith(a + "."):
                problems.append(
                    Problem(f"column {b}", b, f"conflicts with column {a}: give one or the other")
                )
    if not fields:
        problems.append(Problem("variants", ",".join(header), "no column overrides a scene field"))
    if problems:
        raise SceneError(problems, source)
    return fields


def _check_size(source: str, fields: int, rows: int) -> None:
    """At most :data:`MAX_FIELDS` override columns and :data:`MAX_VARIANTS` rows (not blank)."""
    problems = []
    if fields > MAX_FIELDS:
        problems.append(
            Problem(
                "variants",
                f"{fields} scene field columns",
                f"at most {MAX_FIELDS} scene fields (besides the {VARIANT_COLUMN} column)",
            )
        )
    if rows > MAX_VARIANTS:
        problems.append(
            Problem("variants", f"{rows} rows", f"at most {MAX_VARIANTS} variants in one batch")
        )
    if problems:
        raise SceneError(problems, source)


def folder_name(wanted: str, fallback: str) -> str:
    """The folder of the variant ``wanted``: its id with only letters, digits, ``_ . -`` kept
    (``fallback`` when nothing is left), cut to :data:`MAX_VARIANT_NAME_CHARS` with a stable hash
    suffix when longer."""
    name = _SAFE.sub("_", wanted).strip("._") or fallback
    if len(name) <= MAX_VARIANT_NAME_CHARS and len(name.encode("utf-8")) <= MAX_VARIANT_NAME_BYTES:
        return name
    suffix = "-" + hashlib.sha256(wanted.encode("utf-8", "surrogatepass")).hexdigest()[:8]
    head = name[: MAX_VARIANT_NAME_CHARS - len(suffix)]
    while len(head.encode("utf-8")) > MAX_VARIANT_NAME_BYTES - len(suffix):
        head = head[:-1]
    head = head.rstrip("._-")
    return head + suffix if head else suffix[1:]


# --------------------------------------------------------------------------- one row


def _registry_or_default(registry: Registry | None) -> Registry:
    return registry if registry is not None else default_registry()


def _dask_worker():
    """The Dask worker this code runs in, or None (any other process or thread)."""
    if "distributed" not in sys.modules:  # a Dask worker has it loaded; nothing else needs it
        return None
    from distributed import get_worker  # lazy: heavy optional import (the dask extra)

    try:
        return get_worker()
    except ValueError:
        return None


class VariantRun:
    """One batch's or sweep's run of its variants: the plugin registry every variant is computed
    with, built once for the run, and what :meth:`warm` loaded for it.

    Its methods are what the workers run (``run.run_variant``). A local worker is forked from the
    process that warmed the run and inherits both. A Dask task gets a pickled copy without them
    (plugins' functions do not pickle): the worker keeps the state of the run it serves on itself
    (the attribute ``crankdyn_run``) and builds the registry once for the run, in :meth:`warm`,
    which runs before every task.
    """

    def __init__(self, registry: Registry | None = None):
        self.key = uuid.uuid4().hex  # which run a Dask worker's kept state belongs to
        self._local: dict[str, Any] = {} if registry is None else {"registry": registry}

    def __getstate__(self) -> dict[str, Any]:
        return {"key": self.key, "_local": {}}

    def _state(self) -> dict[str, Any]:
        """This run's state in this process: the run's own, or on a Dask worker the worker's
        (each task brings a fresh copy of the run; the worker keeps one run's state)."""
        worker = _dask_worker()
        if worker is None:
            return self._local
        key, state = getattr(worker, "crankdyn_run", (None, None))
        if key != self.key or state is None:
            state = {}
            worker.crankdyn_run = (self.key, state)
        return state

    @property
    def registry(self) -> Registry:
        state = self._state()
        if "registry" not in state:
            state["registry"] = default_registry()
        return state["registry"]

    def warm(self, formats: Iterable[str] = (), languages: Iterable[str] = ()) -> None:
        """Build the run's registry and load, once per process, everything a variant would
        otherwise load for itself: forked workers inherit it.

        Beyond the plugins and the report code: matplotlib with a first figure drawn to SVG (its
        font list, text layout and mathtext parser), the translators of ``languages`` (Babel's
        locale data) and, for PDFs, WeasyPrint with a first page laid out (fontconfig). Without
        this, every variant's worker process would pay for each of them again.
        """
        formats, languages = set(formats), tuple(languages)
        wanted = {f"format:{f}" for f in formats & {"html", "pdf", "docx"}} | {
            f"language:{x}" for x in languages
        }
        warmed = self._state().setdefault("warmed", set())
        if (
            warmed and wanted <= warmed
        ):  # a Dask worker calls this before every task: once is enough
            return
        warmed.update(wanted | {"plugins"})
        _load_for(self.registry, formats, languages)

    def run_variant(
        self,
        base: dict,
        base_dir: str,
        variant: Variant,
        out_dir: str,
        formats: list[str],
        language: str | None,
        stages: list[str] | None,
        data_dirs: tuple[str, ...] = (),
        return_files: bool = False,
        force: bool = False,
    ) -> Outcome:
        """:func:`run_variant` with the run's registry."""
        return run_variant(
            base,
            base_dir,
            variant,
            out_dir,
            formats,
            language,
            stages,
            data_dirs,
            return_files,
            force,
            self.registry,
        )


def warm(
    formats: Iterable[str] = (), languages: Iterable[str] = (), registry: Registry | None = None
) -> None:
    """Load what a variant would load for itself (:meth:`VariantRun.warm`), for one run."""
    VariantRun(registry).warm(formats, languages)


def _load_for(registry: Registry, formats: set[str], languages: tuple[str, ...]) -> None:
    for language in languages:
        if language in i18n.available_languages():
            i18n.translator(language, registry.catalogs).number(1.5)
    if formats & {"html", "pdf", "docx"}:
        from ..report import document  # noqa: F401  # lazy: heavy optional import (jinja2: pre-loaded only for HTML/PDF)
        from ..report.figures import new_figure, to_svg  # lazy: heavy optional import (matplotlib)

        fig, axes = new_figure(4.0, 3.0)
        axes.plot([0.0, 1.0], [0.0, 1.0], label="λ")
        axes.set_xlabel(r"$\varphi$, °")
        axes.legend()
        to_svg(fig)
    if "pdf" in formats:
        from ..report.pdf import html_to_pdf  # lazy: heavy optional import (weasyprint)

        html_to_pdf("<p>crankdyn</p>")


def run_variant(
    base: dict,
    base_dir: str,
    variant: Variant,
    out_dir: str,
    formats: list[str],
    language: str | None,
    stages: list[str] | None,
    data_dirs: tuple[str, ...] = (),
    return_files: bool = False,
    force: bool = False,
    registry: Registry | None = None,
) -> Outcome:
    """Compute and write one variant; never raises (an error is part of the outcome).

    With ``return_files`` the files are rendered in memory and returned in ``Outcome.rendered``
    instead of written (a Dask worker on another machine: the client writes them); with no
    ``formats`` nothing is rendered, only the answers are kept (a sweep without per-point files).
    ``registry``: the run's plugins (by default the installed ones).
    """
    start = time.perf_counter()
    if variant.error:
        return Outcome(variant.row, variant.name, False, 0.0, variant.error)
    try:
        registry = _registry_or_default(registry)
        scene = _variant_scene(base, base_dir, variant, language, data_dirs, registry)
        result, files = _compute(scene, formats, stages, registry)
        rendered = None
        if return_files:
            rendered, count = files, len(files)
        elif formats:
            count = len(write_outputs(Path(out_dir) / variant.name, files, force=force))
        else:
            count = 0

        document = outputs.results_document(result)
        columns = answer_key.answer_columns(registry)
        return Outcome(
            variant.row,
            variant.name,
            True,
            time.perf_counter() - start,
            answers=answer_key.answers(document, columns),
            stages_run=list(result.stages_run),
            files=count,
            rendered=rendered,
            absent=answer_key.absent(document, columns),
        )
    except Exception as exc:  # noqa: BLE001 - one bad row must not stop the batch
        return Outcome(
            variant.row, variant.name, False, time.perf_counter() - start, error_text(exc)
        )


def error_text(exc: Exception) -> str:
    """A variant's error as its failure row states it."""
    if isinstance(exc, SceneError):
        return "invalid scene: " + "; ".join(str(p) for p in exc.problems)
    if isinstance(exc, CrankdynError):
        return str(exc).replace("\n", " ")
    return f"internal error: {exc.__class__.__name__}: {exc}"


def _variant_scene(
    base: dict,
    base_dir: str,
    variant: Variant,
    language: str | None,
    data_dirs: tuple[str, ...],
    registry: Registry | None = None,
):
    """The base scene with the variant's overrides, its id on the title page and the batch's language."""

    data = merge(base, variant.overrides)
    if "variant" not in variant.overrides.get("report", {}):  # the title page names its own variant
        data = merge(
            data, {"report": {"variant": variant.cells.get(VARIANT_COLUMN) or variant.name}}
        )
    if language:
        data = merge(data, {"report": {"language": language}})
    return scene_from_dict(
        data,
        base_dir=base_dir,
        source=f"row {variant.row}",
        data_dirs=data_dirs,
        registry=_registry_or_default(registry),
    )


def _compute(scene, formats: list[str], stages: list[str] | None, registry: Registry):
    """(run result, rendered files) through the one path of ``crankdyn report``; one process per
    variant (the batch's ``--jobs`` share the CPUs between variants, not between figures)."""

    return run_and_render(scene, registry, formats, stages, available_languages(), figure_workers=1)


def answers(document: dict, registry: Registry | None = None) -> dict[str, Any]:
    """The answer-key values of one results.json document (missing stages give None)."""
    return answer_key.answers(document, answer_key.answer_columns(_registry_or_default(registry)))


# --------------------------------------------------------------------------- the batch


def available_cores() -> int:
    """The cores this process may run on (a container's CPU set, not the host's count)."""
    try:
        return len(os.sched_getaffinity(0)) or 1
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


class Progress:
    """A text progress bar on stderr; one line per finished row when stderr is not a terminal."""

    def __init__(self, total: int, stream: TextIO | None = None, enabled: bool = True):
        self.total, self.done, self.failed = total, 0, 0
        self.stream = stream or sys.stderr
        self.enabled = enabled
        self.tty = enabled and hasattr(self.stream, "isatty") and self.stream.isatty()
        self.start = time.perf_counter()

    def update(self, outcome: Outcome) -> None:
        self.done += 1
        self.failed += not outcome.ok
        if not self.enabled:
            return
        elapsed = time.perf_counter() - self.start
        eta = elapsed / self.done * (self.total - self.done)
        width = 30
        filled = int(round(width * self.done / self.total)) if self.total else width
        bar = "#" * filled + "." * (width - filled)
        status = f"[{bar}] {self.done}/{self.total}  failed {self.failed}  {elapsed:5.1f} s  eta {eta:4.0f} s"
        if self.tty:
            self.stream.write("\r" + status)
            if self.done == self.total:
                self.stream.write("\n")
        else:
            verdict = "ok" if outcome.ok else "FAILED"
            self.stream.write(f"{status}  row {outcome.row} {outcome.name}: {verdict}\n")
        self.stream.flush()


@dataclass
class RunOptions:
    """How a batch or sweep runs its variants (the command line's options)."""

    formats: list[str]
    jobs: int | None = None  # local worker processes (default: the available cores)
    language: str | None = None
    stages: list[str] | None = None
    progress: bool = True
    on_outcome: Callable[[Outcome], None] | None = None
    timeout: float | None = None  # seconds per variant (default 120)
    data_dirs: tuple[str, ...] = ()
    scheduler: str | None = None  # a Dask scheduler's address: the variants run on that cluster
    connect_timeout: float = 10.0  # seconds to reach the scheduler
    force: bool = False  # replace files in the output folder that crankdyn did not write


def run_batch(
    csv_path: Path,
    base_path: Path,
    out_dir: Path,
    formats: Iterable[str] = ("html", "pdf", "json", "csv"),
    jobs: int | None = None,
    language: str | None = None,
    stages: list[str] | None = None,
    progress: bool = True,
    on_outcome: Callable[[Outcome], None] | None = None,
    timeout: float | None = None,
    data_dirs: tuple[str, ...] = (),
    scheduler: str | None = None,
    connect_timeout: float = 10.0,
    force: bool = False,
    registry: Registry | None = None,
) -> BatchReport:
    """Run every row of ``csv_path`` over ``base_path``; write the reports, the answer key and the failures.

    ``registry``: the plugins the variants are computed with (by default the installed ones).

    Each row runs in a worker process limited to ``timeout`` seconds (default 120) — on this
    machine, or on the Dask cluster whose scheduler is at ``scheduler``; Ctrl-C or SIGTERM stops
    the workers, and the answer key and failure list are still written for what finished.
    """

    start = time.perf_counter()
    options = RunOptions(
        list(formats),
        jobs,
        language,
        stages,
        progress,
        on_outcome,
        timeout,
        data_dirs,
        scheduler,
        connect_timeout,
        force,
    )
    check_options(options)
    base, base_dir = load_base(base_path)
    fields, variants = read_variants(Path(csv_path))
    check_outputs(Path(out_dir), KEY_FILE_NAMES, force=force)  # refused before hours of computing
    run = VariantRun(registry)
    outcomes, stop_signal = execute(variants, base, base_dir, out_dir, options, run)
    # The manifest removes an earlier run's failures.csv when every row succeeded this time.
    language = batch_language(base, options)
    written = write_outputs(
        Path(out_dir),
        key_files(fields, outcomes, variants, language=language, registry=run.registry),
        force=force,
    )
    return BatchReport(
        Path(out_dir),
        outcomes,
        time.perf_counter() - start,
        written,
        bool(stop_signal),
        key_warnings(outcomes, run.registry),
        stop_signal,
    )


def check_options(options: RunOptions) -> None:
    """The time limits of ``options`` within (0, MAX_TIMEOUT_S] seconds; UsageError otherwise."""
    if options.timeout is not None:
        check_seconds("timeout", options.timeout)
    check_seconds("connect_timeout", options.connect_timeout)


def key_warnings(outcomes: list[Outcome], registry: Registry | None = None) -> list[str]:
    """The answer key's warnings, once per batch (not per variant): columns whose key no variant's
    stage results held (:func:`crankdyn.answer_key.unanswered`)."""
    return answer_key.unanswered(
        answer_key.answer_columns(_registry_or_default(registry)),
        [(o.stages_run, o.absent) for o in outcomes if o.ok],
    )


def load_base(base_path: Path) -> tuple[dict, str]:
    """The base scene's TOML data and its folder (relative data files resolve there)."""
    base_source = str(base_path)
    try:
        base = tomllib.loads(Path(base_path).read_text(encoding="utf-8-sig"))
    except FileNotFoundError:
        raise SceneError(Problem("--base", base_source, "file not found"), base_source) from None
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError, RecursionError) as exc:
        raise SceneError(
            Problem("--base", base_source, f"not a readable TOML scene: {exc}"), base_source
        ) from None
    return base, str(Path(base_path).parent.resolve())


def execute(
    variants: list[Variant],
    base: dict,
    base_dir: str,
    out_dir: Path,
    options: RunOptions,
    run: VariantRun | None = None,
) -> tuple[list[Outcome], int]:
    """Run the variants (local worker processes, or the Dask cluster of ``options.scheduler``)
    with ``run``'s registry (by default a run of the installed plugins).

    Returns the outcomes in row order and the signal that interrupted the run (SIGINT for
    Ctrl-C, SIGTERM; 0 when it ran through; the unfinished variants are then failure rows).
    Raises UsageError, before anything runs, when the scheduler cannot be reached.
    """

    client = _client(options) if options.scheduler else None
    run = run if run is not None else VariantRun()
    bar = Progress(len(variants), enabled=options.progress)
    outcomes: list[Outcome] = []

    def finished(outcome: Outcome) -> None:
        outcomes.append(outcome)
        bar.update(outcome)
        if options.on_outcome:
            options.on_outcome(outcome)

    def failed(variant: Variant, reason: str, seconds: float) -> Outcome:
        return Outcome(variant.row, variant.name, False, seconds, reason)

    formats = options.formats
    data_dirs = tuple(str(Path(d).resolve()) for d in options.data_dirs)
    timeout = DEFAULT_TIMEOUT_S if options.timeout is None else options.timeout
    languages = _languages(base, options)
    with stop_signals() as received:
        try:
            if client is None:
                run.warm(formats, languages)  # forked workers inherit the registry and libraries
                jobs = max(1, min(worker_count(options.jobs), max(len(variants), 1)))
                tail = (
                    str(out_dir),
                    formats,
                    options.language,
                    options.stages,
                    data_dirs,
                    False,
                    options.force,
                )
                run_all(
                    variants,
                    run.run_variant,
                    lambda v: (base, base_dir, v, *tail),
                    jobs,
                    timeout,
                    finished,
                    failed,
                    meanwhile=load_key_writers,
                )
            else:
                tail = (str(out_dir), formats, options.language, options.stages, data_dirs, True)
                try:
                    run_all_dask(
                        variants,
                        run.run_variant,
                        lambda v: (base, base_dir, v, *tail),
                        client,
                        timeout,
                        finished,
                        failed,
                        prepare=partial(run.warm, tuple(formats), languages),
                        collect=partial(_write_rendered, Path(out_dir), force=options.force),
                    )
                finally:
                    client.close()
        except KeyboardInterrupt:  # outside the loop's own handling (loading, closing): kept too
            pass
    return _with_unfinished_rows(variants, outcomes, received)


def _with_unfinished_rows(
    variants: list[Variant], outcomes: list[Outcome], received: list[int]
) -> tuple[list[Outcome], int]:
    """The outcomes in row order, a failure row for each variant without one, and the signal.

    The variants without an outcome are found from the outcomes: an interruption can come while
    one outcome is between its worker and the list."""
    done = {o.row for o in outcomes}
    unfinished = [v for v in variants if v.row not in done]
    stop_signal = received[0] if received else signal.SIGINT if unfinished else 0
    what = "SIGTERM" if stop_signal == signal.SIGTERM else "Ctrl-C"
    reason = f"not finished: the batch was interrupted ({what})"
    outcomes += [Outcome(v.row, v.name, False, 0.0, reason) for v in unfinished]
    outcomes.sort(key=lambda o: o.row)
    return outcomes, int(stop_signal)


def worker_count(jobs: int | None) -> int:
    """The local worker processes for ``jobs`` wanted: at most the available cores (more only
    share the same cores, and their variants run into the time limit), all of them by default."""
    cores = available_cores()
    return cores if jobs is None else max(1, min(jobs, cores))


def _languages(base: dict, options: RunOptions) -> tuple[str, ...]:
    """The report language(s) the variants will most likely use: ``--lang``, else the base scene's."""
    report = base.get("report") if isinstance(base.get("report"), dict) else {}
    language = options.language or report.get("language") or "en"
    return (language,) if isinstance(language, str) else ()


def batch_language(base: dict, options: RunOptions) -> str:
    """The language of the batch's own files (the answer key's labels): the variants' language when it
    has a catalog, else English."""
    language = next(iter(_languages(base, options)), i18n.FALLBACK)
    return language if language in available_languages() else i18n.FALLBACK


def _client(options: RunOptions):
    """The Dask client of ``options.scheduler``; a clear UsageError when dask is missing or the scheduler is not there."""

    address = options.scheduler
    try:
        return connect(address, options.connect_timeout)
    except ImportError:
        raise UsageError(
            f"--scheduler {address}: running on a Dask cluster needs dask and distributed; "
            "install them with: pip install 'crankdyn[dask]'"
        ) from None
    except ValueError as exc:
        raise UsageError(
            f"--scheduler {address}: not a scheduler address ({exc}); give what 'dask scheduler' "
            "prints, e.g. tcp://192.168.1.10:8786"
        ) from None
    except ConnectionError as exc:
        raise UsageError(
            f"--scheduler {address}: cannot reach a Dask scheduler there within "
            f"{options.connect_timeout:g} s ({exc}); start one with 'dask scheduler' and give the "
            "address it prints (tcp://HOST:8786)"
        ) from None


def _write_rendered(out_dir: Path, outcome: Outcome, force: bool = False) -> Outcome:
    """Write the files a Dask worker rendered for one variant below ``out_dir/<variant>/``."""
    files, outcome.rendered = outcome.rendered, None
    if outcome.ok and files:
        try:
            outcome.files = len(write_outputs(out_dir / outcome.name, files, force=force))
        except (OSError, CrankdynError) as exc:
            outcome.ok, outcome.error = False, f"cannot write its files: {exc}"
    return outcome


def load_key_writers() -> None:
    """Import the answer key's workbook writer (openpyxl, a tenth of a second), which the batch's
    own process otherwise imports after the last variant, while its workers compute."""
    with contextlib.suppress(ImportError):  # no openpyxl: the key says so when it is written
        outputs.xlsx_libraries()


def key_files(
    fields: list[str],
    outcomes: list[Outcome],
    variants: list[Variant],
    formats: Iterable[str] = ("csv", "xlsx"),
    language: str = i18n.FALLBACK,
    notes: Iterable[str] = (),
    registry: Registry | None = None,
) -> dict[str, bytes]:
    """``answer_key.<format>`` for each of ``formats`` (csv, xlsx, parquet) and, if rows failed, failures.csv.

    The workbook shows each result column's label (``AnswerColumn.label_key``) in ``language``
    above the column names, and ``notes`` (how the key was computed) on a sheet of their own; the
    CSV and Parquet keys carry the column names only.
    """
    by_row = {v.row: v for v in variants}
    registry = _registry_or_default(registry)
    makers = {
        "csv": _answer_key_csv,
        "xlsx": partial(_answer_key_xlsx, language=language, notes=list(notes)),
        "parquet": _answer_key_parquet,
    }
    files = {f"answer_key.{f}": makers[f](fields, outcomes, by_row, registry) for f in formats}
    if any(not o.ok for o in outcomes):
        files["failures.csv"] = _failures_csv(outcomes, by_row)
    return files


def answer_labels(
    language: str = i18n.FALLBACK, registry: Registry | None = None
) -> dict[str, str]:
    """Answer-key column name -> its label in ``language`` (English where the language has no text);
    a column that declares no ``label_key``, or one no catalog knows, is labelled by its name."""
    registry = _registry_or_default(registry)
    t = i18n.translator(language, registry.catalogs)
    key_columns = answer_key.answer_columns(registry)
    return {
        c.name: t(c.declared.label_key)
        if c.declared.label_key and t.has(c.declared.label_key)
        else c.name
        for c in key_columns
    }


def _answer_rows(
    fields: list[str], outcomes: list[Outcome], by_row: dict[int, Variant], registry: Registry
) -> tuple[list[str], list[list]]:
    """Successful variants only: id, row, the variant's own inputs as given, then the results."""
    answer_names = [c.name for c in answer_key.answer_columns(registry)]
    ran = [o for o in outcomes if o.ok]
    # Leave out result columns no variant has (e.g. a kinematics-only batch).
    answer_names = [c for c in answer_names if any(o.answers.get(c) is not None for o in ran)]
    header = [VARIANT_COLUMN, "row", *fields, *answer_names]
    rows = []
    for o in ran:
        cells = by_row[o.row].cells
        given = [_input_value(cells.get(f, "")) for f in fields]
        rows.append([o.name, o.row, *given, *(o.answers.get(c) for c in answer_names)])
    return header, rows


def _input_value(text: str) -> Any:
    """A variant's input as given; numbers as numbers (so the workbook holds numbers)."""
    value = parse_cell(text) if text else ""
    return value if isinstance(value, (int, float)) and not isinstance(value, bool) else text


def _fmt(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return "" if not math.isfinite(value) else f"{value:.6g}"
    return neutralised(value) if isinstance(value, str) else str(value)


_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


def neutralised(value: Any) -> Any:
    """A text cell a spreadsheet would take for a formula (starting with = + - @, tab or CR) with a
    leading apostrophe, so it shows as text (OWASP CSV injection); other values unchanged."""
    return "'" + value if isinstance(value, str) and value.startswith(_FORMULA_START) else value


def _csv_bytes(header: list[str], rows: list[list]) -> bytes:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(header)
    writer.writerows([[_fmt(v) for v in row] for row in rows])
    return buffer.getvalue().encode("utf-8")


def _answer_key_csv(fields, outcomes, by_row, registry) -> bytes:
    return _csv_bytes(*_answer_rows(fields, outcomes, by_row, registry))


def _failure_rows(
    outcomes: list[Outcome], by_row: dict[int, Variant]
) -> tuple[list[str], list[list]]:
    return [VARIANT_COLUMN, "row", "error"], [
        [o.name, o.row, o.error] for o in outcomes if not o.ok
    ]


def _failures_csv(outcomes, by_row) -> bytes:
    return _csv_bytes(*_failure_rows(outcomes, by_row))


class _Sheet:
    """A sheet's rows as :func:`xlsx_bytes` reads a DataFrame's (``columns``, ``itertuples``),
    each column's numbers of one type as a DataFrame holds them: a column of numbers with a
    float or an empty cell among them holds floats (an empty cell is written empty). The
    answer key's workbook is written at the end of a batch, on its critical path: without
    pandas's import."""

    def __init__(self, rows: list[list], columns: list[str]):
        self.columns = list(columns)
        kinds = [_column_kind([row[k] for row in rows]) for k in range(len(self.columns))]
        self._rows = [
            tuple(
                float(v) if kind is float and v is not None else v
                for v, kind in zip(row, kinds, strict=True)
            )
            for row in rows
        ]

    def itertuples(self, index: bool = False, name: str | None = None) -> Iterator[tuple]:
        return iter(self._rows)


def _column_kind(values: list) -> type | None:
    """``float`` for a column of numbers (no bool) with a float or an empty cell among them,
    else None (each value as it is)."""
    numbers = [v for v in values if v is not None]
    if not numbers or not all(
        isinstance(v, (int, float)) and not isinstance(v, bool) for v in numbers
    ):
        return None
    whole = len(numbers) == len(values) and not any(isinstance(v, float) for v in numbers)
    return None if whole else float


def _answer_key_xlsx(
    fields, outcomes, by_row, registry, language: str = i18n.FALLBACK, notes: list[str] = ()
) -> bytes:
    header, rows = _answer_rows(fields, outcomes, by_row, registry)
    rows = [[neutralised(v) for v in row] for row in rows]
    labels = answer_labels(language, registry)
    # The labels row above the column names: a result column's translated label, any other column
    # (variant, row, the variant's inputs) its own name.
    sheets = [
        (
            "answer key",
            _Sheet(rows, header),
            [neutralised(labels.get(c, c)) for c in header],
        )
    ]
    failed_header, failed_rows = _failure_rows(outcomes, by_row)
    failed_rows = [[neutralised(v) for v in row] for row in failed_rows]
    if failed_rows:
        sheets.append(("failures", _Sheet(failed_rows, failed_header)))
    if notes:
        sheets.append(("notes", _Sheet([[neutralised(n)] for n in notes], ["note"])))
    return xlsx_bytes(sheets)


def _answer_key_parquet(fields, outcomes, by_row, registry) -> bytes:
    """The answer key as a Parquet table (pyarrow, the parquet extra): numbers as numbers, text as text."""
    import pandas as pd  # lazy: heavy optional import (pandas: only for the answer key's workbook)

    header, rows = _answer_rows(fields, outcomes, by_row, registry)
    frame = pd.DataFrame(rows, columns=header)
    for name in frame.columns[frame.dtypes == object]:
        # A column Parquet can type: empty cells missing, mixed numbers and text all as text.
        values = frame[name].map(lambda v: None if v == "" else v)
        kinds = {type(v) for v in values if v is not None}
        frame[name] = (
            values if len(kinds) <= 1 else values.map(lambda v: None if v is None else str(v))
        )
    buffer = io.BytesIO()
    frame.to_parquet(buffer, engine="pyarrow", index=False)
    return buffer.getvalue()
