"""The old path of :mod:`crankdyn.plugin.hooks`, kept for one release: import from there."""

import sys

from crankdyn.plugin import hooks as _module
from crankdyn.plugin.hooks import *  # noqa: F403

sys.modules[__name__] = _module
