"""The old path of :mod:`crankdyn.parallel.fork`, kept for one release: import from there."""

import sys

from crankdyn.parallel import fork as _module
from crankdyn.parallel.fork import *  # noqa: F403

sys.modules[__name__] = _module
