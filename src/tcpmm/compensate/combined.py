"""The command correction and the controller-side compensation together.

The friction pulse acts where the command correction cannot: the friction's fast transient
at a reversal lies above the learning's Q-filter corner, and the pulse is tied to the
instant the controller sees the commanded velocity reverse. The correction acts where the
pulse cannot: on the servo's lag and the structure's deflection, slow and everywhere on the
path. So the controller's pulse and feed-forward are fixed first, and the correction is
learned on the model as the controller runs it with them (:func:`.drive.axis_plant`: the
pulses at the reversals of the corrected setpoint, each learning step), once for each share
of them the draws may keep: it corrects what the pulse leaves, also what the pulse
overdoes below the Q-filter corner. Tuning the pulse
on a corrected command instead would leave the correction cancelling, without the pulse, the
slow part of the friction the pulse then answers a second time.

The robust choice then judges the combination on draws of the model: a share of the
parameters in {0, 1/2, 1}, the correction learned with it, and per axis a share of that
correction in {0, 1/4, ..., 1}; kept is the pair with the smallest worst-draw contour
error plus largest spike (the command is there for the first, the pulse for the second),
lower by more than :func:`.robust.margin` than the uncompensated one, among those whose
every figure the draws vouch for (:func:`.robust.acceptable`): each region's contour error
and the circle's spike and G fall on every draw by more than the margin, or stay within the
sensors' resolution, as in the choice of the command correction alone; then, with that
share of the parameters, the correction's share region by region as for the correction
alone (:func:`.robust.regional_shares`), so that where the draws keep no parameter the
command is the correction alone's: its shares per axis are then chosen as for the
correction alone (:func:`.robust.choose_of`), by the contour error alone.
The corrected command is only right with the parameters kept on the controller.
"""

from __future__ import annotations

import itertools

import numpy as np

from ..whatif.draws import drawn_machines
from .circleguard import CircleGuard
from .cornerguard import CornerGuard, held_entry
from .drawcontour import worst_entry
from .drive import axis_plant
from .learning import CUTOFF_HZ, compensate
from .regional import ROUNDS, per_combo
from .robust import (
    LEVELS,
    acceptable,
    axis_errors,
    choose_of,
    chosen,
    circle_rows,
    corners_hold,
    judged,
    margin,
    record,
    region_rows,
    regional_shares,
    regions,
    rises,
)

#: Shares of the controller-side parameters tried [-].
PARAMETER_SHARES = (0.0, 0.5, 1.0)


def scaled_params(params: dict, share: float) -> dict:
    """Every axis's pulse and feed-forward times ``share``; the decay as it is [-]."""
    return {a: c.scaled(share) for a, c in params.items()}


def plants(params: dict, share: float = 1.0) -> dict:
    """Per axis how the controller runs a command with ``share`` of its parameters [-]."""
    return {a: axis_plant(c, share) for a, c in params.items()}


def choose_combined(errs: dict, target, labels: np.ndarray, guard=None,
                    progress=None, corners=None) -> tuple:
    """The share of the parameters and per axis of the correction (module docstring).

    Parameters
    ----------
    errs : dict of float to ndarray
        Per share of the parameters the TCP errors of :func:`.robust.axis_errors` [m].
    target : Command
        The path the TCP is to follow [m].
    labels : ndarray
        Region per sample [-].
    guard : CircleGuard, optional
        The circle's figures [-].
    progress : callable, optional
        Called with no argument after each combination of shares judged [-].
    corners : CornerGuard, optional
        The corners' overshoot, which no combination kept may raise [-].

    Returns
    -------
    tuple
        ``(parameter share, shares per axis, figures before, figures after, figures of
        every combination of shares per axis with the parameter share chosen)`` [-].
    """
    n_ax, n_reg = next(iter(errs.values())).shape[1], labels.max() + 1
    zero = tuple([0] * n_ax)
    tick = progress if progress is not None else (lambda: None)

    def judge(e, c):
        figs = judged(e, c, target, labels, guard)
        tick()
        return figs

    per = {s: per_combo(e, lambda c, e=e: judge(e, c)) for s, e in errs.items()}
    before = per[0.0][zero]

    def objective(figs):
        return figs[:, :n_reg].max() + (figs[:, -2].max() if guard is not None else 0.0)

    best = (0.0, zero, before, objective(before))
    for s, c in itertools.product(PARAMETER_SHARES, itertools.product(range(len(LEVELS)),
                                                                       repeat=n_ax)):
        if s == 0.0 and c == zero:
            continue
        after = per[s][c]
        if (acceptable(before, after) and objective(after) < best[3] - margin(best[3])
                and (corners is None or corners_hold(corners, errs[s])(c))):
            best = (s, c, after, objective(after))
    if best[0] == 0.0:  # no parameter kept: the correction alone's choice
        shares, figs = choose_of(per[0.0], n_reg, None if corners is None else
                                 corners_hold(corners, errs[0.0]))
        return 0.0, shares, before, figs, per[0.0]
    return best[0], [LEVELS[k] for k in best[1]], before, best[2], per[best[0]]


def robust_combined(machine, comps: dict, params: dict, n_draws: int = 6, seed: int = 0,
                    radius_m=None, centre_m=(0.0, 0.0), plane=("X", "Y"), progress=None):
    """The combination the draws of the model vouch for, with its shares, verdicts and the
    parameters kept (module docstring).

    Parameters
    ----------
    machine : Machine
        The identified model with its uncertainty [SI].
    comps : dict of float to Compensation
        Per share of the parameters the correction learned with that share on the
        controller (:func:`combined_compensation`) [-].
    params : dict of str to AxisController
        The controller-side parameters tuned on the model [-].
    n_draws : int
        Machines drawn with the floors of ``tcpmm spread``; the model itself is judged
        too [-].
    seed : int
        Seed of the draws [-].
    radius_m : float, optional
        The circle's radius: its spike and G are judged too [m].
    centre_m : tuple of float
        Its centre [m].
    plane : tuple of str
        Its axes [-].
    progress : callable, optional
        Called with no argument after each step of :func:`combined_steps` but the
        learning [-].

    Returns
    -------
    Compensation
        The chosen one, its ``factors``, ``controller``, ``trusted`` and ``robustness``
        set [-].
    """
    first = comps[0.0]
    guard = None if radius_m is None else CircleGuard.of(first, radius_m, centre_m, plane)
    machines, labels = drawn_machines(machine, n_draws, seed), regions(first.target)
    tick = progress if progress is not None else (lambda: None)
    errs = {s: axis_errors(machines, c, plants(params, s), tick) for s, c in comps.items()}
    corners = CornerGuard.of(first.target, labels, errs[0.0][:, :, 0])
    share, shares, before, after, per = choose_combined(errs, first.target, labels, guard,
                                                        tick, corners)
    comp, extra = comps[share], {"draws": n_draws, "seed": seed, "parameter_share": share}
    # the correction's share region by region, with the parameters' share chosen, as alone
    step, rest = _rounds(tick)
    got = regional_shares(machines, comp, per, before, labels, guard, after,
                          plants(params, share), step, corners, shares)
    rest()
    errors = None
    if got is not None:
        factors, after, errors = got
        shares, extra = [factors[a] for a in comp.reference.axes], {**extra, "by_region": True}
    # the worst draw read as the figure after, the lag a G0 rapid carries into the cut counted
    extra.update(held_entry(corners), **worst_entry(chosen(errs[share], shares, errors), comp))
    record(comp, shares, region_rows(before, after, comp.target, labels),
           circle_rows(before, after, guard), labels, extra,
           rises(errs[share], shares, comp.target, errors, errs[0.0][:, :, 0]))
    comp.controller = scaled_params(params, share)
    return comp


def _rounds(tick):
    """``(step, rest)``: ``step`` calls ``tick`` after each round of the regions' shares
    (:func:`.robust.regional_shares`), ``rest`` once for each of :data:`.regional.ROUNDS`
    not run: a choice that ends early, or needs no round, still fills the bar whose total
    was counted before the work [-]."""
    done = [0]

    def step():
        done[0] += 1
        tick()

    def rest():
        for _ in range(ROUNDS - done[0]):
            tick()

    return step, rest


def combined_steps(command, iterations: int = 30, n_draws: int = 6) -> int:
    """The calls to ``progress`` of :func:`combined_compensation` with these arguments
    (its ``command``, ``iterations`` and ``n_draws``): for each share of the parameters
    learned, ``iterations + 1`` learning steps per axis; with draws, for each share also
    the model and each draw run at each share of the correction (:data:`.robust.LEVELS`)
    and each combination of those shares per axis judged, then :data:`.regional.ROUNDS`
    for the regions' shares [-].

    Parameters
    ----------
    command : Command
        The programmed command [m].
    iterations : int
        Learning steps [-].
    n_draws : int
        Draws of the model the combination is judged on [-].
    """
    n_ax = len(command.axes)
    learning = n_ax * (iterations + 1)
    if n_draws == 0:
        return learning
    per_share = learning + len(LEVELS) * (1 + n_draws) + len(LEVELS) ** n_ax
    return len(PARAMETER_SHARES) * per_share + ROUNDS


def combined_compensation(machine, command, params: dict, *, bounds=None,
                          iterations: int = 30, cutoff_hz: float = CUTOFF_HZ,
                          n_draws: int = 6, seed: int = 0, radius_m=None,
                          centre_m=(0.0, 0.0), plane=("X", "Y"), progress=None):
    """The command correction learned with the controller-side parameters applied, scaled
    back together with them over draws of the model (module docstring). A correction is
    learned for each share of the parameters the draws may keep: a correction learned with
    the pulse is wrong without it.

    Parameters
    ----------
    machine : Machine
        The identified model [SI].
    command : Command
        The programmed command [m].
    params : dict of str to AxisController
        The controller-side parameters tuned on the model
        (:func:`.controller.controller_compensation`) [-].
    bounds : dict of str to AxisBounds, optional
        Limits of the compensated command [-].
    iterations : int
        Learning steps [-].
    cutoff_hz : float
        Corner of the learning's Q-filter (:func:`.learning.compensate`) [Hz].
    n_draws : int
        Draws of the model it is judged on; 0 keeps the parameters and the correction
        as learned [-].
    seed : int
        Seed of the draws [-].
    radius_m, centre_m, plane
        The circle the command holds, where it is one: radius [m], centre [m] and its
        axes [-] (:func:`robust_combined`).
    progress : callable, optional
        Called with no argument after each step of the work, :func:`combined_steps`
        times in all [-].

    Returns
    -------
    Compensation
        With ``controller`` the parameters kept: the command is right only with them [-].
    """
    shares = PARAMETER_SHARES if n_draws > 0 else (1.0,)
    comps = {s: compensate(machine, command, iterations=iterations, cutoff_hz=cutoff_hz,
                           bounds=bounds, plants=plants(params, s), step=progress)
             for s in shares}
    if n_draws == 0:
        comps[1.0].controller = dict(params)
        return comps[1.0]
    return robust_combined(machine, comps, params, n_draws, seed, radius_m, centre_m, plane,
                           progress)
