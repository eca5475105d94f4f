"""The old path of :mod:`crankdyn.batch.grid_run`, kept for one release: import from there."""

import sys

from crankdyn.batch import grid_run as _module
from crankdyn.batch.grid_run import *  # noqa: F403

sys.modules[__name__] = _module
