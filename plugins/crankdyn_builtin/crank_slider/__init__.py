"""Built-in plugin: the central crank-slider mechanism (single and multi-cylinder)."""
