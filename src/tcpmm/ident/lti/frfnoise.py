"""The noise of a measured frequency response's bins, from its coherence and from its own
roughness (see :mod:`~tcpmm.ident.lti.frffit`)."""

from __future__ import annotations

import numpy as np

__all__ = ["NOISE_WINDOW", "noise_level"]

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
    from scipy.ndimage import median_filter

    H = np.asarray(H, dtype=complex)
    if H.size < 3:
        rough = np.zeros(H.size)
    else:
        d2 = np.abs(H[:-2] - 2 * H[1:-1] + H[2:]) ** 2 / (6.0 * np.abs(H[1:-1]) ** 2)
        d2 = np.r_[d2[0], d2, d2[-1]]
        med = median_filter(d2, size=min(window, d2.size), mode="nearest")
        rough = np.sqrt(med / (2.0 * np.log(2.0)))
    rs = np.zeros(H.size) if rel_std is None else np.asarray(rel_std, dtype=float)
    return np.maximum(np.maximum(rough, rs), 1e-6)
