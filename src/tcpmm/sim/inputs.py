"""The inputs of the axis kernel (:func:`tcpmm.sim.kernel.run_axis`) by name, built from
an axis of a model, and the kernel run on them.

The compiled kernel takes a fixed list of arrays, with its scalar parameters packed into
two vectors (:mod:`tcpmm.sim.layout`); :class:`KernelInputs` holds the same inputs as
named, typed fields and is the one place that list is made (:meth:`KernelInputs.as_args`),
so that a caller never counts positions. :func:`kernel_inputs` builds it from an axis and
a command, :func:`run_kernel` runs it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._compiled import run_axis
from ..mechanics.friction import friction_params_array
from ..mechanics.statespace import (
    discretize_zoh,
    guideway_force_input,
    nut_force_input,
    plant,
    static_equilibrium,
)
from ..model import Axis
from ..servo.currentfilters import biquads
from . import layout as L


@dataclass(frozen=True, eq=False)
class KernelInputs:
    """Everything :func:`tcpmm.sim.kernel.run_axis` reads, by name.

    The matrices are transposed (``AdT[j, i] = Ad[i, j]``) and zero-padded to
    :data:`tcpmm.sim.layout.NX` states; the arrays are C-contiguous float64, as the module
    compiled ahead of time (:mod:`tcpmm._compiled`) was built for. Frozen: the fields are
    not reassigned (``dataclasses.replace`` makes a changed copy); the arrays are shared,
    not copied.

    Attributes
    ----------
    AdT : ndarray (NX, NX)
        Discrete state matrix over one velocity-loop step [-].
    BdT : ndarray (6, NX)
        Discrete input matrix for ``[i, T_m, T_L, F_t, F_nut, F_guide]`` over one step;
        ``F_guide`` is the guideway friction's input (on the table, or on table and
        bed) [-].
    AdsT, BdsT : ndarray
        As ``AdT``, ``BdT`` over one sub-step, ``T_v / n_sub`` [-].
    AdgT, BdgT : ndarray
        As ``AdsT``, ``BdsT`` for the plant without the nut spring (inside the play) [-].
    x0 : ndarray (NX,)
        Initial plant state [SI].
    cmd : ndarray
        Position command at the command period [m].
    vcmd : ndarray
        Command velocity at the command period [m/s].
    excitation : ndarray
        Current added to the applied current command, at the command period [A].
    pf_s, pf_g : ndarray
        Friction parameter vectors of the screw and the guideway, table units
        (:func:`tcpmm.mechanics.friction.friction_params_array`) [-].
    vtaps : ndarray
        FIR taps of the difference velocity, newest first, summing to 1 [-].
    fsec : ndarray (n, 5)
        Current-setpoint filter sections ``b0, b1, b2, a1, a2``, none for no filters [-].
    K_pp : float
        Position-loop gain [1/s].
    K_vp : float
        Velocity-loop proportional gain [A s/rad].
    K_vi : float
        Velocity-loop integral gain [A/rad].
    k_ff : float
        Velocity feedforward factor [-].
    R_L : float
        Screw lead, table travel per motor angle [m/rad].
    current_limit : float
        Current limit [A].
    T_v : float
        Velocity-loop period [s].
    encoder_quantum : float
        Encoder quantum, 0 for none [rad].
    scale_quantum : float
        Scale quantum, 0 for none [m].
    integrator0 : float
        Initial value of the velocity loop's integrator [rad].
    motor_torque : float
        Constant motor torque [N m].
    screw_torque : float
        Constant screw torque [N m].
    carriage_force : float
        Constant carriage force [N].
    cmd_per_step : float
        Command samples per velocity-loop step, ``T_v / T_cmd`` [-].
    half_play : float
        Half the free play of the screw-nut, 0 for none [m].
    K_t : float
        Nut stiffness [N/m].
    n_pos : int
        Velocity-loop steps per position-loop step [-].
    scale_feedback : bool
        Position feedback from the scale, else from the encoder [-].
    difference_velocity : bool
        Velocity feedback from the encoder's backward difference, else the state [-].
    delay : int
        Computation delay of the velocity loop's output [samples].
    closed : bool
        Loops closed, else open-loop torque mode (the current is the excitation) [-].
    rec_every : int
        A record every this many velocity-loop steps [-].
    n_sub : int
        Sub-steps of a step in which friction reverses or sticks, or the nut is in its
        free play [-].
    n_steps : int
        Velocity-loop steps to run [-].
    segment_feedforward : bool
        Feedforward from the slope of the current command segment, else interpolated
        between the samples of ``vcmd`` [-].
    guideway_ref : int
        The state the guideway friction's velocity is relative to, -1 for none [-].
    shortcuts : bool
        The shortcuts of a step in which both contacts slide on or both stay held, else
        the general path for every step (the same numbers, more slowly) [-].
    state : ndarray
        Empty for a run from rest; else the state a run of a piece of the command hands
        the next, read and written by the kernel (:mod:`tcpmm.sim.layout`, ``S_*``) [-].
    """

    AdT: np.ndarray
    BdT: np.ndarray
    AdsT: np.ndarray
    BdsT: np.ndarray
    AdgT: np.ndarray
    BdgT: np.ndarray
    x0: np.ndarray
    cmd: np.ndarray
    vcmd: np.ndarray
    excitation: np.ndarray
    pf_s: np.ndarray
    pf_g: np.ndarray
    vtaps: np.ndarray
    fsec: np.ndarray
    K_pp: float
    K_vp: float
    K_vi: float
    k_ff: float
    R_L: float
    current_limit: float
    T_v: float
    encoder_quantum: float
    scale_quantum: float
    integrator0: float
    motor_torque: float
    screw_torque: float
    carriage_force: float
    cmd_per_step: float
    half_play: float
    K_t: float
    n_pos: int
    scale_feedback: bool
    difference_velocity: bool
    delay: int
    closed: bool
    rec_every: int
    n_sub: int
    n_steps: int
    segment_feedforward: bool
    guideway_ref: int
    shortcuts: bool = True
    state: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def n_records(self) -> int:
        """Columns of the record: the first step's and every ``rec_every``-th after [-]."""
        return (self.n_steps - 1) // self.rec_every + 1

    def float_params(self) -> np.ndarray:
        """The kernel's ``fp``, entries at :mod:`tcpmm.sim.layout`'s ``FP_*`` [SI]."""
        fp = np.empty(L.N_FP)
        fp[L.FP_K_PP], fp[L.FP_K_VP], fp[L.FP_K_VI] = self.K_pp, self.K_vp, self.K_vi
        fp[L.FP_K_FF], fp[L.FP_R_L] = self.k_ff, self.R_L
        fp[L.FP_I_LIMIT], fp[L.FP_T_V] = self.current_limit, self.T_v
        fp[L.FP_Q_ENCODER], fp[L.FP_Q_SCALE] = self.encoder_quantum, self.scale_quantum
        fp[L.FP_INTEGRATOR0] = self.integrator0
        fp[L.FP_MOTOR_TORQUE], fp[L.FP_SCREW_TORQUE] = self.motor_torque, self.screw_torque
        fp[L.FP_CARRIAGE_FORCE] = self.carriage_force
        fp[L.FP_CMD_PER_STEP] = self.cmd_per_step
        fp[L.FP_HALF_PLAY], fp[L.FP_K_NUT] = self.half_play, self.K_t
        return fp

    def int_params(self) -> np.ndarray:
        """The kernel's ``ip``, entries at :mod:`tcpmm.sim.layout`'s ``IP_*`` [-]."""
        ip = np.empty(L.N_IP, dtype=np.int64)
        ip[L.IP_N_POS], ip[L.IP_SCALE_FEEDBACK] = self.n_pos, self.scale_feedback
        ip[L.IP_DIFFERENCE_VELOCITY], ip[L.IP_DELAY] = self.difference_velocity, self.delay
        ip[L.IP_CLOSED], ip[L.IP_REC_EVERY] = self.closed, self.rec_every
        ip[L.IP_N_SUB], ip[L.IP_N_STEPS] = self.n_sub, self.n_steps
        ip[L.IP_SEGMENT_FEEDFORWARD] = self.segment_feedforward
        ip[L.IP_GUIDEWAY_REF], ip[L.IP_SHORTCUTS] = self.guideway_ref, self.shortcuts
        return ip

    def empty_record(self) -> np.ndarray:
        """The array the kernel fills, one row per :data:`tcpmm.sim.layout.REC_COLUMNS`
        signal and one column per record [SI]."""
        return np.empty((len(L.REC_COLUMNS), self.n_records))

    def as_args(self, rec: np.ndarray) -> tuple:
        """The arguments of :func:`tcpmm.sim.kernel.run_axis`, in its order.

        Parameters
        ----------
        rec : ndarray (7, n_records)
            The record the kernel fills (:meth:`empty_record`) [SI].
        """
        return (self.AdT, self.BdT, self.x0, self.cmd, self.vcmd, self.excitation,
                self.float_params(), self.int_params(), rec, self.AdsT, self.BdsT,
                self.pf_s, self.pf_g, self.vtaps, self.AdgT, self.BdgT, self.fsec, self.state)


def run_kernel(inputs: KernelInputs) -> tuple[np.ndarray, np.ndarray]:
    """Run the axis kernel (the compiled module's where there is one, else numba's).

    Parameters
    ----------
    inputs : KernelInputs
        The kernel's inputs [SI].

    Returns
    -------
    rec : ndarray (7, n_records)
        The record, rows :data:`tcpmm.sim.layout.REC_COLUMNS` [SI].
    x : ndarray (NX,)
        The plant state after the last step [SI].
    """
    rec = inputs.empty_record()
    x = run_axis(*inputs.as_args(rec))
    return rec, x


def kernel_inputs(axis: Axis, cmd, excitation, cmd_period_s: float, n_steps: int, *,
                  x_start: float | None = None, open_loop: bool = False, rec_every: int = 1,
                  quantise_feedback: bool = True) -> KernelInputs:
    """The kernel's inputs for one axis driven by a command.

    Parameters
    ----------
    axis : Axis
        The axis [SI].
    cmd : array_like
        Position command, uniformly sampled [m].
    excitation : array_like
        Current injected into the current command, per command sample [A].
    cmd_period_s : float
        Period of the command and excitation samples [s].
    n_steps : int
        Velocity-loop steps to run [-].
    x_start : float, optional
        Position held at the start (the feedback sensor reads it), default the first
        command sample [m].
    open_loop : bool
        Torque mode: the current is the excitation alone [-].
    rec_every : int
        Record every N velocity-loop steps [-].
    quantise_feedback : bool
        Quantise encoder and scale feedback to the sensor resolution [-].

    Returns
    -------
    KernelInputs
        The inputs, the arrays C-contiguous float64 [SI].
    """
    m, s, sen, fr = axis.mechanics, axis.servo, axis.sensors, axis.friction
    cmd = np.ascontiguousarray(cmd, dtype=float)
    play, n_sub = (fr.backlash, fr.substeps) if fr is not None else (0.0, 1)
    relative = fr is not None and fr.guideway_velocity == "relative"
    x0, i_hold = _initial_state(axis, cmd[0] if x_start is None else x_start, play)
    q = quantise_feedback
    return KernelInputs(
        **_matrices(axis, n_sub, play, relative), x0=x0, cmd=cmd,
        vcmd=command_velocity(cmd, cmd_period_s, s.feedforward),
        excitation=np.ascontiguousarray(excitation, dtype=float),
        pf_s=friction_params_array(fr.screw if fr is not None else None),
        pf_g=friction_params_array(fr.guideway if fr is not None else None),
        vtaps=np.asarray(s.velocity_filter, dtype=float), fsec=biquads(s.filters, s.T_v),
        K_pp=s.K_pp, K_vp=s.K_vp, K_vi=s.K_vi, k_ff=s.k_ff, R_L=m.R_L,
        current_limit=s.current_limit, T_v=s.T_v,
        encoder_quantum=sen.encoder_quantum if q else 0.0,
        scale_quantum=sen.scale_resolution if q else 0.0,
        integrator0=i_hold / s.K_vi if s.K_vi > 0 and not open_loop else 0.0,
        motor_torque=0.0, screw_torque=0.0, carriage_force=m.load_force,
        cmd_per_step=s.T_v / (cmd_period_s or s.T_v), half_play=0.5 * play, K_t=m.K_t,
        n_pos=s.n_pos, scale_feedback=s.position_feedback == "scale",
        difference_velocity=s.velocity_feedback == "difference", delay=s.delay_samples,
        closed=not open_loop, rec_every=rec_every, n_sub=n_sub, n_steps=n_steps,
        segment_feedforward=s.feedforward == "segment",
        guideway_ref=L.BED_VELOCITY if relative else -1,
    )


def sensor_datums(axis: Axis) -> tuple[float, float, float]:
    """Each sensor's reading at rest less the position the loop holds: the static
    deflections under the axis's load (the head's sag under gravity, the screw's wind-up),
    which the zero-point, reference and tool-length settings take up on the machine. Runs
    report the motor encoder, the scale and the TCP from these datums, as sensors zeroed
    at rest read them; all zero for an axis without a load [m]."""
    s, fr, m = axis.servo, axis.friction, axis.mechanics
    play = fr.backlash if fr is not None else 0.0
    x0, _ = static_equilibrium(m, 0.0, s.position_feedback, play)
    # R th_m, X_LS = X_t - X_b, X_TCP = X_t - X_h
    return float(m.R_L * x0[0]), float(x0[2] - x0[3]), float(x0[2] - x0[4])


def _initial_state(axis: Axis, x_start: float, play: float) -> tuple[np.ndarray, float]:
    """The plant at rest at ``x_start`` against its load, zero-padded to ``NX`` states
    [SI], and the current that holds it [A]."""
    s = axis.servo
    x0_mech, i_hold = static_equilibrium(axis.mechanics, x_start, s.position_feedback, play)
    x0 = np.zeros(L.NX)
    x0[:L.N_MECH] = x0_mech
    if s.current_bandwidth_hz is not None:
        x0[L.CURRENT_STATE] = i_hold
    return x0, i_hold


def _matrices(axis: Axis, n_sub: int, play: float, relative: bool) -> dict:
    """The discrete matrices of :class:`KernelInputs` (``AdT`` ... ``BdgT``), transposed
    and zero-padded; those of the sub-step zero without friction, those inside the play
    zero without play [-]."""
    m, s = axis.mechanics, axis.servo
    p = plant(m, s.current_bandwidth_hz)
    n = p.A.shape[0]
    B = np.column_stack([p.B, nut_force_input(m, n), guideway_force_input(m, n, relative)])
    out = {k: np.zeros((L.NX, L.NX) if k[0] == "A" else (6, L.NX))
           for k in ("AdT", "BdT", "AdsT", "BdsT", "AdgT", "BdgT")}

    def put(A, h, a, b):
        Ad, Bd = discretize_zoh(A, B, h)
        out[a][:n, :n], out[b][:, :n] = Ad.T, Bd.T

    put(p.A, s.T_v, "AdT", "BdT")
    if axis.friction is not None:
        put(p.A, s.T_v / n_sub, "AdsT", "BdsT")
    if play > 0.0:  # inside the play: the nut force cancelled by state feedback
        put(p.A - np.outer(B[:, 4], p.output_row("F_t")), s.T_v / n_sub, "AdgT", "BdgT")
    return out


def command_velocity(position_m, period_s: float, kind: str = "segment") -> np.ndarray:
    """Command velocity of the feedforward at the command samples.

    Parameters
    ----------
    position_m : ndarray
        Position command, uniformly sampled [m].
    period_s : float
        Command period [s].
    kind : {"segment", "centred"}
        ``segment``: the slope of the segment that starts at each sample, held over it
        (what a drive fed interpolated commands knows); ``centred``: the centred
        difference, which looks half a period ahead [-].

    Returns
    -------
    numpy.ndarray
        Velocity per sample [m/s].
    """
    pos = np.asarray(position_m, dtype=float)
    if pos.size < 2:
        return np.zeros(pos.size)
    if kind == "centred":
        return np.gradient(pos, period_s)
    v = np.empty(pos.size)
    v[:-1] = np.diff(pos) / period_s
    v[-1] = 0.0 if pos.size < 3 else v[-2]
    return v
