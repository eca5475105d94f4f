"""``python -m crankdyn`` is the same as the ``crankdyn`` command."""

import sys

from .cli import main

sys.exit(main())
