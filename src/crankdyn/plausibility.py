"""The old path of :mod:`crankdyn.report.plausibility`, kept for one release: import from there."""

import sys

from crankdyn.report import plausibility as _module
from crankdyn.report.plausibility import *  # noqa: F403

sys.modules[__name__] = _module
