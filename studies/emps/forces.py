"""The force of an EMPS record: the control law, where the validation file's pulses enter
and in what unit, and the reference inverse model's force error as the benchmark's
``Script_IDIM_LS_CTV.m`` computes it."""

from __future__ import annotations

import dataclasses

import numpy as np

from tcpmm.ident.frf import decimate

from .record import DECIMATION, N_BORDER, TAPS, U_MAX_V, EmpsRecord, measured_signals


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
