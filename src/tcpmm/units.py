"""Unit conversions used at the edges (files, CLI, plots). Everything inside is SI."""

from __future__ import annotations

import math

MM = 1e-3  #: one millimetre [m]
UM = 1e-6  #: one micrometre [m]
MM_PER_MIN = 1e-3 / 60.0  #: one mm/min [m/s]
RPM = 2.0 * math.pi / 60.0  #: one rev/min [rad/s]


def mm_to_m(value):
    """Millimetres [mm] to metres [m]."""
    return value * MM


def m_to_mm(value):
    """Metres [m] to millimetres [mm]."""
    return value / MM


def m_to_um(value):
    """Metres [m] to micrometres [um]."""
    return value / UM


def feed_mm_per_min_to_m_per_s(feed_mm_per_min):
    """Feed [mm/min] to path speed [m/s]."""
    return feed_mm_per_min * MM_PER_MIN
