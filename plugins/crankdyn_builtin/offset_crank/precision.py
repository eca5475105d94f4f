"""How many significant digits the offset mechanism's own lengths and angles are printed with,
so that a value reads the same in every sentence, equation and table that gives it."""

#: The piston's stroke S: to the micrometre for a stroke of 10 to 99 mm (its excess over 2R,
#: some tenths of a millimetre, reads off it).
STROKE_DIGITS = 5
#: The dead centres' angles from the cylinder axis: to a thousandth of a degree below 10°.
ANGLE_DIGITS = 4
