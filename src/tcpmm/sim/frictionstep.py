"""One velocity-loop step of an axis with friction and lost motion (compiled, inlined
into :mod:`tcpmm.sim.kernel`'s loop): the exact stick of the static model, the joint stop
of screw and guideway, sub-steps where a friction velocity reverses or the nut crosses
its play, and the shortcuts of the two common steps, both contacts sliding on or both
held, taken in registers with the general path's numbers.

``fk[set, contact]`` holds the friction constants of a matrix set (columns ``FK_*``,
:func:`friction_constants`); ``st`` the friction states (screw, guideway); ``R`` the
screw's lead ratio ``R_L`` [m/rad]; ``g_ref`` the state the guideway's velocity is
relative to (-1 for none).
"""

from __future__ import annotations

from numba import njit

from ..mechanics.friction import MODEL_NONE, MODEL_STATIC, P_FS_NEG, P_FS_POS, SLIDING, STUCK
from .contact import at_rest, friction_force, sliding_friction, static_stop_or_slide
from .layout import BED_VELOCITY, NX
from .linearstep import free_end, free_step, rel

#: Columns of the friction constants ``fk[set, contact]`` (:func:`friction_constants`):
#: ``b``, the effective mass ``h / b``, ``1 / b``, whether the two contacts can be stopped
#: together (1 or 0), the contact's force of that joint stop per unit of the screw's and
#: of the guideway's velocity (:func:`_both_stopped`), then the contact's input column.
FK_B, FK_MASS, FK_INV_B, FK_JOINT, FK_PER_VS, FK_PER_VG, FK_COL = 0, 1, 2, 3, 4, 5, 6


@njit(cache=True)
def friction_constants(BdT, h, R, g_ref, fk):
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


@njit(cache=True)  # called, not inlined: see tcpmm.sim.kernel on its compilation
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
    F_g, stuck_g = _contact_friction(fk, 1, rel(x, 7, g_ref), v_g, h, pf_g, st)
    joint = False
    if stuck_s and stuck_g:
        F_s, F_g, joint = _both_stopped(fk, R * xn[6], rel(xn, 7, g_ref), pf_s, pf_g, F_s,
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
def _in_band(F, pf):
    """Whether a stop force ``F`` lies within the static band of friction ``pf``: the test
    of :func:`static_stop_or_slide` for a contact it stops [-]."""
    return -pf[P_FS_NEG] <= F <= pf[P_FS_POS]


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
    if _in_band(js, pf_s) and _in_band(jg, pf_g):
        return js, jg, True
    return F_s, F_g, False


@njit(cache=True, inline="always")
def _held(x, idx, ref, pf, stk):
    """Whether a contact sits stuck at exactly zero velocity (static model)."""
    return pf[0] != MODEL_NONE and stk == STUCK and rel(x, idx, ref) == 0.0


@njit(cache=True, inline="always")
def _reverses(x, xn, idx, ref, pf, stk):
    """Whether a moving contact's velocity reaches or crosses zero over the free step (a
    held one is judged by whether it stays held)."""
    if pf[0] == MODEL_NONE or _held(x, idx, ref, pf, stk):
        return False
    return rel(x, idx, ref) * rel(xn, idx, ref) <= 0.0


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


@njit(cache=True, inline="always")
def _guide_end(y, g_ref):
    """The guideway's velocity in the state tuple ``y``, ``g_ref`` -1 or
    :data:`BED_VELOCITY` (a tuple is indexed by constants, so that it stays in
    registers)."""
    return y[7] - y[BED_VELOCITY] if g_ref >= 0 else y[7]


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
    general path of :func:`nonlinear_step` takes it, to the bit: the same tests on the
    same numbers (no reversal in the free step, no stop by the sliding force), the
    sliding forces at the velocities at the start of the step applied to the free end
    state in the same order, but in registers. Whether it was that step (else ``xn`` is
    not written, and the general path takes the step).

    The forces are known before the free step ends; what its end decides is a branch the
    processor predicts, not a data dependence of the next step on comparisons, stores
    and loads: a moving axis steps in about 0.8 of the time of the general path."""
    v_s, v_g = R * x[6], rel(x, 7, g_ref)
    if not (_takes(fk, 0, v_s, pf_s) and _takes(fk, 1, v_g, pf_g)
            and (g_ref < 0 or g_ref == BED_VELOCITY)):
        return False
    F_s, F_g = sliding_friction(v_s, pf_s), sliding_friction(v_g, pf_g)  # 0 without
    y = free_end(AdT, BdT, c, x, u0, 0.0)
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
    the general path of :func:`nonlinear_step` takes it, to the bit (see
    :func:`_sliding_step`): each one's stop force within its static band, then the two
    that stop both together (:func:`_both_stopped`), applied to the free end state in
    registers. Whether it was that step (else ``xn`` is not written)."""
    if not (pf_s[0] == MODEL_STATIC and pf_g[0] == MODEL_STATIC
            and _held(x, 6, -1, pf_s, st[0]) and _held(x, 7, g_ref, pf_g, st[1])
            and fk[0, FK_B] > 0.0 and fk[1, FK_B] > 0.0 and (g_ref < 0 or g_ref == BED_VELOCITY)):
        return False
    y = free_end(AdT, BdT, c, x, u0, 0.0)
    F_s = R * y[6] * fk[0, FK_INV_B]
    if not _in_band(F_s, pf_s):
        return False
    F_g = _guide_end(_minus(y, fk[0], F_s), g_ref) * fk[1, FK_INV_B]
    if not _in_band(F_g, pf_g):
        return False
    F_s, F_g, joint = _both_stopped(fk, R * y[6], _guide_end(y, g_ref), pf_s, pf_g, F_s, F_g)
    y = _minus(_minus(y, fk[0], F_s), fk[1], F_g)
    w_s = 0.0 if joint else 0.0 - fk[1, FK_COL + 6] * F_g  # the screw's, set to 0 first
    w_g = y[BED_VELOCITY] if g_ref >= 0 else 0.0
    y = (y[0], y[1], y[2], y[3], y[4], y[5], w_s, w_g, y[8], y[9], y[10])
    for i in range(NX):
        xn[i] = y[i]
    return True


@njit(cache=True, inline="always")
def nonlinear_step(AdT, BdT, AdsT, BdsT, AdgT, BdgT, c, x, xn, u0, h, n_sub, pf_s, pf_g,
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
        free_step(A, B, cm, x, xn, u0, u4)
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
