"""Shapes the compiled kernel and its callers share (no numba: imported at start-up).

The kernel's scalar parameters come in two vectors, ``fp`` (float64) and ``ip`` (int64),
so that the compiled function takes a fixed set of arrays; the constants here name their
entries. They are module-level integers, which numba reads as compile-time constants:
``fp[FP_K_PP]`` compiles to the same load as a literal index. The vectors are built by
:meth:`tcpmm.sim.inputs.KernelInputs.float_params` and
:meth:`~tcpmm.sim.inputs.KernelInputs.int_params`, from named fields.
"""

#: The rows of the kernel's record, one per signal [SI]: ``i_c`` the current applied at
#: the recorded step, ``i_peak`` the largest of its size over the steps since the record
#: before (a record every millisecond misses the velocity loop's peaks between).
REC_COLUMNS = ("th_m", "X_LS", "X_TCP", "w_m", "i_c", "X_M", "cmd", "i_peak")
#: Fixed state size: 10 mechanical states and the optional current-loop state. A fixed
#: size lets the compiler keep the state update in registers; unused states are zero.
NX = 11
#: The mechanical states, first in the state vector; the current-loop state follows.
N_MECH = 10
#: The current-loop state (the current [A]), zero where the model has no current loop.
CURRENT_STATE = N_MECH
#: The bed's velocity, the state a relative guideway velocity is taken to (``v_b`` of
#: :data:`tcpmm.mechanics.statespace.STATES`).
BED_VELOCITY = 8

# Entries of ``fp``, the float parameters.
#: Position-loop gain [1/s].
FP_K_PP = 0
#: Velocity-loop proportional gain [A s/rad].
FP_K_VP = 1
#: Velocity-loop integral gain [A/rad].
FP_K_VI = 2
#: Velocity feedforward factor [-].
FP_K_FF = 3
#: Screw lead, table travel per motor angle [m/rad].
FP_R_L = 4
#: Current limit [A].
FP_I_LIMIT = 5
#: Velocity-loop period [s].
FP_T_V = 6
#: Encoder quantum, 0 for none [rad].
FP_Q_ENCODER = 7
#: Scale quantum, 0 for none [m].
FP_Q_SCALE = 8
#: Initial value of the velocity loop's integrator [rad].
FP_INTEGRATOR0 = 9
#: Constant motor torque [N m].
FP_MOTOR_TORQUE = 10
#: Constant screw torque [N m].
FP_SCREW_TORQUE = 11
#: Constant carriage force [N].
FP_CARRIAGE_FORCE = 12
#: Command samples per velocity-loop step, ``T_v / T_cmd`` [-].
FP_CMD_PER_STEP = 13
#: Half the free play of the screw-nut, 0 for none [m].
FP_HALF_PLAY = 14
#: Nut stiffness ``K_t`` [N/m].
FP_K_NUT = 15
#: Length of ``fp`` [-].
N_FP = 16

# Entries of ``ip``, the integer parameters.
#: Velocity-loop steps per position-loop step [-].
IP_N_POS = 0
#: Position feedback from the scale (1) or the encoder (0) [-].
IP_SCALE_FEEDBACK = 1
#: Velocity feedback from the backward difference of the encoder (1) or the state (0) [-].
IP_DIFFERENCE_VELOCITY = 2
#: Computation delay of the velocity loop's output [samples].
IP_DELAY = 3
#: Loops closed (1), or open-loop torque mode (0) [-].
IP_CLOSED = 4
#: A record every this many velocity-loop steps [-].
IP_REC_EVERY = 5
#: Sub-steps of a step in which friction reverses or sticks, or the nut is in its free
#: play [-].
IP_N_SUB = 6
#: Velocity-loop steps to run [-].
IP_N_STEPS = 7
#: Feedforward from the slope of the current command segment (1), or interpolated between
#: the samples of the command velocity (0) [-].
IP_SEGMENT_FEEDFORWARD = 8
#: The state the guideway friction's velocity is relative to (:data:`BED_VELOCITY`), or -1
#: for none [-].
IP_GUIDEWAY_REF = 9
#: The shortcuts of a step in which both contacts slide on or both stay held (1), or the
#: general path for every step (0: the same numbers, more slowly; for tests) [-].
IP_SHORTCUTS = 10
#: Length of ``ip`` [-].
N_IP = 11

# Entries of ``state``, what a run hands the next when a command is simulated in pieces
# (empty: a run from rest, nothing kept). The header, then the friction states of the
# screw and the guideway (2), the delay line of the current command (``IP_DELAY + 1``),
# the encoder history (taps + 1) and the states of the current-setpoint filters (2 per
# section).
#: Non-zero once a run has written the state; zero: start from rest [-].
S_SET = 0
#: Global index of the first command sample the run is given (the input) [-].
S_CMD0 = 1
#: Next velocity-loop step, counted from the start of the command [-].
S_STEP = 2
#: The velocity loop's integrator [rad].
S_INTEGRATOR = 3
#: The speed command of the last position-loop update [rad/s].
S_SPEED_CMD = 4
#: Steps since the last position-loop update, since the last record; write index of the
#: delay line; index of the newest angle in the encoder history [-].
S_C_POS = 5
S_C_REC = 6
S_C_DL = 7
S_C_H = 8
#: Largest size of the current applied over the steps since the last record [A].
S_I_PEAK = 9
#: Length of the header [-].
S_HEADER = 10


def state_size(delay: int, n_taps: int, n_sections: int) -> int:
    """Length of the ``state`` vector for a delay, velocity taps and filter sections [-]."""
    return S_HEADER + 2 + delay + 1 + n_taps + 1 + 2 * n_sections
