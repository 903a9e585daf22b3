"""Least-squares fit of error terms to one or more circles (or arcs) at once.

Each circle has its own radius and centre; the named terms (:mod:`.circle_model`) are
shared. Terms an arc does not determine are left out of the fit and reported as such
(:func:`.circle_model.determined`); a cyclic error per axis is searched for in the
residual; a servo mismatch is fitted again with the axes' reversals where the previous
fit puts them, its remainder beyond the ellipse taken off the data."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from .circle_cyclic import refine_waves, search_cyclic, search_periods
from .circle_design import base_columns, column_names, design, with_columns
from .circle_model import (
    alias_slopes,
    determined,
    drop_twins,
    fit_mask,
    reversal_lead_deg,
    servo_remainder,
)
from .circle_noise import coef_covariance
from .circle_period import wave_sigma
from .circle_reversal_tail import lingering, search_tail
from .circle_settling import steady_ends
from .circle_takeup import search_widths
from .circle_travel import Widths


@dataclass
class Arc:
    """One circle or arc to fit.

    Parameters
    ----------
    angle : ndarray
        Angle CCW from the first axis about the nominal centre, unwrapped [rad].
    e : ndarray
        Radial error about the nominal centre [m].
    s : float
        +1 CCW, -1 CW [-].
    ratio : float
        Angular speed over the mean of the arcs fitted together [-].
    after_deg : float
        The angle after each reversal left out of the fit, where its transient lies [deg].
    """

    angle: np.ndarray
    e: np.ndarray
    s: float
    ratio: float = 1.0
    after_deg: float = 20.0

    @property
    def mask(self):
        """Samples outside the reversals' transients and the ends'
        (:func:`.circle_settling.steady_ends`) [-]."""
        return fit_mask(self.angle, self.s, after_deg=(0.0, self.after_deg)) & self.ends

    def mask_for(self, mu: float):
        """Samples outside the reversals' transients where each axis reverses with a
        servo mismatch angle ``mu`` [rad]: the leading axis reverses ``|mu|`` before its
        quadrant point, and the window then starts that much (and a sample) earlier;
        else the first and largest sample of its transient is fitted as the circle. It
        stops and starts as much earlier too: as much is left out at the ends [-]."""
        lead = reversal_lead_deg(self.angle, self.ratio * mu)
        return fit_mask(self.angle, self.s, after_deg=(-lead, self.after_deg)) & (
            steady_ends(self.angle, lead) if mu else self.ends)

    @cached_property
    def ends(self):
        """The samples between the pass's unsteady ends
        (:func:`.circle_settling.steady_ends`) [-]."""
        return steady_ends(self.angle)

    def positions(self, radius, angle=None, e=None):
        """``(x, y)`` of the tool about the nominal centre [m]."""
        a, r = self.angle if angle is None else angle, radius + (self.e if e is None else e)
        return r * np.cos(a), r * np.sin(a)


@dataclass
class TermFit:
    """Coefficients of a fit; NaN for a term the arcs do not determine.

    Parameters
    ----------
    names : list of str
        Column names: per arc ``radius_i``, ``centre_X_i``, ``centre_Y_i``, then the shared
        terms, then the cyclic sine and cosine of each axis found [-].
    coef : ndarray
        Coefficient per column [SI].
    waves : tuple
        Wavenumber of the cyclic error of X and Y, None where none is found [1/m].
    mu : float
        Servo mismatch angle placing the reversals [rad].
    residual_rms : float
        Root mean square of what the terms leave over the fitted samples [m].
    centres : tuple
        Per arc, the centre ``(x, y)`` about which its axes reverse: its fitted centre
        offset [m].
    aliases : dict
        Per column left out of the fit (and per term ``unseen`` of :func:`fit_terms`), how
        much each fitted column moves per unit of it (:func:`.circle_model.alias_slopes`)
        [SI/SI].
    periods : tuple
        The longest and shortest period the cyclic errors were searched over; empty where
        they were not searched [m].
    cov : ndarray, optional
        Covariance of the coefficients from what the fit leaves over; NaN for a column not
        fitted, all NaN where not estimated (:func:`.circle_noise.coef_covariance`) [SI^2].
    tail : tuple, optional
        ``(decay, shape)`` of the reversals' tails past the window: the time constant, as
        the angle travelled in it at the mean speed, and the shape; None where they are not
        fitted (:mod:`.circle_reversal_tail`) [rad, -].
    tail_spread : dict
        Per column, its largest move over the tails that fit the samples as well as
        ``tail`` (:func:`.circle_reversal_tail.spread`); empty where none do [SI].
    tail_interval : tuple, optional
        The least and the largest time constant of the tails within the 95 % interval of
        either shape (:func:`.circle_reversal_tail.decay_interval`); None where no tail is
        fitted [rad].
    tail_family : tuple
        For a transient lasting past the window, the fits over the tails it may be
        (:func:`.circle_reversal_tail.lingering`); empty otherwise [SI].
    widths : tuple
        Per axis, the travel after its reversal over which its backlash is taken up, and
        that width's 95 % uncertainty, NaN where the data cannot tell
        (:mod:`.circle_takeup`) [m].
    lost : tuple
        Per axis, the backlash its take-up's travel is read with (:mod:`.circle_travel`) [m].
    wave_sigma : tuple
        Standard uncertainty of each wavenumber of ``waves``, NaN for none
        (:func:`.circle_period.wave_sigma`) [1/m].
    """

    names: list
    coef: np.ndarray
    waves: tuple
    mu: float
    residual_rms: float
    centres: tuple = ()
    aliases: dict = field(default_factory=dict)
    periods: tuple = ()
    cov: np.ndarray | None = None
    tail: tuple | None = None
    tail_spread: dict = field(default_factory=dict)
    tail_interval: tuple | None = None
    widths: tuple = ((0.0, float("nan")), (0.0, float("nan")))
    tail_family: tuple = ()
    lost: tuple = (0.0, 0.0)
    wave_sigma: tuple = (float("nan"), float("nan"))

    def __getitem__(self, name):
        return float(self.coef[self.names.index(name)])

    @property
    def take_up(self) -> Widths:
        """Each axis' take-up width of :attr:`widths`, with :attr:`lost` [m]."""
        return Widths((w for w, _ in self.widths), self.lost)

    def cyclic_amplitude(self, axis: str) -> float:
        """Amplitude of the cyclic error fitted for ``axis`` (``"X"``, ``"Y"``) [m]."""
        return float(np.hypot(self[f"cyclic_sin_{axis}"], self[f"cyclic_cos_{axis}"]))

    def undetermined(self) -> list:
        """Names of the terms left out of the fit [-]."""
        return [n for n, c in zip(self.names, self.coef, strict=True) if np.isnan(c)]


class FitProblem:
    """The arcs, their fitted samples and the columns they determine.

    Parameters
    ----------
    arcs : list of Arc
        The circles or arcs [-].
    radius : float
        Nominal radius [m].
    shared : sequence of str
        Terms common to the arcs [-].
    drop : sequence of str
        Columns left out whatever the arcs determine [-].
    columns : sequence of str, optional
        The columns fitted, whatever the arcs determine (another fit's, to compare
        like with like) [-].
    """

    def __init__(self, arcs, radius, shared, drop=(), columns=None):
        self.arcs, self.radius, self.shared = arcs, radius, list(shared)
        self.masks = [a.mask for a in arcs]
        self.pos = [tuple(p[m] for p in a.positions(radius)) for a, m in
                    zip(arcs, self.masks, strict=True)]
        self.centres = [(0.0, 0.0)] * len(arcs)  # about which the axes reverse
        self.tail = None  # the reversals' tails' (decay, shape), None for none
        self.tail_spread = None  # the columns' moves over the tails that fit as well
        self.tail_interval = None  # the time constants that fit as well
        self.tail_family = ()  # the fits over a transient lasting past the window
        self.widths = ((0.0, float("nan")),) * 2  # the backlashes' take-up, and its +-
        self.lost = (0.0, 0.0)  # the backlashes the take-up's travel is read with
        self._built, self._less = {}, {}  # :meth:`_base`, :meth:`_less_remainder`
        A = self.matrix(0.0, (None, None))
        # each circle's radius and centre first, where the arc determines them: every
        # set-up has a centre offset, and a term that stood in for it (a bow, a
        # squareness over a part of the circle) would read it as an error of the machine
        own = np.arange(3 * len(arcs))
        sure = own[determined(A[:, own], protect=own[::3])]
        self.keep = drop_twins(A, determined(A, protect=sure), protect=sure)
        names = column_names(len(arcs), self.shared)
        self.keep[[names.index(n) for n in drop]] = False
        if columns is not None:
            self.keep = np.isin(names, list(columns))

    def reversals_at(self, mu) -> None:
        """Leave out each reversal's transient from where the axes reverse with the servo
        mismatch ``mu`` (:meth:`Arc.mask_for`) [rad]."""
        self.masks = [a.mask_for(mu) for a in self.arcs]
        self.pos = [tuple(p[m] for p in a.positions(self.radius)) for a, m in
                    zip(self.arcs, self.masks, strict=True)]
        self._built = {}  # of the samples fitted before

    def matrix(self, mu, waves):
        """Design matrix over the fitted samples of every arc [m/unit]."""
        blocks = []
        for i, a in enumerate(self.arcs):
            angle, base = self._base(i, mu, False)
            blocks.append(with_columns(base, a, i, len(self.arcs), mu, waves, angle,
                                       self.tail))
        return np.vstack(blocks)

    def _base(self, i, mu, whole):
        """``(angle, base columns...)`` of arc ``i`` over its fitted samples, or over all
        of them where ``whole`` (:func:`.circle_design.base_columns`), built once for the
        many solutions of a search, which change the cyclic errors and tails alone; kept
        by the exact bits of what they are built with [rad, ...]."""
        take_up = self.take_up
        key = (i, whole, *map(_bits, (mu, *self.centres[i], *take_up, *take_up.lost)))
        if key not in self._built:
            if len(self._built) >= 4 * len(self.arcs):
                self._built.clear()
            a = self.arcs[i]
            angle, pos = ((a.angle, a.positions(self.radius)) if whole else
                          (a.angle[self.masks[i]], self.pos[i]))
            self._built[key] = (angle, base_columns(a, i, len(self.arcs), self.radius,
                                                    self.shared, mu, angle, pos,
                                                    self.centres[i], take_up))
        return self._built[key]

    @property
    def take_up(self) -> Widths:
        """Each axis' take-up width and lost motion (:attr:`TermFit.widths`, ``lost``) [m]."""
        return Widths((w for w, _ in self.widths), self.lost)

    def rest(self, mu, waves, coef):
        """Per arc, what the terms ``coef`` leave over all its samples, the reversals'
        transients too [m]."""
        out = []
        for i, a in enumerate(self.arcs):
            angle, base = self._base(i, mu, True)
            out.append(self._less_remainder(i, mu)
                       - with_columns(base, a, i, len(self.arcs), mu, waves, angle,
                                      self.tail) @ np.nan_to_num(coef))
        return out

    def centres_of(self, coef) -> list:
        """Each arc's fitted centre offset, 0 where it is not determined [m]."""
        return [(float(x), float(y)) for _, x, y in
                np.nan_to_num(coef[:3 * len(self.arcs)]).reshape(-1, 3)]

    def data(self, mu):
        """The fitted samples' radial error less the servo mismatch's remainder [m]."""
        return np.concatenate([self._less_remainder(i, mu)[m]
                               for i, m in enumerate(self.masks)])

    def _less_remainder(self, i, mu):
        """Arc ``i``'s radial error less the servo mismatch's remainder, over all its
        samples, worked out once per mismatch ``mu`` [m]."""
        key = (i, _bits(mu))
        if key not in self._less:
            if len(self._less) >= 4 * len(self.arcs):
                self._less.clear()
            a = self.arcs[i]
            self._less[key] = a.e - servo_remainder(a.angle, a.s, self.radius, a.ratio * mu)
        return self._less[key]

    def solve(self, mu, waves, basis=True):
        """Coefficients (NaN where undetermined) [SI], residual [m] and an orthonormal
        basis of the columns fitted (None unless ``basis``: a factorisation of its own,
        which most solutions do not use) [-]."""
        A, y = self.matrix(mu, waves), self.data(mu)
        keep = np.r_[self.keep, np.ones(A.shape[1] - self.keep.size, bool)]
        fitted = A[:, keep]
        c = np.linalg.lstsq(fitted, y, rcond=None)[0]
        coef = np.full(A.shape[1], np.nan)
        coef[keep] = c
        if not basis:
            return coef, y - fitted @ c, None
        q, r = np.linalg.qr(fitted)
        return coef, y - fitted @ c, q[:, np.abs(np.diag(r)) > 1e-12 * np.abs(r).max()]

    def unseen_columns(self, names, mu):
        """Columns of the terms ``names``, fitted or not, over the fitted samples of every
        arc [m/unit]."""
        n = len(self.arcs)
        return np.vstack([design(a, i, n, self.radius, list(names), mu, (None, None),
                                 a.angle[m], p, c)[:, 3 * n:]
                          for i, (a, m, p, c) in enumerate(zip(
                              self.arcs, self.masks, self.pos, self.centres, strict=True))])

    def mu_of(self, coef):
        """The servo mismatch angle of a solution; 0 where it is not fitted [rad]."""
        return (float(np.nan_to_num(coef[3 * len(self.arcs) + self.shared.index("servo_angle")]))
                if "servo_angle" in self.shared else 0.0)


def _bits(x) -> str:
    """``x``'s exact bits, as a key that tells -0.0 from 0.0 [-]."""
    return float(x).hex()


def fit_terms(arcs, radius, shared, cyclic=True, drop=(), waves=None,
              columns=None, unseen=(), tail=None) -> TermFit:
    """Fit the terms ``shared`` and each arc's radius and centre to the arcs.

    Parameters
    ----------
    arcs : list of Arc
        The circles or arcs [-].
    radius : float
        Nominal radius [m].
    shared : sequence of str
        Terms common to the arcs (:func:`.circle_model.term_columns`) [-].
    cyclic : bool
        Search for a cyclic error of each axis [-].
    drop : sequence of str
        Columns left out of the fit (``centre_X_0``, a shared term) [-].
    waves : tuple, optional
        The wavenumbers of the cyclic errors to fit, not searched for (None for none)
        [1/m].
    columns : sequence of str, optional
        The columns to fit, whatever the arcs determine (:class:`FitProblem`) [-].
    unseen : sequence of str
        Terms not among ``shared`` whose effect on the fitted ones is wanted all the same
        (:attr:`TermFit.aliases`): lateral play, which one direction does not fit [-].
    tail : tuple or str, optional
        ``(decay, shape)`` of the reversals' tails to fit (:mod:`.circle_reversal_tail`),
        ``"search"`` to search for them, None for none [rad, -].
    """
    pb = FitProblem(arcs, radius, shared, drop, columns)
    coef = pb.solve(0.0, (None, None), basis=False)[0]
    # the axes' reversals where the first fit puts them: the servo mismatch, and the
    # centre each circle runs about
    mu, pb.centres = pb.mu_of(coef), pb.centres_of(coef)
    if mu:
        pb.reversals_at(mu)
        coef = pb.solve(mu, (None, None), basis=False)[0]
        mu, pb.centres = pb.mu_of(coef), pb.centres_of(coef)
    periods, search = (), isinstance(tail, str)
    # the tails before the cyclic search, which would take them for cyclic errors, and
    # again with the cyclic errors it finds
    pb.tail = search_tail(pb, mu, (None, None)) if search else tail
    if waves is None and cyclic:
        periods = search_periods(pb)
        waves = search_cyclic(pb, mu, periods)
    waves = (None, None) if waves is None else waves
    if search and any(k is not None for k in waves):  # a transient that lingers still does
        pb.tail = (lingering if pb.tail_family else search_tail)(pb, mu, waves)
    coef = pb.solve(mu, waves, basis=False)[0]
    mu, pb.centres = pb.mu_of(coef), pb.centres_of(coef)
    if periods and any(k is not None for k in waves):
        waves = refine_waves(pb, mu, waves, periods)
        coef = pb.solve(mu, waves, basis=False)[0]
        mu, pb.centres = pb.mu_of(coef), pb.centres_of(coef)
    pb.widths = search_widths(pb, mu, waves, coef)
    return _finished(pb, mu, waves, unseen, periods)


def _finished(pb, mu, waves, unseen, periods) -> TermFit:
    """The fit of ``pb`` with its reversals and cyclic errors placed, its aliases and
    covariances worked out [-]."""
    coef, res, _ = pb.solve(mu, waves, basis=False)
    names = column_names(len(pb.arcs), pb.shared, waves, pb.tail)
    A = pb.matrix(mu, waves)
    extra = dict(zip(unseen, pb.unseen_columns(unseen, mu).T, strict=True)) if unseen else {}
    kept = np.isfinite(coef)
    cov = np.full((coef.size, coef.size), np.nan)
    cov[np.ix_(kept, kept)] = coef_covariance(A[:, kept], res, [m.sum() for m in pb.masks])
    spread = {} if pb.tail_spread is None else {  # of the columns before the tails'
        k: float(v) for k, v in zip(names, pb.tail_spread, strict=False) if v}
    return TermFit(names, coef, tuple(waves), mu, float(np.sqrt(np.mean(res**2))),
                   tuple(pb.centres), alias_slopes(A, kept, names, extra), periods, cov,
                   pb.tail, spread, pb.tail_interval, pb.widths, pb.tail_family, pb.lost,
                   wave_sigma(pb, waves, names, A, coef, res))

