"""The compensation against the model's own error: run on machines drawn from the model's
uncertainty, scaled back per region where the draws cannot guarantee an improvement.

Regions are the windows around every reversal of an axis and the stretches between them. A
share of the correction in {0, 1/4, ..., 1} is chosen per axis: the shares whose largest
contour error is smallest on the worst draw, among those whose every figure the draws
vouch for (:func:`vouched`: on every draw it falls by more than :func:`margin` or stays
within the sensors' resolution): the contour error of each region and, for a circle
(:mod:`.circleguard`), each of its reversal spikes, the largest and G; and no corner's
overshoot, the path's end included, may rise on any draw (:mod:`.cornerguard`). A share is
kept only where it lowers the worst draw's contour error by more than the margin, and a
region, spike or G counts as improved only where every draw falls by more than it. The
margin holds for the contour error too: the correction acts on the servo's lag and the
structure's deflection, which set that error, so it is the figure the correction moves and
claims to improve (a friction pulse hardly moves it, so the controller-side choice only
keeps it from growing), and a fall smaller than the model's error can be a rise on the
machine. A region is *trusted* where the chosen shares improve it on every draw and one
more draw, the machine, would be improved too (a sample of it, where also no draw may see
its own error rise: :mod:`.trust`), and *firm* where it would improve at least
:data:`FIRM_RATIO` times, by the draws' scatter (:func:`next_draw`). The draws carry the
model error's floors that ``tcpmm spread`` uses (:data:`tcpmm.whatif.draws.MODEL_ERROR`),
so that an axis identified with a small deviation is not drawn tighter than identification
can be right. The axes run apart in the model, so that each share is simulated once per
axis and draw and every combination of shares is a sum.
"""

from __future__ import annotations

import numpy as np

from ..analysis.contour import distances_to_polyline
from ..uncertainty.verdict import CALIBRATION
from ..whatif.draws import MODEL_ERROR, drawn_machines
from .circleguard import CircleGuard
from .cornerguard import CornerGuard, held_entry
from .drawcontour import worst_entry
from .regional import per_combo, pick, settle_regions, tcp_errors
from .trust import local_rises, next_draw, record

#: Shares of the correction tried [-].
LEVELS = (0.0, 0.25, 0.5, 0.75, 1.0)

#: Machines drawn from the model's uncertainty by default [-]. A figure can turn on a
#: threshold a draw must cross to show it: on a machine with lost motion whose model had
#: the guideway's share of one axis's friction 0.07 low and the structure behind its table
#: at half its mass and stiffness, the spike after the correction at one reversal stood
#: 27 um from the model's, and no draw of six or
#: eight crossed over: the corrections they kept made that machine's contour error 1.28
#: and 0.66 um worse. Of twelve and of sixteen draws one did, and held it back (a threshold
#: one draw in ten crosses is missed by sixteen draws one time in five, by eight nearly one
#: in two).
DRAWS = 16

#: Half-width of the window around a reversal [s].
REVERSAL_WINDOW_S = 0.06

#: Time around a sample in which its closest point on the path is sought [s].
CONTOUR_WINDOW_S = 0.1

#: Error below which two errors count as equal: the sensors' resolution [m].
EQUAL_M = 0.1e-6

#: Relative change of a figure below which the draws cannot tell an improvement: the floor
#: of the friction level's model error (:data:`tcpmm.whatif.draws.MODEL_ERROR`). A pulse
#: and the friction it answers are known to that share only, and a machine whose friction
#: differs in form rather than level, which no draw varies, moves the figure by as much.
RELATIVE_MARGIN = MODEL_ERROR["friction_level"]

#: Reduction the machine must reach, by the draws, for a firm verdict: the reduction the
#: compensation is to deliver [-].
FIRM_RATIO = 5.0


def margin(before: np.ndarray) -> np.ndarray:
    """The least fall of a figure that counts as an improvement: the sensors' resolution,
    or :data:`RELATIVE_MARGIN` of the figure where that is more [m].

    Parameters
    ----------
    before : ndarray
        The figure without the compensation, per draw [m].
    """
    return np.maximum(EQUAL_M, RELATIVE_MARGIN * np.asarray(before))


def vouched(before: np.ndarray, after: np.ndarray) -> bool:
    """Whether the draws vouch for the change of a figure: on every draw it falls by more
    than :func:`margin`, or it stays within the sensors' resolution. A fall smaller than
    the margin is no improvement the draws can see, and may be a rise on the machine [-].

    Parameters
    ----------
    before, after : ndarray
        The figure per draw without and with the compensation [m].
    """
    d = np.asarray(after) - np.asarray(before)
    # NaN: a spike not read, where a pass does not cross its point (delayed, may not): unjudged
    return bool(np.all((d <= -margin(before)) | (np.abs(d) <= EQUAL_M) | np.isnan(d)))


def verdict(least_ratio: float, improves: bool) -> str:
    """``firm`` where the machine improves at least :data:`FIRM_RATIO` times, ``improves``
    where it improves by less, ``uncertain`` where it may not improve, by the draws [-].

    Parameters
    ----------
    least_ratio : float
        The ratio before / after the machine reaches by the draws (:func:`over_draws`) [-].
    improves : bool
        Whether the machine falls by more than :func:`margin`, by the draws [-].
    """
    if not improves:
        return "uncertain"
    return "firm" if least_ratio >= FIRM_RATIO else "improves"


def regions(target, window_s: float = REVERSAL_WINDOW_S) -> np.ndarray:
    """Region number per sample: windows around each axis reversal (merged where they
    overlap) and the stretches between them, numbered in time order [-]."""
    T = target.period_s
    near = np.zeros(target.time_s.size, dtype=bool)
    w = round(window_s / T)
    for p in target.positions.values():
        v = np.diff(p)
        moving = np.flatnonzero(np.abs(v) > 1e-12)
        s = np.sign(v[moving])
        for k in moving[1:][s[1:] != s[:-1]]:
            near[max(0, k - w):k + w + 1] = True
    return np.concatenate([[0], np.cumsum(near[1:] != near[:-1])])


def contour(err: np.ndarray, target, window_s: float = CONTOUR_WINDOW_S) -> np.ndarray:
    """Distance of the TCP from the path per sample, shape (n,); as ``tcpmm contour`` and
    the figures before and after take it from a program's command (which says which
    samples are in G0 rapids): 0 in a rapid, which is no contour error of the part, and a
    sample out of one measured from its own feed move [m].

    Parameters
    ----------
    err : ndarray
        TCP error per axis, target minus TCP, shape (axes, n) [m].
    target : Command
        The path the TCP is to follow [m].
    window_s : float
        Time around each sample in which its closest point on the path is sought [s].
    """
    p = np.array(list(target.positions.values())).T
    t = target.time_s
    blocks = target.blocks()
    air = None if blocks is None else blocks[1]
    d = np.abs(distances_to_polyline({"tcp": p - err.T}, p, t, t, window_s, False,
                                     air=air)["tcp"][0])
    if air is not None:
        d[air != 0] = 0.0
    return d


def axis_errors(machines, comp, plants=None, progress=None) -> np.ndarray:
    """TCP error per machine, axis, share and sample, shape (m, axes, levels, n); each
    axis run as ``plants`` says (:func:`.learning.learn_axis`), default the command
    alone; ``progress`` called with no argument after each machine at each share. Each
    share's command is the one written with it (``command_with``): a correction beyond a
    limit is scaled back there, which may turn the axis and fire a pulse [m]."""
    axes = comp.reference.axes
    return np.stack([tcp_errors(machines, comp, comp.command_with(dict.fromkeys(axes, lev))
                                .positions, plants, progress)
                     for lev in LEVELS], axis=2)


def judged(errs: np.ndarray, combo, target, labels: np.ndarray, guard=None) -> np.ndarray:
    """Per machine for shares ``combo``: the largest error across the path in each region,
    then with a circle its spikes, the largest and G (:mod:`.circleguard`), shape
    (machines, regions [+ 4 passes + 2]) [m]."""
    n_ax = errs.shape[1]
    return figures(errs[:, np.arange(n_ax), list(combo)], target, labels, guard, any(combo))


def figures(e: np.ndarray, target, labels: np.ndarray, guard=None,
            compensated: bool = True) -> np.ndarray:
    """Per machine the largest error across the path in each region, then with a circle
    its spikes, the largest and G, from the TCP errors ``e`` (machines, axes, n), judged
    on the delayed path's passes where ``compensated``, shape (machines, regions
    [+ 4 passes + 2]) [m]."""
    across = np.array([contour(ei, target) for ei in e])
    out = np.array([across[:, labels == r].max(axis=1) for r in range(labels.max() + 1)]).T
    if guard is None:
        return out
    path = np.array(list(target.positions.values()))
    circle = np.array([guard.figures(path - ei, compensated) for ei in e])
    return np.hstack([out, circle])


def acceptable(before: np.ndarray, after: np.ndarray) -> bool:
    """Whether the draws vouch for the change of every figure (:func:`vouched`): each
    region's contour error and, for a circle, each spike and G fall on every draw by
    more than :func:`margin`, or stay within the sensors' resolution [-].

    Parameters
    ----------
    before, after : ndarray
        The figures of :func:`judged` per draw without and with the compensation [m].
    """
    return all(vouched(before[:, j], after[:, j]) for j in range(before.shape[1]))


def choose(errs: np.ndarray, target, labels: np.ndarray, guard=None) -> tuple:
    """Share per axis, per region the worst draws' errors before and after, and for a
    circle the same of its largest spike and G (:mod:`module docstring <.robust>`) [-]."""
    per = per_combo(errs, lambda c: judged(errs, c, target, labels, guard))
    shares, figs = choose_of(per, labels.max() + 1)
    before = per[tuple([0] * errs.shape[1])]
    return shares, region_rows(before, figs, target, labels), circle_rows(before, figs, guard)


def choose_of(per: dict, n_reg: int, holds=None) -> tuple:
    """The share per axis of :func:`choose` and its figures, from the figures of every
    combination of share levels (:func:`.regional.per_combo`); of those ``holds(combo)``
    passes, where given, asked only of a combination that would be kept [-]."""
    zero = tuple([0] * len(next(iter(per))))
    before = per[zero]
    best, best_worst, best_figs = zero, before[:, :n_reg].max(), before
    for c, after in per.items():
        worst = after[:, :n_reg].max()
        if (acceptable(before, after) and worst < best_worst - margin(best_worst)
                and (holds is None or holds(c))):
            best, best_worst, best_figs = c, worst, after
    return [LEVELS[k] for k in best], best_figs


def region_rows(before: np.ndarray, after: np.ndarray, target, labels: np.ndarray) -> list:
    """Per region its time span and :func:`over_draws` of its worst errors, from the
    figures of :func:`judged` without and with the compensation [-]."""
    rows = []
    for r in range(labels.max() + 1):
        sel = labels == r
        rows.append({"region": r, "start_s": float(target.time_s[sel][0]),
                     "end_s": float(target.time_s[sel][-1]),
                     **over_draws(before[:, r], after[:, r], margin(before[:, r]))})
    return rows


def over_draws(b: np.ndarray, a: np.ndarray, margin_m=EQUAL_M) -> dict:
    """The worst draw's figure before and after, the least ratio over the draws, whether
    every draw improves, the ratio one more draw reaches at 95 % (``ratio_bound``,
    :func:`next_draw` of the ratios' logarithm, each figure after the correction raised by
    the margin, at least the calibration's floor: the model's error on what the correction
    removed stays in what it leaves)
    and the :func:`verdict` on it, from per-draw figures ``b`` and ``a``. The machine is
    judged as one more draw: firm where that bound reaches :data:`FIRM_RATIO`, improved
    where every draw falls by more than the margin and one more would too.

    Parameters
    ----------
    b, a : ndarray
        One figure per draw before and after the compensation [m].
    margin_m : float or ndarray
        The least fall that counts as an improvement, per draw (:func:`margin`) [m].
    """
    b, a = np.asarray(b, float), np.asarray(a, float)
    after = np.maximum(a, EQUAL_M)
    least = float(np.min(b / after))
    improves = bool(np.all(a < b - margin_m))
    # the machine is one more draw, its fall read from the draws' own scatter; what is
    # left after the correction carries the model's error on what it removed (the margin),
    # and no prediction meets the machine closer than the calibration's floor
    left = a + np.maximum(margin_m, CALIBRATION["floor_m"])
    bound = float(np.exp(next_draw(np.log(b / left))))
    cleared = improves and next_draw(np.log(np.maximum(b - margin_m, EQUAL_M) / after)) > 0
    return {"worst_before_um": float(b.max() * 1e6), "worst_after_um": float(a.max() * 1e6),
            "least_ratio": least, "improves_on_every_draw": improves,
            "ratio_bound": bound, "verdict": verdict(bound, cleared)}


def circle_rows(before: np.ndarray, after: np.ndarray, guard) -> dict:
    """The draws' verdict on the circle's largest spike and G, empty without a circle."""
    if guard is None:
        return {}
    return {name: over_draws(before[:, j], after[:, j], margin(before[:, j]))
            for name, j in (("spike", -2), ("circular_deviation", -1))}


def robust_factors(machine, comp, n_draws: int = DRAWS, seed: int = 0, radius_m=None,
                   centre_m=(0.0, 0.0), plane=("X", "Y")) -> None:
    """Scale the compensation back where draws of the model cannot guarantee an improvement;
    sets ``comp.factors``, ``comp.robustness`` and ``comp.trusted`` in place.

    Parameters
    ----------
    machine : Machine
        The identified model with its uncertainty (``axes[..].uncertainty``) [SI].
    comp : Compensation
        From :func:`.learning.compensate` [-].
    n_draws : int
        Machines drawn from the uncertainty; the model as identified is judged too [-].
    seed : int
        Seed of the draws [-].
    radius_m : float, optional
        Radius of the circle the command holds: no draw's largest reversal spike or G may
        get worse either [m].
    centre_m : tuple of float
        Centre of the circle [m].
    plane : tuple of str
        The circle's axes [-].
    """
    guard = None if radius_m is None else CircleGuard.of(comp, radius_m, centre_m, plane)
    machines = drawn_machines(machine, n_draws, seed)
    target, labels = comp.target, regions(comp.target)
    errs = axis_errors(machines, comp)
    per = per_combo(errs, lambda c: judged(errs, c, target, labels, guard))
    n_reg, before = labels.max() + 1, per[tuple([0] * errs.shape[1])]
    corners = CornerGuard.of(target, labels, errs[:, :, 0])
    shares, figs = choose_of(per, n_reg, corners_hold(corners, errs))
    extra = {"draws": n_draws, "seed": seed}
    by_region = regional_shares(machines, comp, per, before, labels, guard, figs,
                                corners=corners, chosen=shares)
    after = None
    if by_region is not None:
        (factors, figs, after), extra = by_region, {**extra, "by_region": True}
        shares = [factors[a] for a in comp.reference.axes]
    after = chosen(errs, shares, after)
    extra.update(held_entry(corners), **worst_entry(after, comp))
    record(comp, shares, region_rows(before, figs, target, labels),
           circle_rows(before, figs, guard), labels, extra, rises(errs, shares, target, after))


def chosen(errs: np.ndarray, shares: list, after=None) -> np.ndarray:
    """The TCP errors with the ``shares`` chosen per axis, read off those of each share
    (:func:`axis_errors`), shape (machines, axes, n); ``after`` where the shares are per
    sample (:func:`.regional.settle_regions` ran them on every draw) [m]."""
    if after is not None:
        return after
    return errs[:, np.arange(len(shares)), [LEVELS.index(s) for s in shares]]


def rises(errs: np.ndarray, shares: list, target, after=None, before=None) -> tuple:
    """:func:`.trust.local_rises` of the ``shares`` chosen per axis, from the TCP errors
    of each share (:func:`axis_errors`), where one share per axis is read off them; shares
    per sample give their errors ``after`` (:func:`.regional.settle_regions` ran them on
    every draw); against the errors ``before``, by default those of no share [-]."""
    after = chosen(errs, shares, after)
    before = errs[:, :, 0] if before is None else before
    return local_rises(np.array([contour(e, target) for e in before]),
                       np.array([contour(e, target) for e in after]), target, margin)


def corners_hold(corners, errs: np.ndarray):
    """``holds(combo)`` of :func:`choose_of`: no corner's overshoot rises on any machine
    with the shares ``combo`` of the TCP errors per share ``errs`` (:func:`axis_errors`)
    (:mod:`.cornerguard`) [-]."""
    return lambda c: corners.holds(errs[:, np.arange(errs.shape[1]), list(c)], EQUAL_M)


def regional_shares(machines, comp, per: dict, before: np.ndarray, labels: np.ndarray, guard,
                    one: np.ndarray, plants=None, progress=None, corners=None, chosen=None):
    """Shares chosen region by region (:mod:`.regional`), run on every draw: ``(factors,
    figures, TCP errors)`` where the draws vouch for them everywhere and, on the worst
    draw, no region, spike or G is above what one share per axis gives (its figures
    ``one``) by more than the margin and some region is below it by more; else ``None``:
    where they gain nothing, the simpler choice stays. ``per``: the figures of each
    combination of shares per axis (:func:`judged`), each axis run as ``plants`` says;
    ``progress`` called with no argument after each round of
    :func:`.regional.settle_regions`; the corners' overshoot held by ``corners``
    (:class:`.cornerguard.CornerGuard`) where given. Where every region picks the same
    shares, they are run only where they are not ``chosen``, the shares per axis
    :func:`choose_of` kept: held back by a figure of one region (a corner's overshoot),
    they may be kept in the others [-]."""
    n_reg = labels.max() + 1
    levels = np.array(LEVELS)[pick(per, before, n_reg, vouched, margin)]
    if np.all(levels == levels[0]) and (chosen is None or np.array_equal(levels[0], chosen)):
        return None  # one share per axis: the choice of :func:`choose_of`

    spikes = [] if guard is None else guard.spike_samples()

    def check(b, a, errors):
        bad = {r for r in range(n_reg) if not vouched(b[:, r], a[:, r])}
        for j, at in enumerate(spikes, start=n_reg):  # a spike worse: where it is crossed
            if not vouched(b[:, j], a[:, j]):
                bad.update(labels[at].tolist())
        if corners is not None and not bad:  # read only of a command that would be kept
            bad.update(corners.rising(errors, EQUAL_M))
        return sorted(bad), all(vouched(b[:, j], a[:, j]) for j in range(n_reg, b.shape[1]))

    got = settle_regions(machines, comp, levels, labels, before, check,
                         lambda e: figures(e, comp.target, labels, guard, True), LEVELS,
                         plants, progress)
    if got is None:
        return None
    worst, worst_one = got[1].max(axis=0), one.max(axis=0)
    if np.any(worst > worst_one + margin(worst_one)) or not np.any(
            worst[:n_reg] < worst_one[:n_reg] - margin(worst_one[:n_reg])):
        return None
    return got
