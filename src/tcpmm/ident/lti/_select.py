"""The choice between fits of one pole count that respects both error measures of
:mod:`~tcpmm.ident.lti.frffit`.

The fit minimises the relative error of each bin weighted by its noise; with fewer poles
than the response needs, that can spend them on the band's small top, leaving a total
error ``sum |H - H_model|^2 / sum |H|^2`` (the large part of the response) many times what
vector fitting's absolute fit leaves. The total error of vector fitting's poles
(:mod:`~tcpmm.ident.lti._relocate`) with their best partial fractions is therefore the
reference. If the fits of the pole count miss it, the weights are mixed with the
magnitude of the response,

    ``w_mix^2 = w^2 + mu mean(w^2) |H|^2 / mean(|H|^2)``,

for ``mu`` rising by decades (:data:`MIXES`), each fit refined from the relocated poles,
from the relative fit's and from the previous ``mu``'s, until one reaches the reference.
Of the fits that do, the lowest information criterion wins, so the relative error is
given up no further than the total error needs; if none does, the lowest total error
wins (the candidate is marked ``short``).

A fit at the noise in both measures is kept where reaching the reference takes the fit
away from the noise: its chi2 ratio at most :data:`AT_NOISE_CHI2` and its total error
within what the noise of the bins leaves by itself (:func:`noise_total`), where the fits
that reach the reference exceed that chi2 ratio. Below the noise's total error an
absolute fit follows the noise of the few bins that carry most of ``sum |H|^2`` (a
resonance's peak); held to it, a fit gives up the small part of the response, an
antiresonance, for that noise (three modes with 1 % noise: vector fitting's 3.9e-5 under
the true response's own 6.7e-5, and the fit that reached it off by 4.9 dB at the
antiresonance, at a chi2 ratio of 14). Every fit keeps the stable sections, the fitted
delay and the needle removal.
"""

from __future__ import annotations

import math

import numpy as np

from ._needles import clean_fit
from ._relocate import partial_fraction_response, relocated_poles, start_poles
from ._tfcore import fit_numerator, refine_vp, relative_cost
from .tfresult import tf_result

#: Weights of the magnitude in the mixed weights, rising by decades [-].
MIXES = (0.0, 1e-2, 1e-1, 1.0, 10.0, 1e2, 1e3, 1e4)
#: Residual evaluations of each refinement [-].
MIX_NFEV = 100
#: Relative rounding within which vector fitting's own fit counts as reaching its total
#: error (the same function, built as a quotient of polynomials) [-].
REACH = 1e-9
#: Standard deviations of its spread above its mean within which a total error is the
#: noise's own (:func:`noise_total`) [-].
NOISE_SDS = 2.0
#: chi2 ratio at most which a fit is at the noise in the relative measure: a residual
#: within 1.4 times the noise the bins are said to carry [-].
AT_NOISE_CHI2 = 2.0


def by_criterion(cand: dict) -> tuple:
    """Order of candidates by the information criterion, a pair outside the band last [-]."""
    return cand["unsupported"], cand["bic"]


def by_total(cand: dict) -> tuple:
    """Order of candidates by the total error, a pair outside the band last [-]."""
    return cand["unsupported"], cand["total"]


def total_error(H, h) -> float:
    """Total relative error ``sum |H - h|^2 / sum |H|^2`` [-]."""
    return float(np.sum(np.abs(H - h) ** 2) / np.sum(np.abs(H) ** 2))


def noise_total(ctx) -> float:
    """The total error the noise of the bins leaves by itself, its mean and
    :data:`NOISE_SDS` of its spread: a bin's ``|H - H_true|^2`` is exponential with mean
    ``2 sigma^2 |H|^2`` (``sigma`` the relative noise of each part, as the chi2 ratio
    takes it), so the sum's variance is the sum of those means squared [-]."""
    a = 2.0 * (ctx["sigma"] * np.abs(ctx["H"])) ** 2
    return float((np.sum(a) + NOISE_SDS * np.sqrt(np.sum(a**2)))
                 / np.sum(np.abs(ctx["H"]) ** 2))


def score(ctx, fit, notes, tried) -> dict:
    """A fit with its criterion: ``chi2 + p ln(2 N)`` of the noise-weighted relative
    error, its total error, and whether it puts a lightly damped pair outside the band."""
    f, H, sigma = ctx["f"], ctx["H"], ctx["sigma"]
    h = fit.freqresp(f)
    chi2 = float(np.sum(np.abs(h / H - 1) ** 2 / sigma**2))
    m = 2 * f.size
    fn, zeta, grid = fit.natural_freq_hz, fit.damping, ctx["grid"]
    # a pair outside the band is unsupported where it is a needle: lightly damped and no
    # wider than a bin of the grid there, so no bin shows its damping (a mode just
    # beyond the band whose tail the bins follow is supported); a pair the floor raised
    # to the spacing has a width of one bin up to rounding, a damping no bin gave it
    spacing = np.interp(fn, grid, np.gradient(grid)) if grid.size > 1 else np.inf
    unsupported = bool(np.any((zeta < 0.2) & (2 * zeta * fn <= spacing * (1 + 1e-9))
                              & ((fn < f[0]) | (fn > f[-1]))))
    return {"fit": fit, "notes": notes, "tried": list(tried),
            "n_poles": int(fit.n_den), "n_zeros": int(fit.n_num),
            "chi2_ratio": chi2 / m, "bic": chi2 + fit.n_params * np.log(m),
            "unsupported": unsupported, "total": total_error(H, h)}


def _references(ctx, n_poles, taus):
    """Vector fitting's poles for each delay tried and each start, the best first, with
    the total error of the best [-]."""
    f, H, omega0 = ctx["f"], ctx["H"], ctx["omega0"]
    x = 2j * np.pi * f / omega0
    found = []
    for tau in taus:
        lag = np.exp(-2 * np.pi * 1j * f * tau)
        for start in start_poles(n_poles, x[0].imag, x[-1].imag):
            pn = relocated_poles(x, H / lag, n_poles, start)
            if pn is not None:
                h = partial_fraction_response(x, H / lag, pn) * lag
                found.append((total_error(H, h), pn, tau))
    found.sort(key=lambda c: c[0])
    return (found[0][0], [(pn, tau) for _, pn, tau in found]) if found else (None, [])


def _refit(ctx, w, n_num, starts, refine: bool = True):
    """The least weighted cost over refinements from ``starts`` (poles in ``x`` and delay
    [s]), as ``(bn, pn, tau, cost)``; None if no start can carry ``n_num`` zeros. With
    ``refine`` false, the starts' poles and delay with their best numerator."""
    f, H, omega0 = ctx["f"], ctx["H"], ctx["omega0"]
    x = 2j * np.pi * f / omega0
    best = None
    for pn, tau in starts:
        if n_num > pn.size:
            continue
        with np.errstate(all="ignore"):
            try:
                bn = fit_numerator(x, H * np.exp(x * omega0 * tau), w, pn, n_num)
                cost = relative_cost(f, H, w, bn, pn, omega0, 0, tau)
                cand = (refine_vp(f, H, w, omega0, 0, n_num, True, ctx["delay"] == "fit",
                                  bn, pn, tau, cost, MIX_NFEV) if refine
                        else (bn, pn, tau, cost))
            except (np.linalg.LinAlgError, ValueError):
                continue
        if np.isfinite(cand[3]) and (best is None or cand[3] < best[3]):
            best = cand
    return best


def _mixed(ctx, w, n_num, starts, mu, refine: bool = True):
    """The mixed-weight fit of ``n_num`` zeros, cleaned and scored, and its poles and delay
    before cleaning (the next start); None if no start gives a finite fit."""
    got = _refit(ctx, w, n_num, starts, refine)
    if got is None:
        return None
    bn, pn, tau, cost = got
    f, H, omega0 = ctx["f"], ctx["H"], ctx["omega0"]
    n_params = n_num + 1 + pn.size + int(ctx["delay"] == "fit")
    try:
        with np.errstate(all="ignore"):
            fit = tf_result(f, H, w, bn, pn, omega0, 0, tau, n_num, pn.size, n_params, cost)
            fit, notes = clean_fit(fit, ctx["sigma"], ctx["floor"], ctx["grid"])
    except (np.linalg.LinAlgError, ValueError):
        return None
    return {**score(ctx, fit, notes, (pn.size, n_num)), "mix": mu}, (pn, tau)


def choose(ctx, tries, n_poles: int) -> dict:
    """The fit of ``n_poles`` poles chosen from the relative fits ``tries`` (scored) and
    the mixed-weight fits, as the module says [-]."""
    first = min(tries, key=by_criterion)
    taus = [0.0]
    if ctx["delay"] == "fit":
        taus.append(first["fit"].delay_s)
    elif ctx["delay"] is not None:
        taus = [float(ctx["delay"])]
    ref, vf_starts = _references(ctx, n_poles, dict.fromkeys(taus))
    if ref is None:
        return first
    if reach := _reaching(tries, ref):
        return min(reach, key=by_criterion)
    n_nums = sorted({max(n_poles - 1, 0), n_poles})
    base = [(first["fit"].pn, first["fit"].delay_s), *vf_starts[:1]]
    pool, prev, noise = list(tries), {}, noise_total(ctx)
    for mu in MIXES:
        pool += _at_mix(ctx, mu, n_nums, base, prev)
        if reach := _reaching(pool, ref):
            return _quiet_or(min(reach, key=by_criterion), pool, ref, noise)
    pool += _relocated_fits(ctx, n_nums, vf_starts[:1])
    if reach := _reaching(pool, ref * (1 + REACH)):
        return _quiet_or(min(reach, key=by_criterion), pool, ref, noise)
    return _quiet_or(min(pool, key=by_total), pool, ref, noise)


def _quiet_or(cand, pool, ref, noise) -> dict:
    """``cand`` noted, or where its chi2 ratio leaves the noise the fit of ``pool`` at the
    noise in both measures (module docstring) of the least criterion, noted so [-]."""
    quiet = [c for c in pool if c["total"] <= noise and c["chi2_ratio"] <= AT_NOISE_CHI2
             and not c["unsupported"]]
    if cand["chi2_ratio"] <= AT_NOISE_CHI2 or not quiet:
        return _noted(cand, ref)
    best = _noted(min(quiet, key=by_criterion), ref)
    if best["total"] <= ref * (1 + REACH):  # it reaches it too, at a larger criterion
        where, others = f"within the {ref:.3g} of", "the fits of a lower criterion"
    else:
        where, others = f"above the {ref:.3g} of", "the fits that reach vector fitting's"
    note = (f"total error {best['total']:.3g}, {where} vector fitting's poles and within "
            f"the {noise:.3g} the noise leaves by itself, at a chi2 ratio of "
            f"{best['chi2_ratio']:.3g}: {others} follow the noise of the largest bins "
            f"(chi2 ratio {cand['chi2_ratio']:.3g} and up)")
    return {**best, "notes": [*best["notes"], note], "short": False, "quiet": True}


def _reaching(fits, bound: float) -> list:
    """The scored ``fits`` whose total error is within ``bound``: those holding a needle
    outside the band (``unsupported``) never are, whatever their error, for they reach it
    by fitting noise [-]."""
    return [c for c in fits if c["total"] <= bound and not c["unsupported"]]


def _relocated_fits(ctx, n_nums, starts) -> list:
    """Vector fitting's poles and delay with the numerator of least absolute error, not
    refined, cleaned and scored: the refinements lower a mixed cost in which the relative
    error of the best measured bins still counts, and may leave a total error above
    theirs even at the largest mix [-]."""
    if not starts:
        return []
    w = np.abs(ctx["H"])  # the relative error weighted by |H|: the absolute error
    out = [_mixed(ctx, w, n_num, starts, math.inf, refine=False) for n_num in n_nums]
    return [got[0] for got in out if got is not None]


def _at_mix(ctx, mu, n_nums, base, prev) -> list:
    """Scored fits of each numerator degree with the mixed weights of ``mu``; ``prev``
    (numerator degree: start) is updated with their poles for the next mix."""
    w = ctx["w"]
    mag = np.abs(ctx["H"]) ** 2 / np.mean(np.abs(ctx["H"]) ** 2)
    wm = np.sqrt(w**2 + mu * np.mean(w**2) * mag)
    out = []
    for n_num in n_nums:
        got = _mixed(ctx, wm, n_num, base + prev.get(n_num, []), mu)
        if got is not None:
            out.append(got[0])
            prev[n_num] = [got[1]]
    return out


def _noted(cand, ref) -> dict:
    """The candidate with a note of the weights mixed and the total error reached."""
    mu = cand.get("mix", 0.0)
    short = cand["total"] > ref * (1 + REACH)
    if mu == 0:
        return {**cand, "short": short, "ref": ref}
    how = "short of" if short else "reaching"
    weights = (f"bins weighted also by |H| (mu = {mu:g})" if math.isfinite(mu) else
               "vector fitting's poles kept, the bins weighted by |H| alone")
    note = (f"{weights}: total error {cand['total']:.3g}, {how} the {ref:.3g} of vector "
            "fitting's poles")
    return {**cand, "notes": [*cand["notes"], note], "short": short, "ref": ref}


def fewer_note(fewer: dict, own: dict, n: int) -> str:
    """Why the fit of ``fewer["asked"]`` poles was kept over that of ``n``, with the total
    errors to the digits in which they differ (at most four) [-]."""
    asked = fewer["asked"]
    kept = f" ({fewer['n_poles']} kept)" if fewer["n_poles"] != asked else ""
    a, b = fewer["total"], own["total"]
    digits = next((d for d in range(3, 5) if f"{a:.{d}g}" != f"{b:.{d}g}"), None)
    if digits is None:
        how = f"the same total error as {n} poles ({a:.4g}) with fewer"
    else:
        how = f"a total error of {a:.{digits}g}, below the {b:.{digits}g} of {n} poles"
    ref = own.get("ref")
    why = (f"; vector fitting's {n} poles leave {ref:.3g}, and the fits of {n} tried fall "
           "short of it once the pole-zero pairs the data do not support are removed"
           if ref is not None and ref < a else "")
    return f"the fit of {asked} poles{kept} leaves {how}: kept{why}"
