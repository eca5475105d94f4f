"""The old path of :mod:`crankdyn.scene.datafiles`, kept for one release: import from there."""

import sys

from crankdyn.scene import datafiles as _module
from crankdyn.scene.datafiles import *  # noqa: F403

sys.modules[__name__] = _module
