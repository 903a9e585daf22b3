"""The EMPS data: the benchmark's published figures and settings, a data file as a record,
a model of the axis, and the measured signals as the benchmark defines them."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import io as sio

from tcpmm.errors import InputError
from tcpmm.ident.frf import central_difference, lowpass_filtfilt
from tcpmm.mechanics.friction import StribeckFriction

PUBLISHED = {
    "identification": {"M": 95.1089, "Fv": 203.5034, "Fc": 20.3935, "offset": -3.1648,
                       "relative_error_percent": 4.0834},
    "simulation": {"position": 0.013752, "velocity": 0.22911, "acceleration": 8.6036,
                   "force": 5.848},
    # Script_IDIM_LS_CTV.m on DATA_EMPS_PULSES.mat with the estimates above
    "idim_cross_validation": {"relative_error_percent": 5.9824, "error_norm_N": 169.4876,
                              "error_std_N": 3.4039, "condition_number": 26.0217},
    # Simulation_EMPS_Validation.m (Simulink model EMPS_Rigide_Pulse) on DATA_EMPS_PULSES.mat
    "validation_simulation": {"position": 0.0080248, "velocity": 0.47888,
                              "acceleration": 19.8152, "force": 8.9409},
}
FILTER_CUTOFF_HZ = 100.0
FILTER_ORDER = 4
DECIMATION = 10
N_BORDER = 50
U_MAX_V = 10.0
TAPS = (0.5, 0.5)
N_SUB = 20
#: Integration steps per sample of the published simulation (Simulink ode45 with the step
#: capped at ``tec / 10`` and zero-crossing detection off).
PUBLISHED_STEPS = 10
#: Largest span of a position in metres: the EMPS table travels some 0.25 m, so a span of
#: more is the record in millimetres (250), not a longer axis.
MAX_TRAVEL_M = 1.0


@dataclass(frozen=True)
class EmpsRecord:
    """One EMPS data file in SI units.

    Parameters
    ----------
    name : str
        File name [-].
    t : numpy.ndarray
        Time [s].
    dt : float
        Sample time (mean step of ``t``; the stored times carry rounding jitter) [s].
    qm : numpy.ndarray
        Measured position at the load [m].
    qg : numpy.ndarray
        Reference position [m].
    vir : numpy.ndarray
        Controller output [V].
    kp : float
        Position gain [1/s].
    kv : float
        Velocity gain [V s/m].
    gtau : float
        Drive gain [N/V].
    pulses : numpy.ndarray or None
        External pulses added to the saturated controller output (validation file) [V].
    """

    name: str
    t: np.ndarray
    dt: float
    qm: np.ndarray
    qg: np.ndarray
    vir: np.ndarray
    kp: float
    kv: float
    gtau: float
    pulses: np.ndarray | None


@dataclass(frozen=True)
class EmpsModel:
    """A rigid-axis model of EMPS and its controller timing.

    Parameters
    ----------
    name : str
        Label [-].
    mass : float
        Moving mass [kg].
    offset : float
        Force offset [N].
    friction : StribeckFriction or LuGreFriction
        Friction model [-].
    delay : float
        Actuation delay after sampling [samples].
    description : str
        What differs from the reference [-].
    integrator : str
        How the closed loop is integrated: ``"exact"`` (closed-form sub-steps with the rest
        phase) or an explicit scheme of :data:`studies.rigidaxis.TABLEAUS` with
        ``sign(0) = 0``, as the benchmark's Simulink model is integrated [-].
    steps : int
        Integration steps per sample; 0 for the run's ``--substeps`` [-].
    """

    name: str
    mass: float
    offset: float
    friction: StribeckFriction
    delay: float
    description: str
    integrator: str = "exact"
    steps: int = 0

    def to_dict(self) -> dict:
        fr = self.friction.model_dump()
        fr["type"] = type(self.friction).__name__
        return {"description": self.description, "mass_kg": self.mass,
                "offset_N": self.offset, "delay_samples": self.delay, "friction": fr,
                "integrator": self.integrator, "steps_per_sample": self.steps or None}


def load_emps(path, need_pulses: bool = False) -> EmpsRecord:
    """Load an EMPS ``.mat`` file and check its variables.

    Parameters
    ----------
    path : str or Path
        ``DATA_EMPS.mat`` or a validation file with ``pulses_N`` [-].
    need_pulses : bool
        Require the ``pulses_N`` variable [-].

    Returns
    -------
    EmpsRecord
        The record [-].
    """
    path = Path(path)
    if not path.is_file():
        raise InputError("file not found; pass the path of DATA_EMPS.mat", file=path)
    try:
        raw = sio.loadmat(path)
    except Exception as exc:  # scipy raises several types on a bad file
        raise InputError(f"cannot read as a MATLAB v5 .mat file: {exc}", file=path) from None
    need = ["t", "qm", "qg", "vir", "kp", "kv", "gtau"] + (["pulses_N"] if need_pulses else [])
    missing = [k for k in need if k not in raw]
    if missing:
        raise InputError(f"missing variable(s) {missing}; EMPS files hold {need}",
                         file=path, column=missing[0])

    def vec(k):
        a = np.asarray(raw[k], dtype=float).ravel()
        if a.size < 10 * N_BORDER or not np.all(np.isfinite(a)):
            raise InputError(f"must be a finite vector of more than {10 * N_BORDER} samples",
                             file=path, column=k)
        return a

    def scalar(k):
        a = np.asarray(raw[k], dtype=float).ravel()
        if a.size != 1 or not np.isfinite(a[0]) or a[0] <= 0:
            raise InputError("must be one positive number", file=path, column=k)
        return float(a[0])

    t, qm, qg, vir = vec("t"), vec("qm"), vec("qg"), vec("vir")
    pulses = vec("pulses_N") if "pulses_N" in raw else None
    for k, a in (("qm", qm), ("qg", qg), ("vir", vir), ("pulses_N", pulses)):
        if a is not None and a.size != t.size:
            raise InputError(f"has {a.size} samples but t has {t.size}", file=path, column=k)
    for k, a in (("qm", qm), ("qg", qg)):
        if np.ptp(a) > MAX_TRAVEL_M:
            raise InputError(f"spans {np.ptp(a):g} m, where the EMPS table travels some "
                             "0.25 m: the positions look like millimetres; give them in "
                             "metres (divide by 1000)", file=path, column=k)
    steps = np.diff(t)
    dt = float((t[-1] - t[0]) / (t.size - 1))
    if dt <= 0 or np.max(np.abs(steps - dt)) > 0.01 * dt:
        raise InputError("time must increase with a uniform step", file=path, column="t")
    return EmpsRecord(path.name, t, dt, qm, qg, vir, scalar("kp"), scalar("kv"),
                      scalar("gtau"), pulses)


def check_moves_both_ways(rec: EmpsRecord, meas: dict) -> None:
    """Refuse a record whose measured velocity ``meas["dq"]`` (from the 50th sample on)
    does not go both ways for at least ``N_BORDER`` samples each, beyond 1 % of its
    largest: ``Fc sign(v)`` is then a constant, and the Coulomb level and the offset one
    column of the regression [-]."""
    dq = meas["dq"][N_BORDER:]
    move = 0.01 * np.max(np.abs(dq))
    if min(np.count_nonzero(dq > move), np.count_nonzero(dq < -move)) < N_BORDER:
        raise InputError("the record moves in one direction only, so Coulomb friction and "
                         "the offset cannot be told apart; give a record that moves both "
                         "ways", file=rec.name, column="qm")


def measured_signals(rec: EmpsRecord) -> dict:
    """Measured position, velocity, acceleration and force as the benchmark defines them.

    Parameters
    ----------
    rec : EmpsRecord
        The data [-].

    Returns
    -------
    dict
        ``q`` [m], ``dq`` [m/s], ``ddq`` [m/s^2] from the zero-phase filtered position and
        ``force = gtau * vir`` [N].
    """
    q = lowpass_filtfilt(rec.qm, rec.dt, FILTER_CUTOFF_HZ, FILTER_ORDER)
    dq = central_difference(q, rec.dt)
    return {"q": q, "dq": dq, "ddq": central_difference(dq, rec.dt),
            "force": rec.gtau * rec.vir}
