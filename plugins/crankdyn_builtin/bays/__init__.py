"""Built-in plugin: bays."""
