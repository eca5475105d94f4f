"""The old path of :mod:`crankdyn.output.pipeline`, kept for one release: import from there."""

import sys

from crankdyn.output import pipeline as _module
from crankdyn.output.pipeline import *  # noqa: F403

sys.modules[__name__] = _module
