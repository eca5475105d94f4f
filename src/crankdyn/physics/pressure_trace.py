"""Measured or simulated in-cylinder pressure traces: reading and regridding.

Readers return crank angle in degrees and absolute pressure in Pa.  Every
problem with the input data raises :class:`PressureTraceError` (a
``ValueError``) whose message names the file, the line where relevant, and
what is allowed.
"""

from __future__ import annotations

import csv
import math
import os
import re
import threading
from array import array

import numpy as np

__all__ = [
    "PressureTraceError",
    "read_pressure_csv",
    "read_diesel_rk_ind",
    "read_diesel_rk_ind_table",
    "to_cycle_grid",
]

# Pressure units accepted in CSV headers (case-insensitive) -> factor to Pa.
_PRESSURE_UNITS_TO_PA = {"bar": 1e5, "mpa": 1e6, "kpa": 1e3, "pa": 1.0}
_ALLOWED_PRESSURE_UNITS = "bar, MPa, kPa, Pa"
_ANGLE_UNITS = {"deg", "degree", "degrees", "\u00b0"}
# Largest cyclic gap in a trace accepted by to_cycle_grid, deg.
_MAX_CYCLE_GAP_DEG = 5.0


class PressureTraceError(ValueError):
    """Invalid pressure-trace file or data."""


# ---------------------------------------------------------------------------
# Limits: a trace is one cycle; one sample per 0.0072 deg of a four-stroke cycle is far finer
# than any measurement or simulation, and the limits keep a run within seconds and its memory
# (the numerics stage integrates between every pair of samples) within a few hundred megabytes.
# ---------------------------------------------------------------------------
#: Data rows of a trace file.
MAX_TRACE_ROWS = 100_000
#: Lines of a trace file, blank ones included.
MAX_TRACE_LINES = 2 * MAX_TRACE_ROWS
#: Bytes of a trace file (a Diesel-RK row of nine columns takes about a hundred).
MAX_TRACE_BYTES = 32 * 1024 * 1024
#: Columns of a Diesel-RK file (it writes nine).
MAX_COLUMNS = 64
#: Characters of one line of a trace file.
MAX_LINE_LENGTH = 10_000
#: Traces kept after reading (the indicator and numerics stages of one run share one reading).
_CACHE_SIZE = 4
_CACHE: dict[tuple, object] = {}
_CACHE_LOCK = threading.Lock()


# ---------------------------------------------------------------------------
# Low-level helpers
# ---------------------------------------------------------------------------
def _read_once(path, kind, parse):
    """``parse(name, numbered lines)`` of the file ``path``, read once as a stream of lines.

    A file already read (same file, size and modification time) is not read again: the
    stages of a run that use the trace share one reading. Size limits are checked before and
    while reading; every problem raises PressureTraceError.
    """
    name = os.fspath(path)
    if not os.path.isfile(name):
        raise PressureTraceError(f"{name}: file not found (a pressure-trace file is required)")
    try:
        with open(name, encoding="utf-8-sig", errors="strict") as handle:
            status = os.fstat(handle.fileno())
            key = (kind, status.st_dev, status.st_ino, status.st_size, status.st_mtime_ns)
            cached = _CACHE.get(key)
            if cached is not None:
                return cached
            if status.st_size > MAX_TRACE_BYTES:
                raise PressureTraceError(
                    f"{name}: the file has {status.st_size} bytes; a pressure trace may have at "
                    f"most {MAX_TRACE_BYTES} bytes and {MAX_TRACE_ROWS} data rows"
                )
            value = parse(name, _numbered_lines(handle, name))
    except UnicodeDecodeError as exc:
        raise PressureTraceError(f"{name}: cannot read the file as UTF-8 text ({exc})") from None
    except OSError as exc:
        raise PressureTraceError(
            f"{name}: cannot read the file ({exc.__class__.__name__})"
        ) from None
    with _CACHE_LOCK:  # stages of a batch may run in threads
        while len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = value
    return value


def _numbered_lines(handle, name):
    """(line number, text) of each non-blank line; no line longer than MAX_LINE_LENGTH is read
    whole, and no more than MAX_TRACE_BYTES characters in all (a file growing meanwhile)."""
    read = 0
    number = 0
    while True:
        line = handle.readline(MAX_LINE_LENGTH + 2)
        if not line:
            return
        number += 1
        if number > MAX_TRACE_LINES:
            raise PressureTraceError(
                f"{name}: more than {MAX_TRACE_LINES} lines; a pressure trace may have at most "
                f"{MAX_TRACE_LINES} lines (blank ones included) and {MAX_TRACE_ROWS} data rows"
            )
        read += len(line)
        text = line.rstrip("\r\n")
        if len(text) > MAX_LINE_LENGTH:
            raise PressureTraceError(
                f"{name}, line {number}: longer than {MAX_LINE_LENGTH} characters; a row of a "
                "pressure trace holds a few numbers"
            )
        if read > MAX_TRACE_BYTES:
            raise PressureTraceError(
                f"{name}: more than {MAX_TRACE_BYTES} bytes; a pressure trace may have at most "
                f"{MAX_TRACE_BYTES} bytes and {MAX_TRACE_ROWS} data rows"
            )
        if text.strip():
            yield number, text


def _too_many_rows(name):
    return PressureTraceError(
        f"{name}: more than {MAX_TRACE_ROWS} data rows; a pressure trace may have at most "
        f"{MAX_TRACE_ROWS} rows (one cycle sampled every {720 / MAX_TRACE_ROWS:g} deg or coarser)"
    )


def _cell(text, limit=30):
    """One cell of a data file for a message: escaped (repr) and cut to ``limit`` characters."""
    text = str(text)
    return repr(text if len(text) <= limit else text[: limit - 3] + "...")


def _to_float(text, name, line_number, column):
    try:
        value = float(text)
    except ValueError:
        raise PressureTraceError(
            f"{name}, line {line_number}: column {column} value {_cell(text.strip())} is not a "
            "number (only numeric data rows are allowed after the header)"
        ) from None
    if not math.isfinite(value):
        raise PressureTraceError(
            f"{name}, line {line_number}: column {column} value {_cell(text.strip())} is not "
            "finite (NaN and infinity are not allowed)"
        )
    return value


def _csv_fields(text, name, line_number):
    """The cells of one CSV line (quoted cells as the csv module reads them)."""
    if '"' not in text:
        return text.split(",")
    try:
        return next(csv.reader([text]))
    except csv.Error as exc:
        raise PressureTraceError(f"{name}, line {line_number}: not a CSV row ({exc})") from None


def _check_trace(name, angle_deg, pressure, line_numbers, pressure_label):
    """Common checks: enough rows, strictly increasing angles, positive pressure (arrays)."""
    if len(angle_deg) < 2:
        raise PressureTraceError(f"{name}: {len(angle_deg)} data row(s); at least 2 are required")
    falling = np.flatnonzero(~(angle_deg[1:] > angle_deg[:-1]))
    if falling.size:
        k = int(falling[0]) + 1
        raise PressureTraceError(
            f"{name}, line {line_numbers[k]}: crank angle {angle_deg[k]:g} deg does not "
            f"exceed the previous {angle_deg[k - 1]:g} deg (angles must be strictly "
            "increasing)"
        )
    negative = np.flatnonzero(pressure < 0)
    if negative.size:
        k = int(negative[0])
        raise PressureTraceError(
            f"{name}, line {line_numbers[k]}: {pressure_label} {pressure[k]:g} is negative "
            "(absolute pressure >= 0 is required)"
        )


def _header_unit(header):
    """Unit of a CSV header: 'p [MPa]', 'p (MPa)' or 'pressure_MPa'; None if absent."""
    text = header.strip()
    match = re.search(r"[\[(]\s*([^\])]+?)\s*[\])]\s*$", text)
    if match:
        return match.group(1)
    if "_" in text:
        return text.rsplit("_", 1)[1].strip()
    return None


# ---------------------------------------------------------------------------
# CSV
# ---------------------------------------------------------------------------
def read_pressure_csv(path):
    """Read a two-column CSV pressure trace (crank angle, pressure).

    Parameters
    ----------
    path : str or os.PathLike
        Comma-separated text file.  The first row is a header; the first
        column is the crank angle in degrees (header unit, if any, must be
        deg), the second the absolute pressure, whose header carries the unit
        in brackets, parentheses or after the last underscore, e.g.
        ``crank_angle_deg,pressure_bar`` or ``angle [deg], p [MPa]``.
        Allowed pressure units (case-insensitive): bar, MPa, kPa, Pa.  Extra
        columns are ignored; blank lines are skipped.

    Returns
    -------
    crank_angle_deg : numpy.ndarray
        Crank angle, deg, strictly increasing.
    pressure_Pa : numpy.ndarray
        Absolute pressure, Pa.

    Raises
    ------
    PressureTraceError
        Missing or empty file, header without a pressure unit or with an
        unsupported unit, rows with fewer than 2 columns, non-numeric or
        non-finite values, non-increasing angles, negative pressure.

    Notes
    -----
    File format defined for crankdyn (derived).
    """
    angle, pressure = _read_once(path, "csv", _parse_csv)
    return angle.copy(), pressure.copy()


def _parse_csv(name, lines):
    """(angle deg, pressure Pa) of the CSV trace whose non-blank ``lines`` are given."""
    first = next(lines, None)
    if first is None:
        raise PressureTraceError(
            f"{name}: the file is empty (a header row and at least 2 data rows are required)"
        )
    header_line, header_text = first
    header = _csv_fields(header_text, name, header_line)
    if len(header) < 2:
        raise PressureTraceError(
            f"{name}, line {header_line}: header has {len(header)} column(s); at least 2 "
            "(crank angle, pressure) are required"
        )
    angle_unit = _header_unit(header[0])
    if angle_unit is not None and angle_unit.strip().lower() not in _ANGLE_UNITS:
        raise PressureTraceError(
            f"{name}, line {header_line}: angle column header {_cell(header[0].strip())} has "
            f"unit {_cell(angle_unit)}; allowed: deg (or no unit)"
        )
    unit = _header_unit(header[1])
    if unit is None or unit.strip().lower() not in _PRESSURE_UNITS_TO_PA:
        found = "no unit" if unit is None else f"unit {_cell(unit)}"
        raise PressureTraceError(
            f"{name}, line {header_line}: pressure column header {_cell(header[1].strip())} has "
            f"{found}; allowed units: {_ALLOWED_PRESSURE_UNITS}, written as "
            "'p [MPa]', 'p (MPa)' or 'pressure_MPa'"
        )
    factor = _PRESSURE_UNITS_TO_PA[unit.strip().lower()]

    angles, pressures, line_numbers = array("d"), array("d"), array("q")
    for line_number, text in lines:
        if len(line_numbers) >= MAX_TRACE_ROWS:
            raise _too_many_rows(name)
        fields = _csv_fields(text, name, line_number)
        if len(fields) < 2:
            raise PressureTraceError(
                f"{name}, line {line_number}: {len(fields)} column(s); at least 2 (crank "
                "angle, pressure) are required"
            )
        try:
            angle, pressure = float(fields[0]), float(fields[1])
        except ValueError:
            angle, pressure = None, None
        if angle is None or not (math.isfinite(angle) and math.isfinite(pressure)):
            angle = _to_float(fields[0], name, line_number, 1)  # raises the worded error
            pressure = _to_float(fields[1], name, line_number, 2)
        angles.append(angle)
        pressures.append(pressure)
        line_numbers.append(line_number)
    angle_deg = np.frombuffer(angles, dtype=float)
    pressure_in_unit = np.frombuffer(pressures, dtype=float)
    _check_trace(name, angle_deg, pressure_in_unit, line_numbers, f"pressure [{unit.strip()}]")
    angle_deg.flags.writeable = False
    pressure_Pa = pressure_in_unit * factor
    pressure_Pa.flags.writeable = False
    return angle_deg, pressure_Pa


# ---------------------------------------------------------------------------
# Diesel-RK .ind
# ---------------------------------------------------------------------------
def read_diesel_rk_ind_table(path):
    """Read all columns of a Diesel-RK ``.ind`` indicator-diagram file.

    Parameters
    ----------
    path : str or os.PathLike
        Text file: line 1 holds the column names (``Fi Pc Tc V Alf_w P_1ring
        G_bb P_pist x``), line 2 the word ``Arrays``, then whitespace-separated
        numeric rows with one value per name.  Blank lines are skipped.

    Returns
    -------
    dict of str to numpy.ndarray
        One array per column name, in the file's own units (Diesel-RK:
        ``Fi`` crank angle deg, ``Pc`` absolute pressure bar, ``Tc`` K,
        ``V`` m^3, ``P_pist`` piston position from BDC mm).

    Raises
    ------
    PressureTraceError
        Missing or empty file, a missing ``Arrays`` line, fewer than 2
        columns, rows whose length differs from the header, non-numeric or
        non-finite values, non-increasing angles (first column), negative
        pressure (second column).

    Notes
    -----
    Format as written by Diesel-RK (derived from the file layout).
    """
    table = _read_once(path, "diesel-rk", _parse_diesel_rk)
    return {column: values.copy() for column, values in table.items()}


def _parse_diesel_rk(name, lines):
    """Every column of the Diesel-RK ``.ind`` file whose non-blank ``lines`` are given."""
    first = next(lines, None)
    if first is None:
        raise PressureTraceError(
            f"{name}: the file is empty (a Diesel-RK .ind file starts with a line of column "
            "names and a line 'Arrays')"
        )
    header_line, header_text = first
    names = header_text.split()
    if len(names) < 2:
        raise PressureTraceError(
            f"{name}, line {header_line}: {len(names)} column name(s); at least 2 (angle, "
            "pressure) are required"
        )
    if len(names) > MAX_COLUMNS:
        raise PressureTraceError(
            f"{name}, line {header_line}: {len(names)} column names; at most {MAX_COLUMNS} are "
            "allowed"
        )
    if len(set(names)) != len(names):
        raise PressureTraceError(
            f"{name}, line {header_line}: duplicate column names {names}; names must be unique"
        )
    second = next(lines, None)
    if second is None or second[1].strip().lower() != "arrays":
        where = second[0] if second is not None else header_line + 1
        raise PressureTraceError(
            f"{name}, line {where}: expected the line 'Arrays' after the column names"
        )
    values, line_numbers = array("d"), array("q")
    for line_number, text in lines:
        if len(line_numbers) >= MAX_TRACE_ROWS:
            raise _too_many_rows(name)
        fields = text.split()
        if len(fields) != len(names):
            raise PressureTraceError(
                f"{name}, line {line_number}: {len(fields)} column(s); exactly "
                f"{len(names)} are required ({' '.join(names)})"
            )
        values.extend(_to_float(f, name, line_number, c + 1) for c, f in enumerate(fields))
        line_numbers.append(line_number)
    if not line_numbers:
        raise PressureTraceError(f"{name}: no data rows after 'Arrays' (at least 2 required)")
    data = np.frombuffer(values, dtype=float).reshape(len(line_numbers), len(names))
    _check_trace(name, data[:, 0], data[:, 1], line_numbers, f"pressure {names[1]}")
    table = {column: data[:, k].copy() for k, column in enumerate(names)}
    for column in table.values():
        column.flags.writeable = False
    return table


def read_diesel_rk_ind(path):
    """Read crank angle and pressure from a Diesel-RK ``.ind`` file.

    Parameters
    ----------
    path : str or os.PathLike
        Diesel-RK indicator file (see :func:`read_diesel_rk_ind_table`);
        first column crank angle in deg, second absolute pressure in bar.

    Returns
    -------
    crank_angle_deg : numpy.ndarray
        Crank angle, deg, strictly increasing (the file's own origin).
    pressure_Pa : numpy.ndarray
        Absolute pressure, Pa.

    Raises
    ------
    PressureTraceError
        As :func:`read_diesel_rk_ind_table`.

    Notes
    -----
    Pressure conversion 1 bar = 1e5 Pa.
    """
    table = read_diesel_rk_ind_table(path)
    columns = list(table)
    return table[columns[0]], table[columns[1]] * 1e5


# ---------------------------------------------------------------------------
# Regridding
# ---------------------------------------------------------------------------
def _check_trace_arrays(angle, pressure, grid, cycle_deg) -> None:
    """Refuse malformed input of :func:`to_cycle_grid` (PressureTraceError naming what is wrong)."""
    if angle.ndim != 1 or angle.shape != pressure.shape or angle.size < 2:
        raise PressureTraceError(
            f"crank_angle_deg shape {angle.shape} and pressure_Pa shape {pressure.shape}: "
            "equal 1-D shapes with at least 2 samples are required"
        )
    if not (
        np.all(np.isfinite(angle)) and np.all(np.isfinite(pressure)) and np.all(np.isfinite(grid))
    ):
        raise PressureTraceError(
            "trace or grid contains NaN or infinity; finite values are required"
        )
    if not (math.isfinite(cycle_deg) and cycle_deg > 0):
        raise PressureTraceError(
            f"cycle_deg = {cycle_deg!r}; a positive angle (720 or 360) is required"
        )
    if not np.all(np.diff(angle) > 0):
        raise PressureTraceError("crank_angle_deg must be strictly increasing")


def to_cycle_grid(
    crank_angle_deg, pressure_Pa, cycle_deg, grid_deg, firing_tdc_deg_in_file, firing_tdc_deg_target
):
    """Shift, wrap and interpolate a one-cycle pressure trace onto a cycle grid.

    Parameters
    ----------
    crank_angle_deg : array_like
        Trace angles, deg, strictly increasing, spanning at most one cycle.
    pressure_Pa : array_like
        Trace pressure, Pa, same shape.
    cycle_deg : float
        Cycle length, deg (720 four-stroke, 360 two-stroke), > 0.
    grid_deg : array_like
        Target angles, deg (any values; reduced modulo ``cycle_deg``).
    firing_tdc_deg_in_file : float
        Angle of the firing TDC in the trace's own angle origin, deg.
    firing_tdc_deg_target : float
        Angle of the firing TDC on the target grid, deg (360 four-stroke,
        0 two-stroke in crankdyn's convention).

    Returns
    -------
    numpy.ndarray
        Pressure on ``grid_deg``, Pa.

    Raises
    ------
    PressureTraceError
        If the arrays are malformed, the trace spans more than one cycle, or,
        after wrapping, the largest cyclic gap between trace angles exceeds
        5 deg (the message states how much of the cycle is covered).

    Notes
    -----
    Angles are shifted by ``firing_tdc_deg_target - firing_tdc_deg_in_file``,
    wrapped modulo ``cycle_deg`` and sorted; a trace spanning exactly one
    cycle has its two end samples on the same point of the cycle, and their
    pressures are averaged.  Interpolation is periodic and linear
    (``numpy.interp(..., period=cycle_deg)``).  Derived.
    """
    angle = np.asarray(crank_angle_deg, dtype=float)
    pressure = np.asarray(pressure_Pa, dtype=float)
    grid = np.asarray(grid_deg, dtype=float)
    _check_trace_arrays(angle, pressure, grid, cycle_deg)
    span = angle[-1] - angle[0]
    tol = 1e-9 * cycle_deg
    if span > cycle_deg + tol:
        raise PressureTraceError(
            f"the trace spans {span:g} deg, more than one cycle of {cycle_deg:g} deg; "
            "pass exactly one cycle"
        )
    if span >= cycle_deg - tol:
        # first and last samples are the same point of the cycle: average them
        last = pressure[-1]
        pressure = pressure[:-1].copy()
        pressure[0] = 0.5 * (pressure[0] + last)
        angle = angle[:-1]
    shifted = np.mod(angle + (firing_tdc_deg_target - firing_tdc_deg_in_file), cycle_deg)
    order = np.argsort(shifted, kind="stable")
    wrapped = shifted[order]
    values = pressure[order]
    gaps = np.diff(np.append(wrapped, wrapped[0] + cycle_deg))
    largest = float(gaps.max())
    if largest > _MAX_CYCLE_GAP_DEG:
        covered = cycle_deg - largest
        start = float(wrapped[int(np.argmax(gaps))])
        raise PressureTraceError(
            f"the trace covers {covered:g} of {cycle_deg:g} deg ({100.0 * covered / cycle_deg:.1f} "
            f"%) of the cycle; its largest gap is {largest:g} deg after {start:g} deg "
            f"(target angles), at most {_MAX_CYCLE_GAP_DEG:g} deg is allowed"
        )
    return np.interp(np.mod(grid, cycle_deg), wrapped, values, period=cycle_deg)
