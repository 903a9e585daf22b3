"""The excitation of a kind for a band, as ``tcpmm excite`` asks for it."""

from __future__ import annotations

from tcpmm.errors import InputError

from .multisines import multisine
from .prbsignal import prbs_for_band
from .waveforms import MAX_SAMPLES, linear_sweep, log_sweep, positive

__all__ = ["KINDS", "design_excitation"]

#: Kinds accepted by :func:`design_excitation` and their aliases.
KINDS = {
    "linear": "linear_sweep",
    "linear_sweep": "linear_sweep",
    "log": "log_sweep",
    "log_sweep": "log_sweep",
    "multisine": "multisine",
    "prbs": "prbs",
}


#: The options each kind takes (the keyword arguments of its designer) [-].
TAKES = {"linear_sweep": {"taper_s"}, "log_sweep": {"taper_s"},
         "multisine": {"n_periods", "spectrum", "phases", "seed"}, "prbs": set()}


def design_excitation(kind, f0_hz, f1_hz, amplitude_A, duration_s, fs_hz, **options):
    """Dispatch for ``tcpmm excite KIND --band F0,F1 --amplitude-A --duration-s --fs-hz``.

    Parameters
    ----------
    kind : str
        ``linear``, ``log``, ``multisine`` or ``prbs`` (or the function names) [-].
    f0_hz : float
        Band start [Hz].
    f1_hz : float
        Band end [Hz].
    amplitude_A : float
        Peak current [A].
    duration_s : float
        Length [s].
    fs_hz : float
        Sample rate [Hz].
    **options
        Keyword options of the chosen designer (``taper_s``, ``n_periods``, ``phases``,
        ``spectrum``, ``seed``); options set to None are dropped, so a CLI can pass all
        of its flags unconditionally [-].

    Returns
    -------
    Excitation
        The signal.
    """
    name = KINDS.get(str(kind).lower().replace("-", "_"))
    if name is None:
        raise InputError(
            f"excitation kind '{kind}' unknown; use linear, log, multisine or prbs",
            column="kind",
        )
    options = {k: v for k, v in options.items() if v is not None}
    for k in options:
        if k not in TAKES[name]:
            takes = [n.removesuffix("_sweep") for n, t in TAKES.items() if k in t]
            raise InputError(f"{k} does not apply to a {kind} signal"
                             + (f"; it is an option of {' and '.join(takes)}" if takes else ""),
                             column=k)
    if not f0_hz > 0.0:
        raise InputError(f"the band starts at {f0_hz:g} Hz: an excitation reaching down to 0 Hz "
                         "is a current held, no frequency response; start it above 0 (the "
                         "lowest mode or friction regime of interest, e.g. 1 Hz)",
                         column="f0_hz")
    n = positive("duration_s", duration_s, "s") * positive("fs_hz", fs_hz, "Hz")
    if n > MAX_SAMPLES:
        raise InputError(f"{duration_s:g} s at {fs_hz:g} Hz is {n:.3g} samples; at most "
                         f"{MAX_SAMPLES:.0e} are designed at once: shorten the signal or "
                         "lower the sample rate", column="duration_s")
    if duration_s * f0_hz < 1.0 and name != "prbs":  # a PRBS says its own period
        raise InputError(f"{duration_s:g} s holds {duration_s * f0_hz:.2g} periods of the band's "
                         f"start, {f0_hz:g} Hz: no signal that short excites it; make it at "
                         f"least {1.0 / f0_hz:g} s long, or start the band higher",
                         column="duration_s")
    if name == "prbs":
        return prbs_for_band(f0_hz, f1_hz, amplitude_A, duration_s, fs_hz)
    fn = {"linear_sweep": linear_sweep, "log_sweep": log_sweep, "multisine": multisine}[name]
    return fn(f0_hz, f1_hz, amplitude_A, duration_s, fs_hz, **options)
