"""How many significant digits the offset mechanism's own lengths and angles are printed with,
so that a value reads the same in every sentence, equation and table that gives it."""

#: The piston's stroke S: to the micrometre for a stroke of 10 to 99 mm (its excess over 2R,
#: some tenths of a millimetre, reads off it).
STROKE_DIGITS = 5
#: The dead centres' angles: to a thousandth of a degree, whatever their size (the TDC's few
#: degrees off the axis and the BDC's 174,011° alike).
ANGLE_DECIMALS = 3


def angle_text(t, angle_deg: float) -> str:
    """A dead centre's angle as every sentence, equation and table of the section prints it."""
    return t.fixed(angle_deg, ANGLE_DECIMALS)
