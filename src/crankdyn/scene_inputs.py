"""The old path of :mod:`crankdyn.plugin.scene_inputs`, kept for one release: import from there."""

import sys

from crankdyn.plugin import scene_inputs as _module
from crankdyn.plugin.scene_inputs import *  # noqa: F403

sys.modules[__name__] = _module
