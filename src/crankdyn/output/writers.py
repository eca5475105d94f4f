"""Writing a run's outputs: results.json, tables/*.csv, tables.xlsx, report.html, report.pdf.

Everything is rendered in memory first; files are written only when all of it
succeeded, each through a temporary file and an atomic rename, so an error never
leaves a half-written report behind.
"""

from __future__ import annotations

import io
import json
import math
import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from ..engine.orchestrator import RunResult
from ..version import __version__
from . import manifest

FORMATS = ("html", "pdf", "json", "csv", "xlsx", "docx")


def results_document(result: RunResult) -> dict[str, Any]:
    """The results.json content (documented in README.md)."""
    scene = result.scene
    doc: dict[str, Any] = {
        "crankdyn_version": __version__,
        "title": scene.report.title,
        "mechanism": scene.engine.mechanism,
        "strokes": scene.engine.strokes,
        "angle_step_deg": scene.analysis.angle_step_deg,
        "stages_run": result.stages_run,
        "stages_skipped": dict(result.plan.skipped),
        "timing_s": {k: round(v, 6) for k, v in result.timing_s.items()},
    }
    for name, output in result.outputs.items():
        doc[name] = _jsonable(output.results)
    return doc


def _jsonable(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return [_jsonable(v) for v in value.tolist()]
    if isinstance(value, (np.floating, float)):
        value = float(value)
        return value if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    return value


def _named_tables(result: RunResult):
    """(file stem, DataFrame) of every table: the stage name, or ``<stage>_<table>``."""
    for stage_name, output in result.outputs.items():
        for table_name, frame in output.tables.items():
            yield (stage_name if table_name == stage_name else f"{stage_name}_{table_name}"), frame


def csv_tables(result: RunResult) -> dict[str, bytes]:
    files = {}
    for name, frame in _named_tables(result):
        buffer = io.StringIO()
        frame.to_csv(buffer, index=False, float_format="%.10g")
        files[f"tables/{name}.csv"] = buffer.getvalue().encode("utf-8")
    return files


XLSX_NAME = "tables.xlsx"


def xlsx_tables(result: RunResult) -> dict[str, bytes]:
    """One workbook ``tables.xlsx`` with one sheet per table, named like the CSV file."""
    tables = list(_named_tables(result))
    if not tables:
        return {}
    return {XLSX_NAME: xlsx_bytes(tables)}


def xlsx_libraries():
    """The openpyxl names :func:`xlsx_bytes` writes with (imported on first use)."""
    from openpyxl import Workbook  # lazy: heavy optional import
    from openpyxl.cell import WriteOnlyCell  # lazy: heavy optional import
    from openpyxl.styles import Font  # lazy: heavy optional import
    from openpyxl.utils import get_column_letter  # lazy: heavy optional import

    return Workbook, WriteOnlyCell, Font, get_column_letter


def xlsx_bytes(sheets) -> bytes:
    """An .xlsx workbook from ``[(sheet name, DataFrame), ...]``.

    Numbers stay numbers (Excel and LibreOffice show them with the reader's own
    decimal separator); NaN becomes an empty cell; the header row is bold and frozen.
    A sheet given as ``(name, DataFrame, labels)`` gets a row of human-readable labels (one per
    column) above the column names; both rows are frozen. Sheet names are cut to Excel's
    31 characters and made unique.
    """
    Workbook, WriteOnlyCell, Font, get_column_letter = xlsx_libraries()
    workbook = Workbook(write_only=True)  # streaming writer: several times faster for grid tables
    bold = Font(bold=True)
    used: set[str] = set()
    for name, frame, *labelled in sheets:
        labels = [str(label) for label in labelled[0]] if labelled else None
        ws = workbook.create_sheet(_sheet_name(name, used))
        ws.freeze_panes = "A3" if labels else "A2"
        for i, column in enumerate(frame.columns, start=1):
            wanted = max(len(str(column)), len(labels[i - 1]) if labels else 0)
            ws.column_dimensions[get_column_letter(i)].width = max(10, min(40, wanted + 2))
        header_rows = ([labels] if labels else []) + [[str(column) for column in frame.columns]]
        for texts in header_rows:
            header = []
            for text in texts:
                cell = WriteOnlyCell(ws, value=text)
                cell.font = bold
                header.append(cell)
            ws.append(header)
        for row in frame.itertuples(index=False, name=None):
            ws.append([_cell(v) for v in row])
    buffer = io.BytesIO()
    workbook.save(buffer)
    return buffer.getvalue()


def _cell(value: Any) -> Any:
    """A cell as a workbook holds it: numpy numbers as Python numbers, a non-finite one empty."""
    if isinstance(value, np.bool_):
        return bool(value)
    return _jsonable(value)


def _sheet_name(name: str, used: set[str]) -> str:
    clean = "".join("_" if c in "[]:*?/\\" else c for c in name)[:31] or "sheet"
    candidate, k = clean, 2
    while candidate.lower() in used:
        suffix = f"~{k}"
        candidate, k = clean[: 31 - len(suffix)] + suffix, k + 1
    used.add(candidate.lower())
    return candidate


def write_atomically(out_dir: Path, files: dict[str, bytes]) -> list[Path]:
    """Write ``files`` (relative name -> bytes) below ``out_dir``; each appears whole or not at all,
    with the mode the user's umask gives new files."""
    written = []
    for name, payload in files.items():
        target = out_dir / name
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
        try:
            with os.fdopen(fd, "wb") as fh:
                fh.write(payload)
            os.chmod(
                tmp, manifest.file_mode()
            )  # mkstemp makes 0600; a report is shared like any file
            os.replace(tmp, target)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
        written.append(target)
    return written


def json_bytes(document: dict) -> bytes:
    return (json.dumps(document, indent=2, ensure_ascii=False, allow_nan=False) + "\n").encode(
        "utf-8"
    )
