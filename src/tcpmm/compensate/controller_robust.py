"""The controller-side compensation judged on machines drawn from the model's uncertainty,
as the command correction is (:mod:`.robust`): the pulses and the cross-talk feed-forward
are scaled together to the largest share in {1, 3/4, ..., 0} that leaves no draw worse than
without them, on the circle's contour error, largest reversal spike or G. A pulse tuned on
a model whose friction is off by its uncertainty can push a reversal the wrong way; the
share is what every draw still gains from.
"""

from __future__ import annotations

import numpy as np

from ..whatif.draws import MODEL_ERROR, draw_machine
from .controller import (
    AxisController,
    ControllerCompensation,
    controller_figures,
    reversal_pulses,
    with_cross_talk,
)
from .robust import EQUAL_M, over_draws

#: Shares of the tuned parameters tried, largest first [-].
SHARES = (1.0, 0.75, 0.5, 0.25)

#: The figures judged on every draw: ``name: (part, key)`` of :func:`.scores.judge` [-].
JUDGED = {"contour_error": ("path", "contour_error_um"),
          "spike": ("circle", "largest_spike_um"),
          "circular_deviation": ("circle", "circular_deviation_um")}


def scaled(cc: ControllerCompensation, share: float) -> dict:
    """Every axis's parameters times ``share`` [-]."""
    return {a: AxisController(c.pulse_A * share, c.decay_s, c.velocity_pulse_m_per_s * share,
                              c.cross_talk_s2 * share) for a, c in cc.axes.items()}


def applied(machine, command, params: dict, judge_args: tuple) -> dict:
    """The model's TCP figures with the parameters applied as the drive applies them.

    Parameters
    ----------
    machine : Machine
        The machine run [SI].
    command : Command
        The programmed circle [m].
    params : dict of str to AxisController
        Per axis [-].
    judge_args : tuple
        ``(radius_m, centre_m, plane)`` [-].
    """
    ctc = with_cross_talk(command, {a: c.cross_talk_s2 for a, c in params.items()})
    pulses = {a: reversal_pulses(ctc, a, c.pulse_A, c.decay_s) for a, c in params.items()
              if c.pulse_A != 0.0}
    return controller_figures(machine, ctc, command, pulses, *judge_args)


def _figure_array(figs: list, part: str, key: str) -> np.ndarray:
    """One figure per draw, NaN (a spike the circle does not cross) as 0 [m]."""
    return np.nan_to_num(np.array([f.get(part, {}).get(key, np.nan) for f in figs]) * 1e-6)


def never_worse(before: list, after: list) -> bool:
    """Whether no draw's judged figure grew by more than the sensors' resolution [-]."""
    return all(np.all(_figure_array(after, *k) <= _figure_array(before, *k) + EQUAL_M)
               for k in JUDGED.values())


def robust_controller(machine, cc: ControllerCompensation, command, radius_m: float,
                      centre_m=(0.0, 0.0), plane=("X", "Y"), n_draws: int = 6,
                      seed: int = 0) -> None:
    """Scale the controller-side compensation back where draws of the model cannot
    guarantee that it helps; sets ``cc.axes``, ``cc.scores["after"]`` and
    ``cc.robustness`` in place.

    Parameters
    ----------
    machine : Machine
        The identified model with its uncertainty [SI].
    cc : ControllerCompensation
        From :func:`.controller.controller_compensation` on that model [-].
    command : Command
        The circle's programmed command [m].
    radius_m : float
        Its radius [m].
    centre_m : tuple of float
        Its centre [m].
    plane : tuple of str
        Its axes [-].
    n_draws : int
        Machines drawn from the uncertainty, with the floors of ``tcpmm spread``; the
        model as identified is judged too [-].
    seed : int
        Seed of the draws [-].
    """
    if not any(c.pulse_A or c.cross_talk_s2 for c in cc.axes.values()):
        cc.robustness = {"draws": n_draws, "seed": seed, "share": 0.0}  # nothing to judge
        return
    args = (radius_m, centre_m, plane)
    rng = np.random.default_rng(seed)
    machines = [machine] + [draw_machine(machine, rng, MODEL_ERROR) for _ in range(n_draws)]
    none = scaled(cc, 0.0)
    before = [applied(m, command, none, args) for m in machines]
    share, after = 0.0, before
    for s in SHARES:
        trial = [applied(m, command, scaled(cc, s), args) for m in machines]
        if never_worse(before, trial):
            share, after = s, trial
            break
    cc.axes = scaled(cc, share)
    cc.scores["after"] = after[0]
    cc.robustness = {"draws": n_draws, "seed": seed, "share": share,
                     **{name: over_draws(_figure_array(before, *k), _figure_array(after, *k))
                        for name, k in JUDGED.items()}}
