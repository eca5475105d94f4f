"""Built-in plugin: balancing."""
