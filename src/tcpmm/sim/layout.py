"""Shapes the compiled kernel and its callers share (no numba: imported at start-up)."""

#: The rows of the kernel's record, one per signal [SI].
REC_COLUMNS = ("th_m", "X_LS", "X_TCP", "w_m", "i_c", "X_M", "cmd")
#: Fixed state size: 10 mechanical states and the optional current-loop state. A fixed
#: size lets the compiler keep the state update in registers; unused states are zero.
NX = 11
#: The bed's velocity, the state a relative guideway velocity is taken to (``v_b`` of
#: :data:`tcpmm.mechanics.statespace.STATES`).
BED_VELOCITY = 8
