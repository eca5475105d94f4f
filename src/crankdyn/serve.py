"""The old path of :mod:`crankdyn.preview.server`, kept for one release: import from there."""

import sys

from crankdyn.preview import server as _module
from crankdyn.preview.server import *  # noqa: F403

sys.modules[__name__] = _module
