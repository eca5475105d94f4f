"""Built-in plugin: forces."""
