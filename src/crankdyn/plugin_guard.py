"""The old path of :mod:`crankdyn.plugin.guard`, kept for one release: import from there."""

import sys

from crankdyn.plugin import guard as _module
from crankdyn.plugin.guard import *  # noqa: F403

sys.modules[__name__] = _module
