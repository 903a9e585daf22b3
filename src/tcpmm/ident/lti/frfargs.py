"""The arguments of :func:`tcpmm.ident.lti.frffit.fit_frf`, checked by name before the
fit: a delay of -1 s or a largest pole count of 0 left to the fit ends in "too few bins
to fit any order; widen the band", which sends the user to the band."""

from __future__ import annotations

from ..._validate import count, instance_of, nonnegative_number
from ...errors import InputError
from ...frfdata import FRF


def checked_fit_args(frf, poles, delay_s, max_poles, min_coherence):
    """``(poles, delay_s, max_poles)`` as the fit takes them, or an :class:`InputError`
    naming the argument: ``frf`` an :class:`~tcpmm.frfdata.FRF`, ``poles`` ``"auto"`` or a
    whole number, ``delay_s`` None, ``"fit"`` or a time of 0 or more,
    ``max_poles`` a whole number of at least 1, ``min_coherence`` within [0, 1]
    [-, s, -].

    Parameters
    ----------
    frf, poles, delay_s, max_poles, min_coherence
        As for :func:`~tcpmm.ident.lti.frffit.fit_frf` [-], [-], [s], [-], [-].
    """
    instance_of("frf", frf, FRF, "a measured response (tcpmm.read_frf(PATH))")
    if poles != "auto":
        poles = count("poles", poles, 0)
    if delay_s is not None and delay_s != "fit":
        delay_s = nonnegative_number("delay_s (None, 'fit' or a time)", delay_s, "s")
    max_poles = count("max_poles", max_poles, 1)
    c = nonnegative_number("min_coherence", min_coherence, "-")
    if c > 1.0:
        raise InputError(f"min_coherence must be within 0 and 1, got {min_coherence!r}")
    return poles, delay_s, max_poles
