"""Built-in plugin: planetary."""
