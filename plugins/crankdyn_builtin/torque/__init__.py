"""Built-in plugin: torque."""
