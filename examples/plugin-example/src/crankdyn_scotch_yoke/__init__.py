"""crankdyn plugin: the Scotch-yoke mechanism (an example of a third-party plugin).

The crank pin slides in a slot of the yoke, which is rigid with the piston rod, so the
piston moves exactly harmonically: s = R (1 - cos alpha). There is no connecting rod.
"""

__version__ = "0.1.0"
