"""Compiled per-step loop of one axis: discrete cascade servo around the exactly
discretised plant. Arrays in, arrays out.

The scalar parameters come in the vectors ``fp`` (float) and ``ip`` (int), whose entries
:mod:`tcpmm.sim.layout` names (``FP_*``, ``IP_*``); :class:`tcpmm.sim.inputs.KernelInputs`
holds them as named fields and builds the vectors.

The velocity-loop output is applied ``ip[IP_DELAY]`` steps later (computation delay); the
excitation is added to the applied current without delay, and the sum is limited.

``vtaps``: FIR taps on the encoder angle (newest first) of the difference velocity.

``fsec``: current-setpoint filters, one row ``b0, b1, b2, a1, a2`` per second-order
section (:func:`tcpmm.servo.currentfilters.biquads`), applied to the velocity controller's
output (after its anti-windup clamp, before the delay and the current limit); no rows
for none.

The command and the excitation come at their own (interpolation, DAQ) period: the
position loop fine-interpolates the command linearly, as drives do; the excitation is
held.

The external inputs (columns 1-4 of ``BdT``) are where nonlinear elements enter: the
constant loads, friction on the screw (torque on ``th_L``) and on the guideway (force
on ``X_t``), both given in table units (force [N] against table velocity [m/s]) with the
parameter vectors of :mod:`tcpmm.mechanics.friction`, and a force added to the nut force
(column 4). In contact, the nut spring acts with its deflection reduced by the half play
(a constant force in column 4); inside the play the nut transmits nothing, and the step
is advanced with the matrices of the plant without the nut spring (``AdgT``, ``BdgT``,
sub-step period), so the play is exact apart from the instant contact changes within a
sub-step. Friction is exact in stick: the
force over a step is the one that brings the body to rest when the static level allows
(its effective mass over the step comes from the discrete input column); where screw and
guideway both stick, the two forces that stop both together. A step in which
a friction velocity reaches or crosses zero, or a held contact breaks away, is redone in
``ip[IP_N_SUB]`` sub-steps; a contact that stays held over a whole step needs none.

Structure (what keeps a step at tens of nanoseconds, ``docs/performance.md``):
:func:`run_axis` compiles the kernel with LLVM's SLP vectoriser on (same operations in
the same order, in vector instructions); ``_run_axis`` allocates every work array and
hands it to ``_steps``, the loop, which is compiled without reference counting
(``_nrt=False``) and so may allocate nothing; a new per-axis state (a filter's delay
line, say) is allocated in ``_run_axis`` and passed in the same way. The helpers of the
loop are inlined (``inline="always"``): a call per step, with its arrays, would cost more
than the step. One is not: the friction of one contact in the general step (reversals,
stick, LuGre), which numba would inline twice per loop with every friction law in it;
called, it halves the kernel's compilation on a fresh install, at no cost found in the
step (``docs/performance.md``).
The free step is :mod:`tcpmm.sim.linearstep`'s; the step with friction and lost motion
:mod:`tcpmm.sim.frictionstep`'s, whose whole step and sub-steps share one loop body, so
that the friction code is inlined once, and whose shortcuts take the common steps in
which both contacts slide on or both stay held, with the same numbers, in registers.
What does not change from step to step (the friction's effective masses, input columns
and joint stop per matrix set) is computed before the loop; state and scratch swap roles
instead of being copied. The loop is compiled twice: once as it is, and once for the
common kind of run (friction without free play, the shortcuts on, no excitation, no
current filters, the loop closed, no difference velocity, ``_plain``) with
those settings as constants, the same operations in the same order.
"""

from __future__ import annotations

import numba
import numpy as np
from numba import literally, njit

from .._pycc import vectorised
from ..mechanics.friction import MODEL_NONE, P_MODEL
from .frictionstep import FK_COL, friction_constants, nonlinear_step
from .layout import (  # noqa: F401  (REC_COLUMNS: the rows of ``rec``)
    FP_CMD_PER_STEP,
    FP_HALF_PLAY,
    FP_I_LIMIT,
    FP_INTEGRATOR0,
    FP_K_FF,
    FP_K_NUT,
    FP_K_PP,
    FP_K_VI,
    FP_K_VP,
    FP_Q_ENCODER,
    FP_Q_SCALE,
    FP_R_L,
    FP_T_V,
    IP_CLOSED,
    IP_DELAY,
    IP_DIFFERENCE_VELOCITY,
    IP_GUIDEWAY_REF,
    IP_N_POS,
    IP_N_STEPS,
    IP_N_SUB,
    IP_REC_EVERY,
    IP_SCALE_FEEDBACK,
    IP_SEGMENT_FEEDFORWARD,
    IP_SHORTCUTS,
    NX,
    REC_COLUMNS,
    S_C_DL,
    S_C_H,
    S_C_POS,
    S_C_REC,
    S_CMD0,
    S_HEADER,
    S_I_PEAK,
    S_INTEGRATOR,
    S_SET,
    S_SPEED_CMD,
    S_STEP,
)
from .linearstep import constant_inputs, free_step
from .servoparts import diff_velocity, filter_rest, filter_step, quantise, record


def run_axis(AdT, BdT, x0, cmd, vcmd, excitation, fp, ip, rec, AdsT, BdsT, pf_s, pf_g,
             vtaps, AdgT, BdgT, fsec, state):
    """Simulate one axis for ``ip[IP_N_STEPS]`` velocity-loop steps.

    Parameters
    ----------
    AdT : ndarray (NX, NX)
        Transposed discrete state matrix (``AdT[j, i] = Ad[i, j]``), zero-padded [-].
    BdT : ndarray (6, NX)
        Transposed discrete input matrix for ``[i, T_m, T_L, F_t, F_nut, F_guide]``,
        zero-padded; ``F_guide`` is the guideway friction's input (on the table, or on
        table and bed) [-].
    x0 : ndarray (NX,)
        Initial plant state, zero-padded [SI].
    cmd, vcmd : ndarray
        Position command [m] and command velocity [m/s] at the command period.
    excitation : ndarray
        Current added to the applied current command (servo excitation, after the
        computation delay), at the command period [A].
    fp, ip : ndarray
        Parameters, entries named in :mod:`tcpmm.sim.layout` [SI].
    rec : ndarray (7, (ip[IP_N_STEPS] - 1) // ip[IP_REC_EVERY] + 1)
        Filled every ``ip[IP_REC_EVERY]`` steps, one column per record, with ``th_m, X_LS, X_TCP,
        w_m, i_c``, the motor angle at the table ``R_L th_m`` and the position command
        the step is at (interpolated like the position loop's) [SI].
    AdsT, BdsT : ndarray
        As ``AdT``, ``BdT`` for one sub-step of ``T_v / ip[IP_N_SUB]`` [-].
    pf_s, pf_g : ndarray
        Friction parameter vectors of the screw and the guideway, table units [-].
    vtaps : ndarray
        FIR taps of the difference velocity, newest first, summing to 1 [-].
    AdgT, BdgT : ndarray
        As ``AdsT``, ``BdsT`` for the plant without the nut spring (inside the play) [-].
    fsec : ndarray (n, 5)
        Current-setpoint filter sections, none for no filters [-].
    state : ndarray
        Empty for a run from rest; else what a run of a piece of the command hands the
        next (entries ``S_*`` of :mod:`tcpmm.sim.layout`, :func:`~tcpmm.sim.layout.state_size`
        long): read at the start unless ``state[S_SET]`` is zero, written at the end. Its
        ``S_CMD0`` says which sample of the whole command ``cmd[0]`` is; the steps
        continue from ``S_STEP`` [-].

    Returns
    -------
    ndarray (NX,)
        The plant state after the last step [SI].
    """
    args = (AdT, BdT, x0, cmd, vcmd, excitation, fp, ip, rec, AdsT, BdsT, pf_s, pf_g, vtaps,
            AdgT, BdgT, fsec, state)
    if not _run_axis.overloads:  # the first call: typing the arguments costs 0.1 ms
        _compile_vectorised(args)
    return _run_axis(*args)


def _compile_vectorised(args) -> None:
    """Compile (or load from the cache) the kernel for these argument types with LLVM's
    SLP vectoriser on: it puts the state update and the friction corrections into vector
    instructions. numba leaves it off by default (``NUMBA_SLP_VECTORIZE``) and reads the
    setting when it optimises, so it is switched on for this compilation alone. The
    vector code does the same IEEE operations in the same order as the scalar code: the
    results are the same to the bit. Done for the types of the first call's arguments
    (those of :meth:`tcpmm.sim.inputs.KernelInputs.as_args`); other types would be compiled
    by numba as usual, without it: the same numbers, more slowly."""
    sig = tuple(numba.typeof(a) for a in args)
    if sig in _run_axis.overloads:
        return
    with vectorised():
        if sig not in _run_axis.overloads:
            _run_axis.compile(sig)


@njit(cache=True, nogil=True)
def _run_axis(AdT, BdT, x0, cmd, vcmd, excitation, fp, ip, rec, AdsT, BdsT, pf_s, pf_g,
              vtaps, AdgT, BdgT, fsec, state):
    """:func:`run_axis`, compiled: allocates the work arrays and runs the loop."""
    x = x0.copy()
    delay, n_taps = ip[IP_DELAY], vtaps.size
    i_hold = fp[FP_K_VI] * fp[FP_INTEGRATOR0] if ip[IP_CLOSED] else 0.0
    dl = np.full(delay + 1, i_hold)  # delay line of i_c
    hist = np.full(n_taps + 1, quantise(x[0], fp[FP_Q_ENCODER]))  # ring buffer of angles
    fst = np.zeros((fsec.shape[0], 2))  # states of the current-setpoint filters
    if fsec.shape[0] > 0:
        filter_rest(fsec, fst, dl[0])
    c = np.zeros((3, NX))  # per matrix set: step, sub-step, sub-step in the play
    fk = np.zeros((3, 2, FK_COL + NX))
    T_v, h_sub = fp[FP_T_V], fp[FP_T_V] / ip[IP_N_SUB]
    for s, (B, h) in enumerate(((BdT, T_v), (BdsT, h_sub), (BdgT, h_sub))):
        constant_inputs(B, fp, c[s])
        friction_constants(B, h, fp[FP_R_L], ip[IP_GUIDEWAY_REF], fk[s])
    excited = np.any(excitation != 0.0)
    st = np.zeros(2)  # friction states: screw, guideway
    carried = state.size > 0 and state[S_SET] != 0.0
    if carried:
        _carry(state, st, dl, hist, fst, False)
    xn = np.empty(NX)
    if _plain(excited, fsec, fp, ip, pf_s, pf_g):  # a constant each: two loops compiled
        _steps(AdT, BdT, x, xn, c, st, dl, hist, cmd, vcmd, excitation, excited, fp, ip, rec,
               AdsT, BdsT, pf_s, pf_g, vtaps, AdgT, BdgT, fsec, fst, fk, state, carried, True)
    else:
        _steps(AdT, BdT, x, xn, c, st, dl, hist, cmd, vcmd, excitation, excited, fp, ip, rec,
               AdsT, BdsT, pf_s, pf_g, vtaps, AdgT, BdgT, fsec, fst, fk, state, carried, False)
    if state.size > 0:
        _carry(state, st, dl, hist, fst, True)
    return x


@njit(cache=True)
def _plain(excited, fsec, fp, ip, pf_s, pf_g):
    """Whether the run is of the common kind :func:`_steps` is compiled apart for:
    friction without free play, the friction shortcuts on, the guideway's velocity its
    own, the position loop closed, none of the servo's options (excitation, current
    filters, difference velocity): compiled with these as constants, without the options'
    code, the loop keeps more in registers and tests less per step
    (``docs/performance.md``)."""
    return (not excited and fsec.shape[0] == 0 and ip[IP_DIFFERENCE_VELOCITY] == 0
            and ip[IP_CLOSED] != 0 and ip[IP_SHORTCUTS] != 0 and ip[IP_GUIDEWAY_REF] < 0
            and fp[FP_HALF_PLAY] == 0.0
            and (pf_s[P_MODEL] != MODEL_NONE or pf_g[P_MODEL] != MODEL_NONE))


@njit(cache=True)
def _carry(state, st, dl, hist, fst, save):
    """The carried arrays into ``state`` where ``save``, else out of it (layout:
    :mod:`tcpmm.sim.layout`)."""
    i = S_HEADER
    for a in (st, dl, hist):
        for q in range(a.size):
            if save:
                state[i] = a[q]
            else:
                a[q] = state[i]
            i += 1
    for q in range(fst.shape[0]):
        for c in range(2):
            if save:
                state[i] = fst[q, c]
            else:
                fst[q, c] = state[i]
            i += 1
    if save:
        state[S_SET] = 1.0


# Compiled without reference counting (``_nrt=False``): the loop allocates nothing, and
# the counts numba keeps on every array passed to an inlined helper were most of its time.
@njit(cache=True, nogil=True, _nrt=False)
def _steps(AdT, BdT, x_out, xn, c, st, dl, hist, cmd, vcmd, excitation, excited, fp, ip,
           rec, AdsT, BdsT, pf_s, pf_g, vtaps, AdgT, BdgT, fsec, fst, fk, state, carried, plain):
    """The loop of :func:`run_axis` on its work arrays: state ``x_out`` (advanced in
    place), scratch ``xn`` (the two swap roles each step), the constant inputs' share of
    ``Bd u`` ``c`` and the friction constants ``fk`` (both per matrix set: step, sub-step,
    sub-step in the play), friction states ``st`` (screw, guideway), the delay line
    ``dl``, the encoder history ``hist`` and the states ``fst`` of the current-setpoint
    filters ``fsec``; ``excited``: whether ``excitation`` is not all zero; the loop's
    counters from ``state`` where ``carried``, and back to it where it is not empty;
    ``plain``: a constant, whether the run is of the kind :func:`_plain` says."""
    x = x_out
    play, K_t = fp[FP_HALF_PLAY], fp[FP_K_NUT]
    nonlinear = pf_s[P_MODEL] != MODEL_NONE or pf_g[P_MODEL] != MODEL_NONE or play > 0.0
    K_pp, K_vp, K_vi, k_ff = fp[FP_K_PP], fp[FP_K_VP], fp[FP_K_VI], fp[FP_K_FF]
    R, i_lim, T_v = fp[FP_R_L], fp[FP_I_LIMIT], fp[FP_T_V]
    q_enc, q_scale, I_w = fp[FP_Q_ENCODER], fp[FP_Q_SCALE], fp[FP_INTEGRATOR0]
    n_pos, fb_scale, vel_diff = ip[IP_N_POS], ip[IP_SCALE_FEEDBACK], ip[IP_DIFFERENCE_VELOCITY]
    delay, closed, rec_every = ip[IP_DELAY], ip[IP_CLOSED], ip[IP_REC_EVERY]
    ff_segment, g_ref, n_sub = ip[IP_SEGMENT_FEEDFORWARD], ip[IP_GUIDEWAY_REF], ip[IP_N_SUB]
    shortcut = ip[IP_SHORTCUTS] != 0 and play == 0.0
    filtered, n_taps, r = fsec.shape[0] > 0, vtaps.size, 0
    if literally(plain):  # compiled for each value: the common kind's without the options
        vel_diff, filtered, excited, closed, nonlinear, shortcut, g_ref, play = 0, False, \
            False, 1, True, True, -1, 0.0
    k_first, j0, I_w, w_c, c_pos, c_rec, c_dl, c_h, i_pk = _loop_start(state, carried, I_w)
    ratio, last = fp[FP_CMD_PER_STEP], cmd.size - 1 + j0
    for k in range(k_first, k_first + ip[IP_N_STEPS]):
        if vel_diff:
            th_q = quantise(x[0], q_enc)
        pos = k * ratio
        i_c = 0.0
        if closed:
            if c_pos == 0:
                if fb_scale:
                    x_fb = quantise(x[2] - x[3], q_scale)
                else:
                    x_fb = R * quantise(x[0], q_enc)
                j, j1, fr = _between(pos, last, j0)
                c_k = cmd[j] + fr * (cmd[j1] - cmd[j])
                if ff_segment:
                    v_k = vcmd[j]
                else:
                    v_k = vcmd[j] + fr * (vcmd[j1] - vcmd[j])
                w_c = (K_pp * (c_k - x_fb) + k_ff * v_k) / R
            w_fb = diff_velocity(hist, c_h, th_q, vtaps, T_v) if vel_diff else x[5]
            e = w_c - w_fb
            I_new = I_w + e * T_v
            i_c = K_vp * e + K_vi * I_new
            if i_c > i_lim:
                i_c = i_lim
                if e < 0.0:
                    I_w = I_new
            elif i_c < -i_lim:
                i_c = -i_lim
                if e > 0.0:
                    I_w = I_new
            else:
                I_w = I_new
            if filtered:
                i_c = filter_step(fsec, fst, i_c)
        if vel_diff:
            c_h = (c_h + 1) % (n_taps + 1)
            hist[c_h] = th_q
        c_pos += 1
        if c_pos == n_pos:
            c_pos = 0
        if delay > 0:
            dl[c_dl] = i_c
            c_dl += 1
            if c_dl > delay:
                c_dl = 0
            i_app = dl[c_dl]
        else:
            i_app = i_c
        if excited:  # its load in the branch: a branch, not a select on the current's path
            i_app += excitation[min(int(pos + 1e-9), last) - j0]
        if i_app > i_lim:
            i_app = i_lim
        elif i_app < -i_lim:
            i_app = -i_lim
        i_pk = max(i_pk, abs(i_app))
        if c_rec == 0:
            j, j1, fr = _between(pos, last, j0)
            record(rec, r, x, i_app, R, cmd[j] + fr * (cmd[j1] - cmd[j]), i_pk)
            i_pk = 0.0
            r += 1
        c_rec += 1
        if c_rec == rec_every:
            c_rec = 0
        if nonlinear:
            x, xn = nonlinear_step(AdT, BdT, AdsT, BdsT, AdgT, BdgT, c, x, xn, i_app, T_v,
                                    n_sub, pf_s, pf_g, st, R, play, K_t, g_ref, fk,
                                    shortcut)
            continue
        free_step(AdT, BdT, c[0], x, xn, i_app, 0.0)
        x, xn = xn, x
    for i in range(NX):
        x_out[i] = x[i]
    if state.size > 0:
        _loop_end(state, k_first + ip[IP_N_STEPS], I_w, w_c, c_pos, c_rec, c_dl, c_h, i_pk)


@njit(cache=True, inline="always")
def _between(pos, last, j0):
    """The samples of the command ``j``, ``j1`` (indices of ``cmd``) a position ``pos``
    [samples] lies between, and its fraction of the way from one to the other [-]."""
    j = min(int(pos), last)
    return j - j0, min(j + 1, last) - j0, pos - j


@njit(cache=True, inline="always")
def _loop_start(state, carried, I_w):
    """The loop's counters and scalars at its start, from rest or carried in ``state``:
    the first step, the sample of the whole command that ``cmd[0]`` is, the integrator,
    the speed command, the steps since the last position-loop update and record, the
    write index of the delay line, the index of the newest angle in ``hist`` and the
    largest current since the last record."""
    j0 = int(state[S_CMD0]) if state.size > 0 else 0
    if carried:
        return (int(state[S_STEP]), j0, state[S_INTEGRATOR], state[S_SPEED_CMD],
                int(state[S_C_POS]), int(state[S_C_REC]), int(state[S_C_DL]),
                int(state[S_C_H]), state[S_I_PEAK])
    return 0, j0, I_w, 0.0, 0, 0, 0, 0, 0.0


@njit(cache=True, inline="always")
def _loop_end(state, k_next, I_w, w_c, c_pos, c_rec, c_dl, c_h, i_pk):
    """The loop's counters and scalars into ``state``, for the next piece."""
    state[S_STEP], state[S_INTEGRATOR], state[S_SPEED_CMD] = k_next, I_w, w_c
    state[S_C_POS], state[S_C_REC], state[S_C_DL], state[S_C_H] = c_pos, c_rec, c_dl, c_h
    state[S_I_PEAK] = i_pk
