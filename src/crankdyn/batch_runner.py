"""The old path of :mod:`crankdyn.parallel.pool`, kept for one release: import from there."""

import sys

from crankdyn.parallel import pool as _module
from crankdyn.parallel.pool import *  # noqa: F403

sys.modules[__name__] = _module
