"""The live preview (``crankdyn serve``): a local HTTP server that rebuilds the report when the
scene is saved."""
