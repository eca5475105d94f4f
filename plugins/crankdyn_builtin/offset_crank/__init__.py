"""Built-in plugin: offset crank."""
