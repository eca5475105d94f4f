"""The old path of :mod:`crankdyn.plugin.registry`, kept for one release: import from there."""

import sys

from crankdyn.plugin import registry as _module
from crankdyn.plugin.registry import *  # noqa: F403

sys.modules[__name__] = _module
