"""The cyclic error of each axis (a screw's pitch error, say) in the residual of a circle
fit: its period is found by a scan (the three highest peaks on the grid each refined), the
stronger axis first, then the other with it fitted, then each again over all periods with
the other fitted, and where both have one the pair of least residual among their peaks,
the two refined at once (:mod:`.circle_cyclic_pair`). An axis' cyclic error counts when it
lowers the sum of squares by 30 noise variances, the noise taken from successive
differences of what the fit leaves without cyclic errors, and when it is an error of the
axis' position: the same where the axis runs towards the end of its travel as where it
runs back from it. A period the fit finds only after the reversals (the structure ringing
once the friction has flipped, or a reversal's slow tail) differs between the two by more
than a fifth of its amplitude, and is no cyclic error: a screw's pitch error does not know
which way the axis turned last. Nor is one smaller than what the fit leaves unexplained: a
residual that large is structured (a reversal's tails, a lag the terms do not model) and
holds periods whose halves agree. Where what it leaves is mostly the sensor's noise, which
holds no periods, the amplitude need only exceed its part beyond the noise. Periods run
from a third of the diameter (:data:`MIN_PERIODS`) down to :func:`shortest_period`: over
fewer than three periods a sine of the position is mostly the circle's own terms.
"""

from __future__ import annotations

import numpy as np

from .circle_cyclic_pair import best_pair, pair_power, refined_pair
from .circle_model import angle_step, cyclic_columns, radial_weights

#: fewest periods of a cyclic error over the circle's diameter: over fewer, a sine of the
#: axis' position is mostly the circle's own terms (its centre, an ellipse, a bow), and a
#: period of the radius had taken a reversal's tails for 43 um of pitch error [-]
MIN_PERIODS = 3.0
#: The shortest period searched, in the tool's largest steps along the path [-]: a sine of
#: the axis' position is a column of the fit whatever its period, and one shorter than the
#: sampling resolves in time is still resolved where the axis moves slowly, towards its
#: reversals (at F10000 on R 35 mm and 1 kHz, a pitch error of 1.5 mm and 3 um went
#: unsearched below ten steps and read as -2.5 um of backlash and -10 ppm of scale
#: mismatch); below two steps it is resolved over too few degrees to stand out of noise.
MIN_STEPS = 2.0
#: Periods down to this length are searched at any feed [m], and down to ten steps where
#: those are shorter: the scan's cost grows with the periods it holds over the diameter,
#: and a circle sampled that finely (F1800 at 1 kHz: 0.3 mm) resolves them in time.
SHORT_PERIOD_M = 0.5e-3


def shortest_period(step: float) -> float:
    """The shortest period of a cyclic error searched, for the tool's largest step along
    the path ``step`` [m]: :data:`MIN_STEPS` steps, but no shorter than the lesser of
    :data:`SHORT_PERIOD_M` and ten steps [m]."""
    return max(MIN_STEPS * step, min(SHORT_PERIOD_M, 10.0 * step))


def search_periods(pb) -> tuple:
    """The longest and the shortest period of a cyclic error searched over the arcs of
    ``pb``: a third of the diameter (:data:`MIN_PERIODS`), and :func:`shortest_period` of
    the tool's largest step along the path [m]."""
    step = pb.radius * max(angle_step(a.angle) for a in pb.arcs)
    return 2.0 * pb.radius / MIN_PERIODS, shortest_period(step)


def _scan(pos, w, resid, basis, radius, periods):
    """``(power, wavenumber)`` of the three strongest cyclic errors (strongest first)
    of an axis at ``pos`` seen along the radius by ``w`` in the residual of a fit whose
    columns span the orthonormal ``basis``: the drop of the sum of squares that adding it
    to that fit brings [m^2] and its wavenumber [1/m], searched over the ``periods``
    from the longest to the shortest (:func:`search_periods`) [m]."""
    lo, hi = 1.0 / periods[0], 1.0 / periods[1]
    step = 1.0 / (4.0 * radius)  # a quarter of the peak's width over the diameter

    weighted = _weighted(w, resid, basis)  # the grid's and the refinement's alike
    power = _power_of(pos, w, resid, basis, weighted)
    ks = np.arange(lo, hi, step)
    if ks.size == 0:
        return [(0.0, None)]
    p = _grid_power(pos, w, resid, basis, ks, weighted)
    # the grid can fall beside a peak and lower it under a smaller one: the three highest
    # peaks on the grid are each refined, and the highest after refining is taken
    peaks = np.flatnonzero((p >= np.r_[-np.inf, p[:-1]]) & (p >= np.r_[p[1:], -np.inf]))
    found = []
    for k in ks[peaks[np.argsort(p[peaks])[::-1][:3]]]:
        k = _refined(power, k, step, (lo, hi), 3)
        found.append((float(power(np.array([k]))[0]), k))
    return sorted(found, reverse=True)


def _refined(power, k, width, band, levels):
    """The wavenumber of most ``power`` near ``k`` [1/m]: 21 points within ``width`` either
    side, then a tenth of that about the best, ``levels`` times; within the ``band``
    (lowest, highest), as a peak at its edge may not leave it [1/m]."""
    for _ in range(levels):
        fine = np.clip(np.linspace(k - width, k + width, 21), *band)
        k, width = fine[np.argmax(power(fine))], width / 10.0
    return k


def _samples(pb, mu):
    """The fitted samples of ``pb``'s arcs: their angle, each axis' position, and how
    each axis is seen along the radius under the servo mismatch ``mu``
    (:func:`.circle_model.radial_weights`) [rad, m, -]."""
    ang = np.concatenate([a.angle[m] for a, m in zip(pb.arcs, pb.masks, strict=True)])
    pos = [np.concatenate([p[axis] for p in pb.pos]) for axis in (0, 1)]
    ws = [radial_weights(a.angle[m], a.s, a.ratio, mu)
          for a, m in zip(pb.arcs, pb.masks, strict=True)]
    return ang, pos, tuple(np.concatenate([w[axis] for w in ws]) for axis in (0, 1))


def _power_of(pos, w, resid, basis, weighted=None):
    """``power(ks)``: for each wavenumber of ``ks`` the drop of the sum of squares of
    ``resid`` that the columns ``S = w sin(2 pi k pos)`` and ``C = w cos(...)`` bring
    beside a fit whose columns span the orthonormal ``basis`` [m^2]; ``weighted`` their
    :func:`_weighted`, where worked out already.

    The columns less their parts in the basis are never formed: S's part is ``B B^T S``, so
    ``|S - B B^T S|^2 = |S|^2 - |B^T S|^2``, and a product with the residual is one with
    the residual's own part outside the basis."""
    wb, w2, wr = weighted or _weighted(w, resid, basis)

    def power(ks):
        zc, zs = _phases(pos, ks)
        ps, pc = zs @ wb, zc @ wb
        ss = np.einsum("ij,ij,j->i", zs, zs, w2) - np.einsum("ij,ij->i", ps, ps)
        cc = np.einsum("ij,ij,j->i", zc, zc, w2) - np.einsum("ij,ij->i", pc, pc)
        sc = np.einsum("ij,ij,j->i", zs, zc, w2) - np.einsum("ij,ij->i", ps, pc)
        return _drop(ss, cc, sc, zs @ wr, zc @ wr)

    return power


def _weighted(w, resid, basis) -> tuple:
    """The basis and the squared weights as the columns see them, and the residual's part
    outside the basis, weighted: ``w B``, ``w^2``, ``w (r - B B^T r)`` [-, -, m]."""
    return w[:, None] * basis, w * w, w * (resid - basis @ (basis.T @ resid))


def _drop(ss, cc, sc, bs, bc):
    """The drop of the residual's sum of squares that a sine and a cosine column bring,
    from their projected Gram matrix ``[[ss, sc], [sc, cc]]`` and their products with the
    residual ``bs``, ``bc``; none where they are dependent [m^2]."""
    det = ss * cc - sc * sc
    return (cc * bs * bs - 2 * sc * bs * bc + ss * bc * bc) / np.where(det > 0, det, np.inf)


#: Relative error of the grid's sums over the samples (finufft's tolerance) [-]: the
#: power of a grid point is read to about this share of the residual's, far below the
#: noise floor a cyclic error must stand out of, and each peak is refined on the sums
#: themselves (:func:`_power_of`).
GRID_TOLERANCE = 1e-12


def _grid_power(pos, w, resid, basis, ks, weighted=None):
    """:func:`_power_of`'s ``power`` on the evenly spaced wavenumbers ``ks`` [1/m], each
    sum over the samples (``B^T S``, ``S^T r``, ``|S|^2`` ...) for every wavenumber at once
    by a non-uniform FFT, in ``n log n`` rather than a product of every sample with every
    wavenumber: a ballbar's R 100 mm at F1000 sampled at 1 kHz holds 38 000 samples a turn
    and 2 400 wavenumbers [m^2].

    A sine's columns span those of the position taken from any origin, so the sums are
    taken about the middle of the axis' travel, where the phases stay within the FFT's
    band; ``sin^2``, ``cos^2`` and their product come from the sums at twice the
    wavenumber. ``weighted``: as for :func:`_power_of`."""
    import finufft  # its start-up (70 ms) is paid by a circle's diagnostics alone

    u = pos - 0.5 * (pos.max() + pos.min())
    # the scan's step keeps the phases 2 pi step u within a quarter turn, as the FFT
    # needs (within three half turns); one wavenumber alone takes a step that does too
    count = ks.size
    step = ks[1] - ks[0] if count > 1 else 0.25 / max(float(np.abs(u).max()), 1e-300)
    modes = count + count % 2  # the FFT's modes run from -modes/2 to modes/2 - 1
    centre = ks[0] + (modes // 2) * step
    x = 2 * np.pi * step * u
    wb, w2, wr = weighted or _weighted(w, resid, basis)
    rows = np.vstack([wb.T, wr]) * np.exp(2j * np.pi * centre * u)
    rows = np.ascontiguousarray(rows)  # a row a sum, as the FFT takes them
    opts = {"eps": GRID_TOLERANCE, "nthreads": 1}  # one thread: the same sums every run
    f = finufft.nufft1d1(x, rows, modes, **opts)[:, :count]
    f2 = finufft.nufft1d1(2 * x, w2 * np.exp(4j * np.pi * centre * u), modes, **opts)
    f2 = f2[:count]
    ps, pc, bs, bc = f[:-1].imag, f[:-1].real, f[-1].imag, f[-1].real
    total = w2.sum()
    ss = 0.5 * (total - f2.real) - np.einsum("ji,ji->i", ps, ps)
    cc = 0.5 * (total + f2.real) - np.einsum("ji,ji->i", pc, pc)
    sc = 0.5 * f2.imag - np.einsum("ji,ji->i", ps, pc)
    return _drop(ss, cc, sc, bs, bc)


def _phases(pos, ks):
    """``cos`` and ``sin`` of ``2 pi k pos`` for wavenumbers ``ks``, one row each: where
    they are evenly spaced, the rows after the first by the angle sum, which costs a tenth
    of a sine and a cosine per sample and wavenumber; its rounding grows with the rows,
    which the scan starts afresh every 64 [-]."""
    ks = np.asarray(ks, float)
    if ks.size > 2 and np.ptp(np.diff(ks)) > 1e-9 * abs(ks[1] - ks[0]):
        # not evenly spaced (a refinement's grid clipped at the band's edge): each row
        # its own
        phase = 2 * np.pi * ks[:, None] * pos[None, :]
        return np.cos(phase), np.sin(phase)
    zc, zs = np.empty((ks.size, pos.size)), np.empty((ks.size, pos.size))
    zc[0], zs[0] = np.cos(2 * np.pi * ks[0] * pos), np.sin(2 * np.pi * ks[0] * pos)
    if ks.size > 1:
        step = 2 * np.pi * (ks[1] - ks[0]) * pos
        dc, ds, t = np.cos(step), np.sin(step), np.empty(pos.size)
        for j in range(1, ks.size):
            np.multiply(zc[j - 1], dc, out=zc[j])
            zc[j] -= np.multiply(zs[j - 1], ds, out=t)
            np.multiply(zc[j - 1], ds, out=zs[j])
            zs[j] += np.multiply(zs[j - 1], dc, out=t)
    return zc, zs


#: The least amplitude of a cyclic error reported: below any sensor's resolution [m].
MIN_AMPLITUDE_M = 0.01e-6


def _noise(res):
    """Sample noise from the successive differences of what the fit without cyclic errors
    leaves, robust to steps and spikes: the circle's own terms taken off first, whose
    slope a coarse sampling would count as noise (a servo mismatch of 1 ms at F10000 on
    R 35 mm sampled every 4 ms moves the radius by some 3 um a sample, read as 2.4 um of
    noise, and a pitch error of 0.76 um fell under the floor and read as backlash) [m]."""
    d = np.diff(res)
    return 1.4826 * np.median(np.abs(d - np.median(d))) / np.sqrt(2)


def search_cyclic(pb, mu, periods) -> tuple:
    """Wavenumber of the cyclic error of X and Y, None where none stands out (module
    docstring) [1/m].

    Parameters
    ----------
    pb : circle_fit.FitProblem
        The arcs and their fitted samples [-].
    mu : float
        Servo mismatch angle of the fit [rad].
    periods : tuple
        The longest and the shortest period searched (:func:`search_periods`) [m].
    """
    ang, pos, ws = _samples(pb, mu)
    fits = _Fits(pb, mu, periods, pos, ws)
    waves, seen = [None, None], ([], [])  # and each axis' peaks: the pair's candidates
    alone = fits.fit(waves)  # the fit without either, beside which a pair is fitted
    # the noise's floor, and an amplitude of MIN_AMPLITUDE_M's drop (N a^2 / 4): a
    # noise-free circle has no noise to stand out of, and found a period in rounding
    floor = max(30.0 * _noise(alone[0]) ** 2, ang.size * MIN_AMPLITUDE_M**2 / 4.0)
    for _ in range(2):
        found = [[(0.0, None)] if waves[ax] is not None else fits.scan(waves, ax)
                 for ax in (0, 1)]
        for ax in (0, 1):
            seen[ax].extend(k for _, k in found[ax] if k is not None)
        ax = int(np.argmax([f[0][0] for f in found]))
        if found[ax][0][0] <= floor:
            break
        waves[ax] = found[ax][0][1]
    if all(k is not None for k in waves):  # each period again, the other one fitted
        for ax in (0, 1):
            found = fits.scan(waves, ax)
            waves[ax] = found[0][1]
            seen[ax].extend(k for _, k in found if k is not None)
        # the pair of least residual among them (:mod:`.circle_cyclic_pair`) where both
        # are errors of the axes' positions; else each is tested as the scans found it
        pair = best_pair(pair_power(pos, ws, *alone), seen, 2.0 / (4.0 * pb.radius),
                         (1.0 / periods[0], 1.0 / periods[1]))
        if all(_of_position(pb, fits.without(pair, ax), ax, pair[ax]) for ax in (0, 1)):
            waves = list(pair)
    for ax in (0, 1):  # a period of the axis' position, else the next that is one, or none
        if waves[ax] is None:
            continue
        without = fits.without(waves, ax)
        if not _of_position(pb, without, ax, waves[ax]):
            waves[ax] = _first_of_position(pb, without, ax, fits.scan(waves, ax), floor)
    return tuple(waves)


class _Fits:
    """The fits and scans of one search (:func:`search_cyclic`), each worked out once: the
    search asks again for the fit beside the same cyclic errors, and for the scan of an
    axis beside the same fit."""

    def __init__(self, pb, mu, periods, pos, ws):
        self.pb, self.mu, self.periods, self.pos, self.ws = pb, mu, periods, pos, ws
        self.fits, self.scans = {}, {}

    def fit(self, waves) -> tuple:
        """Residual [m] and orthonormal basis [-] of the fit with the cyclic errors
        ``waves`` [1/m]."""
        key = tuple(waves)
        if key not in self.fits:
            self.fits[key] = tuple(self.pb.solve(self.mu, list(key))[1:])
        return self.fits[key]

    def without(self, waves, ax) -> tuple:
        """:func:`_without`: the fit with the other axis' cyclic error of ``waves`` and not
        this one's [m, -]."""
        return self.fit(_others(waves, ax))

    def scan(self, waves, ax) -> list:
        """:func:`_scan` of axis ``ax`` beside the fit :meth:`without` its cyclic error
        [m^2, 1/m]."""
        key = (ax, *_others(waves, ax))
        if key not in self.scans:
            self.scans[key] = _scan(self.pos[ax], self.ws[ax], *self.without(waves, ax),
                                    self.pb.radius, self.periods)
        return list(self.scans[key])


def refine_waves(pb, mu, waves, periods) -> tuple:
    """The wavenumbers ``waves`` found [1/m], each refined within a grid step of the scan
    beside the other's, with the servo mismatch ``mu`` [rad] and the centres of the fit
    that holds both: the scan placed them with the reversals and centres of a fit without
    them, which the cyclic errors themselves had moved (two pitch errors, of 12.0 and 7.4
    mm, read the first 11.92 mm and the backlash 0.24 um off). ``periods``: the band
    searched (:func:`search_periods`) [m]. Both at once where both axes have one
    (:mod:`.circle_cyclic_pair`): one refined beside the other's, off, is off too."""
    _, pos, ws = _samples(pb, mu)
    step, band = 1.0 / (4.0 * pb.radius), (1.0 / periods[0], 1.0 / periods[1])
    if all(k is not None for k in waves):
        power = pair_power(pos, ws, *pb.solve(mu, (None, None))[1:])
        return refined_pair(power, waves, step, band, 6)[1]
    out = list(waves)
    for ax in (0, 1):
        if out[ax] is not None:  # from the scan's grid step
            power = _power_of(pos[ax], ws[ax], *_without(pb, mu, out, ax))
            out[ax] = float(_refined(power, out[ax], step, band, 4))
    return tuple(out)


def _without(pb, mu, waves, ax) -> tuple:
    """Residual [m] and orthonormal basis [-] of the fit with the other axis' cyclic error
    and not this one's: over the whole band a scan of it sees its own (the first scan, with
    the other's unfitted, may have put the peak at a period of the other's), and the test
    of a period of it is made on it."""
    _, res, basis = pb.solve(mu, _others(waves, ax))
    return res, basis


def _others(waves, ax) -> list:
    """``waves`` with the cyclic error of axis ``ax`` left out [1/m]."""
    return [k if i != ax else None for i, k in enumerate(waves)]


def _first_of_position(pb, without, ax, found, floor):
    """The strongest of the wavenumbers ``found`` for axis ``ax`` (``(power, k)``) above
    ``floor`` whose cyclic error is one of the axis' position (:func:`_of_position`, on
    the fit ``without`` it); None if none is [1/m]."""
    for power, k in found:
        if k is not None and power > floor and _of_position(pb, without, ax, k):
            return k
    return None


#: the part of a cyclic error's amplitude by which its two halves may differ [-]
_HALVES = 0.2
#: the largest RMS of what the fit leaves beyond the noise, as a part of the noise's, under
#: which a cyclic error need stand out of that part alone, not of the noise too [-]
_SHAPE = 0.5


def _of_position(pb, without, ax, k) -> bool:
    """Whether the cyclic error of axis ``ax`` at wavenumber ``k`` [1/m] is one of its
    position: fitted, beside the fit ``without`` it (:func:`_without`), on the samples
    where the axis runs back from its nearer end (after its reversal) and on those where
    it runs towards it, the two agree
    within :data:`_HALVES` of the amplitude, and the amplitude is no less than the RMS of
    what that fit leaves, or, where that is mostly noise (its part beyond the noise under
    :data:`_SHAPE` of the noise), than that part (module docstring). An arc that holds too
    few samples of either half cannot tell, and keeps it [-]."""
    ang = np.concatenate([a.angle[m] for a, m in zip(pb.arcs, pb.masks, strict=True)])
    s = np.concatenate([np.full(int(m.sum()), a.s) for a, m in
                        zip(pb.arcs, pb.masks, strict=True)])
    pos = np.concatenate([p[ax] for p in pb.pos])
    w, vel = (np.cos(ang), -s * np.sin(ang)) if ax == 0 else (np.sin(ang), s * np.cos(ang))
    back = (pos * vel < 0).astype(float)
    res, basis = without
    S, C = cyclic_columns(pos, w, k)
    A = np.c_[S * back, C * back, S * (1 - back), C * (1 - back)]
    A = A - basis @ (basis.T @ A)
    if min(back.sum(), (1 - back).sum()) < 8 or np.linalg.matrix_rank(A) < 4:
        return True
    c, ss, *_ = np.linalg.lstsq(A, res, rcond=None)
    dof = res.size - basis.shape[1] - 4
    var = float(ss[0]) / dof if ss.size and dof > 0 else float(np.mean(res**2))
    d = np.hypot(c[0] - c[2], c[1] - c[3])
    amp = 0.5 * (np.hypot(c[0], c[1]) + np.hypot(c[2], c[3]))
    # and it stands out of what the fit leaves: a structured residual (the tails of large
    # reversals, a lag the terms do not model) holds periods its halves agree on too.
    # Where what it leaves is mostly the sensor's noise, which holds no such periods, it
    # need stand out of the structure alone: the samples' number resolves it below the
    # noise (1.5 um of pitch error under 2 um of noise went unfound and read as 1.3 um of
    # backlash). A structure of half the noise or more still holds periods of more than
    # itself (a pitch error of 60 mm that the terms take up left one of 13 mm)
    noise = _noise(res - A @ c)
    shape = np.sqrt(max(var - noise**2, 0.0))
    return bool(d <= _HALVES * amp and (amp >= np.sqrt(var)
                                        or (amp >= shape and shape <= _SHAPE * noise)))
