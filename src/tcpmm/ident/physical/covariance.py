"""What a bounded least-squares fit of log-parameters knows of its own accuracy: which
parameters it holds at a bound, and the standard deviations and correlations of the
others, from its Jacobian."""

from __future__ import annotations

import numpy as np

__all__ = ["AT_BOUND_LOG", "BLIND_COLUMN", "held_at_bound", "log_covariance"]

#: Distance in the logarithm within which a parameter counts as held at a bound of its
#: fit: ``least_squares``' own mask leaves out parameters that end within the solver's
#: tolerance of a bound without touching it [-].
AT_BOUND_LOG = 1e-6
#: Norm of a parameter's Jacobian column, relative to the largest, under which the
#: residual does not move with it: its direction is in the null space of the Jacobian,
#: where the pseudo-inverse gives a deviation of 0 instead of an unbounded one [-].
BLIND_COLUMN = 1e-6


def held_at_bound(r) -> np.ndarray:
    """Which parameters of the ``least_squares`` result ``r`` are held at a bound: its
    active mask, or within :data:`AT_BOUND_LOG` of the bounds it carries (``r.bounds``,
    where the fit set them) [-]."""
    at = np.asarray(getattr(r, "active_mask", np.zeros(r.x.size))) != 0
    bounds = getattr(r, "bounds", None)
    if bounds is not None:
        lo, hi = (np.asarray(b, dtype=float) for b in bounds)
        at |= (r.x - lo < AT_BOUND_LOG) | (hi - r.x < AT_BOUND_LOG)
    return at


def log_covariance(r):
    """Standard deviations [-] and correlation matrix [-] of the log-parameters from the
    Jacobian of a ``least_squares`` result, the residual variance from its cost; ``inf``
    for a parameter the residual does not move (:data:`BLIND_COLUMN`)."""
    J = r.jac
    dof = max(1, J.shape[0] - J.shape[1])
    s2 = 2 * r.cost / dof
    try:
        cov = np.linalg.pinv(J.T @ J) * s2
    except np.linalg.LinAlgError:
        cov = np.full((J.shape[1], J.shape[1]), np.inf)
    sd_log = np.sqrt(np.clip(np.diag(cov), 0, None))
    corr = cov / np.outer(sd_log, sd_log).clip(1e-300)
    col = np.linalg.norm(J, axis=0)
    return np.where(col <= BLIND_COLUMN * col.max(initial=0.0), np.inf, sd_log), corr
