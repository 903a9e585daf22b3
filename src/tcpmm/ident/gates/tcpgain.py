"""Gate: the gain of the TCP device against the scale.

Below the first mode the tool follows the table as one body, and the model's ``G_tcp`` is
1 there whatever its parameters. A TCP device that reads a share of the motion (its
scaling, or a cosine error of its alignment with the axis) puts the whole record off by
that share; the fit cannot follow it at the low frequencies and takes it for the
structure's dynamics above them (bench R17 with its TCP scaled by 0.9: the predicted F10000
contour error 38 um off the measured). :func:`check_tcp_gain` compares the measured
``G_tcp`` with the fitted model's in the band :data:`~.masses.MODE_MARGIN` times below the
first mode, where :func:`~.masses.check_static_gains` allows a mode's 12 % against one:
against the model, the six reference machines' axes read within 0.2 % of one
(:data:`TCP_GAIN_RANGE`), and a TCP scaled by 0.9 reads 0.899-0.900.
"""

from __future__ import annotations

import numpy as np

from .finding import Finding
from .masses import MODE_MARGIN, first_mode_hz, low_band

__all__ = ["TCP_GAIN_RANGE", "check_tcp_gain", "tcp_gain"]

#: Range of the measured over the modelled ``G_tcp`` below the first mode taken as a TCP
#: device reading the motion in full: the six reference machines depart from one by up
#: to 0.18 % (bench H's Y), 16 axes of machines of :mod:`studies.unseen` (seed 5) by up to
#: 1.2 %; 3 % is a cosine error of 14 deg [-].
TCP_GAIN_RANGE = (0.97, 1.03)


def tcp_gain(frf, model, mechanics, min_coherence: float, excitation=None):
    """``(gain, frequencies)``: the median of the measured ``G_tcp`` over the model's
    (``model(f)``) in the band :data:`~.masses.MODE_MARGIN` times below the first mode of
    ``mechanics``, and the bins it was read on; ``None`` where the band holds too few
    (:func:`~.masses.low_band`) [-, Hz]."""
    low = low_band(frf, min_coherence, first_mode_hz(mechanics) / MODE_MARGIN, excitation)
    if not np.any(low):
        return None
    f = np.asarray(frf.freq_hz, dtype=float)[low]
    return float(np.median(np.abs(np.asarray(frf.H)[low] / model(f)))), f


def check_tcp_gain(axis: str, frf, model, mechanics, source: str, min_coherence: float,
                   excitation=None) -> list[Finding]:
    """The measured ``G_tcp`` against the fitted model's below the first mode (module
    docstring).

    Parameters
    ----------
    axis : str
        Axis name [-].
    frf : FRF
        The sweep's ``G_tcp`` [-].
    model : callable
        The fitted model's ``G_tcp`` at the frequencies given [-].
    mechanics : AxisMechanics
        The identified mechanics, for their first mode [SI].
    source : str
        The sweep's file, for the message [-].
    min_coherence : float
        Bins with a lower coherence are not used [-].
    excitation : array_like, optional
        The sweep's excitation: only the bins it reaches are judged [A].
    """
    read = tcp_gain(frf, model, mechanics, min_coherence, excitation)
    if read is None:
        return []
    gain, f = read
    lo, hi = TCP_GAIN_RANGE
    if lo <= gain <= hi:
        return []
    return [Finding(axis, "gain of the TCP device against the scale", gain, "",
                    f"outside {lo:g} to {hi:g}: below the first mode the tool follows the "
                    "table as one body, where the model's G_tcp is 1 whatever its parameters",
                    f"{source}, columns tcp_mm / scale_mm, {f[0]:.3g}-{f[-1]:.3g} Hz",
                    f"check the TCP device's scaling and its alignment with the axis (a "
                    f"cosine error), or scale tcp_mm by {1.0 / gain:.4g}, and identify "
                    f"again: the fit takes the gain for the structure's dynamics")]
