"""Built-in plugin: numerics."""
