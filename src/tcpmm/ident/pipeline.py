"""Identification of a machine from a measurement bundle: FRFs, transfer-function fits and
the physical (grey-box) fit per axis, into a model that simulates like the built-in one."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._threads import limit_blas_threads
from ..model import Axis, Machine, Sensors
from ..servo.params import ServoParams
from .frf import reduced_frfs
from .metrics import fit_percent
from .physical import FRFData, PhysicalFit, fit_physical, model_frfs
from .tffit import fit_tf

#: Minimal orders (numerator, denominator, integrators) of the reduced models of the
#: five-inertia axis: G_M has the drive's three modes and the rigid-body integrator, and
#: a fitted delay for the drive's hold of the current; the poles of G_T are the
#: antiresonances of G_M (motor clamped); G_tcp = (G_t - G_h)/(G_t - G_b) is 4/4.
TF_ORDERS = {"G_M": (6, 6, 1), "G_T": (2, 6, 0), "G_tcp": (4, 4, 0)}
TF_DELAY = {"G_M": "fit"}
MIN_COHERENCE = 0.5


@dataclass
class AxisIdentification:
    """Everything identified for one axis.

    Parameters
    ----------
    name : str
        Axis name [-].
    frfs : dict
        Measured FRFs (``tcpmm.ident.frf.FRF``) [SI].
    tf_fits : dict
        Rational transfer-function fits per FRF [SI].
    physical : PhysicalFit
        Grey-box parameters with uncertainty [SI].
    axis : Axis
        The identified axis as it goes into the model file [SI].
    """

    name: str
    frfs: dict
    tf_fits: dict
    physical: PhysicalFit
    axis: Axis
    record: object = None
    friction: object = None

    def physical_response(self, name: str, f_hz) -> np.ndarray:
        """Response of the identified physical model as measured (with the drive's
        zero-order hold of the current) [SI]."""
        return model_frfs(
            self.axis.mechanics,
            {name: f_hz},
            self.axis.servo.current_bandwidth_hz,
            self.axis.servo.T_v,
        )[name]

    def quality(self) -> list[dict]:
        """Fit quality per transfer function: TF fit and physical model."""
        rows = []
        for k, frf in self.frfs.items():
            good = frf.coherence >= MIN_COHERENCE
            ph = self.physical_response(k, frf.freq_hz)
            tf = self.tf_fits.get(k)
            rows.append(
                {
                    "axis": self.name,
                    "tf": k,
                    "tf_order": "{}/{}{}".format(*TF_ORDERS[k][:2],
                                             " + 1/s" if TF_ORDERS[k][2] else ""),
                    "tf_fit_percent": tf.fit_percent if tf is not None else float("nan"),
                    "physical_fit_percent": fit_percent(frf.H[good], ph[good]),
                    "physical_rel_error": self.physical.rel_error.get(k, float("nan")),
                    "modes_hz": [round(float(f), 2) for f in tf.natural_freq_hz]
                    if tf is not None
                    else [],
                }
            )
        return rows


@dataclass
class Identification:
    """Identification of every axis of a bundle and the resulting machine model."""

    axes: dict
    machine: Machine
    meta: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """JSON summary: fit percentage per transfer function and physical parameters."""
        out = {}
        for name, a in self.axes.items():
            d = a.axis.mechanics.model_dump()
            out[name] = {
                "fit": {
                    q["tf"]: {k: v for k, v in q.items() if k not in ("axis", "tf")}
                    for q in a.quality()
                },
                "parameters": {
                    p: {"value": d[p], "std": a.physical.std.get(p)}
                    for p in a.physical.extra["names"]
                    if p in d
                },
                "undetermined": a.physical.undetermined,
                "current_bandwidth_hz": a.axis.servo.current_bandwidth_hz,
            }
            if a.friction is not None:
                out[name]["friction"] = {
                    k: {"value": float(v), "std": float(sd)}
                    for k, v, sd in zip(
                        a.friction.names, a.friction.values, a.friction.std, strict=True
                    )
                }
        return {"machine": self.machine.name, "axes": out}

    def parameters_table(self):
        """Identified parameters with standard deviations, all axes."""
        import pandas as pd

        return pd.concat(
            [a.physical.to_pandas().assign(axis=n) for n, a in self.axes.items()], ignore_index=True
        )

    def quality_table(self):
        """Fit quality, all axes and transfer functions."""
        import pandas as pd

        return pd.DataFrame([q for a in self.axes.values() for q in a.quality()])

    def write_report(self, out_dir) -> dict:
        """Sweep time plots (Fig. 7), measured and fitted Bode plots with coherence
        (Figs. 8-10) and the tables, into a folder. Returns the written paths."""
        from ..io.atomic import write_text_atomic
        from ..plot.bode import plot_bode
        from ..plot.ident import plot_sweep

        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        files = {}
        for name, a in self.axes.items():
            if a.record is not None:
                files[f"sweep_{name}"] = plot_sweep(
                    a.record, a.axis.mechanics.R_L, out / f"sweep_{name}.png", title=name
                )
            curves = {}
            for k, frf in a.frfs.items():
                f = frf.freq_hz
                items = [("Exp", f, frf.H, {"color": "tab:blue"}, frf.coherence)]
                if k in a.tf_fits:
                    items.append(
                        ("TF fit", f, a.tf_fits[k].freqresp(f), {"color": "tab:green", "ls": ":"})
                    )
                items.append(
                    (
                        "ID (physical)",
                        f,
                        a.physical_response(k, f),
                        {"color": "tab:red", "ls": "--"},
                    )
                )
                curves[k] = items
            files[f"bode_{name}"] = plot_bode(
                curves, out / f"bode_{name}.png", title=f"axis {name}: measured and identified"
            )
        q, p = self.quality_table(), self.parameters_table()
        q.to_csv(out / "fit_quality.csv", index=False)
        p.to_csv(out / "parameters.csv", index=False)
        write_text_atomic(out / "identification.json", json.dumps(self.to_dict(), indent=2))
        files.update(
            quality=out / "fit_quality.csv",
            parameters=out / "parameters.csv",
            json=out / "identification.json",
        )
        return files


def axis_config_to_servo(cfg, current_bandwidth_hz=None) -> ServoParams:
    """Servo parameters from a bundle's axis configuration."""
    s = cfg.servo
    return ServoParams.create(
        position_feedback=s.position_feedback,
        K_pp=s.position_gain_1_per_s,
        K_vp=s.velocity_gain_A_s_per_rad,
        K_vi=s.velocity_integral_gain_A_per_rad,
        k_ff=s.velocity_feedforward,
        T_p=s.position_loop_period_s,
        T_v=s.velocity_loop_period_s,
        current_limit=s.current_limit_A,
        current_bandwidth_hz=current_bandwidth_hz,
    )


def axis_config_to_sensors(cfg) -> Sensors:
    """Sensor resolutions from a bundle's axis configuration."""
    s = cfg.sensors
    return Sensors(
        encoder_counts_per_rev=s.encoder_counts_per_rev,
        scale_resolution=s.scale_resolution_m,
        tcp_resolution=s.tcp_resolution_m or 0.0,
    )


def _weights(frf) -> np.ndarray:
    w = 1.0 / np.maximum(frf.rel_std, 0.01)
    return np.where(frf.coherence >= MIN_COHERENCE, w, 0.0)


#: Share of the identified friction put on the guideway, the rest on the screw. Steady
#: runs measure their sum only: the screw windup and nut deflection that would tell them
#: apart are below a micrometre, under the sensors' resolution. The split matters for the
#: TCP (guideway friction reverses the nut force that drives the structure; screw friction
#: does not), so it is a prior: preloaded, sealed linear guides usually carry most of it.
GUIDEWAY_SHARE = 0.7


def identify_friction(record, cfg, mechanics, guideway_share: float = GUIDEWAY_SHARE):
    """Stribeck friction of an axis from its ``friction.csv`` record, in table units.

    The steady motor force at constant speed balances all friction; it is shared between
    guideway and screw by ``guideway_share`` [-]. The viscous part that the linear
    mechanics already carries (``B_m``, ``B_L``, ``C_t``) is taken off.

    Returns
    -------
    AxisFriction, ParameterEstimate
        The friction element and the fitted curve with standard deviations [-].
    """
    from ..mechanics.friction import StribeckFriction
    from ..model import AxisFriction
    from .friction import friction_record_arrays, identify_stribeck_run

    t, x, force = friction_record_arrays(record, cfg.lead_m, cfg.torque_constant)
    est, _ = identify_stribeck_run(t, x, force)
    v = dict(zip(est.names, est.values, strict=True))
    m = mechanics
    linear = (m.B_m + m.B_L) / m.R_L**2 + m.C_t
    fv = max(float(v["Fv"]) - linear, 0.0)

    def part(k):
        return StribeckFriction(
            fc_pos=k * max(v["Fc+"], 0.0), fc_neg=k * max(v["Fc-"], 0.0),
            fs_pos=k * max(v["Fs+"], 0.0), fs_neg=k * max(v["Fs-"], 0.0),
            vs=max(float(v["vs"]), 1e-6), fv_pos=k * fv, fv_neg=k * fv)

    share = min(max(guideway_share, 0.0), 1.0)
    return AxisFriction(guideway=part(share) if share > 0 else None,
                        screw=part(1 - share) if share < 1 else None), est


def identify_axis(
    name: str, sweep, cfg, fmin_hz=None, fmax_hz=None, fit_current_loop: bool = True,
    friction=None, guideway_share: float = GUIDEWAY_SHARE,
) -> AxisIdentification:
    """Identify one axis from its sweep record and its known configuration.

    Parameters
    ----------
    name : str
        Axis name [-].
    sweep : SweepRecord
        Servo-excitation record (SI) [-].
    cfg : AxisConfig
        What the user knows: lead, torque constant, servo, sensors [-].
    fmin_hz, fmax_hz : float, optional
        Band of the FRFs [Hz].
    fit_current_loop : bool
        Also fit a first-order current-loop bandwidth from G_M [-].
    friction : FrictionRecord, optional
        Constant-velocity runs; their Stribeck curve becomes the axis friction [-].
    guideway_share : float
        Share of that friction put on the guideway, the rest on the screw [-].
    """
    limit_blas_threads()
    fmin = fmin_hz if fmin_hz is not None else max(2.0, 8.0 / sweep.duration_s)
    fmax = fmax_hz  # default: the bins the excitation reaches
    frfs = reduced_frfs(
        sweep.excitation_A,
        sweep.current_cmd_A,
        sweep.motor_angle_rad,
        sweep.scale_m,
        sweep.tcp_m,
        time_s=sweep.time_s,
        fmin_hz=fmin,
        fmax_hz=fmax,
        file=sweep.source,
    )
    tf_fits = {}
    for k, frf in frfs.items():
        nn, nd, ni = TF_ORDERS[k]
        if (frf.coherence >= MIN_COHERENCE).sum() > 2 * (nn + nd + 2):
            tf_fits[k] = fit_tf(frf, nn, nd, n_integrators=ni, delay_s=TF_DELAY.get(k),
                                min_coherence=MIN_COHERENCE)
    data = {k: FRFData(f.freq_hz, f.H, _weights(f)) for k, f in frfs.items()}
    phys: PhysicalFit = fit_physical(
        data,
        cfg.lead_m,
        cfg.torque_constant,
        fit_current_loop=fit_current_loop,
        tf_fits=tf_fits,
        hold_period_s=cfg.servo.velocity_loop_period_s,
    )
    fr, est = (
        identify_friction(friction, cfg, phys.mechanics, guideway_share)
        if friction is not None else (None, None)
    )
    axis = Axis(
        mechanics=phys.mechanics,
        servo=axis_config_to_servo(cfg, phys.extra.get("current_bandwidth_hz")),
        sensors=axis_config_to_sensors(cfg),
        friction=fr,
    )
    return AxisIdentification(name, frfs, tf_fits, phys, axis, sweep, est)


def identify_bundle(
    bundle, fmin_hz=None, fmax_hz=None, progress=None, fit_current_loop: bool = True,
    guideway_share: float = GUIDEWAY_SHARE,
) -> Identification:
    """Identify every axis of a measurement bundle.

    Parameters
    ----------
    bundle : Bundle
        Read with :func:`tcpmm.io.bundle.read_bundle` [-].
    fmin_hz, fmax_hz : float, optional
        Band of the FRFs [Hz].
    progress : callable, optional
        Called with the axis name after each axis [-].
    fit_current_loop : bool
        Fit a first-order current-loop bandwidth per axis [-].
    guideway_share : float
        Share of the friction put on the guideway, the rest on the screw [-].
    """
    axes = {}
    for name, rec in bundle.axes.items():
        cfg = bundle.machine.axes[name]
        axes[name] = identify_axis(
            name, rec.sweep, cfg, fmin_hz, fmax_hz, fit_current_loop, rec.friction,
            guideway_share,
        )
        if progress is not None:
            progress(name)
    machine = Machine(
        name=f"{bundle.machine.name} (identified)", axes={n: a.axis for n, a in axes.items()}
    )
    return Identification(axes, machine, {"source": str(getattr(bundle, "path", ""))})
