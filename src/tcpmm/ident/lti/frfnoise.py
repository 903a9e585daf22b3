"""The noise of a measured frequency response's bins, from its coherence and from its own
roughness (see :mod:`~tcpmm.ident.lti.frffit`)."""

from __future__ import annotations

import numpy as np

__all__ = ["LONE_LEAST", "LONE_REACH", "NOISE_WINDOW", "lone_passes", "noise_level",
           "running_level"]

#: Bins of the running median of the roughness noise estimate [-].
NOISE_WINDOW = 31


def noise_level(f_hz, H, rel_std=None, window: int = NOISE_WINDOW) -> np.ndarray:
    """Relative noise per bin, from the roughness of ``H`` and its coherence error.

    Parameters
    ----------
    f_hz : array_like
        Frequencies, increasing [Hz].
    H : array_like
        Complex response [unit].
    rel_std : array_like, optional
        Random error from the coherence (see :class:`~tcpmm.ident.frf.response.FRF`) [-].
    window : int
        Bins of the running median [-].

    Returns
    -------
    ndarray
        Standard deviation of the real and of the imaginary part of ``dH / H`` [-].
    """
    H = np.asarray(H, dtype=complex)
    if H.size < 3:
        rough = np.zeros(H.size)
    else:
        d2 = np.abs(H[:-2] - 2 * H[1:-1] + H[2:]) ** 2 / (6.0 * np.abs(H[1:-1]) ** 2)
        rough = running_level(np.r_[d2[0], d2, d2[-1]], window)
    rs = np.zeros(H.size) if rel_std is None else np.asarray(rel_std, dtype=float)
    return np.maximum(np.maximum(rough, rs), 1e-6)


def running_level(e2, window: int = NOISE_WINDOW) -> np.ndarray:
    """Standard deviation of the real and of the imaginary part of a relative error per
    bin from the squared magnitudes ``e2`` of its samples [-]: the running median over
    ``window`` bins [-] of an exponential variable of mean ``2 sigma^2`` is
    ``2 ln 2 sigma^2``, and the median ignores the few bins a peak or a needle holds."""
    from scipy.ndimage import median_filter

    e2 = np.asarray(e2, dtype=float)
    med = median_filter(e2, size=min(window, e2.size), mode="nearest")
    return np.sqrt(med / (2.0 * np.log(2.0)))


#: Bins on either side of a bin that passes the coherence cut, and how many of them must
#: pass it too, for its own pass to be more than the scatter of its coherence estimate
#: (one: a bin alone over the cut is dropped, two side by side are a band) [-].
LONE_REACH, LONE_LEAST = 4, 1


def lone_passes(coherent: np.ndarray) -> np.ndarray:
    """The bins that pass the coherence cut (``coherent``) where fewer than
    :data:`LONE_LEAST` of the :data:`LONE_REACH` bins on either side do: a coherence
    estimated over few averages scatters, and one bin over the cut among bins under it is
    that scatter, not a band the sweep excited (bench E's G_T kept one bin at 1942 Hz, of
    coherence 0.51 among 0.03-0.5 and 57 times the median magnitude, which held 9 % of
    the fitted bins' sum |H|^2) [-]."""
    c = np.asarray(coherent, bool)
    padded = np.concatenate([np.zeros(LONE_REACH, int), c.astype(int),
                             np.zeros(LONE_REACH, int)])
    window = np.convolve(padded, np.ones(2 * LONE_REACH + 1, int), mode="valid")
    return c & (window - c < LONE_LEAST)
