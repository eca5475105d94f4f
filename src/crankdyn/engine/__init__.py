"""Plan and run a scene's stages: the order from ``requires``/``provides``, each stage's inputs
and services, the studies computed in a forked child, the stage cache of the live preview and
the garbage-collector scope of a report's build."""
