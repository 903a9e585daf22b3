"""A delay held in a fit (none, or a value given) checked against the data.

The standard deviations of :mod:`~tcpmm.ident.lti.tfsd` are linearised at the fit with its
delay held: they say how far the noise moves the parameters *given that delay*. Where the
response holds a delay the fit was told is absent (or another one), the poles and zeros
absorb it, real poles and right-half-plane zeros near the top of the band lagging as a
delay does, and the fit can still reach the noise: two modes over an antiresonance with a
real pole at 900 Hz and a 0.3 ms delay (400 bins 10 Hz-2 kHz, 1 % noise) fitted at 6
poles with no delay left a chi2 ratio of 0.92 and a real pole at 1010 +- 14 Hz, 7.8 of its
sd from the truth, beside a second real pole and a zero pair the response does not have,
each printed with a ``±``.

:func:`check_held_delay` fits the same bins with the same weights and order with the
delay free (a fresh fit, and the held fit refined with the delay freed, each with its
pairs damped at least as the held fit's; the one of less cost kept) and compares:

* **the delay**: the free one differs from the one held by more than a delay whose phase
  at the top bin is the bins' median noise (no bin tells two such delays apart), and it
  lowers the weighted cost by more than one parameter more lowers it by chance: the
  ratio ``F = (cost_held - cost_free) / (cost_free / (2 N - p))`` exceeds :data:`CHANCE`.
  The free fit's own residual sets the scale, so a noise level misjudged in the bins
  does not move it;
* **the values**: each mode's frequency and damping, real pole, zero and the static gain
  that the held fit says determined, against the nearest of its kind in the free fit:
  more than :data:`SHIFT` of its own sd apart.

Either gives an :class:`~tcpmm.errors.InputWarning` naming the delay the data suggest,
and the values more than :data:`SHIFT` sd from the free fit's, or with no counterpart in
it, are undetermined with the reason: their ``±`` holds only for the delay given, which
the data do not bear out. Where the delay held is right nothing changes: 140 draws of the
response above (without a delay fitted with none at 5 poles and at the order the data
chose, with and without the real pole, and with the delay fitted with 0.3 ms given)
gave no warning, and 40 with the delay fitted with none each gave one.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ...errors import InputError, InputWarning
from ._needles import floor_damping
from ._tfcore import refine_vp
from .tffit import fit_tf
from .tfresult import tf_result
from .tfsd import TFDeviations, tf_deviations

__all__ = ["CHANCE", "SHIFT", "check_held_delay"]

#: ``F`` ratio of the cost a free delay saves above which the saving is not chance: five
#: standard errors of one parameter more (chi-square of one degree of freedom exceeds it
#: with a chance of 6e-7). Where the held fit misses the data by more than the noise, its
#: residual is no longer random and one parameter more saves more than chance: a fit of
#: no delay to a response without one, at a chi2 ratio of 12, saved an ``F`` of 14 [-].
CHANCE = 25.0
#: Difference from the free fit's value, in the held fit's sds, beyond which a value's sd
#: does not hold: the values one delay more moves, where the delay held is right, moved
#: by less on every one of the 140 draws of the module [-].
SHIFT = 3.0
#: Largest number of residual evaluations of the free fit's refinements [-].
FREE_NFEV = 100


def free_delay_fit(fit, sigma: np.ndarray, floor: float, grid: np.ndarray):
    """``fit`` fitted again with the delay free, at its order, bins and weights, its pairs
    damped at least as the held fit's were (:func:`~tcpmm.ident.lti._needles.floor_damping`):
    the better of a fresh fit and of ``fit`` refined with its delay freed; None where the
    bins cannot determine one parameter more.

    Parameters
    ----------
    fit : TFFit
        The fit with the delay held [-].
    sigma : ndarray
        Noise of each bin fitted [-].
    floor : float
        Least damping ratio of a pole pair [-].
    grid : ndarray
        Frequencies of the measurement, whose spacing floors the damping too [Hz].

    Returns
    -------
    TFFit or None
        The fit with the delay free [-].
    """
    f, H, w, k = fit.freq_hz, fit.H, fit.weight, fit.n_integrators
    try:
        fresh = fit_tf((f, H, w), fit.n_num, fit.n_den, k, delay_s="fit", max_nfev=FREE_NFEV)
    except InputError:
        return None
    # from the held solution the refinement finds the free fit next to it, the fresh fit
    # one the held delay kept out of reach; the one of less cost is the free fit
    bn, pn, tau, cost = refine_vp(f, H, w, fit.omega0, k, fit.n_num, True, True, fit.bn,
                                  fit.pn, fit.delay_s, fit.cost, FREE_NFEV)
    near = tf_result(f, H, w, bn, pn, fit.omega0, k, tau, fit.n_num, fit.n_den,
                     fit.n_params + 1, cost)
    # a needle the held fit was not let keep would save cost no delay explains; the pairs
    # the data do not support stay, as removing them would change the order compared
    floored = [floor_damping(t, sigma, floor, grid)[0] for t in (fresh, near)]
    return min(floored, key=lambda t: t.cost)


def _nearest(value: float, others: list, key):
    """The one of ``others`` whose ``key`` is nearest ``value`` in ratio; None if none [-]."""
    return min(others, key=lambda o: abs(math.log(max(key(o), 1e-300) / max(value, 1e-300))),
               default=None)


def _apart(e, other) -> float:
    """How many of its sds a determined estimate ``e`` lies from ``other`` (inf where there
    is no counterpart); 0 for a value not determined, which no ``±`` is printed for [-]."""
    if not e.determined:
        return 0.0
    if other is None or not e.sd > 0:
        return math.inf
    return abs(e.value - other.value) / e.sd


def _offsets(held: TFDeviations, free: TFDeviations) -> dict:
    """Each held value's distance from its counterpart in the free fit, in held sds, keyed
    ``("mode", i, 0 or 1)``, ``("real", i)``, ``("zero", i, 0 or 1)`` and ``("gain",)``
    [-]."""
    off = {}
    for i, (fe, ze) in enumerate(held.modes):
        c = _nearest(fe.value, free.modes, lambda m: m[0].value)
        off["mode", i, 0] = _apart(fe, c and c[0])
        off["mode", i, 1] = _apart(ze, c and c[1])
    for i, r in enumerate(held.real_poles):
        off["real", i] = _apart(r, _nearest(r.value, free.real_poles, lambda o: o.value))
    for i, z in enumerate(held.zeros):
        # a real zero is matched in its own half-plane: across it, the phase it gives turns
        alike = [o for o in free.zeros if o.kind == z.kind
                 and (z.kind == "pair" or np.sign(o.root.real) == np.sign(z.root.real))]
        c = _nearest(z.freq.value, alike, lambda o: o.freq.value)
        off["zero", i, 0] = _apart(z.freq, c and c.freq)
        if z.damping is not None:
            off["zero", i, 1] = _apart(z.damping, c and c.damping)
    if held.gain is not None:
        off["gain",] = _apart(held.gain, free.gain)
    return off


def _opened(held: TFDeviations, off: dict, why: str) -> TFDeviations:
    """``held`` with each value more than :data:`SHIFT` sds from the free fit's (or with no
    counterpart) undetermined for the reason ``why``, which joins its notes [-]."""
    def op(e, key):
        return e.opened(why) if off.get(key, 0.0) > SHIFT else e

    modes = [(op(fe, ("mode", i, 0)), op(ze, ("mode", i, 1)))
             for i, (fe, ze) in enumerate(held.modes)]
    reals = [op(r, ("real", i)) for i, r in enumerate(held.real_poles)]
    zeros = [z.opened(why) if max(off.get(("zero", i, 0), 0.0),
                                  off.get(("zero", i, 1), 0.0)) > SHIFT else z
             for i, z in enumerate(held.zeros)]
    gain = None if held.gain is None else op(held.gain, ("gain",))
    notes = [*held.notes, why] if why not in held.notes else list(held.notes)
    return TFDeviations(modes, reals, held.delay, gain, notes, held.describes_data, zeros)


def _given(tau) -> str:
    """The delay held, in words [-]."""
    return "no delay" if tau is None else f"a delay of {tau * 1e3:.4g} ms"


def check_held_delay(fit, devs: TFDeviations, held, sigma: np.ndarray, floor: float,
                     grid: np.ndarray, name: str = ""):
    """The deviations of a fit with its delay held, checked against a fit with the delay
    free (see the module).

    Parameters
    ----------
    fit : TFFit
        The fit with the delay held [-].
    devs : TFDeviations
        Its standard deviations (:func:`~tcpmm.ident.lti.tfsd.tf_deviations`) [-].
    held : None or float
        The delay held: None for none, else its value [s].
    sigma : ndarray
        Noise of each bin fitted, of the real and of the imaginary part of ``dH / H`` [-].
    floor : float
        Least damping ratio of a pole pair the fit was held to [-].
    grid : ndarray
        Frequencies of the measurement, whose spacing floors the damping too [Hz].
    name : str, optional
        The response's name, for the warning [-].

    Returns
    -------
    tuple
        ``(devs, note)``: the deviations, values the delay held leaves unbounded opened,
        and a note for the fit where the data suggest another delay but no value moves,
        else None [-].
    """
    free = free_delay_fit(fit, sigma, floor, grid)
    if free is None:
        return devs, None
    m = 2 * fit.freq_hz.size
    ratio = (fit.cost - free.cost) / max(free.cost / max(m - free.n_params, 1), 1e-300)
    margin = float(np.median(sigma)) / (2 * np.pi * fit.freq_hz[-1])
    other = abs(free.delay_s - fit.delay_s) > margin and ratio > CHANCE
    off = _offsets(devs, tf_deviations(free, True))
    moved = sum(SHIFT < v < math.inf for v in off.values())
    if not (other or moved):
        return devs, None
    suggested = f"{free.delay_s * 1e3:.3g} ms"
    why = (f"a value that moves by more than {SHIFT:g} of its sd, or has no counterpart, "
           f"in the fit with the delay left free ({suggested}): its sd assumes "
           f"{_given(held)}, which the data do not bear out")
    n_open = sum(v > SHIFT for v in off.values())
    opened = _opened(devs, off, why) if n_open else devs
    evidence = ([f"left free at the same order the delay lowers the weighted residual by "
                 f"{100 * (1 - free.cost / fit.cost):.3g} %, an F ratio of {ratio:.3g} "
                 f"where chance gives at most {CHANCE:g}"] if other else [])
    evidence += [f"{moved} value{'s move' if moved != 1 else ' moves'} by more than "
                 f"{SHIFT:g} sd with it"] if moved else []
    opened_text = (f", and {n_open} value{'s' if n_open != 1 else ''} beyond them "
                   f"{'are' if n_open != 1 else 'is'} undetermined" if n_open else "")
    text = (f"{name or 'the response'}: the data suggest a delay of {suggested} where "
            f"{_given(held)} was given ({'; '.join(evidence)}); the standard deviations "
            f"assume the delay given{opened_text}; leave the delay free (--delay fit) or "
            "check the one given")
    warnings.warn(InputWarning(text), stacklevel=3)
    return opened, (None if n_open else text)
