"""Response of a sweep from the DFT of the whole record (local polynomial method).

A Welch segment cuts a lightly damped mode's response off where it outlasts the segment,
and a sweep passes such a mode in less time than it takes to ring down: on reference
machine E's 16 Hz head mode (3.5 % damping) the segment-averaged peak of ``X_TCP / r``
came out 15 % low, its coherence fell to 0.84, and the head damping fitted to it 5-8 %
high. The whole record keeps every response together with the excitation that caused it
(peak within 1 %).

:class:`WholeRecord` estimates the response on the Welch grid by the local polynomial
method (Pintelon et al., *Mech. Syst. Signal Process.* 24 (2010) 573-595);
:func:`combine_estimates` weights it against the Welch estimate by their inverse
variances, and :func:`reduced_with_whole_record` does so for the reduced FRFs of a sweep:
each frequency rests on the estimate that is surer there, the whole record at lightly
damped modes, the segments where nonlinear distortion (a sweep that sticks at its lowest
frequencies) swells the whole record's local residual.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ._spectral import remove_trend

__all__ = ["WholeRecord", "combine_estimates", "reduced_with_whole_record"]

#: Welch bins either side of each frequency over which the local polynomial is fitted [-].
WIDTH = 2
#: ... and at most this fraction of the frequency [-].
REL_WIDTH = 0.1


class WholeRecord:
    """Local polynomial estimates of responses to one excitation.

    Around each Welch frequency, over the bins of the record's DFT within :data:`WIDTH`
    Welch bins (at most :data:`REL_WIDTH` of the frequency) either side, the output is
    fitted as ``H(f) R(f) + T(f)`` with ``H`` and ``T`` quadratic in frequency: ``H`` at
    the centre is the response; ``T`` takes up what the excitation did not cause and
    varies smoothly across the bins, such as the transient of a record that starts from
    rest. The residual gives the noise, and with it the standard deviation of ``H``.

    Parameters
    ----------
    r : numpy.ndarray
        Detrended excitation [SI].
    m : int
        Welch segment length; the grid is ``k fs / m`` [-].
    bins : numpy.ndarray of int
        Welch bin numbers ``k`` wanted [-].
    """

    #: Unknowns per window: H and T, each quadratic [-].
    N_PARAMS = 6

    def __init__(self, r: np.ndarray, m: int, bins: np.ndarray):
        # The record's own DFT grid, not a zero-padded one: padding makes the record end
        # in a jump, whose spectrum turns its phase from bin to bin and is no longer the
        # smooth term T of the method.
        R = np.fft.rfft(r)
        centre = np.asarray(bins, dtype=float) * r.size / m
        h = max(3, int(np.ceil(WIDTH * r.size / m)))
        # no wider than REL_WIDTH of the frequency, where a quadratic no longer follows
        # the response (a rigid body's 1/f^2 across +-30 % at a few hertz)
        half = np.clip(np.floor(REL_WIDTH * centre), 3, h)
        rows = np.rint(centre).astype(int)[:, None] + np.arange(-h, h + 1)[None, :]
        self.rows = np.clip(rows, 0, R.size - 1)
        offset = self.rows - centre[:, None]
        self.mask = (np.abs(offset) <= half[:, None] + 0.5).astype(float)
        d = offset / half[:, None]
        Rw = R[self.rows] * self.mask
        one = self.mask.astype(complex)
        self.K = np.stack([Rw, Rw * d, Rw * d**2, one, one * d, one * d**2], axis=-1)
        KhK = np.einsum("bri,brj->bij", self.K.conj(), self.K)
        self.inv = np.linalg.pinv(KhK, hermitian=True)
        self.dof = np.maximum(self.mask.sum(axis=1) - self.N_PARAMS, 1.0)

    def response(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Response of an output to the excitation on the Welch bins.

        Parameters
        ----------
        y : numpy.ndarray
            Detrended output, as long as the excitation [SI].

        Returns
        -------
        tuple of numpy.ndarray
            The response [SI of y per SI of r] and its standard deviation relative to its
            magnitude [-].
        """
        Y = np.fft.rfft(y)[self.rows] * self.mask
        theta = np.einsum("bij,brj,br->bi", self.inv, self.K.conj(), Y)
        e = Y - np.einsum("bri,bi->br", self.K, theta)
        var = np.sum(np.abs(e) ** 2, axis=1) / self.dof * self.inv[:, 0, 0].real
        H = theta[:, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            rel = np.sqrt(np.clip(var, 0.0, None)) / np.abs(H)
        return H, np.nan_to_num(rel, nan=np.inf, posinf=np.inf)


def combine_estimates(H_a, rel_a, H_b, rel_b):
    """Two estimates of one response, weighted by their inverse variances.

    Parameters
    ----------
    H_a, H_b : numpy.ndarray
        The estimates, on one grid [SI].
    rel_a, rel_b : numpy.ndarray
        Their standard deviations relative to their magnitudes; ``inf`` for none [-].

    Returns
    -------
    tuple of numpy.ndarray
        The weighted response [SI] and the smaller of the two relative standard
        deviations: both come from one record, so the pair is not taken for more than its
        better half [-].
    """
    wa = np.nan_to_num(1.0 / np.maximum(rel_a, 1e-12) ** 2)
    wb = np.nan_to_num(1.0 / np.maximum(rel_b, 1e-12) ** 2)
    total = wa + wb
    with np.errstate(divide="ignore", invalid="ignore"):
        H = np.where(total > 0, (wa * H_a + wb * H_b) / total, H_a)
    return H, np.minimum(rel_a, rel_b)


def reduced_with_whole_record(segments: dict, r, current, angle, scale, tcp=None) -> dict:
    """The reduced FRFs (``G_M``, ``G_T``, ``G_tcp``) from the segments, each weighed
    against the same ratio from the whole record (:func:`combine_estimates`), on the
    segments' grid and with their trend removed alike.

    The ratios are weighed, not their responses apart: apart, the two responses of a ratio
    leaned to different estimators where a sweep sticks and slips, and their ratio came out
    30-100 % off.

    Parameters
    ----------
    segments : dict of str to FRF
        The FRFs from the segments, as :func:`~tcpmm.ident.frf.response.reduced_frfs`
        gives them [SI].
    r : array_like
        The excitation [A].
    current, angle, scale : array_like
        Current command [A], motor angle [rad] and scale [m] of the record [SI].
    tcp : array_like, optional
        TCP position [m].

    Returns
    -------
    dict of str to FRF
        The same names as ``segments``, weighed [SI].
    """
    meta, f = segments["G_M"].meta, segments["G_M"].freq_hz
    order, m = meta["detrend"], meta["nperseg"]
    whole = WholeRecord(remove_trend(r, order), m, np.rint(f * m / meta["fs_hz"]).astype(int))
    (i, rel_i), (th, rel_th), (x, rel_x) = (whole.response(remove_trend(y, order))
                                            for y in (current, angle, scale))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratios = {"G_M": (th * (2j * np.pi * f) / i, np.hypot(rel_th, rel_i)),
                  "G_T": (x / th, np.hypot(rel_x, rel_th))}
        if tcp is not None:
            t, rel_t = whole.response(remove_trend(tcp, order))
            ratios["G_tcp"] = (t / x, np.hypot(rel_t, rel_x))
    out = {}
    for k, (H_w, rel_w) in ratios.items():
        H, rel = combine_estimates(segments[k].H, segments[k].rel_std, H_w, rel_w)
        out[k] = replace(segments[k], H=H, rel_std=rel)
    return out
