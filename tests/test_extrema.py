"""One definition of "the angle of the maximum": the first sample within a relative tolerance."""

from __future__ import annotations

import numpy as np
import pytest

from crankdyn.physics.extrema import EXTREMUM_RTOL, extremum_indices, first_argmax, first_argmin


def _two_equal_peaks(n: int = 720) -> np.ndarray:
    """cos(2 alpha) over one revolution sampled so that both peaks (0 and 180 deg) are samples;
    the second peak is made larger by 1e-15 relative, below the tolerance: still a tie."""
    alpha = np.radians(np.arange(n) * 360.0 / n)
    y = 500.0 + 3.0 * np.cos(2 * alpha - 2 * np.radians(10.0))
    i1, i2 = 10 * n // 360, 190 * n // 360
    y[i1] = y[i2] = 503.0
    y[i2] = y[i2] * (1 + 1e-15)
    return y


@pytest.mark.parametrize("layout", ["contiguous", "strided", "reversed-copy-back"])
def test_two_equal_maxima_give_the_first_on_every_memory_layout(layout):
    y = _two_equal_peaks()
    i1 = 10 * y.size // 360
    assert np.argmax(y) != i1  # raw argmax is decided by the last bit
    if layout == "strided":
        wide = np.empty(2 * y.size)
        wide[::2] = y
        wide[1::2] = np.nan
        values = wide[::2]
        assert not values.flags.c_contiguous
    elif layout == "reversed-copy-back":
        values = y[::-1][::-1]
    else:
        values = np.ascontiguousarray(y)
    assert first_argmax(values) == i1
    assert first_argmin(-values) == i1
    assert list(extremum_indices(values)) == [i1, 190 * y.size // 360]


def test_distinct_peaks_are_not_merged():
    y = _two_equal_peaks()
    i2 = 190 * y.size // 360
    y[i2] += 1e-6 * (y.max() - y.min())  # far above the tolerance
    assert first_argmax(y) == i2


def test_constant_curve_and_nans():
    assert first_argmax(np.full(5, 2.0)) == 0
    assert first_argmin([np.nan, 3.0, 1.0, 1.0]) == 2
    with pytest.raises(ValueError):
        first_argmax([np.nan, np.nan])
    with pytest.raises(ValueError):
        first_argmax(np.zeros((2, 2)))
    assert 0 < EXTREMUM_RTOL < 1e-6
