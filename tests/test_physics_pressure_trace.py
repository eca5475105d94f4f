"""Tests for crankdyn.physics.pressure_trace (readers and cycle regridding)."""

from pathlib import Path

import numpy as np
import pytest

from crankdyn.physics.indicator import indicated_work_J, mean_indicated_pressure_Pa
from crankdyn.physics.pressure_trace import (
    PressureTraceError,
    read_diesel_rk_ind,
    read_diesel_rk_ind_table,
    read_pressure_csv,
    to_cycle_grid,
)

DIESEL_RK_FILE = Path("/work/shared/data/diesel6-1600rpm.ind")
needs_real_file = pytest.mark.skipif(
    not DIESEL_RK_FILE.is_file(), reason="Diesel-RK sample trace not available"
)


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


# ---------------------------------------------------------------------------
# Real Diesel-RK trace
# ---------------------------------------------------------------------------
@needs_real_file
def test_real_diesel_rk_table():
    table = read_diesel_rk_ind_table(DIESEL_RK_FILE)
    assert list(table) == ["Fi", "Pc", "Tc", "V", "Alf_w", "P_1ring", "G_bb", "P_pist", "x"]
    angle = table["Fi"]
    assert angle.size == 721
    assert angle[0] == 180.0 and angle[-1] == 900.0
    np.testing.assert_allclose(np.diff(angle), 1.0)
    # firing TDC at 360 deg: smallest volume, piston 92 mm (one stroke) above BDC
    assert angle[np.argmin(table["V"])] == 360.0
    assert angle[np.argmax(table["P_pist"])] == 360.0
    assert table["P_pist"].max() == pytest.approx(92.0)
    # swept volume matches bore 83 mm x stroke 92 mm
    swept = table["V"].max() - table["V"].min()
    assert swept == pytest.approx(np.pi / 4 * 0.083**2 * 0.092, rel=1e-4)


@needs_real_file
def test_real_diesel_rk_pressure_and_work():
    angle, pressure = read_diesel_rk_ind(DIESEL_RK_FILE)
    table = read_diesel_rk_ind_table(DIESEL_RK_FILE)
    np.testing.assert_array_equal(pressure, table["Pc"] * 1e5)
    peak_bar = pressure.max() / 1e5
    peak_angle = angle[np.argmax(pressure)]
    # a plausible diesel peak: 216.6 bar at 366 deg in this file
    assert 100.0 < peak_bar < 250.0
    assert 360.0 <= peak_angle <= 380.0
    assert pressure.min() > 0.5e5
    # indicated work from the file's own volume column; 900 deg repeats 180 deg
    volume = table["V"]
    work = indicated_work_J(pressure[:-1], volume[:-1])
    p_i = mean_indicated_pressure_Pa(work, volume.max() - volume.min())
    assert work > 0
    assert 0.5e6 < p_i < 3.0e6


@needs_real_file
def test_real_trace_onto_four_stroke_grid():
    angle, pressure = read_diesel_rk_ind(DIESEL_RK_FILE)
    grid = np.arange(0.0, 720.0, 0.5)
    on_grid = to_cycle_grid(angle, pressure, 720.0, grid, 360.0, 360.0)
    assert on_grid.shape == grid.shape
    assert 360.0 <= grid[np.argmax(on_grid)] <= 380.0
    assert on_grid.max() == pytest.approx(pressure.max())
    # samples that land on the grid are reproduced: 720..899 wrapped onto 0..179
    np.testing.assert_allclose(on_grid[grid == 100.0], pressure[angle == 820.0])
    np.testing.assert_allclose(on_grid[grid == 400.0], pressure[angle == 400.0])
    # 180 and 900 are the same point of the cycle: their mean
    np.testing.assert_allclose(on_grid[grid == 180.0], 0.5 * (pressure[0] + pressure[-1]))
    # shifting the firing TDC to 0 (two-stroke style origin) moves the peak by -360
    shifted = to_cycle_grid(angle, pressure, 720.0, grid, 360.0, 0.0)
    assert 0.0 <= grid[np.argmax(shifted)] <= 20.0


# ---------------------------------------------------------------------------
# CSV reader
# ---------------------------------------------------------------------------
@pytest.mark.parametrize(
    "header, factor",
    [
        ("crank_angle_deg,pressure_bar", 1e5),
        ("angle [deg], p [MPa]", 1e6),
        ("angle (deg),p (kPa)", 1e3),
        ("angle,pressure_Pa", 1.0),
        ("angle_deg,P [mpa]", 1e6),
    ],
)
def test_csv_units(tmp_path, header, factor):
    path = write(tmp_path, "trace.csv", f"{header}\n0,1.5\n1,2.0\n\n2.5,3.25,extra\n")
    angle, pressure = read_pressure_csv(path)
    np.testing.assert_array_equal(angle, [0.0, 1.0, 2.5])
    np.testing.assert_allclose(pressure, np.array([1.5, 2.0, 3.25]) * factor, rtol=1e-15)


@pytest.mark.parametrize(
    "text, fragment",
    [
        ("angle_deg,pressure\n0,1\n1,2\n", "allowed units"),  # no unit
        ("angle_deg,pressure [psi]\n0,1\n1,2\n", "allowed units"),  # unsupported unit
        ("angle [rad],p [bar]\n0,1\n1,2\n", "deg"),  # angle in radians
        ("angle_deg,p_bar\n0,1\n1,2x\n", "line 3"),  # garbled value
        ("angle_deg,p_bar\n0,1\n1\n", "line 3"),  # one column
        ("angle_deg\n0\n1\n", "line 1"),  # one header column
        ("angle_deg,p_bar\n0,1\n1,nan\n", "line 3"),  # NaN
        ("angle_deg,p_bar\n5,1\n4,2\n", "strictly increasing"),  # descending angles
        ("angle_deg,p_bar\n0,1\n0,2\n", "strictly increasing"),  # repeated angle
        ("angle_deg,p_bar\n0,1\n1,-2\n", "negative"),  # negative pressure
        ("angle_deg,p_bar\n0,1\n", "at least 2"),  # one data row
        ("", "empty"),  # empty file
        ("\n  \n", "empty"),  # blank lines only
    ],
)
def test_csv_errors_name_the_file(tmp_path, text, fragment):
    path = write(tmp_path, "bad_trace.csv", text)
    with pytest.raises(PressureTraceError) as info:
        read_pressure_csv(path)
    message = str(info.value)
    assert "bad_trace.csv" in message
    assert fragment in message
    assert isinstance(info.value, ValueError)


def test_csv_missing_file(tmp_path):
    path = tmp_path / "no_such_trace.csv"
    with pytest.raises(PressureTraceError, match="no_such_trace.csv.*not found"):
        read_pressure_csv(path)


# ---------------------------------------------------------------------------
# Diesel-RK reader on synthetic files
# ---------------------------------------------------------------------------
IND_HEADER = "Fi        Pc        Tc        V\nArrays\n"


def test_ind_synthetic(tmp_path):
    path = write(
        tmp_path, "t.ind", IND_HEADER + " 0.0  1.5  300.0  0.5E-03\n 1.0  2.0  301.0  0.49E-03\n \n"
    )
    angle, pressure = read_diesel_rk_ind(path)
    np.testing.assert_array_equal(angle, [0.0, 1.0])
    np.testing.assert_allclose(pressure, [1.5e5, 2.0e5])
    table = read_diesel_rk_ind_table(path)
    np.testing.assert_allclose(table["V"], [0.5e-3, 0.49e-3])


@pytest.mark.parametrize(
    "text, fragment",
    [
        ("Fi Pc\n0 1\n1 2\n", "Arrays"),
        (IND_HEADER + "0 1 300\n1 2 300 0.5\n", "line 3"),
        (IND_HEADER + "0 1 300 0.5\n1 ? 300 0.5\n", "line 4"),
        (IND_HEADER + "1 1 300 0.5\n0 2 300 0.5\n", "strictly increasing"),
        (IND_HEADER + "0 1 300 0.5\n1 -2 300 0.5\n", "negative"),
        (IND_HEADER, "no data rows"),
        ("Fi\nArrays\n0\n1\n", "at least 2"),
        ("", "empty"),
    ],
)
def test_ind_errors_name_the_file(tmp_path, text, fragment):
    path = write(tmp_path, "bad.ind", text)
    with pytest.raises(PressureTraceError) as info:
        read_diesel_rk_ind(path)
    assert "bad.ind" in str(info.value)
    assert fragment in str(info.value)


def test_ind_missing_file(tmp_path):
    with pytest.raises(PressureTraceError, match="missing.ind"):
        read_diesel_rk_ind_table(tmp_path / "missing.ind")


# ---------------------------------------------------------------------------
# to_cycle_grid on synthetic traces
# ---------------------------------------------------------------------------
def test_to_cycle_grid_shift_and_wrap():
    # a trace over [100, 460) with its "TDC" at 200, moved so that TDC is at 0 of a 360 cycle
    angle = np.arange(100.0, 460.0, 2.0)
    pressure = 1e5 + 1e3 * np.cos(np.radians(angle - 200.0))
    grid = np.arange(0.0, 360.0, 1.0)
    out = to_cycle_grid(angle, pressure, 360.0, grid, 200.0, 0.0)
    expected = 1e5 + 1e3 * np.cos(np.radians(grid))
    # linear interpolation of a cosine sampled every 2 deg
    np.testing.assert_allclose(out, expected, rtol=0, atol=1e3 * (np.radians(2.0) ** 2) / 8 + 1e-9)
    assert out[0] == pytest.approx(1.01e5)
    # grid angles outside [0, cycle) are reduced modulo the cycle
    np.testing.assert_allclose(to_cycle_grid(angle, pressure, 360.0, grid + 360.0, 200.0, 0.0), out)


def test_to_cycle_grid_rejects_partial_trace():
    angle = np.arange(0.0, 500.0, 1.0)
    with pytest.raises(PressureTraceError, match=r"covers 499 of 720 deg"):
        to_cycle_grid(angle, np.full(angle.shape, 1e5), 720.0, np.arange(720.0), 360.0, 360.0)


def test_to_cycle_grid_accepts_gaps_up_to_5_deg():
    angle = np.arange(0.0, 720.0, 5.0)
    pressure = np.full(angle.shape, 2e5)
    np.testing.assert_allclose(to_cycle_grid(angle, pressure, 720.0, np.arange(720.0), 0, 0), 2e5)
    with pytest.raises(PressureTraceError, match="largest gap"):
        to_cycle_grid(np.arange(0.0, 720.0, 6.0), np.full(120, 2e5), 720.0, np.arange(720.0), 0, 0)


def test_to_cycle_grid_rejects_more_than_a_cycle():
    angle = np.arange(0.0, 800.0, 1.0)
    with pytest.raises(PressureTraceError, match="more than one cycle"):
        to_cycle_grid(angle, np.full(angle.shape, 1e5), 720.0, np.arange(720.0), 0, 0)


def test_to_cycle_grid_averages_the_two_ends_of_a_closed_trace():
    angle = np.arange(0.0, 721.0, 1.0)  # 0 and 720 are the same point
    pressure = np.full(angle.shape, 1e5)
    pressure[0], pressure[-1] = 1.0e5, 1.2e5
    out = to_cycle_grid(angle, pressure, 720.0, np.array([0.0, 1.0, 719.5]), 0.0, 0.0)
    np.testing.assert_allclose(out, [1.1e5, 1e5, 1.05e5])
