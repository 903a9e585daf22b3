"""Grey-box fit of the five-inertia parameters to the measured FRFs G_M, G_T, G_tcp.

The lead and the torque constant are known (``machine.yaml``); the other fourteen
parameters of physics.md section 1 are fitted jointly by nonlinear least squares on the
relative complex error of the three FRFs, weighted by their per-bin uncertainty.
Positivity comes from fitting log-parameters; bounds keep them physical. The Jacobian is
analytic (:mod:`tcpmm.ident.physical.jacobian`); standard deviations and correlations come from it
at the solution; parameters the data cannot determine are named in a warning.

The starting point matters for a nonlinear fit with several resonances. It is built from
the data: the rigid-body inertia from the low-frequency slope of G_M, the structural
modes from the poles of G_tcp (whose denominator is ``(M_b+M_t) s^2 + ... + K_b`` times
``M_h s^2 + C_h s + K_h``), and the drive modes from the resonances of G_T; several
splits of the inertia are tried and the best fit is kept (:mod:`tcpmm.ident.physical.starts`).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import asdict, dataclass, field

import numpy as np
from scipy.optimize import least_squares

from ..._threads import limit_blas_threads
from ...errors import InputError, InputWarning
from ...mechanics.lumped import RANGES, AxisMechanics
from ..lti.goodness import rel_error
from .axisfrfs import model_frfs, nut_path
from .covariance import held_at_bound, log_covariance
from .fitdata import band_model, fit_weight, log_binned, log_residual
from .jacobian import residual_jacobian
from .starts import guesses_from_tf, initial_guesses, j_total_from_g_m

# nut_path is imported from here as well as from its module
__all__ = ["FITTED", "TIGHT", "FitObjective", "PhysicalFit", "SweepPlay", "fit_physical",
           "fitted_names", "log_covariance", "nut_path"]

FITTED = ("J_m", "B_m", "J_L", "B_L", "K_L", "M_t", "C_t", "K_t", "M_b", "C_b", "K_b",
          "M_h", "C_h", "K_h")
#: Tolerances of the final refinements: tight enough that the point where a fit stops does
#: not follow rounding in the records (analytic Jacobians make them reachable) [-].
TIGHT = dict(ftol=1e-12, xtol=1e-12, gtol=1e-12)

@dataclass(frozen=True)
class SweepPlay:
    """How the nut's lost motion softened it where the sweep crossed the play.

    Parameters
    ----------
    bias_force_N : float
        Friction force on the table at the sweep's travel speed, holding the nut on one
        flank [N].
    lowest_nut_gain : float
        Smallest factor on ``K_t`` over the sweep's band [-].
    at_hz : float
        Frequency of that smallest factor [Hz].
    nut_amplitude_there_m : float
        Amplitude of the nut deflection at that frequency [m].
    """

    bias_force_N: float
    lowest_nut_gain: float
    at_hz: float
    nut_amplitude_there_m: float

    def to_dict(self) -> dict:
        """Plain dictionary for the JSON report [-]."""
        return asdict(self)


@dataclass
class PhysicalFit:
    """Identified axis mechanics with uncertainty.

    Parameters
    ----------
    mechanics : AxisMechanics
        Identified parameters [SI].
    std : dict
        Standard deviation per fitted parameter [SI].
    correlation : ndarray
        Correlation matrix of the log-parameters, order of :data:`FITTED` [-].
    undetermined : list of str
        Parameters the data cannot determine (relative std above 50 %) [-].
    rel_error : dict
        RMS relative complex error per FRF [-].
    cost : float
        Final least-squares cost [-].
    names : list of str
        The reported parameters: those fitted or held in proportion to ``M_t``, in the
        order of :data:`FITTED`, then ``f_i`` when the current loop was fitted [-].
    nfev : int
        Function evaluations of the final refinement [-].
    current_bandwidth_hz : float or None
        Fitted first-order current-loop bandwidth; ``None`` when it was not fitted or lies
        beyond the data's reach (the loop is then taken as ideal) [Hz].
    tied : dict
        Parameters held in proportion to ``M_t``, ``{name: value / M_t}`` [SI / kg].
    nut_gain : callable or None
        The factor on ``K_t`` per frequency the fit was made with (the nut's lost motion as
        the sweep saw it, :func:`tcpmm.ident.friction.play_gain`); ``None``: a linear
        nut [-].
    sweep_play : SweepPlay or None
        How the play softened the nut where the sweep crossed it, when the fit was made
        with ``nut_gain`` and kept [-].
    crossed_play_gain : float or None
        Where the sweep crossed a lost motion the friction runs found and the fit kept
        treats the nut as linear, the lowest factor the play put on the nut's stiffness
        over the band (:func:`tcpmm.ident.steps.playrefit.lowest_nut_gain`): the axial
        modes' masses and damping are then those of a describing function [-].
    """

    mechanics: AxisMechanics
    std: dict
    correlation: np.ndarray
    undetermined: list
    rel_error: dict
    cost: float
    names: list = field(default_factory=list)
    nfev: int = 0
    current_bandwidth_hz: float | None = None
    tied: dict = field(default_factory=dict)
    nut_gain: Callable | None = None
    sweep_play: SweepPlay | None = None
    crossed_play_gain: float | None = None

    def to_pandas(self):
        """Table of parameters, standard deviations and relative uncertainty."""
        import pandas as pd

        d = self.mechanics.model_dump()
        rows = [{"parameter": k, "value": d[k], "std": self.std[k],
                 "rel_std_percent": 100 * self.std[k] / d[k] if d[k] else float("nan"),
                 "determined": k not in self.undetermined} for k in FITTED]
        return pd.DataFrame(rows)


def fit_physical(data: dict, lead: float, K_tc: float, initial: dict | None = None,
                 current_bandwidth_hz=None, fit_current_loop: bool = False,
                 max_nfev: int = 2000, tf_fits: dict | None = None,
                 hold_period_s: float = 0.0, nut_gain=None,
                 structure: dict | None = None, structure_log_std: dict | None = None,
                 warn: bool = True) -> PhysicalFit:
    """Fit the axis mechanics jointly to G_M, G_T and (when present) G_tcp.

    Parameters
    ----------
    data : dict of str to FRFData
        Measured FRFs keyed ``"G_M"``, ``"G_T"``, ``"G_tcp"`` [SI].
    lead : float
        Ball-screw lead, known [m].
    K_tc : float
        Torque constant, known [N m/A].
    initial : dict, optional
        Starting values of the fitted parameters; default from the data [SI].
    current_bandwidth_hz : float, optional
        Current loop bandwidth if the drive's is known [Hz].
    fit_current_loop : bool
        Fit a first-order current-loop bandwidth too (it shows in G_M only); reported
        as ``current_bandwidth_hz`` of the result, ``None`` when beyond the data's reach [-].
    max_nfev : int
        Function evaluations of the final refinement [-].
    tf_fits : dict, optional
        Rational fits of the same FRFs; their poles and zeros seed the starts [-].
    hold_period_s : float
        Velocity-loop period of the drive (zero-order hold of the current) [s].
    nut_gain : callable, optional
        Factor on ``K_t`` per frequency (lost motion crossed by the sweep), see
        :func:`model_frfs` [-].
    structure : dict, optional
        Parameters held in proportion to ``M_t``, ``{name: value / M_t}``, e.g. the bed and
        TCP structure from ``G_tcp`` alone (:func:`tcpmm.ident.physical.structure.fit_structure`);
        they are not fitted [SI / kg].
    structure_log_std : dict, optional
        Deviation of the logarithm of each ratio of ``structure`` from its fit (``nan`` at
        a bound), combined with that of ``M_t``; without, held ones have ``M_t``'s [-].
    warn : bool
        Warn of the parameters the data do not determine (:func:`undetermined_words`);
        an identification that fits an axis several times says it once, of the fit it
        keeps [-].
    """
    limit_blas_threads()
    names, tied, reported = fitted_names(data, structure, fit_current_loop)
    f_top = max(float(d.freq_hz.max()) for d in data.values())
    binned = {k: log_binned(v) for k, v in data.items()}
    fixed = dict(lead=lead, K_tc=K_tc, M_h=1.0, C_h=1.0, K_h=1e9)
    objective = FitObjective(binned, names, tied, fixed, fit_current_loop, current_bandwidth_hz,
                           hold_period_s, nut_gain)
    if initial is not None:
        starts = [initial]
    else:
        starts = _starts(binned, data, lead, K_tc, tf_fits, f_top)
    r = _multistart(objective.resid, objective.jac, starts, names, fit_current_loop, max_nfev)
    fit = _physical_fit(r, objective, data, reported, f_top, structure_log_std or {})
    if warn and fit.undetermined:
        warnings.warn(undetermined_words(fit.undetermined), InputWarning, stacklevel=2)
    return fit


def undetermined_words(undetermined) -> str:
    """The warning of parameters the FRFs do not determine [-]."""
    return ("the FRFs do not determine " + ", ".join(undetermined) + " (relative standard "
            "deviation above 50 %); their values are a guess")


def fitted_names(data: dict, structure: dict | None, fit_current_loop: bool) -> tuple:
    """The parameters fitted (``f_i`` last when the current loop is), those held in
    proportion to ``M_t`` ``{name: value / M_t}``, and those reported; raises without
    G_M or G_T [-]."""
    for need in ("G_M", "G_T"):
        if need not in data:
            raise InputError(f"the physical fit needs {need}; only {', '.join(data)} given")
    has_tcp = "G_tcp" in data
    names = list(FITTED) if has_tcp else [p for p in FITTED if p not in ("M_h", "C_h", "K_h")]
    tied = {p: float(r) for p, r in (structure or {}).items() if p in names}
    reported = list(names)
    names = [p for p in names if p not in tied]
    if fit_current_loop:
        names = [*names, "f_i"]
    return names, tied, reported


class FitObjective:
    """The weighted log residual of the binned FRFs against the model and its analytic
    Jacobian, as functions of the log-parameters ``theta`` (in the order of ``names``).

    The residual at the last point is kept: the Jacobian there needs its fallbacks."""

    def __init__(self, binned: dict, names: list, tied: dict, fixed: dict,
                 fit_current_loop: bool, current_bandwidth_hz, hold_period_s: float,
                 nut_gain):
        self.data = binned
        self.freqs = {k: v.band_points() for k, v in binned.items()}
        self.w = {k: fit_weight(v) for k, v in binned.items()}
        self.names, self.tied, self.fixed = names, tied, fixed
        self.n_mech = len(names) - int(fit_current_loop)
        self.fit_current_loop = fit_current_loop
        self.current_bandwidth_hz = current_bandwidth_hz
        self.hold_period_s, self.nut_gain = hold_period_s, nut_gain
        self.last = {}

    def mech_of(self, theta) -> AxisMechanics:
        """The mechanics at ``theta``, unchecked [SI]."""
        n = self.n_mech
        vals = dict(zip(self.names[:n], np.exp(theta[:n]), strict=True))
        vals.update({p: r * vals["M_t"] for p, r in self.tied.items()})
        return AxisMechanics.model_construct(**{**self.fixed, **vals, "load_force": 0.0})

    def bandwidth(self, theta):
        """The current-loop bandwidth at ``theta``, fitted or given [Hz]."""
        if self.fit_current_loop:
            return float(np.exp(theta[self.n_mech]))
        return self.current_bandwidth_hz

    def resid(self, theta) -> np.ndarray:
        """The stacked weighted log residual [-]."""
        r, model = _band_residual(self.mech_of(theta), self.data, self.freqs, self.w,
                                  self.bandwidth(theta), self.hold_period_s, self.nut_gain)
        self.last.update(x=np.array(theta), r=r, model=model)
        return r

    def jac(self, theta) -> np.ndarray:
        """Its Jacobian by ``theta`` [-]."""
        if not np.array_equal(self.last.get("x"), theta):
            self.resid(theta)
        return residual_jacobian(self.mech_of(theta), self.freqs, self.w, self.last["r"],
                                 self.names, self.tied, self.bandwidth(theta), self.nut_gain,
                                 pairs=self.last.get("model"))


def _physical_fit(r, objective: FitObjective, full: dict, reported: list,
                  f_top: float, tied_log_std: dict) -> PhysicalFit:
    """The fit at the ``least_squares`` result ``r``: mechanics, uncertainty (with what
    the data do not determine, the held parameters' deviations ``tied_log_std`` counted)
    and the error against the unbinned FRFs ``full``; a current loop beyond the data's
    reach is kept ideal [-]."""
    names, tied, n_mech = objective.names, objective.tied, objective.n_mech
    mech = AxisMechanics.create(**_within_ranges(objective.mech_of(r.x).model_dump()))
    f_i = objective.bandwidth(r.x)
    std, corr, undetermined = _std(r, names, tied, tied_log_std)
    model = model_frfs(mech, {k: d.freq_hz for k, d in full.items()}, f_i,
                       objective.hold_period_s, objective.nut_gain)
    rel = {k: rel_error(d.H[d.weight > 0], model[k][d.weight > 0]) for k, d in full.items()}
    if objective.fit_current_loop and ("f_i" in undetermined or f_i > 3 * f_top):
        f_i = None  # the data cannot see the current loop: keep it ideal
    return PhysicalFit(mech, std, corr, undetermined, rel, float(r.cost),
                       names=reported + names[n_mech:], nfev=int(r.nfev),
                       current_bandwidth_hz=f_i, tied=tied, nut_gain=objective.nut_gain)


def _within_ranges(values: dict) -> dict:
    """``values`` clipped into the plausible range of each parameter
    (:data:`~tcpmm.mechanics.lumped.RANGES`). A structure the band does not show can run
    to a bound of the fit beyond it (a head stiffer than 1e16 N/m, held in proportion to a
    table mass that moved): at the range's end it is as rigid, and the axis can still be
    written [SI]."""
    return {p: min(max(v, RANGES[p][0]), RANGES[p][1]) if p in RANGES else v
            for p, v in values.items()}


def _band_residual(mech, data: dict, freqs: dict, w: dict, f_i, hold_period_s: float,
                   nut_gain):
    """Log residual of the model averaged over each bin of the binned ``data`` against
    them, and the model at ``freqs``, the bins' two points (:meth:`FRFData.band_points`);
    a singular model counts 1e3 in every bin, with no model values (NaN) [-]."""
    try:
        model = model_frfs(mech, freqs, f_i, hold_period_s, nut_gain)
    except np.linalg.LinAlgError:
        return (np.full(sum(2 * d.freq_hz.size for d in data.values()), 1e3),
                {k: np.full(f.size, np.nan) for k, f in freqs.items()})
    r = np.concatenate([log_residual(band_model(model[k]), d.H, w[k])
                        for k, d in data.items()])
    return r, model


def _starts(binned: dict, full: dict, lead: float, K_tc: float, tf_fits, f_top: float) -> list:
    """Starting points from the data: from the poles and zeros of the rational fits when
    there are any, then from the log-binned FRFs themselves [SI]."""
    starts = initial_guesses(binned, lead, K_tc)
    if tf_fits:
        starts = guesses_from_tf(tf_fits, lead, K_tc, j_total_from_g_m(full["G_M"], K_tc),
                                 f_top_hz=f_top) + starts
    return starts


def _std(r, names: list, tied: dict, tied_log_std: dict):
    """Standard deviation per parameter [SI], the correlation matrix of the
    log-parameters [-] and the parameters the data do not determine (relative std above
    50 %, or held at a bound of the fit) of a ``least_squares`` result; ``nan`` for a TCP
    structure not fitted and for a parameter at a bound, whose linearised deviation says
    nothing (the cost does not rise across the bound, and it often comes out 0). A
    parameter held in proportion to ``M_t`` varies with ``M_t`` and with its ratio, whose
    own fit (``tied_log_std``) can leave it far looser than ``M_t``: a sweep that misses
    a structural mode leaves its damping to a guess, however well the table's mass is
    known."""
    sd_log, corr = log_covariance(r)
    at_bound = held_at_bound(r)
    sd_log = np.where(at_bound, np.nan, sd_log)
    vals = dict(zip(names, np.exp(r.x), strict=True))
    std = {p: float(vals[p] * sd_log[i]) for i, p in enumerate(names)}
    rel = dict(zip(names, sd_log, strict=True))
    for p, ratio in tied.items():
        # nan (a ratio held at its fit's bound) stays nan: the parameter is undetermined
        rel[p] = float(np.hypot(rel["M_t"], tied_log_std.get(p, 0.0)))
        std[p] = float(ratio * vals["M_t"] * rel[p])
    for p in ("M_h", "C_h", "K_h"):
        std.setdefault(p, float("nan"))
    order = [*FITTED, "f_i"]
    return std, corr, sorted((p for p, x in rel.items() if not x <= 0.5), key=order.index)


def _multistart(resid, jac, starts, names, fit_current_loop: bool, max_nfev: int):
    """A short bounded run from every start (each parameter within a factor 1e3 of its
    start), then the best one to convergence; the ``least_squares`` result [-]."""
    best, best_bounds = None, None
    for g in starts:
        g = {"f_i": 3000.0, **g}
        theta0 = np.log([g[p] for p in names])
        lo, hi = theta0 - np.log(1e3), theta0 + np.log(1e3)
        if fit_current_loop:
            lo[-1], hi[-1] = np.log(20.0), np.log(1e5)
        r = least_squares(resid, theta0, jac=jac, bounds=(lo, hi),
                          max_nfev=25 if len(starts) > 1 else max_nfev, method="trf")
        if best is None or r.cost < best.cost:
            best, best_bounds = r, (lo, hi)
    r = least_squares(resid, best.x, jac=jac, bounds=best_bounds, max_nfev=max_nfev,
                      method="trf", **TIGHT)
    r.bounds = best_bounds
    return r
