"""Transfer functions fitted to measured frequency responses, with the order chosen by data.

:func:`fit_frf` wraps :func:`~tcpmm.ident.lti.tffit.fit_tf` with what a measured FRF needs:

* **Noise level per bin.** The coherence of few averages is biased towards 1, so the random
  error it implies can be far too small. The relative noise is also estimated from the
  roughness of the response itself: for a smooth response the second difference
  ``H[k-1] - 2 H[k] + H[k+1]`` is noise, of variance six times that of one bin; its running
  median over :data:`NOISE_WINDOW` bins gives a robust level that follows the frequency.
  The larger of the two is the noise ``sigma`` of a bin (standard deviation of each of the
  real and imaginary parts of ``H_model / H - 1`` for the true model).
* **Order by information.** Pole counts 1, 2, ... are fitted (numerator degree ``n`` or
  ``n - 1``) and scored by ``chi2 + p ln(2 N)`` (Bayesian information criterion with the
  known noise; ``chi2 = sum |H_model / H - 1|^2 / sigma^2``, ``p`` real parameters, ``N``
  bins). The scan stops once the residual reaches the noise (``chi2 <= 2 N``) or the
  criterion has not improved over :data:`PATIENCE` pole counts.
* **No needles.** A pole pair less damped than the floor (``damping_floor``, or a
  half-power bandwidth below the spacing of the measured bins, gaps left by the
  coherence cut not counted, unless the bins beside its peak show the lower damping) is
  raised to it and the numerator fitted again. Then a pole
  and a zero (pairs or real) whose joint factor changes the response by more than
  :data:`~tcpmm.ident.lti._needles.CANCEL_SIGMA` noise levels at fewer than
  :data:`~tcpmm.ident.lti._needles.SUPPORT_BINS` bins are not supported by the data (a
  resonance needs more than one bin) and are removed, the numerator fitted again each
  time; then two poles with two zeros, which may cancel only together. Both tests take
  the noise, or where less the running level of the fit's own residual: the roughness
  takes the curvature of a peak one bin wide for noise. A lightly damped
  pair (damping below 0.2) outside the band counts against a candidate order.
* **Both error measures.** The fit of the pole count chosen or given must leave a total
  relative error ``sum |H - H_model|^2 / sum |H|^2`` no larger than vector fitting's
  relocated poles do; where the relative fit leaves more (too few poles spent on the small
  top of the band), the bins are weighted also by ``|H|``, no more than needed, and the
  fit started again from those poles (:mod:`~tcpmm.ident.lti._select`; a note says so).
  Where no fit of a given pole count reaches it, the fit of one pole fewer is kept if it
  leaves less total error: the larger count holds it, and its refinements missed it.
* **A delay held, checked.** With the delay held (none, or a value given) the fit is made
  again with it free, and where the data suggest another delay a warning says so and the
  values whose sd assumed it are undetermined (:mod:`~tcpmm.ident.lti.delayheld`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...errors import InputError
from ...frfdata import FRF
from ._needles import clean_fit
from ._select import AT_NOISE_CHI2, by_criterion, by_total, choose, fewer_note, score
from .delayheld import check_held_delay
from .frfargs import checked_fit_args
from .frfnoise import NOISE_WINDOW, lone_passes, noise_level
from .goodness import warn_if_misfit, warn_if_off
from .tffit import WEIGHT_FLOOR, TFFit, check_order_resolved, fit_tf
from .tfsd import TFDeviations, tf_deviations

__all__ = ["DAMPING_FLOOR", "NOISE_WINDOW", "FRFFit", "fit_frf", "noise_level"]

#: Least damping ratio of a fitted pole pair [-]. The floor that matters is the bins' own
#: spacing (a resonance narrower than one bin is not in the data); this one only keeps a
#: pair off the imaginary axis where the bins are dense. Machine tools' screw and torsion
#: modes are damped by 0.0002 to 0.002: a floor among them biases the fit.
DAMPING_FLOOR = 1e-4
#: Largest pole count tried by the automatic order [-].
MAX_POLES = 16
#: Pole counts without improvement of the criterion before the scan stops [-].
PATIENCE = 3
WEIGHTINGS = ("relative", "absolute", "magnitude")


@dataclass(frozen=True)
class FRFFit:
    """A transfer function fitted to a measured frequency response, with its quality.

    Parameters
    ----------
    tf : TFFit
        The fitted model; ``tf.poles`` and ``tf.zeros`` are in rad/s [-].
    band_hz : tuple of float
        Band fitted [Hz].
    weighting : str
        ``"relative"``, ``"absolute"`` or ``"magnitude"`` [-].
    rel_rms : float
        RMS of ``|H_model / H - 1|`` over the bins fitted [-].
    noise_rms : float
        The same RMS that the noise alone gives, ``sqrt(mean(2 sigma^2))`` [-].
    chi2_ratio : float
        ``chi2 / (2 N)``: 1 when the residual is at the noise [-].
    damping_floor : float
        Least damping ratio allowed [-].
    notes : list of str
        Pole-zero pairs removed and poles raised to the floor [-].
    candidates : list of dict
        Orders tried by the automatic choice with their criterion [-].
    deviations : TFDeviations, optional
        Standard deviations of the modes, real poles, zeros, delay and gain
        (:mod:`~tcpmm.ident.lti.tfsd`) [-].
    name, input, output, unit : str
        Labels of the measured response [-].
    """

    tf: TFFit
    band_hz: tuple[float, float]
    weighting: str
    rel_rms: float
    noise_rms: float
    chi2_ratio: float
    damping_floor: float
    notes: list = field(default_factory=list)
    candidates: list = field(default_factory=list)
    deviations: TFDeviations | None = None
    name: str = ""
    input: str = ""
    output: str = ""
    unit: str = ""

    @property
    def poles(self) -> np.ndarray:
        """Poles, sorted by magnitude [rad/s]."""
        return self.tf.poles

    @property
    def zeros(self) -> np.ndarray:
        """Zeros, sorted by magnitude [rad/s]."""
        return self.tf.zeros

    def freqresp(self, f_hz) -> np.ndarray:
        """Model response at ``f_hz`` [Hz]; returns the complex response [unit]."""
        return self.tf.freqresp(f_hz)

    def to_dict(self) -> dict:
        """Plain dict: model (poles and zeros as [real, imaginary] in rad/s), the standard
        deviations of its modes, real poles, zeros, delay and gain, and quality."""
        pairs = lambda p: [[float(v.real), float(v.imag)] for v in p]  # noqa: E731
        tf = self.tf
        modes = [{"freq_hz": float(fn), "damping": float(z)}
                 for fn, z in zip(tf.natural_freq_hz, tf.damping, strict=True)]
        # with the deviations, modes carry their sds and real poles, zeros, delay and gain
        # follow
        sds = self.deviations.to_dict() if self.deviations is not None else {"modes": modes}
        return {
            "name": self.name, "input": self.input, "output": self.output,
            "unit": self.unit, "band_hz": [float(b) for b in self.band_hz],
            "weighting": self.weighting, "n_poles": int(tf.n_den),
            "n_zeros": int(tf.n_num), "delay_s": float(tf.delay_s),
            "poles": pairs(tf.poles), "zeros": pairs(tf.zeros),
            "num": [float(v) for v in tf.num], "den": [float(v) for v in tf.den],
            **sds,
            "quality": {"rel_rms": self.rel_rms, "noise_rms": self.noise_rms,
                        "chi2_ratio": self.chi2_ratio, "fit_percent": tf.fit_percent,
                        "bins": int(tf.freq_hz.size)},
            "damping_floor": self.damping_floor, "notes": list(self.notes),
            "candidates": list(self.candidates),
        }

    def to_pandas(self):
        """Pole table, one row per real pole or complex pair (see :meth:`TFFit.to_pandas`),
        with the standard deviations ``freq_sd_hz`` and ``damping_sd`` (inf where undetermined,
        NaN where the row has none)."""
        df = self.tf.to_pandas()
        rows = (self.deviations.by_row(df["kind"]) if self.deviations is not None
                else [(None, None)] * len(df))
        for col, i in (("freq_sd_hz", 0), ("damping_sd", 1)):
            df[col] = [np.nan if r[i] is None else r[i].bound for r in rows]
        return df

    def plot(self, ax=None, path=None, frf: FRF | None = None):
        """Measured against fitted response with the residual.

        Parameters
        ----------
        ax : sequence of 3 matplotlib Axes, optional
            Axes to draw into [-].
        path : str or Path, optional
            Where to save the figure [-].
        frf : FRF, optional
            The whole measurement, drawn beyond the bins fitted [-].
        """
        from ...plot.frf import plot_frf_fit  # tcpmm.plot is a floor above this one

        if frf is not None:
            f, H, coh = frf.freq_hz, frf.H, frf.coherence
        else:
            f, H, coh = self.tf.freq_hz, self.tf.H, None
        title = (f"{self.name}: {self.tf.n_den} poles, {self.tf.n_num} zeros, "
                 f"residual {self.rel_rms:.3g} (noise {self.noise_rms:.3g})")
        return plot_frf_fit(f, H, self.freqresp(f), coherence=coh, band_hz=self.band_hz,
                            path=path, ax=ax, title=title)


# ----------------------------------------------------------------------------- weights


def _weights(H, sigma, mode):
    if mode == "relative":
        return 1.0 / np.sqrt(sigma**2 + WEIGHT_FLOOR**2)
    mag = np.abs(H) / np.max(np.abs(H))
    return mag if mode == "absolute" else np.sqrt(mag)


# ----------------------------------------------------------------------------- fitting


def fit_frf(frf: FRF, poles="auto", band_hz: tuple[float | None, float | None] | None = None,
            weighting: str = "relative", delay_s="fit", damping_floor: float = DAMPING_FLOOR,
            max_poles: int = MAX_POLES, min_coherence: float = 0.5) -> FRFFit:
    """Fit a transfer function to a measured frequency response.

    Parameters
    ----------
    frf : FRF
        The measurement [unit].
    poles : int or "auto"
        Number of poles, or ``"auto"`` to choose it from the data (see the module) [-].
    band_hz : tuple of float, optional
        ``(f0, f1)``; either may be None for the edge of the data [Hz].
    weighting : {"relative", "absolute", "magnitude"}
        Error minimised: relative error weighted by the noise of each bin; absolute error
        ``|H_model - H|``; relative error weighted by ``|H|`` (resonances count more) [-].
    delay_s : None, float or "fit"
        Pure delay: none, a known value [s], or fitted [s].
    damping_floor : float
        Least damping ratio of a pole pair [-].
    max_poles : int
        Largest pole count the automatic order tries [-].
    min_coherence : float
        Bins of lower coherence are left out [-].

    Returns
    -------
    FRFFit
        The model, its quality and the orders tried [-].
    """
    poles, delay_s, max_poles = checked_fit_args(frf, poles, delay_s, max_poles,
                                                 min_coherence)
    if weighting not in WEIGHTINGS:
        raise InputError(f"weighting must be one of {', '.join(WEIGHTINGS)}, got {weighting!r}")
    if not (np.isfinite(damping_floor) and 0 <= damping_floor < 1):
        raise InputError(f"the damping floor must be in [0, 1), got {damping_floor}")
    lo, hi = band_hz if band_hz is not None else (None, None)
    data = frf.band(lo, hi)
    ctx = _context(data, weighting, delay_s, damping_floor, min_coherence)
    ctx["auto"] = poles == "auto"
    if poles == "auto":
        best, cands = _auto(ctx, max_poles)
        best = choose(ctx, [best], best["tried"][0])
    else:
        best, cands = _given_order(ctx, poles)
    return _frf_fit(frf, data, ctx, best, cands, weighting)


def _too_few(data: FRF, coherent: np.ndarray, valid: np.ndarray,
             min_coherence: float) -> str:
    """Why fewer than four bins can be fitted: the band's bins, those of low coherence and
    those of enough whose response is zero or not finite (not ``valid``), each with its
    fix [-]."""
    low, void = ~coherent, coherent & ~valid
    why = [f"{np.count_nonzero(low)} have coherence below {min_coherence:g} (measure again "
           "with more excitation)"] if low.any() else []
    if void.any():
        why.append(f"{np.count_nonzero(void)} have a response of zero or not a number "
                   "(check the re/im or magnitude columns)")
    return (f"only {np.count_nonzero(coherent & valid)} of the band's {data.freq_hz.size} "
            "bins can be fitted, at least 4 are needed" + (": " + "; ".join(why) if why else "")
            + "; widen the band or give a file with more bins")


def _context(data: FRF, weighting: str, delay_s, damping_floor: float,
             min_coherence: float) -> dict:
    """What every candidate fit needs: the bins of the band of enough coherence, their
    noise and weights, the delay handling, the damping floor and the frequency scale [-]."""
    sigma_all = noise_level(data.freq_hz, data.H, data.rel_std)
    coherent = data.coherence >= min_coherence
    coherent &= ~lone_passes(coherent)
    valid = np.isfinite(data.H) & (data.H != 0)
    keep = coherent & valid
    if np.count_nonzero(keep) < 4:
        raise InputError(_too_few(data, coherent, valid, min_coherence))
    f, H, sigma = data.freq_hz[keep], data.H[keep], sigma_all[keep]
    # the damping floor follows the measurement's own bin spacing: the bins left after the
    # coherence cut have gaps (most often at resonances), which would double it there
    return {"f": f, "H": H, "sigma": sigma, "w": _weights(H, sigma, weighting),
            "delay": delay_s, "floor": float(damping_floor), "grid": data.freq_hz,
            "omega0": 2 * np.pi * float(np.sqrt(f[0] * f[-1]))}


def _given_order(ctx: dict, n: int) -> tuple:
    """The best of ``n`` poles over ``n - 1`` or ``n`` zeros, and the candidates; ``n`` a
    whole number of 0 or more (:func:`.frfargs.checked_fit_args`) [-]."""
    check_order_resolved(ctx["f"], n)  # else no order is tried, or it is not determined
    tries = _tries(ctx, n)
    if not tries:
        raise InputError(f"{ctx['f'].size} bins cannot determine {n} poles; fewer poles or a "
                         "wider band")
    own = {**choose(ctx, tries, n), "asked": n}
    best = _fewer_if_better(ctx, own, n)
    if best is not own:
        best = {**best, "notes": [*best["notes"], fewer_note(best, own, n)]}
    return best, tries


def _tries(ctx: dict, n: int) -> list:
    """The relative fits of ``n`` poles over ``n - 1`` and ``n`` zeros that the bins
    determine [-]."""
    tries = [_candidate(ctx, nn, n) for nn in sorted({max(n - 1, 0), n})]
    return [t for t in tries if t is not None]


def _fewer_if_better(ctx: dict, best: dict, n: int) -> dict:
    """``best``, the fit chosen for ``n`` poles, or where it falls short of its bound the
    fit of fewer poles (chosen likewise) if that leaves less total error: ``n`` poles hold
    every fit of ``n - 1`` and a pair that cancels, so the refinements of ``n`` missed it.
    A fit kept for being at the noise (``quiet``) gives way only to one at the noise too
    (a chi2 ratio of at most AT_NOISE_CHI2): the least criterion among the fits at the
    noise of ``n`` poles may leave several times the total error of ``n - 1`` [-]."""
    if not (best.get("short") or best.get("quiet")) or n <= 1:
        return best
    tries = _tries(ctx, n - 1)
    if not tries:
        return best
    fewer = _fewer_if_better(ctx, {**choose(ctx, tries, n - 1), "asked": n - 1}, n - 1)
    if best.get("quiet") and fewer["chi2_ratio"] > AT_NOISE_CHI2:
        return best
    return fewer if by_total(fewer) < by_total(best) else best


def _frf_fit(frf: FRF, data: FRF, ctx: dict, best: dict, cands: list,
             weighting: str) -> FRFFit:
    """The chosen candidate with its quality against the noise and the orders tried [-]."""
    f, H, sigma = ctx["f"], ctx["H"], ctx["sigma"]
    fit = best["fit"]
    h = fit.freqresp(f)
    e2 = np.abs(h / H - 1) ** 2
    chi2 = float(np.sum(e2 / sigma**2) / (2 * f.size))
    devs, notes = tf_deviations(fit, ctx["delay"] == "fit", chi2_ratio=chi2), best["notes"]
    warn_if_off(frf.name, fit.n_den, h, H, auto=ctx["auto"], delay=ctx["delay"])
    warn_if_misfit(frf.name, chi2, devs.describes_data)
    if ctx["delay"] != "fit":  # its sds hold only if the delay held is the data's
        devs, note = check_held_delay(fit, devs, ctx["delay"], sigma, ctx["floor"],
                                      ctx["grid"], frf.name)
        notes = [*notes, note] if note else notes
    return FRFFit(
        tf=fit, band_hz=(float(data.freq_hz[0]), float(data.freq_hz[-1])),
        weighting=weighting, rel_rms=float(np.sqrt(np.mean(e2))),
        noise_rms=float(np.sqrt(np.mean(2 * sigma**2))),
        chi2_ratio=chi2,
        damping_floor=ctx["floor"], notes=notes,
        candidates=[{k: c[k] for k in ("tried", "n_poles", "n_zeros", "chi2_ratio", "bic",
                                        "unsupported")} for c in cands],
        deviations=devs, name=frf.name, input=frf.input, output=frf.output,
        unit=frf.meta.get("unit", ""))


def _auto(ctx, max_poles):
    """Candidates by pole count until the noise is reached or the criterion stalls,
    screened on at most about 400 bins; the winner is fitted again on all of them."""
    stride = max(1, int(np.ceil(ctx["f"].size / 400)))
    sub = {k: (v[::stride] if isinstance(v, np.ndarray) and k != "grid" else v)
           for k, v in ctx.items()}
    cands, best_bic, stall = [], np.inf, 0
    for n in range(1, max_poles + 1):
        tries = [_candidate(sub, nn, n) for nn in (n - 1, n)]
        tries = [t for t in tries if t is not None]
        if not tries:
            break
        cands += tries
        top = min(t["bic"] for t in tries)
        stall = 0 if top < best_bic else stall + 1
        best_bic = min(best_bic, top)
        if min(t["chi2_ratio"] for t in tries) <= 1.0 or stall >= PATIENCE:
            break
    if not cands:
        raise InputError(f"{ctx['f'].size} bins are too few to fit any order; widen the band")
    best = min(cands, key=by_criterion)
    if stride > 1:
        best = _candidate(ctx, best["tried"][1], best["tried"][0]) or best
    return best, cands


def _candidate(ctx, n_num, n_den):
    """Fit, clean and score one order; None if the bins cannot determine it."""
    f, H, w = ctx["f"], ctx["H"], ctx["w"]
    try:
        fit = fit_tf((f, H, w), n_num, n_den, delay_s=ctx["delay"], max_nfev=100)
    except InputError:
        return None
    fit, notes = clean_fit(fit, ctx["sigma"], ctx["floor"], ctx["grid"])
    return score(ctx, fit, notes, (n_den, n_num))
