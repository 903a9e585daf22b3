"""LTI step: rational transfer functions of the orders the five-inertia axis needs, fitted
to the FRFs; their modes are reported and their poles and zeros seed the physical fit."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lti.tffit import fit_tf
from ..options import MIN_COHERENCE

if TYPE_CHECKING:
    from ..chain import AxisRun
    from ..options import IdentifyOptions

#: Minimal orders (numerator, denominator, integrators) of the reduced models of the
#: five-inertia axis: G_M has the drive's three modes and the rigid-body integrator, and
#: a fitted delay for the drive's hold of the current; the poles of G_T are the
#: antiresonances of G_M (motor clamped); G_tcp = (G_t - G_h)/(G_t - G_b) is 4/4.
TF_ORDERS = {"G_M": (6, 6, 1), "G_T": (2, 6, 0), "G_tcp": (4, 4, 0)}
TF_DELAY = {"G_M": "fit"}


def fit_transfer_functions(frfs: dict) -> dict:
    """Rational fits of the orders of :data:`TF_ORDERS` to the FRFs with enough coherent
    bins for them [SI]."""
    tf_fits = {}
    for k, frf in frfs.items():
        nn, nd, ni = TF_ORDERS[k]
        if (frf.coherence >= MIN_COHERENCE).sum() > 2 * (nn + nd + 2):
            tf_fits[k] = fit_tf(frf, nn, nd, n_integrators=ni, delay_s=TF_DELAY.get(k),
                                min_coherence=MIN_COHERENCE)
    return tf_fits


def fit_lti(run: AxisRun, options: IdentifyOptions) -> dict:
    """Rational transfer functions fitted to an axis's FRFs
    (:func:`fit_transfer_functions`) [SI].

    Parameters
    ----------
    run : AxisRun
        The axis with its FRFs [-].
    options : IdentifyOptions
        Not read by this step [-].
    """
    return fit_transfer_functions(run.frfs.frfs)
