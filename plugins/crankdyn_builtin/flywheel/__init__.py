"""Built-in plugin: flywheel."""
