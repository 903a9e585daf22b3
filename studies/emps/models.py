"""The models of EMPS: closed-loop simulation, the benchmark's relative errors, the
reference model by IDIM-LS and the improvements fitted in closed loop."""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy import optimize

from tcpmm.mechanics.friction import LuGreFriction

from ..rigidaxis import friction_from_idim, idim_ls
from ..rigidaxis.simulator import DiscreteServo, RigidAxis, RigidServoResult, simulate_rigid_servo
from .forces import vir_includes_pulses
from .record import (
    DECIMATION,
    FILTER_CUTOFF_HZ,
    FILTER_ORDER,
    N_BORDER,
    N_SUB,
    PUBLISHED,
    PUBLISHED_STEPS,
    TAPS,
    U_MAX_V,
    EmpsModel,
    EmpsRecord,
    check_moves_both_ways,
    measured_signals,
)


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
    def score(d):
        m = EmpsModel(base.name, base.mass, base.offset, base.friction, float(d), "")
        return _score(relative_errors(rec, simulate(rec, m, n_sub), meas), ref_err)

    grid = np.linspace(0.0, 1.0, 11)
    costs = [score(d) for d in grid]
    i = int(np.argmin(costs))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    fine = np.arange(round(lo * n_sub), round(hi * n_sub) + 1) / n_sub
    best, cost = float(grid[i]), costs[i]
    for d in fine:
        c = score(d)
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
    check_moves_both_ways(rec, measured_signals(rec))
    ref_est = _reference_estimate(rec)
    models = {"reference": reference_model(rec, ref_est)}
    models["reference_converged"] = converged_reference(models["reference"])
    asym_est = idim_ls(rec.qm, rec.gtau * rec.vir, rec.dt, friction="asymmetric",
                       **_IDIM_SETTINGS)
    fr_a, off_a = friction_from_idim(asym_est)
    models["asymmetric"] = EmpsModel(
        "asymmetric", asym_est["M"], off_a, fr_a, 1.0,
        "asymmetric Coulomb and viscous friction (IDIM-LS), one-sample delay")
    fits = _closed_loop_models(rec, ref_est, models, n_sub)
    ident = {
        "reference": ref_est.to_dict(),
        "asymmetric": asym_est.to_dict(),
        "asymmetric_delay": fits["asymmetric_delay"].to_dict(),
        "asymmetric_stribeck_delay": fits["asymmetric_stribeck_delay"].to_dict(),
        "fitted_delay_samples": fits["delay"],
        "fitted_sigma0_N_per_m": fits["sigma0"],
        "reference_vs_published_percent": {
            k: 100.0 * (ref_est[k] - v) / abs(v)
            for k, v in PUBLISHED["identification"].items() if k in ref_est.names
        },
    }
    return ident, models


def _closed_loop_models(rec: EmpsRecord, ref_est, models: dict, n_sub: int) -> dict:
    """Add to ``models`` the improvements fitted in closed loop: the actuation delay, the
    asymmetric friction re-identified with the force aligned to it, a low-speed friction
    term and LuGre pre-sliding; the estimates, the delay [samples] and sigma0 [N/m]."""
    force = rec.gtau * rec.vir
    fr_ref, off_ref = friction_from_idim(ref_est)
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
    return {"asymmetric_delay": asym_d, "asymmetric_stribeck_delay": strib, "delay": delay,
            "sigma0": s0}


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
    # the script's clock starts at 0, the record's at its first sample
    return tec, np.interp(rec.t[0] + np.arange(rec.t.size) * tec, rec.t, rec.qg)


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
