"""The scene: its model (:mod:`crankdyn.scene.model`, validated, SI), the one parser of values
with units (:mod:`crankdyn.scene.units`), the policy for the data files a scene names
(:mod:`crankdyn.scene.datafiles`) and the limits on a scene's structure
(:mod:`crankdyn.scene.inputcheck`).

``crankdyn.scene`` exports what the model module exports (``load_scene``, ``Scene``,
``options``, ``quantity``, ``number``, …).
"""

from __future__ import annotations

from .model import *  # noqa: F403 - the scene model is this package's public face
from .model import _problems  # noqa: F401 - a plugin's own checks reuse the model's
