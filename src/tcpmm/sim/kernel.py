"""Compiled per-step loop of one axis: discrete cascade servo around the exactly
discretised plant. Arrays in, arrays out.

Layout of the parameter vectors (built by :func:`tcpmm.simulate.axis_kernel_inputs`):

``fp`` (float): 0 K_pp [1/s], 1 K_vp [A s/rad], 2 K_vi [A/rad], 3 k_ff [-], 4 R_L [m/rad],
5 current limit [A], 6 T_v [s], 7 encoder quantum [rad] (0: none), 8 scale quantum [m]
(0: none), 9 initial integrator [rad], 10 constant motor torque [N m], 11 constant screw
torque [N m], 12 constant carriage force [N].

``ip`` (int): 0 velocity-loop steps per position-loop step, 1 feedback (1 scale,
0 encoder), 2 velocity feedback (0 state, 1 backward difference), 3 delay [samples],
4 loops closed (1) or open-loop torque mode (0), 5 record every N steps.

The external inputs (columns 1-3 of ``BdT``) are where nonlinear elements enter: in
:func:`_external` the torques and forces of friction or lost motion are computed from the
state; here they are the constant loads.
"""

from __future__ import annotations

import numpy as np
from numba import njit

REC_COLUMNS = ("th_m", "X_LS", "X_TCP", "w_m", "i_c")
#: Fixed state size: 10 mechanical states and the optional current-loop state. A fixed
#: size lets the compiler unroll and vectorise the state update; unused states are zero.
NX = 11


@njit(cache=True, inline="always")
def _quantise(v, q):
    if q > 0.0:
        return np.floor(v / q + 0.5) * q
    return v


@njit(cache=True, inline="always")
def _external(x, fp, u):
    u[1] = fp[10]
    u[2] = fp[11]
    u[3] = fp[12]


@njit(cache=True, fastmath=True, nogil=True)
def run_axis(AdT, BdT, x0, cmd, vcmd, excitation, fp, ip, rec):
    """Simulate one axis for ``cmd.size`` velocity-loop steps.

    Parameters
    ----------
    AdT : ndarray (NX, NX)
        Transposed discrete state matrix (``AdT[j, i] = Ad[i, j]``), zero-padded [-].
    BdT : ndarray (4, NX)
        Transposed discrete input matrix for ``[i, T_m, T_L, F_t]``, zero-padded [-].
    x0 : ndarray (NX,)
        Initial plant state, zero-padded [SI].
    cmd, vcmd : ndarray (N,)
        Position command [m] and command velocity [m/s] at each velocity-loop step.
    excitation : ndarray (N,)
        Current added to the velocity-loop output (servo excitation) [A].
    fp, ip : ndarray
        Parameters, see the module docstring [SI].
    rec : ndarray (N // ip[5] + 1, 5)
        Filled with ``th_m, X_LS, X_TCP, w_m, i_c`` every ``ip[5]`` steps [SI].
    """
    x = x0.copy()
    xn = np.empty(NX)
    u = np.zeros(4)
    K_pp, K_vp, K_vi, k_ff, R = fp[0], fp[1], fp[2], fp[3], fp[4]
    i_lim, T_v, q_enc, q_scale = fp[5], fp[6], fp[7], fp[8]
    I_w = fp[9]
    n_pos, fb_scale, vel_diff, delay, closed, rec_every = ip[0], ip[1], ip[2], ip[3], ip[4], ip[5]
    dl = np.full(delay + 1, K_vi * I_w if closed else 0.0)
    th_prev = _quantise(x[0], q_enc)
    w_c = 0.0
    r = 0
    c_pos = 0  # steps since the last position-loop update
    c_rec = 0  # steps since the last recorded sample
    c_dl = 0  # write index of the delay line
    for k in range(cmd.size):
        th_q = _quantise(x[0], q_enc)
        i_c = excitation[k]
        if closed:
            if c_pos == 0:
                if fb_scale:
                    x_fb = _quantise(x[2] - x[3], q_scale)
                else:
                    x_fb = R * th_q
                w_c = (K_pp * (cmd[k] - x_fb) + k_ff * vcmd[k]) / R
            if vel_diff:
                w_fb = (th_q - th_prev) / T_v
            else:
                w_fb = x[5]
            e = w_c - w_fb
            I_new = I_w + e * T_v
            i_c += K_vp * e + K_vi * I_new
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
        th_prev = th_q
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
        if c_rec == 0:
            rec[r, 0] = x[0]
            rec[r, 1] = x[2] - x[3]
            rec[r, 2] = x[2] - x[4]
            rec[r, 3] = x[5]
            rec[r, 4] = i_app
            r += 1
        c_rec += 1
        if c_rec == rec_every:
            c_rec = 0
        u[0] = i_app
        _external(x, fp, u)
        for i in range(NX):
            xn[i] = BdT[0, i] * u[0] + BdT[1, i] * u[1] + BdT[2, i] * u[2] + BdT[3, i] * u[3]
        for j in range(NX):
            xj = x[j]
            for i in range(NX):
                xn[i] += AdT[j, i] * xj
        for i in range(NX):
            x[i] = xn[i]
    return x
