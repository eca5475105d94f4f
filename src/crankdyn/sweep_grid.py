"""The old path of :mod:`crankdyn.batch.sweep`, kept for one release: import from there."""

import sys

from crankdyn.batch import sweep as _module
from crankdyn.batch.sweep import *  # noqa: F403

sys.modules[__name__] = _module
