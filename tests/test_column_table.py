"""A stage's tables read without pandas (the report's serial start): ``Tables.arrays``
gives the same numbers as the DataFrame, a pickled ``Tables`` stays as stored, and a report
renders without importing pandas."""

from __future__ import annotations

import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from crankdyn.plugin.types import ColumnTable, StageOutput, Tables

ROOT = Path(__file__).resolve().parent.parent

COLUMNS = {"crank_angle_deg": np.arange(0.0, 360.0, 30.0), "torque_Nm": np.linspace(-5.0, 7.0, 12)}
ROWS = [{"step_deg": 1.0, "error": 0.1}, {"step_deg": 0.5, "error": 0.02, "note": 3.0}]


@pytest.mark.parametrize(
    "stored", [COLUMNS, ROWS, pd.DataFrame(COLUMNS)], ids=["columns", "rows", "frame"]
)
def test_arrays_hold_what_the_dataframe_holds(stored):
    tables = Tables(t=stored)
    arrays = tables.arrays("t")
    frame = Tables(t=stored)["t"]
    assert arrays.columns == list(frame.columns) and len(arrays) == len(frame)
    for name in frame.columns:
        np.testing.assert_array_equal(arrays[name], frame[name].to_numpy())
    rows = np.array([len(frame) - 1, 0])
    taken, iloc = arrays.take(rows), frame.iloc[rows]
    for name in frame.columns:
        np.testing.assert_array_equal(taken[name], iloc[name].to_numpy())
    assert {k: float(v) for k, v in arrays.row(1).items()} == pytest.approx(
        frame.iloc[1].astype(float).to_dict(), nan_ok=True
    )


def test_a_column_table_answers_membership_and_is_empty_without_columns():
    table = ColumnTable(COLUMNS)
    assert "torque_Nm" in table and "speed" not in table
    with pytest.raises(KeyError):
        table["speed"]
    assert len(ColumnTable({})) == 0 and ColumnTable({}).columns == []


def test_pickled_tables_stay_as_stored_and_read_the_same():
    output = StageOutput(tables={"a": COLUMNS, "b": ROWS})
    back = pickle.loads(pickle.dumps(output))
    assert isinstance(back.tables, Tables)
    assert (
        dict.__getitem__(back.tables, "b") == ROWS
    )  # not a DataFrame: nothing was built on the way
    assert dict.__getitem__(output.tables, "a") is COLUMNS  # nor in the original
    np.testing.assert_array_equal(back.tables["a"]["torque_Nm"].to_numpy(), COLUMNS["torque_Nm"])


def _modules_after(code: str) -> str:
    return subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout


def test_pickling_tables_imports_no_pandas():
    code = (
        "import pickle, sys\nfrom crankdyn.plugin.types import Tables\n"
        "pickle.loads(pickle.dumps(Tables(a={'x': [1.0, 2.0]}, b=[{'x': 1.0}])))\n"
        "print('pandas' in sys.modules)"
    )
    assert _modules_after(code).split() == ["False"]


# the V8 runs every built-in section the single cylinder does, and the multi-cylinder ones besides;
# a whole report in a process of its own: in the slow tier, which CI runs
@pytest.mark.slow
@pytest.mark.parametrize("example", ["v8-petrol.toml"])
def test_an_html_report_imports_no_pandas(tmp_path, example):
    """Every built-in section reads its tables as arrays: pandas is left to the CSV and XLSX files."""
    report = (
        f"main(['report', {str(ROOT / 'examples' / example)!r}, '-o', {str(tmp_path / '{}')!r}, "
        "'--format', '{}', '-q'])"
    )
    # One fresh interpreter: the HTML report first (pandas not imported), then, to show that the same
    # check can fail, the example's CSV tables in the same process (a table file needs pandas).
    code = (
        "import sys\nfrom crankdyn.cli import main\n"
        f"code = {report.format('html', 'html')}\n"
        "print('pandas' in sys.modules, code)\n"
        f"code = {report.format('csv', 'csv')}\n"
        "print('pandas' in sys.modules, code)"
    )
    assert _modules_after(code).split() == ["False", "0", "True", "0"]
    assert (tmp_path / "html" / "report.html").is_file()
