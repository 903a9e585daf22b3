"""A rigid axis with friction under a discrete servo, and its inverse dynamic
identification (IDIM-LS, :mod:`~tcpmm.rigidaxis.idim`), as the EMPS benchmark poses them
(../shared/data/emps).

This is not the five-inertia feed axis that :mod:`tcpmm.ident` identifies from servo
sweeps: one body, the force known from the drive, the friction fitted in the time domain.
It lives beside that pipeline, not in it. Its simulator, a compiled kernel, stays with the
others in :mod:`tcpmm.sim.rigid` and is exported here with the model it simulates.
"""

from ..sim.rigid import (
    TABLEAUS,
    DiscreteServo,
    RigidAxis,
    RigidServoResult,
    simulate_rigid_servo,
)
from .idim import friction_from_idim, idim_ls

__all__ = ["TABLEAUS", "DiscreteServo", "RigidAxis", "RigidServoResult", "friction_from_idim",
           "idim_ls", "simulate_rigid_servo"]
