"""Built-in plugin: vane."""
