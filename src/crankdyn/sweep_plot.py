"""The old path of :mod:`crankdyn.batch.sweep_plot`, kept for one release: import from there."""

import sys

from crankdyn.batch import sweep_plot as _module
from crankdyn.batch.sweep_plot import *  # noqa: F403

sys.modules[__name__] = _module
