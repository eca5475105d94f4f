"""The old path of :mod:`crankdyn.scene.quick_units`, kept for one release: import from there."""

import sys

from crankdyn.scene import quick_units as _module
from crankdyn.scene.quick_units import *  # noqa: F403

sys.modules[__name__] = _module
