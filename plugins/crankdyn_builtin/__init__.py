"""crankdyn's built-in mechanisms and analysis stages.

They register through the ``crankdyn`` entry-point group, exactly as a third-party
plugin does (see pyproject.toml); nothing in the core imports this package.
"""
