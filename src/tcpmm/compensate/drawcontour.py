"""The compensated TCP's contour error to the command on each drawn machine, taken as the
figure after (:func:`.scores.contour_figures`) takes it of the model: against the program
as planned, the lag a G0 rapid carries into the cut counted. The regions' figures
(:mod:`.robust`) are judged on the delayed path, where that lag belongs to the rapid: a
square entered from a rapid read 120.9 um after on its worst draw, below the model's own
190.7 um and the machine's 190.7 um."""

from __future__ import annotations

import numpy as np

from ..result import AxisRun, Run
from .scores import contour_figures, with_program_flags


def worst_to_command(after: np.ndarray, target, reference) -> float:
    """The largest contour error to ``reference`` over the drawn machines.

    Parameters
    ----------
    after : ndarray
        TCP error per machine, axis and sample with the chosen shares, target minus TCP,
        shape (machines, axes, n); the first machine is the model as identified, the
        others its draws [m].
    target : Command
        The path the TCP is to follow, on whose samples ``after`` is [m].
    reference : Command
        The program as planned, whose contour error the figure after reports [m].

    Returns
    -------
    float
        The largest over the draws [m].
    """
    p = {a: np.asarray(v, dtype=float) for a, v in target.positions.items()}
    worst = 0.0
    for e in after[1:]:
        run = with_program_flags(Run(target.time_s, {a: AxisRun(cmd=p[a], tcp=p[a] - e[i])
                                                      for i, a in enumerate(p)}), reference)
        worst = max(worst, contour_figures(run, reference)["contour_error_um"] * 1e-6)
    return worst


def worst_entry(after: np.ndarray, comp) -> dict:
    """``{"worst_after_to_command_um": ...}`` of the robustness: :func:`worst_to_command`
    of the errors ``after`` (as :func:`worst_to_command` takes them) of ``comp``'s path,
    against its program as planned [um]."""
    return {"worst_after_to_command_um": worst_to_command(after, comp.target,
                                                          comp.reference) * 1e6}
