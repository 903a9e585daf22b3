"""What a run checks of its position command before the axes take it, for a command made
whole and for one that comes in pieces (a program streamed) alike: an axis the machine
does not have may not move, and a position beyond any machine tool's travel or a speed
beyond the machine's rapid traverse is warned of as a units or sampling error."""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError, InputWarning
from ..path.settings import AXES, InterpolatorSettings

#: Speed above which a command is taken as a unit or sampling error when the model has no
#: rapid traverse of its own (300 m/min, beyond the feed axes of machine tools) [m/s].
SPEED_LIMIT_M_PER_S = 5.0
#: Position beyond which a command is taken as a unit error: the travel of the largest
#: gantry and floor-type machine tools is some tens of metres [m].
TRAVEL_LIMIT_M = 100.0


class CommandCheck:
    """The checks of a command taken a piece at a time (:meth:`add`), its warnings said
    once at the end (:meth:`warn`) with the figures of the whole command.

    The limit of speed is 1.05 times the rapid traverse of the model's interpolation
    settings, or :data:`SPEED_LIMIT_M_PER_S` when it has none.

    Parameters
    ----------
    machine : Machine
        The machine model [SI].
    """

    def __init__(self, machine):
        self.axes = tuple(machine.axes)
        settings = InterpolatorSettings.model_validate(machine.interpolation or {})
        self.rapid = {}
        if "rapid_m_per_s" in settings.model_fields_set:  # not the interpolator's default
            self.rapid = dict(zip(AXES, settings.rapid(), strict=True))
        self.first: dict = {}  # per axis its first position [m]
        self.last: dict = {}  # per axis its last sample: time [s], position [m]
        self.far: dict = {}  # per axis the largest distance from zero [m]
        self.fastest: dict = {}  # per axis the largest speed [m/s] and its time [s]

    def add(self, time_s, positions: dict) -> None:
        """The next piece of the command: refused where it moves an axis the machine does
        not have (one it holds still is no matter: the interpreter writes every axis a
        program names, an X-only test on a one-axis rig too).

        Parameters
        ----------
        time_s : ndarray
            The piece's sample times [s].
        positions : dict of str to ndarray
            Position per axis [m].
        """
        t = np.asarray(time_s, dtype=float)
        positions = {a: np.asarray(p, dtype=float) for a, p in positions.items()}
        unknown = [a for a, p in positions.items() if a not in self.axes
                   and p.size and np.any(p != self.first.setdefault(a, p[0]))]
        if unknown:
            raise InputError(
                f"the command drives axis {', '.join(unknown)} that the machine does not "
                f"have (machine axes: {', '.join(self.axes)})")
        dt = np.diff(t)
        for name, pos in positions.items():
            if not pos.size:
                continue
            self.far[name] = max(self.far.get(name, 0.0), float(np.max(np.abs(pos))))
            if name in self.last:  # the step from the last piece's end, before this one's
                t0, x0 = self.last[name]
                self._faster(name, abs(float(pos[0]) - x0) / (float(t[0]) - t0), t0)
            if pos.size > 1:
                v = np.abs(np.diff(pos)) / dt
                k = int(np.argmax(v))
                self._faster(name, float(v[k]), float(t[k]))
            self.last[name] = (float(t[-1]), float(pos[-1]))

    def _faster(self, name: str, v: float, t: float) -> None:
        """Keep the speed ``v`` [m/s] at ``t`` [s] where it is the axis's first fastest."""
        if name not in self.fastest or v > self.fastest[name][0]:
            self.fastest[name] = (v, t)

    def warn(self) -> None:
        """Warn where the command moved an axis faster than the machine can, or to a
        position no machine tool reaches (:data:`TRAVEL_LIMIT_M`) [-]."""
        for name in self.far:
            if self.far[name] > TRAVEL_LIMIT_M:
                warnings.warn(
                    f"axis {name}: the command goes to {self.far[name] * 1e3:.4g} mm, beyond "
                    f"the travel of any machine tool ({TRAVEL_LIMIT_M * 1e3:.4g} mm); check "
                    "the command's units (mm)", InputWarning, stacklevel=3)
            if name not in self.fastest:
                continue
            v, t = self.fastest[name]
            limit = self.rapid.get(name, max(self.rapid.values(), default=None))
            bound = SPEED_LIMIT_M_PER_S if limit is None else 1.05 * float(limit)
            if v > bound:
                what = ("the rapid traverse of the model's interpolation settings"
                        if limit is not None else "any machine-tool feed axis")
                warnings.warn(
                    f"axis {name}: the command moves at {v * 60:.4g} m/min at t = {t:.6g} s, "
                    f"faster than {what} ({bound * 60:.4g} m/min); check the command's units "
                    "(mm) and sampling", InputWarning, stacklevel=3)
