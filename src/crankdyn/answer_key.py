"""The old path of :mod:`crankdyn.batch.answer_key`, kept for one release: import from there."""

import sys

from crankdyn.batch import answer_key as _module
from crankdyn.batch.answer_key import *  # noqa: F403

sys.modules[__name__] = _module
