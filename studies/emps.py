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

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import io as sio
from scipy import optimize

from tcpmm.errors import InputError
from tcpmm.ident.frf import central_difference, decimate, lowpass_filtfilt
from tcpmm.mechanics.friction import LuGreFriction, StribeckFriction

from .rigidaxis import friction_from_idim, idim_ls
from .rigidaxis.simulator import DiscreteServo, RigidAxis, RigidServoResult, simulate_rigid_servo

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
    steps = np.diff(t)
    dt = float((t[-1] - t[0]) / (t.size - 1))
    if dt <= 0 or np.max(np.abs(steps - dt)) > 0.01 * dt:
        raise InputError("time must increase with a uniform step", file=path, column="t")
    return EmpsRecord(path.name, t, dt, qm, qg, vir, scalar("kp"), scalar("kv"),
                      scalar("gtau"), pulses)


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


def _control_law(rec: EmpsRecord) -> np.ndarray:
    """Saturated controller output computed from the measured position [V]."""
    qf = TAPS[0] * rec.qm + TAPS[1] * np.r_[rec.qm[0], rec.qm[:-1]]
    dq = np.r_[0.0, np.diff(qf)] / rec.dt
    return np.clip(rec.kv * (rec.kp * (rec.qg - rec.qm) - dq), -U_MAX_V, U_MAX_V)


def vir_includes_pulses(rec: EmpsRecord) -> bool:
    """Whether the recorded ``vir`` contains the pulses (tested on the control law).

    Parameters
    ----------
    rec : EmpsRecord
        The data [-].

    Returns
    -------
    bool
        True if ``vir - pulses`` follows the control law better than ``vir`` [-].
    """
    if rec.pulses is None or not np.any(rec.pulses):
        return False
    law = _control_law(rec)
    s = slice(N_BORDER, None)
    return bool(np.linalg.norm((rec.vir - rec.pulses - law)[s])
                < np.linalg.norm((rec.vir - law)[s]))


def _idim_force(meas: dict, params: dict) -> np.ndarray:
    """Force the reference inverse model predicts from the measured motion [N]."""
    return (params["M"]["value"] * meas["ddq"] + params["Fv"]["value"] * meas["dq"]
            + params["Fc"]["value"] * np.sign(meas["dq"]) + params["offset"]["value"])


def idim_cross_validation(rec: EmpsRecord, params: dict) -> dict:
    """Force error of the reference inverse model on a data set, as the benchmark's
    ``Script_IDIM_LS_CTV.m`` defines it.

    The force is the recorded ``gtau * vir`` (whatever ``vir`` holds; pulses outside it
    are not added), the regressors ``[q'', q', sign(q'), 1]`` come from the published
    position filter, samples from the 50th on are kept, and regressors and force are
    decimated in parallel by 10 (``decimate``: 8th-order Chebyshev low-pass, zero phase)
    before the error is taken. On the estimation file this gives the published direct
    validation (4.0834 %), on ``DATA_EMPS_PULSES.mat`` the published cross-test validation.

    Parameters
    ----------
    rec : EmpsRecord
        The data [-].
    params : dict
        Reference IDIM-LS parameters (``M``, ``Fv``, ``Fc``, ``offset`` with ``value``)
        [SI].

    Returns
    -------
    dict
        ``relative_error_percent`` [%], ``error_norm_N`` and ``error_std_N`` (the norm and
        sample standard deviation of the decimated force error) [N], ``condition_number``
        of the decimated regressor [-] and ``n_samples`` after decimation [-].
    """
    meas = measured_signals(rec)
    s = slice(N_BORDER - 1, None)
    dq = meas["dq"][s]
    regressor = decimate(np.column_stack([meas["ddq"][s], dq, np.sign(dq), np.ones_like(dq)]),
                         DECIMATION)
    theta = np.array([params[k]["value"] for k in ("M", "Fv", "Fc", "offset")])
    force = decimate(meas["force"][s], DECIMATION)
    err = force - regressor @ theta
    return {"relative_error_percent": float(100.0 * np.linalg.norm(err)
                                            / np.linalg.norm(force)),
            "error_norm_N": float(np.linalg.norm(err)),
            "error_std_N": float(np.std(err, ddof=1)),
            "condition_number": float(np.linalg.cond(regressor)),
            "n_samples": int(force.size)}


def applied_force_error_undecimated(rec: EmpsRecord, params: dict) -> float:
    """Force error of the reference inverse model against the force the axis received,
    on every sample from the 50th on, without decimation.

    Not the benchmark's figure (:func:`idim_cross_validation`): the force here includes
    the pulses, which the inverse model must then explain from the motion, and the
    undecimated force keeps the high-frequency ripple the benchmark filters out.

    Parameters
    ----------
    rec : EmpsRecord
        The data, pulses in controller units [-].
    params : dict
        Reference IDIM-LS parameters (``M``, ``Fv``, ``Fc``, ``offset`` with ``value``)
        [SI].

    Returns
    -------
    float
        ``100 ||applied - predicted|| / ||applied||`` [%].
    """
    u = rec.vir
    if rec.pulses is not None and not vir_includes_pulses(rec):
        u = rec.vir + rec.pulses
    applied = rec.gtau * u
    s = slice(N_BORDER - 1, None)
    pred = _idim_force(measured_signals(rec), params)
    return float(100.0 * np.linalg.norm((applied - pred)[s]) / np.linalg.norm(applied[s]))


def pulses_in_controller_units(rec: EmpsRecord, params: dict) -> tuple[EmpsRecord, str]:
    """Express ``pulses_N`` in controller-output units, deciding from the data how they
    were recorded.

    The pulses enter after the saturation, before the gain ``gtau``. A file may store them
    in controller units (so the force is ``gtau * pulses``) or as the force itself
    (``pulses_N`` [N], so ``pulses / gtau`` in controller units), and ``vir`` may or may
    not already contain them. Whether ``vir`` contains them is tested on the control law;
    the unit on the inverse dynamic model identified on the estimation data, whose force
    must match the measured motion.

    Parameters
    ----------
    rec : EmpsRecord
        Validation record with pulses [-].
    params : dict
        Reference IDIM-LS parameters (``M``, ``Fv``, ``Fc``, ``offset`` with ``value``)
        [SI].

    Returns
    -------
    tuple
        ``(record with pulses in controller units, "controller" or "newton")`` [-].
    """
    if rec.pulses is None or not np.any(rec.pulses):
        return rec, "controller"
    s = slice(N_BORDER, None)
    law = _control_law(rec)
    scales = {"controller": 1.0, "newton": 1.0 / rec.gtau}
    dev = {u: np.linalg.norm((rec.vir - k * rec.pulses - law)[s]) for u, k in scales.items()}
    unit = min(dev, key=dev.get)
    if dev[unit] >= np.linalg.norm((rec.vir - law)[s]):  # vir without the pulses
        pred = _idim_force(measured_signals(rec), params)
        res = {u: np.linalg.norm((rec.gtau * (rec.vir + k * rec.pulses) - pred)[s])
               for u, k in scales.items()}
        unit = min(res, key=res.get)
    return dataclasses.replace(rec, pulses=rec.pulses * scales[unit]), unit


def simulate(rec: EmpsRecord, model: EmpsModel, n_sub: int = N_SUB, period=None,
             ref=None) -> RigidServoResult:
    """Closed-loop simulation of a model with the reference position as input.

    Parameters
    ----------
    rec : EmpsRecord
        The data (reference, gains, pulses) [-].
    model : EmpsModel
        The model, with its integrator [-].
    n_sub : int
        Mechanical sub-steps per sample, unless the model fixes its own [-].
    period : float, optional
        Controller period; default the data's sample time [s].
    ref : numpy.ndarray, optional
        Reference per controller sample; default ``qg`` [m].

    Returns
    -------
    RigidServoResult
        Sampled simulation [-].
    """
    servo = DiscreteServo(period=rec.dt if period is None else period, kp=rec.kp,
                          kv=rec.kv, taps=TAPS, delay=model.delay, u_max=U_MAX_V,
                          gain=rec.gtau)
    axis = RigidAxis(mass=model.mass, offset=model.offset, friction=model.friction)
    return simulate_rigid_servo(rec.qg if ref is None else ref, axis, servo, ext=rec.pulses,
                                n_sub=model.steps or n_sub, q0=float(rec.qm[0]),
                                integrator=model.integrator)


def relative_errors(rec: EmpsRecord, sim: RigidServoResult, meas: dict) -> dict:
    """Benchmark relative errors of a simulation, from the 50th sample on.

    Parameters
    ----------
    rec : EmpsRecord
        The data [-].
    sim : RigidServoResult
        The simulation [-].
    meas : dict
        Output of ``measured_signals`` [-].

    Returns
    -------
    dict
        ``position``, ``velocity``, ``acceleration``, ``force`` errors [%].
    """
    s = slice(N_BORDER - 1, None)
    u = sim.u_applied
    if rec.pulses is not None and vir_includes_pulses(rec):
        u = u + rec.pulses
    pairs = {"position": (meas["q"], sim.q), "velocity": (meas["dq"], sim.v),
             "acceleration": (meas["ddq"], sim.a), "force": (meas["force"], rec.gtau * u)}
    return {k: float(100.0 * np.linalg.norm(m[s] - x[s]) / np.linalg.norm(m[s]))
            for k, (m, x) in pairs.items()}


def _score(err: dict, ref: dict) -> float:
    return err["velocity"] / ref["velocity"] + err["force"] / ref["force"]


def fit_delay(rec, meas, base: EmpsModel, ref_err: dict, n_sub: int = N_SUB) -> float:
    """Actuation delay minimising the closed-loop velocity and force errors.

    Parameters
    ----------
    rec : EmpsRecord
        Estimation data [-].
    meas : dict
        Measured signals [-].
    base : EmpsModel
        Model whose delay is varied [-].
    ref_err : dict
        Errors of the reference model, used to weigh velocity and force [%].
    n_sub : int
        Sub-steps per sample, also the delay resolution [-].

    Returns
    -------
    float
        Delay [samples], a multiple of ``1 / n_sub`` in ``[0, 1]``.
    """
    grid = np.linspace(0.0, 1.0, 11)
    costs = []
    for d in grid:
        m = EmpsModel(base.name, base.mass, base.offset, base.friction, float(d), "")
        costs.append(_score(relative_errors(rec, simulate(rec, m, n_sub), meas), ref_err))
    i = int(np.argmin(costs))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    fine = np.arange(round(lo * n_sub), round(hi * n_sub) + 1) / n_sub
    best, cost = float(grid[i]), costs[i]
    for d in fine:
        m = EmpsModel(base.name, base.mass, base.offset, base.friction, float(d), "")
        c = _score(relative_errors(rec, simulate(rec, m, n_sub), meas), ref_err)
        if c < cost:
            best, cost = float(d), c
    return best


def fit_sigma0(rec, meas, base: EmpsModel, ref_err: dict, n_sub: int = N_SUB) -> float:
    """LuGre bristle stiffness minimising the closed-loop velocity and force errors.

    Parameters
    ----------
    rec : EmpsRecord
        Estimation data [-].
    meas : dict
        Measured signals [-].
    base : EmpsModel
        Model with static friction whose levels the LuGre model keeps [-].
    ref_err : dict
        Errors of the reference model [%].
    n_sub : int
        Sub-steps per sample [-].

    Returns
    -------
    float
        ``sigma0`` [N/m].
    """
    def cost(log_s0):
        fr = LuGreFriction(**base.friction.model_dump(), sigma0=10.0**log_s0, sigma1=0.0)
        m = EmpsModel(base.name, base.mass, base.offset, fr, base.delay, "")
        return _score(relative_errors(rec, simulate(rec, m, n_sub), meas), ref_err)

    res = optimize.minimize_scalar(cost, bounds=(5.0, 9.0), method="bounded",
                                   options={"xatol": 0.05})
    return 10.0 ** float(res.x)


_IDIM_SETTINGS = {"cutoff": FILTER_CUTOFF_HZ, "order": FILTER_ORDER, "decimation": DECIMATION,
                  "skip": N_BORDER - 1}


def _reference_estimate(rec: EmpsRecord):
    return idim_ls(rec.qm, rec.gtau * rec.vir, rec.dt, friction="symmetric", **_IDIM_SETTINGS)


def reference_model(rec: EmpsRecord, estimate=None) -> EmpsModel:
    """The benchmark's reference model identified by IDIM-LS with the published filter,
    integrated as the benchmark integrates it.

    Parameters
    ----------
    rec : EmpsRecord
        Estimation data [-].
    estimate : ParameterEstimate, optional
        Its IDIM-LS estimate, if already computed [SI].

    Returns
    -------
    EmpsModel
        Symmetric Coulomb and viscous friction, offset, one-sample delay; ``sign(v)``
        integrated by Dormand-Prince steps of a tenth of the sample [-].
    """
    est = _reference_estimate(rec) if estimate is None else estimate
    fr, off = friction_from_idim(est)
    return EmpsModel("reference", est["M"], off, fr, 1.0,
                     "published structure: symmetric Coulomb + viscous + offset, "
                     "one-sample delay; integrated as published (sign(v), Dormand-Prince "
                     "steps of T/10, no rest phase)", "dopri5", PUBLISHED_STEPS)


def converged_reference(reference: EmpsModel) -> EmpsModel:
    """The reference model integrated to convergence (closed-form sub-steps, rest phase).

    Parameters
    ----------
    reference : EmpsModel
        Output of :func:`reference_model` [-].

    Returns
    -------
    EmpsModel
        The same parameters with ``integrator="exact"`` [-].
    """
    return dataclasses.replace(
        reference, name="reference_converged", integrator="exact", steps=0,
        description="reference parameters, integrated to convergence (closed-form "
                    "sub-steps, rest phase solved)")


def identify(rec: EmpsRecord, n_sub: int = N_SUB) -> tuple[dict, dict]:
    """Identify the reference model and the improved models on the estimation data.

    Parameters
    ----------
    rec : EmpsRecord
        Estimation data [-].
    n_sub : int
        Sub-steps per sample [-].

    Returns
    -------
    tuple of dict
        ``(identification results for JSON, {name: EmpsModel})`` [-].
    """
    force = rec.gtau * rec.vir
    ref_est = _reference_estimate(rec)
    fr_ref, off_ref = friction_from_idim(ref_est)
    models = {"reference": reference_model(rec, ref_est)}
    models["reference_converged"] = converged_reference(models["reference"])
    asym_est = idim_ls(rec.qm, force, rec.dt, friction="asymmetric", **_IDIM_SETTINGS)
    fr_a, off_a = friction_from_idim(asym_est)
    models["asymmetric"] = EmpsModel(
        "asymmetric", asym_est["M"], off_a, fr_a, 1.0,
        "asymmetric Coulomb and viscous friction (IDIM-LS), one-sample delay")

    meas = measured_signals(rec)
    ref_err = relative_errors(rec, simulate(rec, models["reference"], n_sub), meas)
    delay = fit_delay(rec, meas, models["reference"], ref_err, n_sub)
    models["delay"] = EmpsModel(
        "delay", ref_est["M"], off_ref, fr_ref, delay,
        "reference parameters, actuation delay fitted in closed loop")
    shift = delay + 0.5
    asym_d = idim_ls(rec.qm, force, rec.dt, friction="asymmetric", force_shift=shift,
                     **_IDIM_SETTINGS)
    fr_ad, off_ad = friction_from_idim(asym_d)
    models["asymmetric_delay"] = EmpsModel(
        "asymmetric_delay", asym_d["M"], off_ad, fr_ad, delay,
        "asymmetric friction re-identified with the force aligned to the fitted delay")
    strib = idim_ls(rec.qm, force, rec.dt, friction="asymmetric", force_shift=shift,
                    stribeck_velocity="fit", **_IDIM_SETTINGS)
    fr_s, off_s = friction_from_idim(strib)
    models["asymmetric_stribeck_delay"] = EmpsModel(
        "asymmetric_stribeck_delay", strib["M"], off_s, fr_s, delay,
        "plus a low-speed (Stribeck-form) friction term, velocity fitted")
    s0 = fit_sigma0(rec, meas, models["asymmetric_stribeck_delay"], ref_err, n_sub)
    lugre = LuGreFriction(**fr_s.model_dump(), sigma0=s0, sigma1=0.0)
    models["lugre"] = EmpsModel(
        "lugre", strib["M"], off_s, lugre, delay,
        "plus LuGre pre-sliding, bristle stiffness fitted in closed loop")
    ident = {
        "reference": ref_est.to_dict(),
        "asymmetric": asym_est.to_dict(),
        "asymmetric_delay": asym_d.to_dict(),
        "asymmetric_stribeck_delay": strib.to_dict(),
        "fitted_delay_samples": delay,
        "fitted_sigma0_N_per_m": s0,
        "reference_vs_published_percent": {
            k: 100.0 * (ref_est[k] - v) / abs(v)
            for k, v in PUBLISHED["identification"].items() if k in ref_est.names
        },
    }
    return ident, models


def published_time_base(rec: EmpsRecord) -> tuple[float, np.ndarray]:
    """Controller period and reference of the published simulation script.

    The script runs its controller with ``tec = t(10) - t(9)`` and compares sample by
    sample with the measurement.

    Parameters
    ----------
    rec : EmpsRecord
        The data [-].

    Returns
    -------
    tuple
        ``(tec [s], reference position at k * tec [m])``.
    """
    tec = float(rec.t[9] - rec.t[8])
    return tec, np.interp(np.arange(rec.t.size) * tec, rec.t, rec.qg)


def evaluate(rec: EmpsRecord, models: dict, n_sub: int = N_SUB) -> dict:
    """Closed-loop errors of every model on one data set.

    Parameters
    ----------
    rec : EmpsRecord
        Data set [-].
    models : dict
        ``{name: EmpsModel}`` [-].
    n_sub : int
        Sub-steps per sample [-].

    Returns
    -------
    dict
        Errors per model, the reference simulated exactly as the published script does (its
        time base ``tec = t(10) - t(9)``), and which models beat the reference on which
        quantities [%, -].
    """
    meas = measured_signals(rec)
    sims = {name: simulate(rec, m, n_sub) for name, m in models.items()}
    errors = {name: relative_errors(rec, s, meas) for name, s in sims.items()}
    out = {"file": rec.name, "n_samples": int(rec.t.size), "errors_percent": errors}
    tec, ref_tb = published_time_base(rec)
    sim_tb = simulate(rec, models["reference"], n_sub, period=tec, ref=ref_tb)
    out["reference_published_script_percent"] = relative_errors(rec, sim_tb, meas)
    ref = errors["reference"]
    out["beats_reference"] = {
        name: [k for k in ("position", "velocity", "acceleration", "force") if e[k] < ref[k]]
        for name, e in errors.items() if name != "reference"
    }
    if rec.pulses is not None:
        out["vir_includes_pulses"] = vir_includes_pulses(rec)
    out["_sims"] = sims
    out["_meas"] = meas
    return out


def _is_reference(name: str) -> bool:
    """Whether a model is the reference (as published or converged), not an improvement."""
    return name.startswith("reference")


def _plot(path, rec, result, models):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    meas = result["_meas"]
    sims = result["_sims"]
    best = min((n for n in sims if not _is_reference(n)),
               key=lambda n: result["errors_percent"][n]["force"])
    fig, axs = plt.subplots(4, 1, sharex=True, figsize=(10, 10))
    for ax, key, mk, lab in zip(
        axs, ("q", "v", "a", "u"), ("q", "dq", "ddq", "force"),
        ("position [m]", "velocity [m/s]", "acceleration [m/s^2]", "force [N]"), strict=True,
    ):
        ax.plot(rec.t, meas[mk], "k", lw=0.8, label="measured")
        for name, c in (("reference", "tab:red"), (best, "tab:blue")):
            s = sims[name]
            y = rec.gtau * s.u_applied if key == "u" else getattr(s, key)
            ax.plot(rec.t, y, color=c, lw=0.6, label=name)
        ax.set_ylabel(lab)
        ax.grid(True)
    axs[0].legend(loc="best")
    axs[-1].set_xlabel("time [s]")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _clean(d):
    return {k: v for k, v in d.items() if not k.startswith("_")}


#: How the validation-file simulation differs from, or is not known to match, the
#: published Simulation_EMPS_Validation.m, whose Simulink model is not available here.
VALIDATION_DEFINITION = (
    "pulses added to the saturated controller output before the gain gtau, their unit "
    "(controller or newton) and whether vir holds them read from the data; the published "
    "validation (Simulation_EMPS_Validation.m with the Simulink model EMPS_Rigide_Pulse, "
    "PUBLISHED['validation_simulation']) is not available here, so where it injects the "
    "pulses and which force it compares are unknown: these figures are this definition's, "
    "not the published one's, and need not match it")


def _validate(path, ident: dict, models: dict, n_sub: int) -> tuple[dict, tuple]:
    """Evaluate the models and the reference inverse model on a validation file.

    Parameters
    ----------
    path : str or Path
        Validation file with ``pulses_N`` [-].
    ident : dict
        Identification results of :func:`identify` [-].
    models : dict
        ``{name: EmpsModel}`` [-].
    n_sub : int
        Sub-steps per sample [-].

    Returns
    -------
    tuple
        ``(validation section of the report, (record, evaluation))`` [-].
    """
    ref_est = ident["reference"]["parameters"]
    val, unit = pulses_in_controller_units(load_emps(path, need_pulses=True), ref_est)
    res_val = evaluate(val, models, n_sub)
    section = {
        **_clean(res_val), "pulses_unit": unit,
        "simulation_definition": VALIDATION_DEFINITION,
        "idim_cross_validation_benchmark_definition": idim_cross_validation(val, ref_est),
        "idim_force_error_applied_force_undecimated_percent":
            applied_force_error_undecimated(val, ref_est),
    }
    return section, (val, res_val)


def run(estimation, validation=None, n_sub: int = N_SUB) -> tuple[dict, dict]:
    """Identify on the estimation file, evaluate on both files.

    Parameters
    ----------
    estimation : str or Path
        Estimation file (``DATA_EMPS.mat``) [-].
    validation : str or Path, optional
        Validation file with ``pulses_N`` [-].
    n_sub : int
        Sub-steps per sample [-].

    Returns
    -------
    tuple of dict
        ``(report, raw)``: the JSON-ready report, and the records and simulations [-].
    """
    est = load_emps(estimation)
    ident, models = identify(est, n_sub)
    res_est = evaluate(est, models, n_sub)
    report = {
        "published": PUBLISHED,
        "models": {n: m.to_dict() for n, m in models.items()},
        "estimation": {"identification": ident, **_clean(res_est)},
    }
    raw = {"estimation": (est, res_est), "models": models}
    if validation is not None:
        report["validation"], raw["validation"] = _validate(validation, ident, models, n_sub)
    best = {}
    for key in ("estimation", "validation"):
        if key in report:
            errs = report[key]["errors_percent"]
            ref = errs["reference"]
            winners = [n for n, e in errs.items() if not _is_reference(n)
                       and e["velocity"] < ref["velocity"] and e["force"] < ref["force"]]
            best[key] = min(winners, key=lambda n: errs[n]["force"]) if winners else None
    report["best_model"] = best
    return report, raw


def _print_errors(rows: dict) -> None:
    print(f"{'model':28s} {'position':>9s} {'velocity':>9s} {'accel.':>9s} {'force':>9s}")
    for n, e in rows.items():
        print(f"{n:28s} {e['position']:9.4f} {e['velocity']:9.4f} "
              f"{e['acceleration']:9.4f} {e['force']:9.4f}")


def _print_estimation(sec: dict) -> None:
    idp = sec["identification"]["reference"]
    print("IDIM-LS (published filter):")
    for n, p in idp["parameters"].items():
        pub = PUBLISHED["identification"][n]
        print(f"  {n:7s} {p['value']:10.4f} +/- {p['std']:.4f}   published {pub:9.4f}")
    print(f"  relative force error {idp['relative_error_percent']:.4f} %")
    print(f"  fitted delay {sec['identification']['fitted_delay_samples']:.2f} samples, "
          f"sigma0 {sec['identification']['fitted_sigma0_N_per_m']:.3g} N/m")
    errs = sec["errors_percent"]
    _print_errors({"published reference": PUBLISHED["simulation"],
                   "reference": errs["reference"],
                   "reference, published script": sec["reference_published_script_percent"],
                   **errs})
    print("(reference: sign(v) by Dormand-Prince steps of T/10 as published, on the data's "
          "time base; published script: also its tec = t(10) - t(9);\n converged: the "
          "same model solved exactly, python -m studies.emps_numerics shows the step study)")


def _print_validation(sec: dict) -> None:
    ctv = sec["idim_cross_validation_benchmark_definition"]
    pub = PUBLISHED["idim_cross_validation"]
    print(f"IDIM cross-test validation as Script_IDIM_LS_CTV.m (recorded gtau*vir, decimated "
          f"by {DECIMATION}): {ctv['relative_error_percent']:.4f} % (published "
          f"{pub['relative_error_percent']:.4f} %), error norm {ctv['error_norm_N']:.4f} N "
          f"({pub['error_norm_N']:.4f}), condition {ctv['condition_number']:.4f} "
          f"({pub['condition_number']:.4f})")
    print(f"  not the benchmark's figure: against the applied force (pulses included), every "
          f"sample: {sec['idim_force_error_applied_force_undecimated_percent']:.4f} %")
    errs = sec["errors_percent"]
    _print_errors({"published (other definition)": PUBLISHED["validation_simulation"],
                   "reference": errs["reference"],
                   "reference, script time base": sec["reference_published_script_percent"],
                   **errs})
    print(f"(simulated here: {sec['simulation_definition']})")


def _print_table(report):
    for key, show in (("estimation", _print_estimation), ("validation", _print_validation)):
        if key in report:
            print(f"\n== {key}: {report[key]['file']} ==")
            show(report[key])
    print(f"\nbest model (beats the reference on velocity and force): {report['best_model']}")


def main(argv=None) -> dict:
    """Command-line entry point.

    Parameters
    ----------
    argv : list of str, optional
        Arguments; default ``sys.argv[1:]`` [-].

    Returns
    -------
    dict
        The report (also printed, as JSON with ``--json``) [-].
    """
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--estimation", required=True, help="DATA_EMPS.mat")
    ap.add_argument("--validation", help="validation file with pulses_N")
    ap.add_argument("--json", action="store_true", help="print the report as JSON")
    ap.add_argument("--plot", metavar="FILE", help="save a comparison figure (needs matplotlib)")
    ap.add_argument("--substeps", type=int, default=N_SUB, help="mechanical sub-steps/sample")
    args = ap.parse_args(argv)
    report, raw = run(args.estimation, args.validation, args.substeps)
    if args.json:
        print(json.dumps(report, indent=2, default=_json_default))
    else:
        _print_table(report)
    if args.plot:
        rec, res = raw["estimation"]
        _plot(args.plot, rec, res, raw["models"])
    return report


def _json_default(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, float) and not math.isfinite(o):
        return None
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")


if __name__ == "__main__":
    try:
        main()
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        sys.exit(2)
