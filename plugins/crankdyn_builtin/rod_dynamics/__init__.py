"""Built-in plugin: rod dynamics."""
