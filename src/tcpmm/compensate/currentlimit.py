"""The drive's current the compensated command may ask: :data:`.bounds.CURRENT_SHARE` of
its limit on the model's run with the velocity unquantised, and below the limit itself on
the run ``tcpmm simulate`` makes, the feedback quantised.

The learning runs the axis with its feedback unquantised, as the error it learns from
would otherwise carry the sensors' steps. A velocity read as the difference of encoder
counts over one velocity-loop period ripples the current command by a count over that
period times the velocity gain: on bench C's model (2^20 counts per revolution, 62.5 µs,
1.7 A s/rad) by up to 0.2 A about the unquantised current, at random; the program's own
X current of 1.00 A read up to 1.15 A, and a command a picometre apart peaks elsewhere.
A current held to the share on the unquantised run alone reached a limit of 1.2 A; one
held on a single quantised run holds only that run. So the unquantised current is held
to the share, and below the limit by the ripple of the program's own run (which the
quantised run of any command near it shows again): the share keeps its margin for the
model's own error, the ripple's peaks stay off the clamp. Held below the share by the
ripple as well, a limit of 2.8 A on bench C's model cut the correction to the program's
own peak, and its largest spike after was 8.2 µm for 1.7 µm.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .bounds import CURRENT_SHARE, shrink

#: Share of the limit the quantised run keeps off it: the ripple is measured on one run
#: and peaks a little otherwise on another [-].
CLAMP_MARGIN = 0.01
#: Rounds of scaling the correction back to the current after the learning, before what
#: is still above it is dropped [-].
CURRENT_ROUNDS = 12


@dataclass(frozen=True)
class CurrentHold:
    """The unquantised current an axis's command may ask.

    Parameters
    ----------
    own : ndarray
        The program's own unquantised current per sample [A].
    allowed : float
        :data:`CURRENT_SHARE` of the limit, or the limit less the ripple where that is
        less, and no less than the program's own peak: where the program leaves no room,
        the correction asks no more than it does [A].
    """

    own: np.ndarray
    allowed: float

    @classmethod
    def of(cls, current_of, reference: np.ndarray, limit_A: float) -> CurrentHold:
        """The hold of the program ``reference`` on an axis of current limit ``limit_A``,
        ``current_of(position_m, quantised) -> current_A`` its run [A]."""
        own = np.abs(current_of(reference, False))
        ripple = float(np.max(np.abs(np.abs(current_of(reference, True)) - own)))
        room = min(CURRENT_SHARE * limit_A, (1 - CLAMP_MARGIN) * limit_A - ripple)
        return cls(own, max(room, float(np.max(own))))

    def keep(self, current: np.ndarray, last: bool = False) -> np.ndarray:
        """Per sample the share of the correction that brings the unquantised
        ``current`` of the command within :attr:`allowed`, taken as in proportion to what
        the correction adds to the program's own; 0 where above it with ``last``, 1 where
        not above it [-]."""
        now = np.abs(current)
        room = np.clip((self.allowed - self.own) / np.maximum(now - self.own, 1e-12), 0, 1)
        return np.where(now > self.allowed, 0.0 if last else room, 1.0)


def within_current(hold: CurrentHold, current_of, reference: np.ndarray, corr: np.ndarray,
                   fit, period_s: float) -> np.ndarray:
    """The correction scaled back about each sample where the unquantised current of the
    command exceeds what ``hold`` allows, round by round, and dropped where it still does
    after :data:`CURRENT_ROUNDS` [m].

    Parameters
    ----------
    hold : CurrentHold
        What the axis may ask [A].
    current_of : callable
        ``(position_m, quantised) -> current_A`` of the axis's run [A].
    reference, corr : ndarray
        Programmed command and its correction [m].
    fit : callable
        ``correction -> correction`` within the axis's other limits [m].
    period_s : float
        Command period [s].
    """
    for k in range(CURRENT_ROUNDS + 1):
        if not np.any(corr):
            break
        keep = hold.keep(current_of(reference + corr, False), last=k == CURRENT_ROUNDS)
        if np.all(keep >= 1.0):
            break
        corr = fit(shrink(corr, keep, period_s))
    return corr
