"""Where a run holds its circles and arcs."""

#: The shortest arc analysed [deg]
MIN_ARC_DEG = 30.0
