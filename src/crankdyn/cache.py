"""The old path of :mod:`crankdyn.engine.stage_cache`, kept for one release: import from there."""

import sys

from crankdyn.engine import stage_cache as _module
from crankdyn.engine.stage_cache import *  # noqa: F403

sys.modules[__name__] = _module
