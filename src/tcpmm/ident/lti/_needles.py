"""Needles out of a fitted transfer function: damping raised to a floor, and pole-zero pairs
the measured bins do not support removed (see :mod:`~tcpmm.ident.lti.frffit`)."""

from __future__ import annotations

from itertools import combinations

import numpy as np

from ._tfcore import fit_numerator, relative_cost
from .frfnoise import running_level
from .tfresult import TFFit, tf_result

#: A pole-zero pair changing the response by less than this many sigma is removed [-].
CANCEL_SIGMA = 2.0
#: Bins a pole-zero pair must change beyond CANCEL_SIGMA to be kept [-].
SUPPORT_BINS = 3


def _units(r: np.ndarray) -> list[np.ndarray]:
    """Roots grouped as conjugate pairs (upper first) and single real roots."""
    r = np.asarray(r, dtype=complex)
    real = np.abs(r.imag) <= 1e-9 * np.maximum(np.abs(r), 1e-300)
    units = [np.array([p]) for p in r[real]]
    units += [np.array([p, np.conj(p)]) for p in r[~real] if p.imag > 0]
    return units


def _factor_deviation(x, p, z, sigma):
    """The change, in sigma, that the factor prod(x - z) / prod(x - p) makes to the
    response beyond the best constant gain, at the SUPPORT_BINS-th most changed bin."""
    F = np.prod([x - zz for zz in z], axis=0) / np.prod([x - pp for pp in p], axis=0)
    g = np.sum(F / sigma**2) / np.sum(1 / sigma**2)
    if g == 0 or not np.isfinite(g):
        return np.inf
    dev = np.sort(np.abs(F / g - 1) / sigma)[::-1]
    return float(dev[min(SUPPORT_BINS, dev.size) - 1])


def clean_fit(fit: TFFit, sigma, floor, grid):
    """Raise damping to the floor (``floor`` [-], or the spacing of the measurement's
    frequency grid ``grid`` [Hz]), then remove the pole-zero pairs the data do not support;
    the numerator is fitted again after each change."""
    sigma = support_noise(fit, sigma)
    fit, notes = floor_damping(fit, sigma, floor, grid)
    fit, notes = without_far_poles(fit, sigma, notes)
    while (step := without_unsupported(fit, sigma)) is not None:
        fit, what, dev = step
        notes.append(removal_note(what, dev))
    return fit, notes


def without_unsupported(fit: TFFit, sigma):
    """The fit without the pole-zero pairs the data support least, with what they are in
    words and the change they make in noise levels, ``(fit, what, deviation)``; None if
    the data support every pair (``sigma``, the bins' noise [-])."""
    if fit.n_num == 0 or fit.pn.size == 0:
        return None
    found = _unsupported(2j * np.pi * fit.freq_hz / fit.omega0, fit.pn,
                         fit.zeros / fit.omega0, sigma)
    if found is None:
        return None
    dev, p, z = found
    at = place(abs(p[0]) * fit.omega0 / 2 / np.pi, fit.freq_hz)
    n = len(_units(p))
    what = f"a pole-zero pair at {at}" if n == 1 else f"{n} pole-zero pairs near {at}"
    return _refit_numerator(fit, _without(fit.pn, p), fit.n_num - z.size), what, dev


def without_far_poles(fit: TFFit, sigma, notes: list):
    """The fit with each pole above the band that changes the response by less than
    CANCEL_SIGMA noise levels beyond a constant gain (``sigma``, the bins' noise [-])
    folded into the gain, where it carries zeros: kept, it lets the numerator hold more
    zeros than the poles the bins see, and the response grows between the band and it (a
    real pole at 5600 times the top of a narrow band, 1.8e-4 of the response there, let
    a fit of 3 poles have 4 zeros and grow 17-fold two decades above). The numerator is
    fitted again with at most as many zeros as poles are left; ``notes`` gains one a
    pole folded [-]."""
    x = 2j * np.pi * fit.freq_hz / fit.omega0
    for unit in sorted(_units(fit.pn), key=lambda u: -abs(u[0])):
        left = fit.pn.size - unit.size + fit.n_integrators
        if abs(unit[0]) <= abs(x[-1]) or fit.n_num <= left:
            break
        dev = _factor_deviation(x, unit, np.empty(0), sigma)
        if not dev < CANCEL_SIGMA:
            break
        fn = abs(unit[0]) * fit.omega0 / (2 * np.pi)
        fit = _refit_numerator(fit, _without(fit.pn, unit), left)
        notes = [*notes, f"folded the {'pair' if unit.size == 2 else 'real pole'} at "
                 f"{fn:.4g} Hz into the gain (it changes the response by {dev:.2g} noise "
                 "levels at most) and fitted the numerator again with no more zeros than "
                 "poles"]
    return fit, notes


def removal_note(what: str, dev: float) -> str:
    """The note of pole-zero pairs removed (``what``, words), which change the response by
    ``dev`` noise levels at most [-]."""
    one = what.startswith("a ")
    return (f"removed {what} ({'it changes' if one else 'together they change'} "
            f"the response by {dev:.2g} noise levels at most)")


def floor_damping(fit: TFFit, sigma, floor, grid):
    """Raise each pair's damping to the floor (``floor`` [-], or the spacing of the
    measurement's frequency grid ``grid`` [Hz]) and fit the numerator again where one was
    raised; returns the fit and the notes saying which [-]."""
    x = 2j * np.pi * fit.freq_hz / fit.omega0
    notes = []
    pn = _floor(fit.pn, grid, fit.omega0, floor, notes, (x, support_noise(fit, sigma)))
    return (_refit_numerator(fit, pn, fit.n_num) if notes else fit), notes


def support_noise(fit: TFFit, sigma) -> np.ndarray:
    """The noise ``sigma`` [-] of the bins, or where less the running level of the fit's
    own residual: the roughness of a response takes the curvature of a lightly damped
    peak for noise over many bins, and a pair judged against that would be raised or
    removed although the bins show it; the residual of a fit that follows the peak does
    not (a needle holds one bin of the running median) [-]."""
    with np.errstate(all="ignore"):
        e2 = np.abs(fit.freqresp(fit.freq_hz) / fit.H - 1) ** 2
    level = running_level(np.where(np.isfinite(e2), e2, np.inf))
    return np.minimum(sigma, np.maximum(level, 1e-12))


def _unsupported(x, pn, zn, sigma):
    """The poles and zeros the data support least, ``(deviation, poles, zeros)``, if their
    joint factor changes the response by less than CANCEL_SIGMA; else ``None``. One pole
    with one zero (pairs or real) first; then two with two, which cancel only together (a
    double pair between two zeros: either zero alone leaves a peak or a dip) [-]."""
    pu, zu = _units(pn), _units(zn)
    for k in (1, 2):
        found = [(_factor_deviation(x, np.concatenate(p), np.concatenate(z), sigma),
                  np.concatenate(p), np.concatenate(z))
                 for p in combinations(pu, k) for z in combinations(zu, k)
                 if sum(u.size for u in p) == sum(u.size for u in z)]
        if found:
            best = min(found, key=lambda c: c[0])
            if best[0] < CANCEL_SIGMA:
                return best
    return None


def place(f_hz: float, band_hz) -> str:
    """Where a pole or zero of frequency ``f_hz`` [Hz] lies, in words: a millionth of the
    band's lowest frequency [Hz] or less is the origin, whatever its rounding."""
    return "the origin (0 Hz)" if f_hz <= 1e-6 * np.min(band_hz) else f"{f_hz:.4g} Hz"


def _floor(pn, f, omega0, floor, notes, bins):
    """Poles with every pair damped at least by the floor, and by the bin spacing of the
    frequency grid ``f`` [Hz] (a half-power bandwidth below one bin is not measured)
    unless the bins fitted, ``bins = (x, sigma)``, show the lower damping: raised to the
    spacing's, the pair would change at least SUPPORT_BINS of them by CANCEL_SIGMA noise
    levels or more, as a mode does between coarse bins (the bins beside its peak and its
    phase), and no needle on the noise of one bin can."""
    pn = pn.copy()
    df = np.gradient(f) if f.size > 1 else np.zeros(1)
    for i, p in enumerate(pn):
        if abs(p.imag) <= 1e-9 * abs(p):
            continue
        fn = abs(p) * omega0 / (2 * np.pi)
        # at most critical damping: a pair below the first bins would take a half-power
        # bandwidth wider than itself, and a damping above 1 has no pair (its root NaN)
        least = min(max(floor, float(np.interp(fn, f, df)) / (2 * fn)), 1.0)
        zeta = -p.real / abs(p)
        upper = p if p.imag > 0 else np.conj(p)  # one decision for both poles of a pair
        if zeta < least and _shown(upper, _damped(upper, least), *bins):
            least = floor
        if zeta < least:
            pn[i] = _damped(p, least)
            if p.imag > 0:
                notes.append(f"raised the damping of the pair at {fn:.4g} Hz from "
                             f"{zeta:.2g} to {least:.2g}")
    return pn


def _damped(p, zeta):
    """The pole ``p`` at its natural frequency with the damping ``zeta`` [-]."""
    return abs(p) * (-zeta + 1j * np.sign(p.imag) * np.sqrt(1 - zeta**2))


def _shown(p, raised, x, sigma) -> bool:
    """Whether the bins ``x`` show the pair ``p`` as less damped than ``raised``: moving it
    there changes SUPPORT_BINS of them by CANCEL_SIGMA noise levels or more [-]."""
    with np.errstate(all="ignore"):
        dev = _factor_deviation(x, np.array([raised, np.conj(raised)]),
                                np.array([p, np.conj(p)]), sigma)
    return bool(np.isfinite(dev) and dev >= CANCEL_SIGMA)


def _without(roots, unit):
    out = list(roots)
    for r in unit:
        out.pop(int(np.argmin(np.abs(np.asarray(out) - r))))
    return np.asarray(out, dtype=complex)


def _refit_numerator(fit: TFFit, pn, n_num):
    f, H, w, omega0, k, tau = fit.freq_hz, fit.H, fit.weight, fit.omega0, fit.n_integrators, \
        fit.delay_s
    s = 2j * np.pi * f
    x = s / omega0
    bn = fit_numerator(x, H * x**k * np.exp(s * tau), w, pn, n_num)
    n_params = n_num + 1 + pn.size + (fit.n_params - fit.n_num - 1 - fit.n_den)
    cost = relative_cost(f, H, w, bn, pn, omega0, k, tau)
    return tf_result(f, H, w, bn, pn, omega0, k, tau, n_num, pn.size, n_params, cost)

