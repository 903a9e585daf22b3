"""Excitation check: whether the sweep travelled (the guideway friction then holds the nut
on one flank) and whether friction held the axis at the bottom of the sweep's band; a
warning for each, since the FRFs are then not those of the linear mechanics."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ...io.csvutil import warn_input
from ..friction.sweepforce import MIN_SWEEP_TRAVEL_M, travel_velocity
from ..gates.findings import STANDING_SWEEP
from ..gates.sanity import FrictionHold, warn_friction_holds_sweep
from ..options import MIN_COHERENCE

if TYPE_CHECKING:
    from ..chain import AxisRun
    from ..options import IdentifyOptions


@dataclass(frozen=True)
class ExcitationCheck:
    """What the sweep's motion says about its FRFs.

    Parameters
    ----------
    velocity : float
        Steady travel velocity of the sweep, signed; zero when it stands [m/s].
    friction_hold : FrictionHold, optional
        Friction held the axis at the bottom of the sweep's band [-].
    """

    velocity: float
    friction_hold: FrictionHold | None = None

    @property
    def travel_speed(self) -> float:
        """Steady travel speed of the sweep, zero when it stands [m/s]."""
        return abs(self.velocity)


def check_excitation(run: AxisRun, options: IdentifyOptions) -> ExcitationCheck:
    """Check the sweep of one axis, and warn where it stood or friction held it.

    Parameters
    ----------
    run : AxisRun
        The axis with its FRFs [-].
    options : IdentifyOptions
        Not read by this step [-].
    """
    name, sweep = run.name, run.sweep
    velocity = travel_velocity(sweep, MIN_SWEEP_TRAVEL_M)
    standing = abs(velocity) == 0.0
    held = warn_friction_holds_sweep(name, sweep, run.frfs.frfs["G_M"], MIN_COHERENCE,
                                     standing=standing)
    if standing:
        warn_input(f"axis {name}: {STANDING_SWEEP}; the model fitted to it can be off by "
                   "tens of micrometres at the reversals (a machine's torque-mode sweep put "
                   "its X spikes 44 um off, of the wrong sign), and the verdict leaves its "
                   "mechanics open", file=getattr(sweep, "source", None))
    return ExcitationCheck(velocity, held)
