"""The G-code dialect: which words are executed, which are skipped with a warning, which refused.

G and M codes are keyed by ten times their number (G90.1 -> 901). Each skipped or
refused code carries the sentence that tells the user why.
"""

from __future__ import annotations

#: G and M numbers at or above this are no code of any controller [-]
MAX_CODE = 1000
#: Largest coordinate, centre offset or radius taken, a thousand metres: beyond any
#: machine's travel, a typo; next to it the interpolator's doubles lose the path's
#: micrometres, and past 1e308 a coordinate is infinite [m].
MAX_COORDINATE_M = 1e3
#: A straight move no longer than this on every axis goes nowhere: a repeated point, or
#: one that rounding moved (0.3 + 0.3 + 0.3 mm in G91, then G90 X0.9: 1e-16 mm), which a
#: controller skips and which would stop the feed at a corner of no size. 1 nm, to the
#: rounding of the coordinates: a jog of 0.000001 mm, the difference of two positions in
#: metres, rounds to either side of 1e-9, and some were skipped, some run [m].
ZERO_MOVE_M = 1e-9 * (1.0 + 1e-6)
#: Highest feed taken, 16.7 m/s, faster than any feed axis [mm/min or in/min].
MAX_FEED = 1e6
#: A length word (X, Y, Z, I, J, K, R) written without a decimal point whose number, as
#: written, is this large or larger is warned of, once a program: a Fanuc control without
#: calculator-type input reads it in its least input increment (0.001 mm, 0.0001 in), so
#: that X50000 is 50 mm there, 50 m here; a length of 1 m or more without a point is
#: rarely meant [mm or in].
WHOLE_LENGTH = 1000
#: the key of that warning [-]
NO_POINT = "length without a decimal point"

#: motion codes -> 0 (G0) .. 3 (G3)
MOTION = {0: 0, 10: 1, 20: 2, 30: 3}
#: executed G codes -> their modal group
G_GROUP = {
    0: "motion",
    10: "motion",
    20: "motion",
    30: "motion",
    40: "dwell",
    170: "plane",
    180: "plane",
    190: "plane",
    200: "units",
    210: "units",
    900: "distance",
    910: "distance",
    901: "arc distance",
    911: "arc distance",
    610: "path mode",
    640: "path mode",
    90: "exact stop once",
}
#: G codes that do not change the tool path: skipped with a warning
G_IGNORED = {
    400: "cutter radius compensation is not modelled and G40 (off) changes nothing",
    430: "tool length offsets only shift Z by a constant; the offset is taken as zero",
    490: "tool length offsets only shift Z by a constant; G49 changes nothing",
    540: "work offsets only shift the program by a constant; taken as zero",
    550: "work offsets only shift the program by a constant; taken as zero",
    560: "work offsets only shift the program by a constant; taken as zero",
    570: "work offsets only shift the program by a constant; taken as zero",
    580: "work offsets only shift the program by a constant; taken as zero",
    590: "work offsets only shift the program by a constant; taken as zero",
    800: "no canned cycle is supported, so cancelling one (G80) changes nothing",
    940: "feed per minute is the only feed mode; G94 changes nothing",
    980: "canned cycle return level has no effect without canned cycles",
    990: "canned cycle return level has no effect without canned cycles",
    150: "polar coordinates are not supported, so G15 (off) changes nothing",
    690: "coordinate rotation is not supported, so G69 (off) changes nothing",
    500: "scaling is not supported, so G50 (off) changes nothing",
}
#: G codes that would change the tool path but are not modelled: an error
G_REFUSED = {
    410: "cutter radius compensation (G41) would move the path; program the tool centre",
    420: "cutter radius compensation (G42) would move the path; program the tool centre",
    930: "inverse-time feed (G93) is not supported; program F in mm/min (G94)",
    950: "feed per revolution (G95) is not supported; program F in mm/min (G94)",
    280: "reference-point return (G28) is not supported; program the move with G0",
    300: "reference-point return (G30) is not supported; program the move with G0",
    530: "machine coordinates (G53) are not supported; program in work coordinates",
    920: "coordinate-system setting (G92) is not supported; program absolute positions",
    160: "polar coordinates (G16) are not supported; program X, Y, Z",
    510: "scaling (G51) is not supported; scale the program itself",
    680: "coordinate rotation (G68) is not supported; rotate the program itself",
    100: "data setting (G10) is not supported; remove it",
}
#: M codes skipped with a warning (M2/M30 end the program; M98/M99 are an error)
M_IGNORED = {
    0: "a program stop is not modelled; the program runs on",
    1: "an optional stop is not modelled; the program runs on",
    3: "the spindle is not modelled",
    4: "the spindle is not modelled",
    5: "the spindle is not modelled",
    6: "tool changes are not modelled",
    7: "coolant is not modelled",
    8: "coolant is not modelled",
    9: "coolant is not modelled",
}
#: letters skipped with a warning
LETTER_IGNORED = {
    "S": "spindle speed is not modelled",
    "T": "tool selection is not modelled",
    "H": "tool length offsets are taken as zero",
    "D": "cutter radius offsets are not modelled",
    "O": "the program number is not used",
}
KNOWN_LETTERS = set("GMNFXYZIJKRPQ") | set(LETTER_IGNORED)
OTHER_AXES = set("ABCUVW")
