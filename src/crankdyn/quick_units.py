"""The old path of :mod:`crankdyn.scene.units`, kept for one release: import from there."""

import sys

from crankdyn.scene import units as _module
from crankdyn.scene.units import *  # noqa: F403

sys.modules[__name__] = _module
