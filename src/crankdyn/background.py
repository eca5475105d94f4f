"""The old path of :mod:`crankdyn.engine.studies`, kept for one release: import from there."""

import sys

from crankdyn.engine import studies as _module
from crankdyn.engine.studies import *  # noqa: F403

sys.modules[__name__] = _module
