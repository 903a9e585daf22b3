"""Geometry checks of the G-code interpreter: coordinate sizes, lengths written without a
decimal point, arc centres and radii.

A mixin of the interpreter in :mod:`tcpmm.path.gcode`, which holds the modal state
(``pos``, ``unit``, ``plane``, ``motion``, ``arc_absolute``, ``feed``, ``exact_stop``)
and reports through ``error`` and ``warn``.
"""

from __future__ import annotations

import math

from .gcode_words import MAX_COORDINATE_M, NO_POINT, WHOLE_LENGTH
from .segments import AXIS_INDEX, FULL_CIRCLE_TOL_M, PLANES, Arc

MM_M = 1e-3
INCH_M = 25.4e-3
#: allowed difference between the radius to the start and to the end of an arc:
#: the larger of this [m] and ARC_REL_TOL times the radius
ARC_ABS_TOL_M = 5e-6
ARC_REL_TOL = 1e-4

_CENTRE_LETTER = {"X": "I", "Y": "J", "Z": "K"}


def short_text(text: str) -> str:
    """A word as written, cut short where its number is very long [-]."""
    return text if len(text) <= 20 else f"{text[:16]}... ({len(text) - 1} characters)"


class GeometryMixin:
    """Coordinate-size and arc checks, and the arc segment, of the interpreter."""

    def _check_sizes(self, w, target, line):
        """Coordinates, centre offsets and radii within :data:`MAX_COORDINATE_M`."""
        unit_name = "in" if self.unit == INCH_M else "mm"
        limit = f"{MAX_COORDINATE_M / self.unit:.6g} {unit_name}"
        for axis in "XYZ":
            at = target[AXIS_INDEX[axis]]
            if axis in w and not abs(at) <= MAX_COORDINATE_M:
                self.error(f"{axis} would be at {at / self.unit:.6g} {unit_name}, beyond "
                           f"{limit} from zero, more than any machine travels; check the "
                           "number (and G20/G21, G90/G91)", line, w[axis].column)
        for L in "IJKR":
            if L in w and not abs(w[L].value * self.unit) <= MAX_COORDINATE_M:
                self.error(f"{short_text(w[L].text)} is beyond {limit}, more than any machine "
                           "travels; check the number (and G20/G21)", line, w[L].column)

    def no_point(self, w, line):
        """Warn of the block's first length word written without a decimal point whose
        number reaches :data:`~tcpmm.path.gcode_words.WHOLE_LENGTH`: a Fanuc control
        without calculator-type input reads it in 0.001 mm (0.0001 in)."""
        word = min((w[k] for k in "XYZIJKR" if k in w and "." not in w[k].text
                    and abs(w[k].value) >= WHOLE_LENGTH),
                   key=lambda x: x.column, default=None)
        if word is None:
            return
        unit, step, digits = ("in", 1e-4, 4) if self.unit == INCH_M else ("mm", 1e-3, 3)
        there = f"{word.value * step:.{digits}f}".rstrip("0")
        self.warn(NO_POINT, f"tcpmm reads it as {word.value:.0f} {unit}; a Fanuc control "
                  f"without calculator-type input reads it in {step:g} {unit} "
                  f"({there.rstrip('.')} {unit}): write {word.letter}{there} if that is "
                  "meant", line, word.column,
                  head=f"{short_text(word.text)} has no decimal point")

    def arc(self, w, end, gword, line):
        a, b = PLANES[self.plane]
        ia, ib = AXIS_INDEX[a], AXIS_INDEX[b]
        ca_letter, cb_letter = _CENTRE_LETTER[a], _CENTRE_LETTER[b]
        self._check_arc_words(w, gword, line, a + b, ca_letter, cb_letter)
        s = self.pos
        if "R" in w:
            ca, cb = self._radius_centre(w["R"], end, ia, ib, (ca_letter, cb_letter), line)
        else:
            ca, cb = self._offset_centre(w, end, ia, ib, (ca_letter, cb_letter), line)
        centre = [0.0, 0.0, 0.0]
        centre[ia], centre[ib] = ca, cb
        centre[3 - ia - ib] = s[3 - ia - ib]
        direction = "ccw" if self.motion == 3 else "cw"
        return Arc(
            s,
            end,
            tuple(centre),
            (a, b),
            direction,
            self.feed,
            exact_stop=self.exact_stop,
            line=line,
        )

    def _unit_name(self) -> str:
        return "in" if self.unit == INCH_M else "mm"

    def _radius_centre(self, rw, end, ia, ib, letters, line):
        """The centre (in the plane's two axes) of an arc given by its radius R [m]."""
        s = self.pos
        da, db = end[ia] - s[ia], end[ib] - s[ib]
        chord = math.hypot(da, db)
        r = rw.value * self.unit
        if chord < FULL_CIRCLE_TOL_M:
            self.error(
                f"the R form cannot describe a full circle (end = start); give "
                f"the centre with {letters[0]} and {letters[1]}",
                line,
                rw.column,
            )
        if r == 0.0:
            self.error("arc radius R0 is zero; give the radius of the arc", line, rw.column)
        half = 0.5 * chord
        h2 = r * r - half * half
        if h2 < 0.0:
            if half - abs(r) > max(ARC_ABS_TOL_M, ARC_REL_TOL * abs(r)):
                self.error(
                    f"radius {rw.text} is smaller than half the distance from "
                    f"start to end ({half / self.unit:.6g} {self._unit_name()}); "
                    "increase R or move the end point",
                    line,
                    rw.column,
                )
            h2 = 0.0
        h = math.sqrt(h2)
        # centre left of the chord for a short CCW arc; R < 0 takes the long way
        side = (1.0 if self.motion == 3 else -1.0) * (1.0 if r > 0 else -1.0)
        return (s[ia] + 0.5 * da - side * h * db / chord,
                s[ib] + 0.5 * db + side * h * da / chord)

    def _offset_centre(self, w, end, ia, ib, letters, line):
        """The centre (in the plane's two axes) of an arc given by I, J or K [m]."""
        s = self.pos
        ca_letter, cb_letter = letters
        cw_a, cw_b = w.get(ca_letter), w.get(cb_letter)
        col = (cw_a or cw_b).column
        if self.arc_absolute:
            if cw_a is None or cw_b is None:
                self.error(
                    f"with G90.1 the centre needs both {ca_letter} and {cb_letter}", line, col
                )
            ca, cb = cw_a.value * self.unit, cw_b.value * self.unit
        else:
            ca = s[ia] + (cw_a.value * self.unit if cw_a else 0.0)
            cb = s[ib] + (cw_b.value * self.unit if cw_b else 0.0)
        r0 = math.hypot(s[ia] - ca, s[ib] - cb)
        r1 = math.hypot(end[ia] - ca, end[ib] - cb)
        if r0 <= ARC_ABS_TOL_M or r1 <= ARC_ABS_TOL_M:
            # within the radii's own tolerance of 0, no arc's centre and sweep are defined
            unit_name = self._unit_name()
            self.error(
                f"arc of zero radius: the centre is {min(r0, r1) / self.unit:.6g} "
                f"{unit_name} from the start or end point, within the arcs' tolerance of "
                f"{ARC_ABS_TOL_M / self.unit:.6g} {unit_name}; check {ca_letter} and "
                f"{cb_letter}",
                line,
                col,
            )
        if abs(r1 - r0) > max(ARC_ABS_TOL_M, ARC_REL_TOL * r0):
            unit_name = self._unit_name()
            self.error(
                f"the arc's radius to the start is {r0 / self.unit:.6g} "
                f"{unit_name} but to the end {r1 / self.unit:.6g} {unit_name}; "
                f"correct the end point or the centre ({ca_letter}, {cb_letter})",
                line,
                col,
            )
        return ca, cb

    def _check_arc_words(self, w, gword, line, plane_axes, ca_letter, cb_letter):
        """The centre words of the plane, or R, one of the two."""
        name = f"G{self.motion}"
        for L in "IJK":
            if L in w and L not in (ca_letter, cb_letter):
                self.error(
                    f"{L} is not a centre word of the G{self.plane} plane ({plane_axes}); "
                    f"use {ca_letter} and {cb_letter}",
                    line,
                    w[L].column,
                )
        has_ijk = ca_letter in w or cb_letter in w
        if has_ijk and "R" in w:
            self.error(
                f"give the arc centre ({ca_letter}, {cb_letter}) or the radius R, not both",
                line,
                w["R"].column,
            )
        if not has_ijk and "R" not in w:
            col = gword.column if gword is not None else next(w[k] for k in "XYZ" if k in w).column
            self.error(
                f"{name} needs the centre ({ca_letter}, {cb_letter}) or the radius R", line, col
            )
