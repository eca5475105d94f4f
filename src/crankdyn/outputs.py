"""Writing a run's outputs: results.json, tables/*.csv, report.html, report.pdf.

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

from . import __version__
from .orchestrator import RunResult

FORMATS = ("html", "pdf", "json", "csv")


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


def csv_tables(result: RunResult) -> dict[str, bytes]:
    files = {}
    for stage_name, output in result.outputs.items():
        for table_name, frame in output.tables.items():
            buffer = io.StringIO()
            frame.to_csv(buffer, index=False, float_format="%.10g")
            name = stage_name if table_name == stage_name else f"{stage_name}_{table_name}"
            files[f"tables/{name}.csv"] = buffer.getvalue().encode("utf-8")
    return files


def write_atomically(out_dir: Path, files: dict[str, bytes]) -> list[Path]:
    """Write ``files`` (relative name -> bytes) below ``out_dir``; each appears whole or not at all."""
    written = []
    for name, payload in files.items():
        target = out_dir / name
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
        try:
            with os.fdopen(fd, "wb") as fh:
                fh.write(payload)
            os.replace(tmp, target)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
        written.append(target)
    return written


def json_bytes(document: dict) -> bytes:
    return (json.dumps(document, indent=2, ensure_ascii=False, allow_nan=False) + "\n").encode("utf-8")
