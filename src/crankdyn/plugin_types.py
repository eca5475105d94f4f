"""The old path of :mod:`crankdyn.plugin.types`, kept for one release: import from there."""

import sys

from crankdyn.plugin import types as _module
from crankdyn.plugin.types import *  # noqa: F403

sys.modules[__name__] = _module
