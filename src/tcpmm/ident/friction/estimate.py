"""Least-squares parameter estimates with their standard deviations.

``ParameterEstimate`` holds the result of a linear (IDIM-LS) or nonlinear (Stribeck
curve) least-squares fit: the values, their standard deviations, the residual and the
condition number of the problem.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["ParameterEstimate"]


@dataclass(frozen=True)
class ParameterEstimate:
    """Least-squares parameter estimates with their standard deviations.

    Parameters
    ----------
    names : tuple of str
        Parameter names [-].
    values : numpy.ndarray
        Estimates, in the units of each parameter (kg, N s/m, N, m/s) [-].
    std : numpy.ndarray
        Standard deviations, same units; ``nan`` where not estimated [-].
    relative_error : float
        ``100 ||y - y_hat|| / ||y||`` on the data used for the fit [%].
    residual_std : float
        ``sigma = ||y - y_hat|| / sqrt(N - p)`` [N].
    condition : float
        Condition number of the regressor matrix (linear fits) or of the Jacobian [-].
    n_samples : int
        Number of equations used [-].
    extra : dict
        Other settings or results (e.g. a fitted Stribeck velocity) [-].
    """

    names: tuple[str, ...]
    values: np.ndarray
    std: np.ndarray
    relative_error: float
    residual_std: float
    condition: float
    n_samples: int
    extra: dict = field(default_factory=dict)

    def __getitem__(self, name: str) -> float:
        try:
            return float(self.values[self.names.index(name)])
        except ValueError:
            raise KeyError(f"no parameter {name!r}; have {self.names}") from None

    def std_of(self, name: str) -> float:
        """Standard deviation of one parameter.

        Parameters
        ----------
        name : str
            Parameter name [-].

        Returns
        -------
        float
            Its standard deviation, in the parameter's unit [-].
        """
        return float(self.std[self.names.index(name)])

    def to_dict(self) -> dict:
        """Plain dictionary for JSON output.

        Returns
        -------
        dict
            ``{"parameters": {name: {"value", "std", "std_percent"}}, ...}`` [-].
        """
        params = {}
        for n, v, s in zip(self.names, self.values, self.std, strict=True):
            params[n] = {
                "value": float(v),
                "std": None if not np.isfinite(s) else float(s),
                "std_percent": None if not np.isfinite(s) or v == 0 else float(100.0 * s / abs(v)),
            }
        out = {
            "parameters": params,
            "relative_error_percent": float(self.relative_error),
            "residual_std": float(self.residual_std),
            "condition_number": float(self.condition),
            "n_samples": int(self.n_samples),
        }
        out.update({k: v for k, v in self.extra.items()})
        return out
