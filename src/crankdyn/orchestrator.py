"""The old path of :mod:`crankdyn.engine.orchestrator`, kept for one release: import from there."""

import sys

from crankdyn.engine import orchestrator as _module
from crankdyn.engine.orchestrator import *  # noqa: F403

sys.modules[__name__] = _module
