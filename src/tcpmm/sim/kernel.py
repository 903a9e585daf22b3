"""Compiled per-step loop of one axis: discrete cascade servo around the exactly
discretised plant. Arrays in, arrays out.

Layout of the parameter vectors (built by :func:`tcpmm.simulate.axis_kernel_inputs`):

``fp`` (float): 0 K_pp [1/s], 1 K_vp [A s/rad], 2 K_vi [A/rad], 3 k_ff [-], 4 R_L [m/rad],
5 current limit [A], 6 T_v [s], 7 encoder quantum [rad] (0: none), 8 scale quantum [m]
(0: none), 9 initial integrator [rad], 10 constant motor torque [N m], 11 constant screw
torque [N m], 12 constant carriage force [N], 13 command samples per velocity-loop step
(``T_v / T_cmd``), 14 half the free play of the screw-nut [m] (0: none), 15 nut
stiffness ``K_t`` [N/m].

``ip`` (int): 0 velocity-loop steps per position-loop step, 1 feedback (1 scale,
0 encoder), 2 velocity feedback (0 state, 1 backward difference), 3 delay [samples],
4 loops closed (1) or open-loop torque mode (0), 5 record every N steps, 6 sub-steps
of a step in which friction reverses or sticks or the nut is in its free play, 7 number
of velocity-loop steps, 8 feedforward from the slope of the current command segment (1)
or interpolated between the samples of ``vcmd`` (0), 9 state the guideway friction's
velocity is relative to (8, the bed, or -1 for none), 10 the shortcuts of a step in which
both contacts slide on or both stay held (1), or the general path for every step (0; the
same numbers, more slowly: for tests).

The velocity-loop output is applied ``ip[3]`` steps later (computation delay); the
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
``ip[6]`` sub-steps; a contact that stays held over a whole step needs none.

Structure (what keeps a step at tens of nanoseconds, ``docs/performance.md``):
:func:`run_axis` compiles the kernel with LLVM's SLP vectoriser on (same operations in
the same order, in vector instructions); ``_run_axis`` allocates every work array and
hands it to ``_steps``, the loop, which is compiled without reference counting
(``_nrt=False``) and so may allocate nothing; a new per-axis state (a filter's delay
line, say) is allocated in ``_run_axis`` and passed in the same way. The helpers of the
loop, and the friction functions of :mod:`tcpmm.sim.contact`, are inlined
(``inline="always"``): a call per step, with its arrays, would cost more than the step.
The whole step and its sub-steps share one loop body in ``_nonlinear_step``, so that the
friction code is inlined once; before it, ``_sliding_step`` and ``_held_step`` take the
common steps in which both contacts slide on or both stay held, with the same numbers, in
registers. What does not change from
step to step (the friction's effective masses and input columns per matrix set) is
computed before the loop; state and scratch swap roles instead of being copied.
"""

from __future__ import annotations

import threading
from contextlib import contextmanager

import numba
import numpy as np
from numba import njit

from ..mechanics.friction import MODEL_NONE, MODEL_STATIC, P_FS_NEG, P_FS_POS, SLIDING, STUCK
from .contact import at_rest, friction_force, sliding_friction, static_stop_or_slide
from .layout import NX, REC_COLUMNS  # noqa: F401  (REC_COLUMNS: the rows of ``rec``)


@njit(cache=True, inline="always")
def _quantise(v, q):
    if q > 0.0:
        return np.floor(v / q + 0.5) * q
    return v


@njit(cache=True, inline="always")
def _free_step(AdT, BdT, c, x, xn, u0, u4):
    """``xn = Ad x + Bd u``, see :func:`_free_end`."""
    y = _free_end(AdT, BdT, c, x, u0, u4)
    for i in range(NX):
        xn[i] = y[i]


@njit(cache=True, inline="always")
def _free_end(AdT, BdT, c, x, u0, u4):
    """The tuple ``Ad x + Bd u``: the current ``u0``, the constant inputs (their sum ``c``),
    the nut force ``u4``, then the states in order. The sums are carried in a tuple,
    i.e. in registers: through ``xn`` the compiler must assume that each store may change
    ``AdT``, and the product takes twice as long."""
    y = (BdT[0, 0] * u0 + c[0], BdT[0, 1] * u0 + c[1], BdT[0, 2] * u0 + c[2],
         BdT[0, 3] * u0 + c[3], BdT[0, 4] * u0 + c[4], BdT[0, 5] * u0 + c[5],
         BdT[0, 6] * u0 + c[6], BdT[0, 7] * u0 + c[7], BdT[0, 8] * u0 + c[8],
         BdT[0, 9] * u0 + c[9], BdT[0, 10] * u0 + c[10])
    if u4 != 0.0:
        y = (y[0] + BdT[4, 0] * u4, y[1] + BdT[4, 1] * u4, y[2] + BdT[4, 2] * u4,
             y[3] + BdT[4, 3] * u4, y[4] + BdT[4, 4] * u4, y[5] + BdT[4, 5] * u4,
             y[6] + BdT[4, 6] * u4, y[7] + BdT[4, 7] * u4, y[8] + BdT[4, 8] * u4,
             y[9] + BdT[4, 9] * u4, y[10] + BdT[4, 10] * u4)
    for j in range(NX):
        xj = x[j]
        if xj != 0.0 or j < NX - 1:  # no current loop: the last state is 0 and adds nothing
            y = (y[0] + AdT[j, 0] * xj, y[1] + AdT[j, 1] * xj, y[2] + AdT[j, 2] * xj,
                 y[3] + AdT[j, 3] * xj, y[4] + AdT[j, 4] * xj, y[5] + AdT[j, 5] * xj,
                 y[6] + AdT[j, 6] * xj, y[7] + AdT[j, 7] * xj, y[8] + AdT[j, 8] * xj,
                 y[9] + AdT[j, 9] * xj, y[10] + AdT[j, 10] * xj)
    return y


@njit(cache=True)
def _constant_inputs(BdT, fp, c):
    """``c`` = the part of ``Bd u`` from the constant inputs ``fp[10:13]`` (T_m, T_L,
    F_t)."""
    for i in range(NX):
        c[i] = BdT[1, i] * fp[10] + BdT[2, i] * fp[11] + BdT[3, i] * fp[12]


@njit(cache=True, inline="always")
def _rel(x, idx, ref):
    """Velocity ``x[idx]``, relative to ``x[ref]`` when ``ref >= 0``."""
    if ref >= 0:
        return x[idx] - x[ref]
    return x[idx]


#: Columns of the friction constants ``fk[set, contact]`` (:func:`_friction_constants`):
#: ``b``, the effective mass ``h / b``, ``1 / b``, whether the two contacts can be stopped
#: together (1 or 0), the contact's force of that joint stop per unit of the screw's and
#: of the guideway's velocity (:func:`_both_stopped`), then the contact's input column.
FK_B, FK_MASS, FK_INV_B, FK_JOINT, FK_PER_VS, FK_PER_VG, FK_COL = 0, 1, 2, 3, 4, 5, 6


@njit(cache=True)
def _friction_constants(BdT, h, R, g_ref, fk):
    """Constants of the screw (row 0) and guideway (row 1) friction over a step ``h`` of
    one matrix set: ``b = d v_end / d F`` (the contact's velocity change per newton of
    its friction over the step, > 0), the effective mass ``h / b``, ``1 / b``, the input
    column times the velocity ratio (``d x_end / d F``), and the forces that stop both
    contacts together per unit of their free velocities (the inverse of their 2 x 2
    coupling, :func:`_both_stopped`), so that a held step divides nothing."""
    for k in range(2):
        col, idx, ref, ratio = (2, 6, -1, R) if k == 0 else (5, 7, g_ref, 1.0)
        b = (BdT[col, idx] - BdT[col, ref] if ref >= 0 else BdT[col, idx]) * ratio * ratio
        fk[k, FK_B] = b
        fk[k, FK_MASS] = h / b if b > 0.0 else 0.0
        fk[k, FK_INV_B] = 1.0 / b if b > 0.0 else 0.0
        for i in range(NX):
            fk[k, FK_COL + i] = BdT[col, i] * ratio
    # how the screw's friction moves the guideway's velocity, and the guideway's the screw's
    c_gs = fk[0, FK_COL + 7] - (fk[0, FK_COL + g_ref] if g_ref >= 0 else 0.0)
    c_sg = R * fk[1, FK_COL + 6]
    b_s, b_g = fk[0, FK_B], fk[1, FK_B]
    det = b_s * b_g - c_sg * c_gs
    if det > 0.0:  # [js, jg] = [[b_g, -c_sg], [-c_gs, b_s]] / det [v_s, v_g]
        fk[:, FK_JOINT] = 1.0
        fk[0, FK_PER_VS], fk[0, FK_PER_VG] = b_g / det, -c_sg / det
        fk[1, FK_PER_VS], fk[1, FK_PER_VG] = -c_gs / det, b_s / det


@njit(cache=True, inline="always")
def _contact_friction(fk, k, v, v_free, h, pf, st):
    """Friction force of contact ``k`` over a step in which its velocity goes from ``v``
    to ``v_free`` without it; ``(F, stuck)``: the force (0 without friction) and whether
    it holds the contact at rest at the end of the step.

    The static model takes the force that stops the contact at the end of the step as
    ``v_free / b``: the same as ``friction_force``'s ``f_applied + m_eff v / h`` with
    ``f_applied = m_eff (v_free - v) / h``, without the two divisions in the chain from
    one step to the next."""
    if pf[0] == MODEL_NONE or fk[k, FK_B] <= 0.0:
        return 0.0, False
    if pf[0] == MODEL_STATIC:
        F, st[k] = static_stop_or_slide(v, v_free * fk[k, FK_INV_B], pf)
    else:
        m_eff = fk[k, FK_MASS]
        F, st[k] = friction_force(v, m_eff * (v_free - v) / h, st[k], pf, h, m_eff)
    return F, at_rest(st[k], pf)


@njit(cache=True, inline="always")
def _frictions(fk, x, xn, h, pf_s, pf_g, st, R, g_ref):
    """Screw and guideway friction over a step of length ``h`` from ``x``, applied to the
    free end state ``xn``; ``fk`` the friction constants of the step's matrix set.

    The screw's velocity is ``R x[6]``; the guideway's ``x[7]``, relative to ``x[g_ref]``
    when ``g_ref >= 0``, after the screw's friction. Both corrections are applied in one
    pass over the states, element by element in the order screw, screw at rest, guideway:
    the numbers of applying them one after the other, without storing the states
    in between."""
    F_s, stuck_s = _contact_friction(fk, 0, R * x[6], R * xn[6], h, pf_s, st)
    v_g = xn[7] - fk[0, FK_COL + 7] * F_s
    if g_ref >= 0:
        v_g -= xn[g_ref] - fk[0, FK_COL + g_ref] * F_s
    F_g, stuck_g = _contact_friction(fk, 1, _rel(x, 7, g_ref), v_g, h, pf_g, st)
    joint = False
    if stuck_s and stuck_g:
        F_s, F_g, joint = _both_stopped(fk, R * xn[6], _rel(xn, 7, g_ref), pf_s, pf_g, F_s,
                                        F_g)
    for i in range(NX):
        xi = xn[i] - fk[0, FK_COL + i] * F_s
        if i == 6 and stuck_s:
            xi = 0.0
        xn[i] = xi - fk[1, FK_COL + i] * F_g
    if joint:
        xn[6] = 0.0
    if stuck_g:
        xn[7] = xn[g_ref] if g_ref >= 0 else 0.0


@njit(cache=True, inline="always")
def _both_stopped(fk, v_s, v_g, pf_s, pf_g, F_s, F_g):
    """The two forces that bring screw and guideway to rest together at the end of the
    step, where each alone sticks (``v_s``, ``v_g``: their velocities at the end of the
    free step): ``(F_s, F_g, joint)``. Taken one after the other, the
    guideway's stopping force moves the stopped screw by its coupling (the nut), and the
    screw's velocity, then some 1e-16 m/s instead of 0, changed sign from step to step
    with the rounding of the discretisation, each time a reversal redone in sub-steps: a
    held axis cost 1.7 times a moving one. Solved jointly (2 x 2), both velocities are 0
    and the contact stays held; the forces sequentially found are kept where the joint
    ones leave a static band."""
    if fk[0, FK_JOINT] == 0.0:
        return F_s, F_g, False
    js = fk[0, FK_PER_VS] * v_s + fk[0, FK_PER_VG] * v_g
    jg = fk[1, FK_PER_VS] * v_s + fk[1, FK_PER_VG] * v_g
    if (-pf_s[P_FS_NEG] <= js <= pf_s[P_FS_POS]) and (-pf_g[P_FS_NEG] <= jg <= pf_g[P_FS_POS]):
        return js, jg, True
    return F_s, F_g, False


@njit(cache=True, inline="always")
def _held(x, idx, ref, pf, stk):
    """Whether a contact sits stuck at exactly zero velocity (static model)."""
    return pf[0] != MODEL_NONE and stk == STUCK and _rel(x, idx, ref) == 0.0


@njit(cache=True, inline="always")
def _reverses(x, xn, idx, ref, pf, stk):
    """Whether a moving contact's velocity reaches or crosses zero over the free step (a
    held one is judged by whether it stays held)."""
    if pf[0] == MODEL_NONE or _held(x, idx, ref, pf, stk):
        return False
    return _rel(x, idx, ref) * _rel(xn, idx, ref) <= 0.0


@njit(cache=True, inline="always")
def _nut_deflection(x, R):
    return R * x[1] - (x[2] - x[3])


@njit(cache=True, inline="always")
def _contact_force(x, R, play, K_t):
    """Force added to the nut spring in contact: 0 inside the play, where the plant
    without the nut spring is used instead."""
    d = _nut_deflection(x, R)
    if d > play:
        return -K_t * play
    if d < -play:
        return K_t * play
    return 0.0


@njit(cache=True, inline="always")
def _same_contact(x, xn, R, play):
    d0, d1 = _nut_deflection(x, R), _nut_deflection(xn, R)
    return (d0 > play and d1 > play) or (d0 < -play and d1 < -play)


@njit(cache=True, inline="always")
def _takes(fk, k, v, pf):
    """Whether contact ``k`` moving at ``v`` is one :func:`_sliding_step` takes: without
    friction, or of the static model, moving and with an effective mass."""
    return pf[0] == MODEL_NONE or (pf[0] == MODEL_STATIC and v != 0.0 and fk[k, FK_B] > 0.0)


@njit(cache=True, inline="always")
def _slides_on(v, F, f_stop):
    """:func:`static_stop_or_slide`'s test that the sliding force ``F`` does not stop a
    contact moving at ``v`` (``f_stop``: the force that would)."""
    return (v > 0.0 and F < f_stop) or (v < 0.0 and F > f_stop)


#: The state of the bed's velocity, the one a relative guideway velocity is taken to.
_BED = 8


@njit(cache=True, inline="always")
def _guide_end(y, g_ref):
    """The guideway's velocity in the state tuple ``y``, ``g_ref`` -1 or ``_BED`` (a
    tuple is indexed by constants, so that it stays in registers)."""
    return y[7] - y[_BED] if g_ref >= 0 else y[7]


@njit(cache=True, inline="always")
def _minus(y, f, F):
    """The tuple ``y - f[FK_COL:] F``, element by element."""
    o = FK_COL
    return (y[0] - f[o] * F, y[1] - f[o + 1] * F, y[2] - f[o + 2] * F, y[3] - f[o + 3] * F,
            y[4] - f[o + 4] * F, y[5] - f[o + 5] * F, y[6] - f[o + 6] * F,
            y[7] - f[o + 7] * F, y[8] - f[o + 8] * F, y[9] - f[o + 9] * F,
            y[10] - f[o + 10] * F)


@njit(cache=True, inline="always")
def _sliding_step(AdT, BdT, c, x, xn, u0, pf_s, pf_g, st, R, g_ref, fk):
    """The whole step when screw and guideway (static model, or none) slide on, as the
    general path of :func:`_nonlinear_step` takes it, to the bit: the same tests on the
    same numbers (no reversal in the free step, no stop by the sliding force), the
    sliding forces at the velocities at the start of the step applied to the free end
    state in the same order, but in registers. Whether it was that step (else ``xn`` is
    not written, and the general path takes the step).

    The forces are known before the free step ends; what its end decides is a branch the
    processor predicts, not a data dependence of the next step on comparisons, stores
    and loads: a moving axis steps in about 0.8 of the time of the general path."""
    v_s, v_g = R * x[6], _rel(x, 7, g_ref)
    if not (_takes(fk, 0, v_s, pf_s) and _takes(fk, 1, v_g, pf_g)
            and (g_ref < 0 or g_ref == _BED)):
        return False
    F_s, F_g = sliding_friction(v_s, pf_s), sliding_friction(v_g, pf_g)  # 0 without
    y = _free_end(AdT, BdT, c, x, u0, 0.0)
    ys = _minus(y, fk[0], F_s)
    if not ((pf_s[0] == MODEL_NONE
             or (x[6] * y[6] > 0.0  # else the free step reverses (_reverses)
                 and _slides_on(v_s, F_s, R * y[6] * fk[0, FK_INV_B])))
            and (pf_g[0] == MODEL_NONE
                 or (v_g * _guide_end(y, g_ref) > 0.0
                     and _slides_on(v_g, F_g, _guide_end(ys, g_ref) * fk[1, FK_INV_B])))):
        return False
    y = _minus(ys, fk[1], F_g)
    for i in range(NX):
        xn[i] = y[i]
    st[0], st[1] = SLIDING, SLIDING
    return True


@njit(cache=True, inline="always")
def _held_step(AdT, BdT, c, x, xn, u0, pf_s, pf_g, st, R, g_ref, fk):
    """The whole step when screw and guideway (static model) are held and stay held, as
    the general path of :func:`_nonlinear_step` takes it, to the bit (see
    :func:`_sliding_step`): each one's stop force within its static band, then the two
    that stop both together (:func:`_both_stopped`), applied to the free end state in
    registers. Whether it was that step (else ``xn`` is not written)."""
    if not (pf_s[0] == MODEL_STATIC and pf_g[0] == MODEL_STATIC
            and _held(x, 6, -1, pf_s, st[0]) and _held(x, 7, g_ref, pf_g, st[1])
            and fk[0, FK_B] > 0.0 and fk[1, FK_B] > 0.0 and (g_ref < 0 or g_ref == _BED)):
        return False
    y = _free_end(AdT, BdT, c, x, u0, 0.0)
    F_s = R * y[6] * fk[0, FK_INV_B]
    if not -pf_s[P_FS_NEG] <= F_s <= pf_s[P_FS_POS]:
        return False
    v_g = y[7] - fk[0, FK_COL + 7] * F_s
    if g_ref >= 0:
        v_g -= y[_BED] - fk[0, FK_COL + _BED] * F_s
    F_g = v_g * fk[1, FK_INV_B]
    if not -pf_g[P_FS_NEG] <= F_g <= pf_g[P_FS_POS]:
        return False
    F_s, F_g, joint = _both_stopped(fk, R * y[6], _guide_end(y, g_ref), pf_s, pf_g, F_s, F_g)
    y = _minus(_minus(y, fk[0], F_s), fk[1], F_g)
    w_s = 0.0 if joint else 0.0 - fk[1, FK_COL + 6] * F_g  # the screw's, set to 0 first
    w_g = y[_BED] if g_ref >= 0 else 0.0
    y = (y[0], y[1], y[2], y[3], y[4], y[5], w_s, w_g, y[8], y[9], y[10])
    for i in range(NX):
        xn[i] = y[i]
    return True


@njit(cache=True, inline="always")
def _nonlinear_step(AdT, BdT, AdsT, BdsT, AdgT, BdgT, c, x, xn, u0, h, n_sub, pf_s, pf_g,
                    st, R, play, K_t, g_ref, fk, shortcut):
    """One velocity-loop step with friction and lost motion; sub-steps where a friction
    velocity reaches or crosses zero, where a held contact breaks away, or where the nut
    is inside or crosses its free play. A contact that stays held over the whole step
    needs none: its friction is exact in stick. Returns ``(x, xn)``: the end state and
    the scratch (the two arrays swap roles at each (sub-)step instead of copying).
    ``shortcut``: try :func:`_sliding_step` and :func:`_held_step` first (never with free
    play).

    The whole step and the sub-steps share one loop body, so that the friction code is
    compiled once (it is inlined: a call per step would cost more than the step)."""
    if shortcut and (
            _sliding_step(AdT, BdT, c[0], x, xn, u0, pf_s, pf_g, st, R, g_ref, fk[0])
            or _held_step(AdT, BdT, c[0], x, xn, u0, pf_s, pf_g, st, R, g_ref, fk[0])):
        return xn, x
    whole, n, hh = True, 1, h
    u4 = 0.0  # force added to the nut spring
    A, B, cm, f = AdT, BdT, c[0], fk[0]
    k = 0
    while k < n:
        if play > 0.0:
            u4 = _contact_force(x, R, play, K_t)
            if not whole:
                A, B, cm, f = ((AdgT, BdgT, c[2], fk[2]) if u4 == 0.0
                               else (AdsT, BdsT, c[1], fk[1]))
        _free_step(A, B, cm, x, xn, u0, u4)
        if whole:
            redo = (_reverses(x, xn, 6, -1, pf_s, st[0])
                    or _reverses(x, xn, 7, g_ref, pf_g, st[1])
                    or (play > 0.0 and not _same_contact(x, xn, R, play)))
            if not redo:
                held_s, held_g = _held(x, 6, -1, pf_s, st[0]), _held(x, 7, g_ref, pf_g, st[1])
                st0, st1 = st[0], st[1]
        if not (whole and redo):
            _frictions(f, x, xn, hh, pf_s, pf_g, st, R, g_ref)
            if whole and ((held_s and st[0] != STUCK) or (held_g and st[1] != STUCK)):
                st[0], st[1] = st0, st1  # a held contact breaks away within the step
                redo = True
        if whole and redo:
            whole, n, hh = False, n_sub, h / n_sub
            A, B, cm, f = AdsT, BdsT, c[1], fk[1]
            continue
        x, xn = xn, x
        k += 1
    return x, xn


@njit(cache=True)
def _filter_rest(fsec, fst, i0):
    """Filter states at rest under a constant input ``i0``."""
    u = i0
    for q in range(fsec.shape[0]):
        b0, b1, b2, a1, a2 = fsec[q, 0], fsec[q, 1], fsec[q, 2], fsec[q, 3], fsec[q, 4]
        y = u * (b0 + b1 + b2) / (1.0 + a1 + a2)
        fst[q, 0] = y - b0 * u
        fst[q, 1] = b2 * u - a2 * y
        u = y


@njit(cache=True, inline="always")
def _filter_step(fsec, fst, u):
    """One step of the filter cascade (transposed direct form II); its output."""
    for q in range(fsec.shape[0]):
        y = fsec[q, 0] * u + fst[q, 0]
        fst[q, 0] = fsec[q, 1] * u - fsec[q, 3] * y + fst[q, 1]
        fst[q, 1] = fsec[q, 2] * u - fsec[q, 4] * y
        u = y
    return u


@njit(cache=True, inline="always")
def _diff_velocity(hist, c_h, th_q, vtaps, T_v):
    """Motor speed from the FIR of encoder differences, newest first [rad/s]."""
    n_taps = vtaps.size
    w_fb = 0.0
    newer = th_q
    for i in range(n_taps):
        older = hist[(c_h - i) % (n_taps + 1)]
        w_fb += vtaps[i] * (newer - older)
        newer = older
    return w_fb / T_v


@njit(cache=True, inline="always")
def _record(rec, r, x, i_app, R, c_k):
    """Column ``r`` of the record: ``th_m, X_LS, X_TCP, w_m, i_c, R th_m, cmd``."""
    rec[0, r] = x[0]
    rec[1, r] = x[2] - x[3]
    rec[2, r] = x[2] - x[4]
    rec[3, r] = x[5]
    rec[4, r] = i_app
    rec[5, r] = R * x[0]
    rec[6, r] = c_k


def run_axis(AdT, BdT, x0, cmd, vcmd, excitation, fp, ip, rec, AdsT, BdsT, pf_s, pf_g,
             vtaps, AdgT, BdgT, fsec):
    """Simulate one axis for ``ip[7]`` velocity-loop steps.

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
        Parameters, see the module docstring [SI].
    rec : ndarray (7, ip[7] // ip[5] + 1)
        Filled every ``ip[5]`` steps, one column per record, with ``th_m, X_LS, X_TCP,
        w_m, i_c``, the motor angle at the table ``R_L th_m`` and the position command
        the step is at (interpolated like the position loop's) [SI].
    AdsT, BdsT : ndarray
        As ``AdT``, ``BdT`` for one sub-step of ``T_v / ip[6]`` [-].
    pf_s, pf_g : ndarray
        Friction parameter vectors of the screw and the guideway, table units [-].
    vtaps : ndarray
        FIR taps of the difference velocity, newest first, summing to 1 [-].
    AdgT, BdgT : ndarray
        As ``AdsT``, ``BdsT`` for the plant without the nut spring (inside the play) [-].
    fsec : ndarray (n, 5)
        Current-setpoint filter sections, none for no filters [-].

    Returns
    -------
    ndarray (NX,)
        The plant state after the last step [SI].
    """
    args = (AdT, BdT, x0, cmd, vcmd, excitation, fp, ip, rec, AdsT, BdsT, pf_s, pf_g, vtaps,
            AdgT, BdgT, fsec)
    if not _run_axis.overloads:  # the first call: typing the arguments costs 0.1 ms
        _compile_vectorised(args)
    return _run_axis(*args)


_COMPILING = threading.Lock()


def _compile_vectorised(args) -> None:
    """Compile (or load from the cache) the kernel for these argument types with LLVM's
    SLP vectoriser on: it puts the state update and the friction corrections into vector
    instructions. numba leaves it off by default (``NUMBA_SLP_VECTORIZE``) and reads the
    setting when it optimises, so it is switched on for this compilation alone. The
    vector code does the same IEEE operations in the same order as the scalar code: the
    results are the same to the bit. Done for the types of the first call's arguments
    (those of :func:`tcpmm.simulate.axis_kernel_inputs`); other types would be compiled
    by numba as usual, without it: the same numbers, more slowly."""
    sig = tuple(numba.typeof(a) for a in args)
    if sig in _run_axis.overloads:
        return
    with vectorised():
        if sig not in _run_axis.overloads:
            _run_axis.compile(sig)


@contextmanager
def vectorised():
    """Compilations in this block with LLVM's SLP vectoriser on, one at a time in the
    process (numba's setting is global): the kernel's here, and the ahead-of-time build
    of :mod:`tcpmm.sim.compiled`."""
    with _COMPILING:
        before = numba.config.SLP_VECTORIZE
        numba.config.SLP_VECTORIZE = 1
        try:
            yield
        finally:
            numba.config.SLP_VECTORIZE = before


@njit(cache=True, nogil=True)
def _run_axis(AdT, BdT, x0, cmd, vcmd, excitation, fp, ip, rec, AdsT, BdsT, pf_s, pf_g,
              vtaps, AdgT, BdgT, fsec):
    """:func:`run_axis`, compiled: allocates the work arrays and runs the loop."""
    x = x0.copy()
    delay, n_taps = ip[3], vtaps.size
    dl = np.full(delay + 1, fp[2] * fp[9] if ip[4] else 0.0)  # delay line of i_c
    hist = np.full(n_taps + 1, _quantise(x[0], fp[7]))  # ring buffer of encoder angles
    fst = np.zeros((fsec.shape[0], 2))  # states of the current-setpoint filters
    if fsec.shape[0] > 0:
        _filter_rest(fsec, fst, dl[0])
    c = np.zeros((3, NX))  # per matrix set: step, sub-step, sub-step in the play
    fk = np.zeros((3, 2, FK_COL + NX))
    for s, (B, h) in enumerate(((BdT, fp[6]), (BdsT, fp[6] / ip[6]), (BdgT, fp[6] / ip[6]))):
        _constant_inputs(B, fp, c[s])
        _friction_constants(B, h, fp[4], ip[9], fk[s])
    excited = np.any(excitation != 0.0)
    _steps(AdT, BdT, x, np.empty(NX), c, np.zeros(2), dl, hist, cmd, vcmd, excitation,
           excited, fp, ip, rec, AdsT, BdsT, pf_s, pf_g, vtaps, AdgT, BdgT, fsec, fst, fk)
    return x


# Compiled without reference counting (``_nrt=False``): the loop allocates nothing, and
# the counts numba keeps on every array passed to an inlined helper were most of its time.
@njit(cache=True, nogil=True, _nrt=False)
def _steps(AdT, BdT, x_out, xn, c, st, dl, hist, cmd, vcmd, excitation, excited, fp, ip,
           rec, AdsT, BdsT, pf_s, pf_g, vtaps, AdgT, BdgT, fsec, fst, fk):
    """The loop of :func:`run_axis` on its work arrays: state ``x_out`` (advanced in
    place), scratch ``xn`` (the two swap roles each step), the constant inputs' share of
    ``Bd u`` ``c`` and the friction constants ``fk`` (both per matrix set: step, sub-step,
    sub-step in the play), friction states ``st`` (screw, guideway), the delay line
    ``dl``, the encoder history ``hist`` and the states ``fst`` of the current-setpoint
    filters ``fsec``; ``excited``: whether ``excitation`` is not all zero."""
    x = x_out
    play, K_t = fp[14], fp[15]
    nonlinear = pf_s[0] != MODEL_NONE or pf_g[0] != MODEL_NONE or play > 0.0
    n_sub = ip[6]
    K_pp, K_vp, K_vi, k_ff, R = fp[0], fp[1], fp[2], fp[3], fp[4]
    i_lim, T_v, q_enc, q_scale = fp[5], fp[6], fp[7], fp[8]
    I_w = fp[9]
    n_pos, fb_scale, vel_diff, delay, closed, rec_every = ip[0], ip[1], ip[2], ip[3], ip[4], ip[5]
    ff_segment, g_ref = ip[8], ip[9]
    shortcut = ip[10] != 0 and play == 0.0
    filtered = fsec.shape[0] > 0
    n_taps = vtaps.size
    c_h = 0  # index of the newest angle in hist
    w_c = 0.0
    r = 0
    c_pos = 0  # steps since the last position-loop update
    c_rec = 0  # steps since the last recorded sample
    c_dl = 0  # write index of the delay line
    ratio = fp[13]
    last = cmd.size - 1
    for k in range(ip[7]):
        if vel_diff:
            th_q = _quantise(x[0], q_enc)
        pos = k * ratio
        i_exc = excitation[min(int(pos + 1e-9), last)] if excited else 0.0
        i_c = 0.0
        if closed:
            if c_pos == 0:
                if fb_scale:
                    x_fb = _quantise(x[2] - x[3], q_scale)
                else:
                    x_fb = R * _quantise(x[0], q_enc)
                j = min(int(pos), last)
                fr = pos - j
                j1 = min(j + 1, last)
                c_k = cmd[j] + fr * (cmd[j1] - cmd[j])
                if ff_segment:
                    v_k = vcmd[j]
                else:
                    v_k = vcmd[j] + fr * (vcmd[j1] - vcmd[j])
                w_c = (K_pp * (c_k - x_fb) + k_ff * v_k) / R
            w_fb = _diff_velocity(hist, c_h, th_q, vtaps, T_v) if vel_diff else x[5]
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
                i_c = _filter_step(fsec, fst, i_c)
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
            i_app = dl[c_dl] + i_exc if excited else dl[c_dl]
        else:
            i_app = i_c + i_exc if excited else i_c
        if i_app > i_lim:
            i_app = i_lim
        elif i_app < -i_lim:
            i_app = -i_lim
        if c_rec == 0:
            j = min(int(pos), last)
            j1 = min(j + 1, last)
            _record(rec, r, x, i_app, R, cmd[j] + (pos - j) * (cmd[j1] - cmd[j]))
            r += 1
        c_rec += 1
        if c_rec == rec_every:
            c_rec = 0
        if nonlinear:
            x, xn = _nonlinear_step(AdT, BdT, AdsT, BdsT, AdgT, BdgT, c, x, xn, i_app, T_v,
                                    n_sub, pf_s, pf_g, st, R, play, K_t, g_ref, fk,
                                    shortcut)
            continue
        _free_step(AdT, BdT, c[0], x, xn, i_app, 0.0)
        x, xn = xn, x
    for i in range(NX):
        x_out[i] = x[i]
