"""Built-in plugin: speed fluctuation."""
