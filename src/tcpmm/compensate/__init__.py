"""From prediction to correction: a position command pre-compensated on the identified model
so that the predicted TCP follows the programmed path.

:func:`compensate` learns the correction on the model (:mod:`.learning`), within the axes'
limits (:mod:`.bounds`); :func:`robust_factors` scales it back where draws of the model from
its uncertainty cannot guarantee an improvement (:mod:`.robust`); :func:`predicted_scores`
gives the figures before and after (:mod:`.scores`); :func:`combined_compensation` learns
the correction with the controller's friction pulse and feed-forward applied
(:mod:`.combined`).
"""

from .bounds import AxisBounds, machine_bounds
from .combined import combined_compensation
from .learning import compensate
from .outcome import Compensation
from .robust import robust_factors
from .scores import predicted_scores, runs_before_after

__all__ = ["AxisBounds", "Compensation", "combined_compensation", "compensate",
           "machine_bounds", "predicted_scores", "robust_factors", "runs_before_after"]
