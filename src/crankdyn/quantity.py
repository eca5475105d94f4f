"""The old path of :mod:`crankdyn.scene.unit_grammar`, kept for one release: import from there."""

import sys

from crankdyn.scene import unit_grammar as _module
from crankdyn.scene.unit_grammar import *  # noqa: F403

sys.modules[__name__] = _module
