"""The old path of :mod:`crankdyn.scene.inputcheck`, kept for one release: import from there."""

import sys

from crankdyn.scene import inputcheck as _module
from crankdyn.scene.inputcheck import *  # noqa: F403

sys.modules[__name__] = _module
