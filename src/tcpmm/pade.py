"""The pure delay of a fitted transfer function as a rational factor for python-control,
for the fits of :mod:`tcpmm.ident.lti` and the transfer functions read by
:mod:`tcpmm.io.tffragment`.

A state-space model cannot hold ``exp(-s tau)``; the Pade approximant of order ``n`` is
an all-pass of ``n`` poles and zeros whose phase matches the delay's at low frequency
and falls behind it above ``omega tau ~ n``. The default order is the smallest one that
keeps the complex relative error ``|P(j omega) exp(j omega tau) - 1|`` below
:data:`PADE_TOLERANCE` up to the top of the band the fit holds for (at most
:data:`MAX_PADE_ORDER`): 8 for the 0.33 ms delay of the Sinumerik trace fitted to 4 kHz.
"""

from __future__ import annotations

import warnings

import numpy as np

from .errors import InputError, InputWarning

__all__ = ["MAX_PADE_ORDER", "PADE_TOLERANCE", "pade_error", "pade_order", "with_delay"]

#: Largest relative error of the default Pade approximant over the band [-].
PADE_TOLERANCE = 1e-3
#: Highest default Pade order (beyond, its coefficients span more than doubles resolve) [-].
MAX_PADE_ORDER = 12


def pade_error(delay_s: float, order: int, f_hz) -> np.ndarray:
    """Relative error of the Pade approximant of a delay.

    Parameters
    ----------
    delay_s : float
        Delay [s].
    order : int
        Order of the approximant [-].
    f_hz : array_like
        Frequencies [Hz].

    Returns
    -------
    ndarray
        ``|P(j omega) exp(j omega tau) - 1|`` [-].
    """
    import control

    s = 2j * np.pi * np.asarray(f_hz, dtype=float)
    num, den = control.pade(float(delay_s), int(order))
    return np.abs(np.polyval(num, s) / np.polyval(den, s) * np.exp(s * delay_s) - 1.0)


def pade_order(delay_s: float, f_max_hz: float, tolerance: float = PADE_TOLERANCE) -> int:
    """Smallest Pade order that approximates a delay to ``tolerance`` up to ``f_max_hz``.

    Parameters
    ----------
    delay_s : float
        Delay [s]; 0 needs no approximant [s].
    f_max_hz : float
        Top of the band the model is used in [Hz].
    tolerance : float
        Largest relative error allowed [-].

    Returns
    -------
    int
        Order, at most :data:`MAX_PADE_ORDER`; 0 for no delay [-].
    """
    if delay_s <= 0:
        return 0
    for n in range(1, MAX_PADE_ORDER + 1):
        if pade_error(delay_s, n, [f_max_hz])[0] <= tolerance:
            return n
    return MAX_PADE_ORDER


def with_delay(tf, delay_s: float, f_max_hz: float, order="auto"):
    """A python-control transfer function times the Pade approximant of a delay.

    Parameters
    ----------
    tf : control.TransferFunction
        Rational part [SI].
    delay_s : float
        Delay [s].
    f_max_hz : float
        Top of the band the model holds for; sets the ``"auto"`` order [Hz].
    order : int or "auto"
        Pade order; 0 leaves the delay out; ``"auto"``: :func:`pade_order` [-].

    Returns
    -------
    control.TransferFunction
        The rational part with the delay's approximant [SI].
    """
    import control

    if order == "auto":
        order = pade_order(delay_s, f_max_hz)
        if delay_s > 0:
            _warn_short(delay_s, order, f_max_hz)
    if isinstance(order, bool) or not isinstance(order, int | np.integer) or order < 0:
        raise InputError(f"pade_order must be 'auto' or an integer >= 0, got {order!r}")
    if order == 0 or delay_s <= 0:
        return tf
    num, den = control.pade(float(delay_s), int(order))
    return tf * control.TransferFunction(num, den)


def held_up_to(delay_s: float, order: int, f_max_hz: float,
               tolerance: float = PADE_TOLERANCE) -> float:
    """The highest frequency up to which the Pade approximant of ``order`` keeps the
    delay's relative error within ``tolerance``, no higher than ``f_max_hz`` [Hz].

    Parameters
    ----------
    delay_s : float
        Delay [s].
    order : int
        Order of the approximant [-].
    f_max_hz : float
        Top of the band [Hz].
    tolerance : float
        Largest relative error allowed [-].
    """
    f = np.geomspace(f_max_hz * 1e-3, f_max_hz, 2001)
    bad = np.flatnonzero(pade_error(delay_s, order, f) > tolerance)
    if not bad.size:
        return float(f_max_hz)
    return float(f[bad[0] - 1]) if bad[0] > 0 else 0.0


def _warn_short(delay_s: float, order: int, f_max_hz: float) -> None:
    """Warn where even the highest order leaves the delay's approximant off by more than
    :data:`PADE_TOLERANCE` at the top of the band: up to where it holds, and how far
    off it is at the top [-]."""
    top = float(pade_error(delay_s, order, [f_max_hz])[0])
    if top <= PADE_TOLERANCE:
        return
    warnings.warn(InputWarning(
        f"the delay of {delay_s * 1e3:.3g} ms is exported as a Pade approximant of order "
        f"{order}, the highest, which holds it within {PADE_TOLERANCE:.1%} only up to "
        f"{held_up_to(delay_s, order, f_max_hz):.4g} Hz; at the band's top, "
        f"{f_max_hz:.4g} Hz, it is {top:.0%} off: use the model below that frequency, or "
        "keep the delay apart (freqresp holds it exactly)"), stacklevel=3)
