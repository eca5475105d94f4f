"""Built-in plugin: kinematics."""
