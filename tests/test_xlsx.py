"""Tables as an Excel workbook: one sheet per table, the same numbers as the CSV files."""

from __future__ import annotations

import io

import numpy as np
import openpyxl
import pandas as pd
import pytest

from crankdyn.cli import examples_dir, main
from crankdyn.output.writers import _sheet_name, xlsx_bytes


def test_xlsx_round_trips_with_pandas_and_matches_csv(tmp_path):
    out = tmp_path / "out"
    assert (
        main(
            [
                "report",
                str(examples_dir() / "petrol-1cyl.toml"),
                "-o",
                str(out),
                "--format",
                "csv,xlsx",
                "-q",
            ]
        )
        == 0
    )
    workbook = out / "tables.xlsx"
    assert workbook.is_file() and not (out / "report.html").exists()
    sheets = pd.read_excel(workbook, sheet_name=None, engine="openpyxl")
    csv_files = {p.stem: p for p in (out / "tables").glob("*.csv")}
    assert set(sheets) == set(csv_files) and {"kinematics", "indicator", "forces"} <= set(sheets)
    for name, frame in sheets.items():
        expected = pd.read_csv(csv_files[name])
        assert list(frame.columns) == list(expected.columns), name
        assert frame.shape == expected.shape, name
        for column in expected.columns:
            if pd.api.types.is_numeric_dtype(expected[column]):
                # CSV keeps 10 significant digits, the workbook the full double.
                np.testing.assert_allclose(
                    frame[column].to_numpy(float),
                    expected[column].to_numpy(float),
                    rtol=1e-9,
                    atol=1e-12,
                    equal_nan=True,
                    err_msg=f"{name}.{column}",
                )
            else:
                assert (
                    frame[column].fillna("").astype(str).tolist()
                    == expected[column].fillna("").astype(str).tolist()
                )
    # Numbers are stored as numbers (the reader's spreadsheet applies its own decimal separator),
    # the header is frozen and bold.
    book = openpyxl.load_workbook(workbook)
    sheet = book["forces"]
    assert sheet.freeze_panes == "A2" and sheet["A1"].font.b
    assert isinstance(sheet["B3"].value, float)


def test_xlsx_sheet_names_are_valid_and_unique():
    used: set[str] = set()
    long = "a_table_name_that_is_much_longer_than_excel_allows"
    first, second = _sheet_name(long, used), _sheet_name(long, used)
    assert len(first) <= 31 and len(second) <= 31 and first != second
    assert _sheet_name("odd[name]:*?/\\", used) == "odd_name______"
    frame = pd.DataFrame({"x_m": [1.0, float("nan"), np.float64(3.5)], "label": ["a", "b", "c"]})
    data = xlsx_bytes([(first, frame), (second, frame)])
    back = pd.read_excel(io.BytesIO(data), sheet_name=None)
    assert list(back) == [first, second]
    assert back[first]["x_m"].isna().tolist() == [False, True, False]  # NaN -> empty cell
    assert back[first]["x_m"].iloc[2] == pytest.approx(3.5)


def test_unknown_format_is_refused(tmp_path, capsys):
    assert (
        main(
            [
                "report",
                str(examples_dir() / "petrol-1cyl.toml"),
                "-o",
                str(tmp_path / "o"),
                "--format",
                "xls",
            ]
        )
        == 2
    )
    assert "xlsx" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()
