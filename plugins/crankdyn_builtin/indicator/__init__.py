"""Built-in plugin: indicator."""
