"""The balancing physics' internal moments of the centrifugal forces."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crankdyn.physics import balancing as bal


@pytest.mark.parametrize(
    "lags_deg, expected",
    [
        ([0, 180, 180, 0], 1.0),  # in-line four: C a in the middle
        ([0, 240, 120, 120, 240, 0], math.sqrt(3.0)),  # in-line six (1-5-3-6-2-4)
        ([0], 0.0),  # one crank: no section between cranks
    ],
)
def test_the_internal_moment_is_the_largest_over_the_shafts_sections(lags_deg, expected):
    g = bal.geometry([0.0] * len(lags_deg), range(len(lags_deg)), lags_deg, 0.0)
    assert bal.internal_moment_max(g) == pytest.approx(expected, rel=1e-12)
    if len(lags_deg) < 2:
        return
    # independent: M(x) from the left and from the right on a fine grid of sections
    unit = np.exp(-1j * np.radians(lags_deg))
    x = np.arange(len(lags_deg)) - 0.5 * (len(lags_deg) - 1)
    sections = np.linspace(x[0], x[-1], 2001)
    left = [abs(np.sum(unit[x < s] * (s - x[x < s]))) for s in sections]
    right = [abs(np.sum(unit[x >= s] * (x[x >= s] - s))) for s in sections]
    np.testing.assert_allclose(left, right, atol=1e-12)  # balanced: either side gives it
    assert max(left) == pytest.approx(expected, rel=1e-9)
