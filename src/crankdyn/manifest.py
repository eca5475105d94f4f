"""The old path of :mod:`crankdyn.output.manifest`, kept for one release: import from there."""

import sys

from crankdyn.output import manifest as _module
from crankdyn.output.manifest import *  # noqa: F403

sys.modules[__name__] = _module
