"""The old path of :mod:`crankdyn.plugin.contracts`, kept for one release: import from there."""

import sys

from crankdyn.plugin import contracts as _module
from crankdyn.plugin.contracts import *  # noqa: F403

sys.modules[__name__] = _module
