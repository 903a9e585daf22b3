"""The pair of wavenumbers of the two axes' cyclic errors, chosen together
(:mod:`.circle_cyclic` finds each axis' candidates): the pair whose four columns, fitted
beside the circle's terms, leave the least sum of squares.

Each axis searched alone, beside the other's error fitted at the wavenumber found so far,
can settle beside its own: over few periods along the travel a sine of X's position and
one of Y's are much alike, and a period found beside the other's, off, is off too. Pitch
errors of 0.8 um at 18 mm on X and 1.0 um at 22 mm on Y on R 35 mm, noise-free, read 0.62
um at 17.43 mm and 1.00 um at 21.06 mm, and a scale mismatch of -21 ppm that was not there,
however often each axis was searched again beside the other. Every pair of the axes'
candidates is fitted together, and the best few refined over both wavenumbers at once;
whether the pair found is one of the axes' positions is :mod:`.circle_cyclic`'s test.
"""

from __future__ import annotations

import numpy as np

#: The pairs of candidates refined over both wavenumbers, those of least sum of squares
#: first [-]: a candidate's grid point can fall beside its optimum and fit worse than a
#: pair of another's, which refining lifts above it.
PAIRS_REFINED = 3
#: Wavenumbers on either side of the middle of each axis' refinement grid [-]
HALF_POINTS = 5
#: Levels of the refinement: each narrows the grid to one of its steps about the best
#: point, a fifth of its width, so five take a grid step of the scan to some 6e-4 of one
#: [-].
LEVELS = 5


def pair_power(pos, ws, resid, basis):
    """``power(kx, ky)``: for each pair of a wavenumber of ``kx`` for X and one of ``ky``
    for Y [1/m], the drop of the sum of squares of ``resid`` that the sine and cosine
    columns of both axes bring together beside a fit whose columns span the orthonormal
    ``basis``: that fit's residual less that of the fit that holds both cyclic errors
    [m^2].

    Parameters
    ----------
    pos : sequence of ndarray
        Position of X and of Y at the fitted samples [m].
    ws : sequence of ndarray
        How X and Y are seen along the radius at those samples
        (:func:`.circle_model.radial_weights`) [-].
    resid : ndarray
        Residual of the fit without the cyclic errors [m].
    basis : ndarray
        Orthonormal basis of that fit's columns [-].
    """
    r = resid - basis @ (basis.T @ resid)

    def columns(ax, ks):
        # sine and cosine of each wavenumber side by side, and their parts in the basis
        a = ws[ax][:, None, None] * np.stack(_sin_cos(pos[ax], ks), axis=2)
        a = a.reshape(pos[ax].size, -1)
        return a, basis.T @ a

    def power(kx, ky):
        # the columns less their parts in the basis are never formed: their products
        # are those of the columns less those of their parts, and the residual has none
        (ax, bx), (ay, by) = columns(0, np.atleast_1d(kx)), columns(1, np.atleast_1d(ky))
        mx, my = ax.shape[1] // 2, ay.shape[1] // 2
        gram = np.empty((mx, my, 4, 4))
        gram[..., :2, :2] = _blocks(ax.T @ ax - bx.T @ bx, mx)[:, None]
        gram[..., 2:, 2:] = _blocks(ay.T @ ay - by.T @ by, my)[None, :]
        cross = (ax.T @ ay - bx.T @ by).reshape(mx, 2, my, 2).transpose(0, 2, 1, 3)
        gram[..., :2, 2:], gram[..., 2:, :2] = cross, cross.swapaxes(-1, -2)
        b = np.concatenate([np.broadcast_to((r @ ax).reshape(mx, 1, 2), (mx, my, 2)),
                            np.broadcast_to((r @ ay).reshape(1, my, 2), (mx, my, 2))], -1)
        # the pseudo-inverse drops what the columns do not determine, as the fit's own
        # rank does (:meth:`.circle_fit.FitProblem.solve`)
        inv = np.linalg.pinv(gram, rcond=1e-12)
        return np.einsum("...i,...ij,...j->...", b, inv, b)

    return power


def _sin_cos(pos, ks):
    """``sin`` and ``cos`` of ``2 pi k pos``, a column for each wavenumber of ``ks``
    [1/m]: where they are evenly spaced, each after the first by the angle sum, a complex
    product that costs a fraction of a sine and a cosine per sample and wavenumber (the
    refinement's grids, over the hundred thousand samples of a large circle) [-]."""
    d = np.diff(ks)
    if d.size == 0 or np.ptp(d) > 1e-9 * abs(d[0]):  # one alone, or clipped at the band
        phase = 2 * np.pi * np.multiply.outer(pos, ks)
        return np.sin(phase), np.cos(phase)
    z = np.empty((ks.size, pos.size), complex)
    z[0], turn = np.exp(2j * np.pi * ks[0] * pos), np.exp(2j * np.pi * d[0] * pos)
    for j in range(1, ks.size):
        np.multiply(z[j - 1], turn, out=z[j])
    return z.imag.T, z.real.T


def _blocks(gram, m):
    """The ``m`` 2x2 blocks on the diagonal of ``gram``, a wavenumber's sine and cosine
    against each other [-]."""
    return np.einsum("iaib->iab", gram.reshape(m, 2, m, 2))


def best_pair(power, candidates, width, band) -> tuple:
    """The wavenumbers of X's and Y's cyclic errors [1/m] that ``power``
    (:func:`pair_power`) finds most for: every pair of the ``candidates`` of each axis
    [1/m], the :data:`PAIRS_REFINED` best of them each refined over both wavenumbers
    within ``width`` [1/m] (:func:`refined_pair`), and the best of those.

    Parameters
    ----------
    power : callable
        :func:`pair_power`'s function of the wavenumbers of X and of Y [m^2].
    candidates : sequence of sequence of float
        Each axis' candidate wavenumbers [1/m].
    width : float
        How far on either side each is refined [1/m].
    band : tuple
        The lowest and the highest wavenumber searched [1/m].
    """
    kx, ky = (np.unique(np.asarray(c, float)) for c in candidates)
    p = power(kx, ky)
    order = np.argsort(p, axis=None)[::-1][:PAIRS_REFINED]
    # each on the widest grid, and the best of them on the finer ones: within two fifths
    # of the scan's grid step of its optimum, a pair ranks as it does refined, and the
    # finer grids, over every sample, cost most
    found = [refined_pair(power, (kx[i], ky[j]), width, band, 1)
             for i, j in zip(*np.unravel_index(order, p.shape), strict=True)]
    return refined_pair(power, max(found)[1], width / HALF_POINTS, band, LEVELS - 1)[1]


def refined_pair(power, ks, width, band, levels) -> tuple:
    """``(power, (kx, ky))``: the pair of wavenumbers of most ``power`` near ``ks`` [m^2,
    1/m], on a grid of both within ``width`` either side, then a fifth of that about the
    best, ``levels`` times; within the ``band`` (lowest, highest), as a peak at its edge
    may not leave it [1/m].

    Parameters
    ----------
    power : callable
        :func:`pair_power`'s function of the wavenumbers of X and of Y [m^2].
    ks : tuple
        The wavenumbers of X and of Y to start from [1/m].
    width : float
        How far on either side of them the first grid reaches [1/m].
    band : tuple
        The lowest and the highest wavenumber searched [1/m].
    levels : int
        Grids, each narrower than the last; one at least [-].
    """
    (kx, ky), best = ks, float("nan")
    offsets = np.linspace(-1.0, 1.0, 2 * HALF_POINTS + 1)  # the middle one the best so far
    for _ in range(levels):
        gx, gy = (np.clip(k + width * offsets, *band) for k in (kx, ky))
        p = power(gx, gy)
        i, j = np.unravel_index(np.argmax(p), p.shape)
        best, kx, ky = float(p[i, j]), float(gx[i]), float(gy[j])
        width /= HALF_POINTS
    return best, (kx, ky)
