"""A rigid axis with friction under a discrete servo, and its inverse dynamic
identification (IDIM-LS, :mod:`studies.rigidaxis.idim`), as the EMPS benchmark poses them
(../shared/data/emps).

This is not the five-inertia feed axis that :mod:`tcpmm.ident` identifies from servo
sweeps: one body, the force known from the drive, the friction fitted in the time domain.
Only the EMPS study (``studies/emps/``) uses it, so it lives with the studies, outside
the installed package; its compiled kernel (:mod:`studies.rigidaxis.simulator`) calls the
package's contact functions, so it steps friction as the feed-axis simulator does.
"""

from .idim import friction_from_idim, idim_ls
from .simulator import (
    TABLEAUS,
    DiscreteServo,
    RigidAxis,
    RigidServoResult,
    simulate_rigid_servo,
)

__all__ = ["TABLEAUS", "DiscreteServo", "RigidAxis", "RigidServoResult", "friction_from_idim",
           "idim_ls", "simulate_rigid_servo"]
