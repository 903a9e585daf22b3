"""Rational transfer functions fitted to frequency responses: the fit of given orders
(:mod:`~tcpmm.ident.lti.tffit`, on the variable-projection core of
:mod:`~tcpmm.ident.lti._tfcore`, its result in :mod:`~tcpmm.ident.lti.tfresult`), the choice
of orders (:mod:`~tcpmm.ident.lti.tforder`), the fit of a measured FRF file with its order chosen
(:mod:`~tcpmm.ident.lti.frffit`, the noise of its bins in :mod:`~tcpmm.ident.lti.frfnoise`),
the standard deviations of a fit's modes, poles, delay and gain
(:mod:`~tcpmm.ident.lti.tfsd`) and of its zeros (:mod:`~tcpmm.ident.lti.zerosd`), a
delay held checked against the data (:mod:`~tcpmm.ident.lti.delayheld`), and the
goodness-of-fit measures (:mod:`~tcpmm.ident.lti.goodness`)."""

from .frffit import DAMPING_FLOOR, FRFFit, fit_frf, noise_level
from .goodness import fit_percent, rel_error
from .tffit import TFFit, fit_tf
from .tforder import suggest_order
from .tfsd import TFDeviations, tf_deviations

__all__ = ["DAMPING_FLOOR", "FRFFit", "TFDeviations", "TFFit", "fit_frf", "fit_percent",
           "fit_tf", "noise_level", "rel_error", "suggest_order", "tf_deviations"]
