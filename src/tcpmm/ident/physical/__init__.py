"""The physical (grey-box) fit of an axis: the five-inertia parameters fitted jointly to
G_M, G_T and G_tcp (:mod:`~tcpmm.ident.physical.greybox`; the model's FRFs in
:mod:`~tcpmm.ident.physical.axisfrfs`, the binned data in
:mod:`~tcpmm.ident.physical.fitdata`) with an analytic Jacobian
(:mod:`~tcpmm.ident.physical.jacobian`) from starts built from the data
(:mod:`~tcpmm.ident.physical.starts`); the bed and TCP structure from G_tcp alone
(:mod:`~tcpmm.ident.physical.structure`); the model file's uncertainty block
(:mod:`~tcpmm.ident.physical.uncertainty`); and the servo loop's timing read from the
sweep (:mod:`~tcpmm.ident.physical.loop_timing`)."""

from .axisfrfs import model_frfs, nut_path
from .fitdata import FRFData
from .greybox import FITTED, PhysicalFit, SweepPlay, fit_physical
from .jacobian import PARAMS, log_sensitivities, residual_jacobian
from .loop_timing import (
    COMPUTATION_DELAY,
    LoopTiming,
    identify_loop_timing,
    sampled_in_step,
)
from .loop_warnings import sweep_timing
from .starts import guesses_from_tf, initial_guesses, j_total_from_g_m
from .structure import STRUCTURE, fit_structure
from .uncertainty import axis_uncertainty

__all__ = ["COMPUTATION_DELAY", "FITTED", "PARAMS", "STRUCTURE", "FRFData", "LoopTiming",
           "PhysicalFit", "SweepPlay", "axis_uncertainty", "fit_physical", "fit_structure",
           "guesses_from_tf", "identify_loop_timing", "initial_guesses", "j_total_from_g_m",
           "log_sensitivities", "model_frfs", "nut_path", "residual_jacobian",
           "sampled_in_step", "sweep_timing"]
