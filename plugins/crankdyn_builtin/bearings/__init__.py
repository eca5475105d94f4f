"""Built-in plugin: bearings."""
