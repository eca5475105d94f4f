"""The old path of :mod:`crankdyn.engine.frozen_heap`, kept for one release: import from there."""

import sys

from crankdyn.engine import frozen_heap as _module
from crankdyn.engine.frozen_heap import *  # noqa: F403

sys.modules[__name__] = _module
