"""The controller-side compensation judged on machines drawn from the model's uncertainty,
as the command correction is (:mod:`.robust`): the pulses and the cross-talk feed-forward
are scaled together to the largest share in {1, 3/4, ..., 0} under which every draw's
largest reversal spike falls by more than the margin the draws can see
(:func:`.robust.margin`), its G falls by more than that margin too or stays within the
sensors' resolution (:func:`.robust.vouched`), and its contour error grows on no draw. A
pulse tuned on a model whose friction is off by its uncertainty can push a reversal the
wrong way; the share is what every draw still gains from, by more than the model's error
could hide.
"""

from __future__ import annotations

import numpy as np

from ..whatif.draws import drawn_machines
from .controller import ControllerCompensation
from .drive import controlled_run
from .robust import EQUAL_M, margin, over_draws, vouched
from .scores import judge

#: Shares of the tuned parameters tried, largest first [-].
SHARES = (1.0, 0.75, 0.5, 0.25)

#: The figures judged on every draw: ``name: (part, key)`` of :func:`.scores.judge` [-].
JUDGED = {"contour_error": ("path", "contour_error_um"),
          "spike": ("circle", "largest_spike_um"),
          "circular_deviation": ("circle", "circular_deviation_um")}


def scaled(cc: ControllerCompensation, share: float) -> dict:
    """Every axis's parameters times ``share`` [-]."""
    return {a: c.scaled(share) for a, c in cc.axes.items()}


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
    return judge(controlled_run(machine, command, params), command, *judge_args)


def _figure_array(figs: list, part: str, key: str) -> np.ndarray:
    """One figure per draw, NaN (a spike the circle does not cross) as 0 [m]."""
    return np.nan_to_num(np.array([f.get(part, {}).get(key, np.nan) for f in figs]) * 1e-6)


def never_worse(before: list, after: list) -> bool:
    """Whether the draws vouch for the parameters: the largest spike, which the pulse is
    for, falls on every draw by more than :func:`.robust.margin`; G, which the spikes
    shape, falls by more than that too or stays within the sensors' resolution
    (:func:`.robust.vouched`); the contour error, which the servo's lag sets more than a
    reversal does, grows on no draw beyond the sensors' resolution [-]."""
    def fig(runs, name):
        return _figure_array(runs, *JUDGED[name])

    b, a = fig(before, "spike"), fig(after, "spike")
    return bool(np.all(a <= b - margin(b))) and vouched(
        fig(before, "circular_deviation"), fig(after, "circular_deviation")) and bool(
        np.all(fig(after, "contour_error") <= fig(before, "contour_error") + EQUAL_M))


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
    machines = drawn_machines(machine, n_draws, seed)
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
                     **{name: figure_verdict(before, after, k) for name, k in JUDGED.items()}}


def figure_verdict(before: list, after: list, key: tuple) -> dict:
    """:func:`.robust.over_draws` of one judged figure, an improvement counted beyond
    :func:`.robust.margin` [-]."""
    b, a = _figure_array(before, *key), _figure_array(after, *key)
    return over_draws(b, a, margin(b))
