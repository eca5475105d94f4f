"""``python -m crankdyn`` is the same as the ``crankdyn`` command."""

from .cli import run

run()
