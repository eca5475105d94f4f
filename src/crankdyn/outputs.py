"""The old path of :mod:`crankdyn.output.writers`, kept for one release: import from there."""

import sys

from crankdyn.output import writers as _module
from crankdyn.output.writers import *  # noqa: F403

sys.modules[__name__] = _module
