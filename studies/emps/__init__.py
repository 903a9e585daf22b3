"""EMPS benchmark: identify a rigid feed axis with friction and simulate its closed loop.

The Electro-Mechanical Positioning System (EMPS, Janot, Gautier and Brunot,
nonlinearbenchmark.org) is a DC motor driving a ball-screw table in a cascade
position/velocity loop at 1 kHz. This script

1. identifies ``tau = M q'' + Fv q' + Fc sign(q') + offset`` by IDIM-LS exactly as the
   benchmark's published script (force ``gtau * vir``, position filtered by a 4th-order
   Butterworth at 100 Hz with ``filtfilt``, central differences, samples from the 50th
   on, parallel decimation by 10);
2. simulates the closed loop with the reference position ``qg`` as input (controller
   ``vir = kv (kp (qg - q) - dq)``, ``dq`` from the difference of the two-tap filtered
   position, one-sample delay, saturation at +/-10 V, force ``gtau * vir``) and reports
   the benchmark's relative errors ``100 ||meas - sim|| / ||meas||`` from the 50th sample
   on, for position, velocity and acceleration (measured ones from the filtered position)
   and force. The reference model is integrated as the benchmark integrates it
   (``Fc sign(v)`` by Dormand-Prince steps of a tenth of the sample, no rest phase), on the
   data's time base and on the published script's, and also to convergence
   (``reference_converged``: closed-form sub-steps with the rest phase);
3. improves the model step by step: actuation delay fitted in closed loop (the data show
   ``vir(k)`` is computed from ``qm(k)`` of the same sample, so the command acts within
   the sample, not one sample later), asymmetric friction re-identified with the force
   aligned to that delay, a low-speed friction term (Stribeck form, velocity fitted),
   and LuGre pre-sliding with its bristle stiffness fitted in closed loop.

Validation files (``DATA_EMPS_PULSES.mat``) also hold ``pulses_N``: force pulses added
to the saturated controller output before the gain ``gtau``. Whether a file stores them in
controller units or as the force in newtons, and whether ``vir`` already contains them, is
decided from the data (control law and the estimation model's inverse dynamics). They
are run through the same models (identified on the estimation file); the published pulse
model is not available, so those closed-loop figures are labelled with the definition used
here, not the published one. The reference inverse model's force error on that file is
computed as the benchmark's ``Script_IDIM_LS_CTV.m`` computes it (recorded force, parallel
decimation by 10), and, under a name that says so, against the applied force undecimated.

Usage::

    python -m studies.emps --estimation DATA_EMPS.mat [--validation DATA_EMPS_PULSES.mat]
                            [--json] [--plot FIGURE.png]
"""

from .forces import applied_force_error_undecimated, idim_cross_validation
from .models import _reference_estimate, relative_errors, simulate
from .record import DECIMATION, N_BORDER, PUBLISHED, EmpsModel, load_emps, measured_signals
from .report import _print_table, main, run

__all__ = ["DECIMATION", "N_BORDER", "PUBLISHED", "EmpsModel", "_print_table",
           "_reference_estimate", "applied_force_error_undecimated", "idim_cross_validation",
           "load_emps", "main", "measured_signals", "relative_errors", "run", "simulate"]
