"""Identification of a machine from a measurement bundle: FRFs, transfer-function fits and
the physical (grey-box) fit per axis, into a model that simulates like the built-in one."""

from __future__ import annotations

import json
from dataclasses import dataclass, field, replace
from functools import partial

import numpy as np

from .._threads import limit_blas_threads
from ..errors import InputError
from ..mechanics.friction import friction_params_array
from ..mechanics.lumped import AxisMechanics
from ..model import Axis, Machine, Sensors
from ..servo.params import ServoParams
from ..sim.contact import sliding_friction
from .frf.response import reduced_frfs
from .frf.wholerecord import reduced_with_whole_record
from .friction.nutstiffness import LOST_MOTION_Z
from .friction.playdf import nut_deflection_amplitude, play_gain, sweep_motion
from .friction.presliding import PRESLIDING, with_presliding
from .friction.preslidingfit import PreslidingFit, fit_presliding
from .friction.sensitivity import (
    LostMotionSensitivity,
    PreslidingSensitivity,
    ShareSensitivity,
    warn_lost_motion_sensitivity,
    warn_presliding_sensitivity,
    warn_share_sensitivity,
)
from .friction.split import (
    identify_friction,
    place_steady_viscous,
    share_uncertainty_warning,
    stribeck_from_record,
)
from .friction.sweepforce import sweep_deflection, travel_velocity
from .gates.columns import check_record_units
from .gates.findings import (
    SuspectModelError,
    axis_findings,
    time_base_findings,
    trimmed_fit_percent,
)
from .gates.sanity import FrictionHold, warn_friction_holds_sweep, warn_unstable_sampled_loop
from .lti.goodness import fit_percent
from .lti.tffit import fit_tf
from .physical.greybox import FRFData, PhysicalFit, SweepPlay, fit_physical, model_frfs
from .physical.loop_timing import COMPUTATION_DELAY, LoopTiming, sampled_in_step, sweep_timing
from .physical.structure import fit_structure
from .physical.uncertainty import axis_uncertainty

#: Minimal orders (numerator, denominator, integrators) of the reduced models of the
#: five-inertia axis: G_M has the drive's three modes and the rigid-body integrator, and
#: a fitted delay for the drive's hold of the current; the poles of G_T are the
#: antiresonances of G_M (motor clamped); G_tcp = (G_t - G_h)/(G_t - G_b) is 4/4.
TF_ORDERS = {"G_M": (6, 6, 1), "G_T": (2, 6, 0), "G_tcp": (4, 4, 0)}
TF_DELAY = {"G_M": "fit"}
MIN_COHERENCE = 0.5
#: Refits of the mechanics with the nut's lost motion as the sweep saw it; each one takes
#: the nut deflection through the torsion of the previous fit. They can swing about their
#: fixed point before they settle (M_t 1.34 -> 1.10 -> 1.04 -> 1.09 -> 1.05 -> 1.06 of the
#: truth on one axis, self-consistent from the fourth) [-].
PLAY_ITERATIONS = 8
#: A refit with the play counts only when it is a solution of its own describing function:
#: its table mass and the nut stiffness of the runs on it within this of those the
#: describing function was computed with. Where the FRFs barely fix the table mass, the
#: refits wander (0.9 -> 1.26 -> 0.56 -> 0.79 of the truth on one axis), and the least
#: cost among them is chance [-].
SELF_CONSISTENT_REL = 0.05
#: ... and the nut stiffness the FRFs give through the play's factor within this of the one
#: the factor was computed with (the friction runs'): 4-12 % on one unseen axis whose refits
#: settle (M_t 1.04-1.08 of the truth), 1.8-5.8 times on one where they wander, one of
#: them a false fixed point at M_t 0.45 of the truth with a nut fitted 5.8 times stiffer
#: than the factor assumed [-].
FITTED_STIFFNESS_REL = 0.25
#: Refits stop once one comes back within this of the fit before it: the next would
#: repeat it [-].
CONVERGED_REL = 0.01
#: A refit with the play replaces the linear fit only when it explains the FRFs better by
#: more than this share of the linear fit's cost: a tie is not decided by rounding [-].
COST_MARGIN_REL = 0.01
#: Travel over a sweep record below which it counts as standing still: the guideway
#: friction then holds the nut on no particular flank [m].
MIN_SWEEP_TRAVEL_M = 1e-3


@dataclass
class AxisIdentification:
    """Everything identified for one axis.

    Parameters
    ----------
    name : str
        Axis name [-].
    frfs : dict
        Measured FRFs (``tcpmm.ident.frf.response.FRF``) [SI].
    tf_fits : dict
        Rational transfer-function fits per FRF [SI].
    physical : PhysicalFit
        Grey-box parameters with uncertainty [SI].
    axis : Axis
        The identified axis as it goes into the model file [SI].
    record : SweepRecord, optional
        The sweep record, for the time plots [SI].
    friction : ParameterEstimate, optional
        Stribeck curve fitted to the friction runs [-].
    friction_split : FrictionSplit, optional
        Split of that friction between guideway and screw, and the lost motion [-].
    friction_hold : FrictionHold, optional
        Friction held the axis at the bottom of the sweep's band (a warning said so) [-].
    sampled_loop_spectral_radius : float, optional
        Spectral radius of the identified loop as the drive samples it (below 1:
        stable) [-].
    presliding_m : float, optional
        Pre-sliding displacement given to the identified friction contacts [m].
    presliding_fit : PreslidingFit, optional
        The fit of that displacement to the reversals of the friction runs, when it was
        not given [-].
    loop_timing : LoopTiming, optional
        Computation delay and velocity estimate read from a closed-loop sweep [-].
    share_sensitivity : ShareSensitivity, optional
        How far the TCP spikes move over a guideway share the runs leave open [m].
    lost_motion_sensitivity : LostMotionSensitivity, optional
        How far they move with a lost motion the runs would not find [m].
    presliding_sensitivity : PreslidingSensitivity, optional
        How far they move over the pre-sliding distances the fit leaves [m].
    """

    name: str
    frfs: dict
    tf_fits: dict
    physical: PhysicalFit
    axis: Axis
    record: object = None
    friction: object = None
    friction_split: object = None
    friction_hold: FrictionHold | None = None
    sampled_loop_spectral_radius: float | None = None
    presliding_m: float | None = None
    presliding_fit: PreslidingFit | None = None
    loop_timing: LoopTiming | None = None
    share_sensitivity: ShareSensitivity | None = None
    lost_motion_sensitivity: LostMotionSensitivity | None = None
    presliding_sensitivity: PreslidingSensitivity | None = None

    def _as_measured(self, mechanics, name: str, f_hz) -> np.ndarray:
        return model_frfs(mechanics, {name: f_hz}, self.axis.servo.current_bandwidth_hz,
                          _current_hold(self.record, self.axis.servo.T_v),
                          self.physical.nut_gain)[name]

    def notes(self) -> dict:
        """What identification found on the way besides the parameters, for the JSON
        report: the play the sweep crossed, friction holding the sweep, the sampled loop's
        spectral radius, pre-sliding and its fit, loop timing and the spikes'
        sensitivities [SI]."""
        found = {"sweep_play": self.physical.sweep_play,
                 "friction_holds_sweep": self.friction_hold,
                 "sampled_loop_spectral_radius": self.sampled_loop_spectral_radius,
                 "presliding_m": self.presliding_m, "presliding_fit": self.presliding_fit,
                 "loop_timing": self.loop_timing,
                 "share_sensitivity": self.share_sensitivity,
                 "lost_motion_sensitivity": self.lost_motion_sensitivity,
                 "presliding_sensitivity": self.presliding_sensitivity}
        return {k: v.to_dict() if hasattr(v, "to_dict") else v
                for k, v in found.items() if v is not None}

    def physical_response(self, name: str, f_hz) -> np.ndarray:
        """Response of the identified physical model as measured (with the drive's
        zero-order hold of the current, and the nut as soft as the sweep saw it when it
        crossed the play) [SI]."""
        return self._as_measured(self.axis.mechanics, name, f_hz)

    def fitted_response(self, name: str, f_hz) -> np.ndarray:
        """Response of the physical fit to the FRFs itself, before the friction runs'
        nut stiffness and viscous placement replace its values, as measured [SI]."""
        return self._as_measured(self.physical.mechanics, name, f_hz)

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
                    # on the logarithm, as the fit and the gates judge it: a resonance a
                    # few bins off does not outweigh the band
                    "physical_log_fit_percent": trimmed_fit_percent(frf.H[good], ph[good]),
                    "physical_rel_error": self.physical.rel_error.get(k, float("nan")),
                    "modes_hz": [round(float(f), 2) for f in tf.natural_freq_hz]
                    if tf is not None
                    else [],
                }
            )
        return rows


@dataclass
class Identification:
    """Identification of every axis of a bundle and the resulting machine model.

    Parameters
    ----------
    axes : dict
        :class:`AxisIdentification` per axis name [-].
    machine : Machine
        The identified model; it carries the findings as ``suspect`` marks [SI].
    meta : dict
        Where it came from [-].
    findings : list of Finding
        What the gates (:mod:`tcpmm.ident.gates`) found physically suspect; non-empty only
        when identification was told to accept a suspect model [-].
    """

    axes: dict
    machine: Machine
    meta: dict = field(default_factory=dict)
    findings: list = field(default_factory=list)

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
                    for p in a.physical.names
                    if p in d
                },
                "undetermined": a.physical.undetermined,
                "current_bandwidth_hz": a.axis.servo.current_bandwidth_hz,
                **a.notes(),
            }
            if a.friction is not None:
                out[name]["friction"] = {
                    k: {"value": float(v), "std": float(sd)}
                    for k, v, sd in zip(
                        a.friction.names, a.friction.values, a.friction.std, strict=True
                    )
                }
            if a.friction_split is not None:
                out[name]["friction_split"] = a.friction_split.to_dict()
        return {"machine": self.machine.name, "axes": out,
                "suspect": [str(f) for f in self.findings]}

    def bode_curves(self, name: str) -> dict:
        """Measured FRFs with coherence, TF fits and the physical model's response of axis
        ``name``, as :func:`tcpmm.plot.bode.plot_bode` draws them [-].

        Parameters
        ----------
        name : str
            Axis name [-].
        """
        a = self.axes[name]
        curves = {}
        for k, frf in a.frfs.items():
            f = frf.freq_hz
            items = [("Exp", f, frf.H, {"color": "tab:blue"}, frf.coherence)]
            if k in a.tf_fits:
                items.append(("TF fit", f, a.tf_fits[k].freqresp(f),
                              {"color": "tab:green", "ls": ":"}))
            items.append(("ID (physical)", f, a.physical_response(k, f),
                          {"color": "tab:red", "ls": "--"}))
            curves[k] = items
        return curves

    def plot(self, axis: str | None = None, ax=None, path=None):
        """Measured and identified Bode plots of one axis (paper Figs. 8-10); the figure.

        Parameters
        ----------
        axis : str, optional
            Axis name; the first axis when omitted [-].
        ax : array-like of matplotlib Axes, optional
            Two per transfer function (magnitudes, then phases); a new figure when
            omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        """
        from ..plot.bode import plot_bode

        name = axis if axis is not None else next(iter(self.axes))
        if name not in self.axes:
            raise InputError(f"no axis {name!r} in this identification "
                             f"(axes: {', '.join(self.axes)})")
        return plot_bode(self.bode_curves(name), path,
                         title=f"axis {name}: measured and identified", ax=ax)

    def to_pandas(self):
        """Identified parameters with standard deviations, all axes (as
        :meth:`parameters_table`) [-]."""
        return self.parameters_table()

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
        (Figs. 8-10), the plateau deflections of the friction runs and the tables, into a
        folder. Returns the written paths."""
        from ..io.atomic import output_folder, write_table_atomic, write_text_atomic
        from ..plot.ident import plot_lost_motion, plot_sweep

        out = output_folder(out_dir)
        files = {}
        for name, a in self.axes.items():
            if a.record is not None:
                files[f"sweep_{name}"] = out / f"sweep_{name}.png"
                plot_sweep(a.record, a.axis.mechanics.R_L, files[f"sweep_{name}"], title=name)
            split = a.friction_split
            if split is not None and split.estimate is not None and split.estimate.velocity.size:
                files[f"lostmotion_{name}"] = out / f"lostmotion_{name}.png"
                plot_lost_motion(split.estimate, files[f"lostmotion_{name}"],
                                 title=f"axis {name}: deflection between encoder and scale "
                                       f"({split.source})")
            files[f"bode_{name}"] = out / f"bode_{name}.png"
            self.plot(name, path=files[f"bode_{name}"])
        q, p = self.quality_table(), self.parameters_table()
        write_table_atomic(q, out / "fit_quality.csv")
        write_table_atomic(p, out / "parameters.csv")
        write_text_atomic(out / "identification.json", json.dumps(self.to_dict(), indent=2))
        files.update(
            quality=out / "fit_quality.csv",
            parameters=out / "parameters.csv",
            json=out / "identification.json",
        )
        return files


def axis_config_to_servo(cfg, current_bandwidth_hz=None, timing=None) -> ServoParams:
    """Servo parameters from a bundle's axis configuration, with the computation delay and
    the velocity estimate read from the sweep (``timing``, a
    :class:`~tcpmm.ident.physical.loop_timing.LoopTiming`) or, without it, those of
    :data:`COMPUTATION_DELAY` and a differenced encoder angle."""
    s = cfg.servo
    delay, kind = COMPUTATION_DELAY, "difference"
    if timing is not None and timing.determined:
        delay, kind = timing.delay_samples, timing.velocity_feedback
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
        delay_samples=delay,
        velocity_feedback=kind,
        feedforward="segment",
        filters=list(s.current_setpoint_filters),
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


#: Largest relative standard deviation of the identified ``B_m``, ``B_L`` and ``C_t`` for
#: which the friction split takes them as known; a few per cent of ``C_t`` already moves the
#: share by 0.02, so otherwise the speed-proportional deflection is fitted [-].
DAMPING_KNOWN_REL_STD = 0.03


def identify_axis(
    name: str, sweep, cfg, fmin_hz=None, fmax_hz=None, fit_current_loop: bool = True,
    friction=None, guideway_share: float | None = None, presliding: float | None = None,
) -> AxisIdentification:
    """Identify one axis from its sweep record and its known configuration.

    With friction runs that show lost motion in the nut and a sweep that travels, the
    mechanics are fitted again with the nut as soft as the sweep saw it (the describing
    function of the play at the measured nut deflection, the guideway friction holding the
    nut on one flank; :mod:`tcpmm.ident.friction.playdf`), and the friction on those mechanics.

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
    guideway_share : float, optional
        Share of that friction put on the guideway, the rest on the screw; ``None``: from
        the friction runs (encoder-minus-scale deflection) [-].
    presliding : float, optional
        Pre-sliding displacement given to the identified contacts (LuGre); ``0``: static
        friction that sticks rigidly; ``None``: fitted to the reversals of the friction
        runs (:mod:`tcpmm.ident.friction.preslidingfit`), or :data:`PRESLIDING` where they
        do not determine it [m].
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
    velocity = travel_velocity(sweep, MIN_SWEEP_TRAVEL_M)
    v_travel = abs(velocity)
    held = warn_friction_holds_sweep(name, sweep, frfs["G_M"], MIN_COHERENCE,
                                     standing=v_travel == 0.0)
    if v_travel == 0.0:
        from ..io.csvutil import warn_input
        from .gates.findings import STANDING_SWEEP

        warn_input(f"axis {name}: {STANDING_SWEEP}; the model fitted to it can be off by "
                   "micrometres at the reversals", file=getattr(sweep, "source", None))
    tf_fits = _tf_fits(frfs)
    data = {k: FRFData(f.freq_hz, f.H, _weights(f)) for k, f in frfs.items()}
    fit_on = _physical_fit_on(cfg, fit_current_loop, tf_fits,
                              _current_hold(sweep, cfg.servo.velocity_loop_period_s))
    phys: PhysicalFit = fit_on(data)()
    kept = AxisFit(phys, phys.mechanics)
    presliding_m = presliding_fit = None
    if friction is not None:
        friction_on = partial(_friction_and_mechanics, name, friction, cfg,
                              guideway_share=guideway_share,
                              sweep=sweep_deflection(sweep, velocity))
        kept = _fit_with_friction(name, sweep, data, fit_on, friction_on, phys, v_travel,
                                  (fmin, fmax), partial(_whole_record_data, sweep, frfs))
        message = share_uncertainty_warning(name, kept.split, kept.curve, kept.mechanics, cfg)
        if message is not None:
            from ..io.csvutil import warn_input

            warn_input(message, file=getattr(friction, "source", None))
        fr, presliding_m, presliding_fit = _presliding(kept.friction, kept.mechanics, friction,
                                                       presliding)
        kept = replace(kept, friction=fr)
    phys = kept.physical
    timing = sweep_timing(name, sweep, cfg)
    axis = Axis(
        mechanics=kept.mechanics,
        servo=axis_config_to_servo(cfg, phys.current_bandwidth_hz, timing),
        sensors=axis_config_to_sensors(cfg),
        friction=kept.friction,
        uncertainty=axis_uncertainty(phys, kept.mechanics, kept.curve, kept.split,
                                     presliding_fit),
    )
    return AxisIdentification(
        name, frfs, tf_fits, phys, axis, sweep, kept.curve, kept.split, friction_hold=held,
        sampled_loop_spectral_radius=warn_unstable_sampled_loop(name, axis, phys.undetermined),
        presliding_m=presliding_m, presliding_fit=presliding_fit, loop_timing=timing)


def _presliding(fr, mech, record, presliding):
    """The friction with its pre-sliding, given or fitted, the distance used [m] and the
    fit when there was one."""
    if presliding is not None:
        return with_presliding(fr, mech, presliding), presliding, None
    fit = fit_presliding(record, mech, fr)
    if not fit.determined:
        return with_presliding(fr, mech, PRESLIDING), PRESLIDING, fit
    return with_presliding(fr, mech, fit.presliding, fit.damping_ratio), fit.presliding, fit


@dataclass(frozen=True)
class AxisFit:
    """A physical fit with the friction runs' results on it: one candidate for an axis.

    Parameters
    ----------
    physical : PhysicalFit
        The fit to the FRFs [SI].
    mechanics : AxisMechanics
        The mechanics as they go into the model: the fit's, with the nut stiffness and the
        steady viscous force the friction runs give [SI].
    friction : AxisFriction, optional
        The friction of the runs, split between guideway and screw [-].
    curve : ParameterEstimate, optional
        The Stribeck curve of the runs [-].
    split : FrictionSplit, optional
        The split and the lost motion [-].
    """

    physical: PhysicalFit
    mechanics: AxisMechanics
    friction: object = None
    curve: object = None
    split: object = None

    @property
    def cost(self) -> float:
        """Least-squares cost of the physical fit [-]."""
        return self.physical.cost


def _tf_fits(frfs: dict) -> dict:
    """Rational fits of the orders of :data:`TF_ORDERS` to the FRFs with enough coherent
    bins for them [SI]."""
    tf_fits = {}
    for k, frf in frfs.items():
        nn, nd, ni = TF_ORDERS[k]
        if (frf.coherence >= MIN_COHERENCE).sum() > 2 * (nn + nd + 2):
            tf_fits[k] = fit_tf(frf, nn, nd, n_integrators=ni, delay_s=TF_DELAY.get(k),
                                min_coherence=MIN_COHERENCE)
    return tf_fits


def _current_hold(record, T_v: float) -> float:
    """Hold of the current command that ``G_M`` carries beyond the record (``None``: a
    record sampled at the ticks) of a loop of period ``T_v`` [s].

    A record sampled at the velocity-loop ticks holds the command values, and the drive
    holds each over the period that follows: ``G_M`` from the samples carries that
    hold. A record that reads the held current on a clock of its own already holds the
    staircase the motor is driven by: modelled with the hold as well, reference machines
    C, D and E (10 kHz records of an 8 kHz loop) came out with every inertia, mass and
    stiffness 0.4-2.3 % high, and E's F10000 contour 0.56 um off (0.46 without)."""
    return T_v if record is None or sampled_in_step(record.fs_hz, T_v) else 0.0


def _physical_fit_on(cfg, fit_current_loop: bool, tf_fits: dict, hold_period_s: float):
    """``fit_on(data)``: :func:`fit_physical` on the FRFs ``data`` with the axis's known
    values bound; called with the remaining keywords (start, structure, nut) [-]."""
    def fit_on(data: dict):
        return partial(fit_physical, data, cfg.lead_m, cfg.torque_constant,
                       fit_current_loop=fit_current_loop, tf_fits=tf_fits,
                       hold_period_s=hold_period_s)

    return fit_on


def _whole_record_data(sweep, frfs: dict) -> dict:
    """The FRFs weighed against their estimates from the whole record, as fit data
    (:func:`~tcpmm.ident.frf.wholerecord.reduced_with_whole_record`)."""
    f = reduced_with_whole_record(frfs, sweep.excitation_A, sweep.current_cmd_A,
                                  sweep.motor_angle_rad, sweep.scale_m, sweep.tcp_m)
    return {k: FRFData(v.freq_hz, v.H, _weights(v)) for k, v in f.items()}


def _fit_with_friction(name: str, sweep, data: dict, fit_on, friction_on, phys: PhysicalFit,
                       v_travel: float, band: tuple, whole=None) -> AxisFit:
    """The friction runs on the physical fit; with lost motion that the sweep crosses, the
    structure held at what ``G_tcp`` alone says and the refits with the play
    (:func:`_refit_with_play`), or a warning where the play cannot be modelled.

    Parameters
    ----------
    name : str
        Axis name [-].
    sweep : SweepRecord
        The sweep record [-].
    data : dict
        The FRFs to fit, :class:`FRFData` per name [SI].
    fit_on : callable
        ``fit_on(data)``: :func:`fit_physical` with those FRFs and the axis's known values
        bound [-].
    friction_on : callable
        :func:`_friction_and_mechanics` with the runs bound [-].
    phys : PhysicalFit
        The linear fit [SI].
    v_travel : float
        Steady travel speed of the sweep, 0 when it stands [m/s].
    band : tuple
        ``(fmin_hz, fmax_hz)`` of the FRFs [Hz].
    whole : callable, optional
        ``whole()``: the FRFs weighed against the whole record, for the fits of an axis
        with a TCP record whose sweep does not cross lost motion; worked out only there
        [-].
    """
    kept = AxisFit(phys, *friction_on(phys))
    structure, fit = None, fit_on(data)
    if "G_tcp" in data:
        # G_tcp does not see the nut force, so nothing that distorts G_M and G_T (lost
        # motion crossed by the sweep, the friction it travels against, a drive mode the
        # model lacks) reaches it: hold the bed and TCP structure at what G_tcp alone
        # says, relative to the table. A joint fit let G_M and G_T pull the head damping
        # 12-16 % above what G_tcp alone gives. The segments cut the ringing of a lightly
        # damped mode, so from here on each FRF weighs in the whole record, except where
        # the sweep crosses the play: there the refits with the play, which swing about
        # their fixed point, stopped settling, and G_M and G_T went into other minima.
        if not (whole is None or _play_significant(kept.split)):
            data = whole()
            fit = fit_on(data)
        structure, _ = fit_structure(data["G_tcp"], [phys.mechanics])
        phys = fit(initial=_fit_values(phys), structure=structure)
        kept = AxisFit(phys, *friction_on(phys))
    bias = _bias_force(v_travel, kept.mechanics, kept.friction)
    if _play_significant(kept.split) and bias > 0:
        kept = _refit_with_play(sweep, fit, friction_on, kept, structure, v_travel, bias, band)
        if kept.physical.nut_gain is None:
            _warn_sweep_crosses_play(name, sweep, kept.split, modelled=True)
    elif kept.split.nut is not None or _play_significant(kept.split):
        _warn_sweep_crosses_play(name, sweep, kept.split)
    return kept


def _refit_with_play(sweep, fit, friction_on, kept: AxisFit, structure, v_travel: float,
                     bias: float, band: tuple) -> AxisFit:
    """Refit with the nut as soft as the sweep saw it, and keep whichever fit, linear or
    with the play, explains the FRFs best; a refit counts only if it agrees with the
    describing function it was fitted with (:data:`SELF_CONSISTENT_REL`).

    Parameters
    ----------
    sweep : SweepRecord
        The sweep record [-].
    fit, friction_on : callable
        As for :func:`_fit_with_friction` [-].
    kept : AxisFit
        The linear fit with the friction on it [SI].
    structure : dict or None
        Bed and TCP structure held in proportion to ``M_t`` [SI / kg].
    v_travel : float
        Steady travel speed of the sweep [m/s].
    bias : float
        Friction force holding the nut on one flank on the linear fit [N].
    band : tuple
        ``(fmin_hz, fmax_hz)`` of the FRFs [Hz].
    """
    best, current = kept, kept
    freq, theta_m, scale = sweep_motion(sweep, *band)
    for _ in range(PLAY_ITERATIONS):
        seen = current.mechanics
        amp = nut_deflection_amplitude(freq, theta_m, scale, seen)
        gain = play_gain(freq, amp, current.split.backlash, bias, seen.K_t)
        phys = fit(initial=_fit_values(current.physical) if structure else None,
                   nut_gain=gain, structure=structure)
        current = AxisFit(phys, *friction_on(phys))
        if (phys.cost < (1.0 - COST_MARGIN_REL) * best.cost
                and _self_consistent(seen, current.mechanics, fitted=phys.mechanics)):
            g = gain(freq)
            lowest = int(np.argmin(g))
            phys.sweep_play = SweepPlay(bias_force_N=bias, lowest_nut_gain=float(g[lowest]),
                                        at_hz=float(freq[lowest]),
                                        nut_amplitude_there_m=float(amp[lowest]))
            best = current
        bias = _bias_force(v_travel, current.mechanics, current.friction)
        converged = _self_consistent(seen, current.mechanics, CONVERGED_REL)
        if converged or not (_play_significant(current.split) and bias > 0):
            break
    return best


def _self_consistent(seen, mech, rel: float = SELF_CONSISTENT_REL, fitted=None) -> bool:
    """Whether a refit with the play's describing function came back to the table mass
    and nut stiffness the describing function was computed with, within ``rel`` [-].

    ``fitted``, the mechanics as the FRFs gave them before the friction runs replaced the
    nut stiffness, must also have the contact stiffness the describing function assumed:
    the fit scales ``K_t`` by the factor per frequency, and a fit that needs a nut several
    times stiffer than the one the factor was computed for is not a solution of it, even
    where the runs then hand back the same stiffness and table mass."""
    same = all(abs(getattr(mech, p) / getattr(seen, p) - 1.0) <= rel for p in ("M_t", "K_t"))
    return same and (fitted is None
                     or abs(fitted.K_t / seen.K_t - 1.0) <= FITTED_STIFFNESS_REL)


def _fit_values(phys: PhysicalFit) -> dict:
    """The values of a physical fit as a starting point for another [SI]."""
    start = phys.mechanics.model_dump()
    if phys.current_bandwidth_hz is not None:
        start["f_i"] = phys.current_bandwidth_hz
    return start


def _friction_and_mechanics(name: str, friction, cfg, phys: PhysicalFit, guideway_share,
                            sweep=None):
    """Friction from the runs on the mechanics of a physical fit, the nut stiffness and
    the steady viscous force placed."""
    mech = phys.mechanics

    def rel_std(p):
        sd = phys.std.get(p, float("nan"))
        return float(sd / getattr(mech, p)) if np.isfinite(sd) else float("inf")

    damping_known = all(rel_std(p) <= DAMPING_KNOWN_REL_STD for p in ("B_m", "B_L", "C_t"))
    fr, est, split = identify_friction(
        friction, cfg, mech, guideway_share, axis=name,
        stiffness_rel_std=_finite_or(rel_std("K_t"), 0.0),
        viscous="known" if damping_known else "fit",
        neglect_motor_bearing=not damping_known, sweep=sweep,
        K_h_rel_std=_finite_or(rel_std("K_h"), 0.0),
        C_t_std=_finite_or(phys.std.get("C_t", float("nan")), 0.0))
    if split.source != "prior" and not damping_known:
        # Motor-bearing damping does not twist the shaft, so with it the runs would put
        # less of the steady viscous force through the nut. A sweep does not tell it
        # from the rest of the damping (it came out up to 30 times too large): the
        # motor-bearing part is taken as negligible, which shifts the nut's share by
        # K_t B_m/K_L, a few per cent for usual bearings. (Without a split from the
        # data the viscous force is not placed, and the FRF damping stays.)
        mech = mech.replace(B_m=0.0)
    if split.nut is not None:
        # the nut in contact, as the accelerations of the friction runs show it
        mech = mech.replace(K_t=split.nut.stiffness)
    table_viscous = split.table_viscous
    if split.source != "prior" and np.isfinite(table_viscous) and "Fv" in est.names:
        mech, fr = place_steady_viscous(
            mech, fr, est.values[est.names.index("Fv")], table_viscous)
    return mech, fr, est, split


def _finite_or(x: float, default: float) -> float:
    """``x``, or ``default`` where it is not finite (an undetermined std) [-]."""
    return float(x) if np.isfinite(x) else default


def _play_significant(split, z: float = LOST_MOTION_Z) -> bool:
    """Whether the friction runs found lost motion beyond ``z`` standard deviations."""
    if split is None or not split.backlash > 0:
        return False
    if split.nut is not None:
        return split.nut.lost_motion_found(z)
    lm = split.estimate
    return bool(lm is not None and lm.determined and split.backlash > z * lm.backlash_std)


def _travel_speed(sweep) -> float:
    """Steady travel speed of a sweep record, zero when it travels less than
    :data:`MIN_SWEEP_TRAVEL_M` [m/s]."""
    return abs(travel_velocity(sweep, MIN_SWEEP_TRAVEL_M))


def _bias_force(v: float, mech, fr) -> float:
    """Friction force on the table at travel speed ``v``: it holds the nut on one flank of
    its play [N]. Zero without travel or guideway friction."""
    if v <= 0 or fr is None or fr.guideway is None:
        return 0.0
    return float(sliding_friction(v, friction_params_array(fr.guideway))) + mech.C_t * v


def _warn_sweep_crosses_play(name: str, sweep, split, modelled: bool = False) -> None:
    """Warn that the sweep crossed the nut's play and the mechanics fitted to it are
    those of a linear axis.

    Parameters
    ----------
    name : str
        Axis name [-].
    sweep : SweepRecord
        The sweep, for the file named in the warning [-].
    split : FrictionSplit
        The split of the kept fit: its lost motion and that estimate's std [m].
    modelled : bool
        The play was modelled in refits, none of which was kept [-].
    """
    from ..io.csvutil import warn_input

    remedy = ("no refit with the play modelled both fitted the FRFs better and came back to "
              "the table mass and nut stiffness its describing function was computed with, "
              "so the linear fit is kept"
              if modelled else "a sweep recorded while the axis travels at constant speed "
              "lets the play be modelled (the guideway friction holds the nut on one flank)")
    stiffness = ("The nut stiffness is taken from the friction runs" if split.nut is not None
                 else "The friction runs do not determine the nut stiffness either: K_t is "
                 "the sweep's, as soft as the play made it look")
    warn_input(
        f"axis {name}: the friction runs show {split.backlash * 1e6:.2f} +/- "
        f"{split.backlash_std * 1e6:.2f} um of lost motion in the nut, which the sweep crosses "
        "every cycle; around the axial modes its FRFs are not those of a linear axis, and "
        "the fitted split of inertia between motor side and table (M_t, and with it the "
        f"structure's M_b, K_b, M_h, K_h) can be off by tens of per cent. {stiffness}; "
        f"{remedy}. A larger excitation amplitude (within "
        "the current limit) makes the play a smaller part of the vibration; a smaller one "
        "makes it worse", file=getattr(sweep, "source", None))


def identify_bundle(
    bundle, fmin_hz=None, fmax_hz=None, progress=None, fit_current_loop: bool = True,
    guideway_share: float | None = None, presliding: float | None = None,
    accept_suspect: bool = False,
) -> Identification:
    """Identify every axis of a measurement bundle.

    The records and the identified axes pass the gates of :mod:`tcpmm.ident.gates`
    (time base, static friction, fit quality, sampled-loop stability); a physically
    suspect result is an error unless ``accept_suspect``, and the model then carries the
    findings (``Machine.suspect``).

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
    guideway_share : float, optional
        Share of the friction put on the guideway, the rest on the screw; ``None``: from
        each axis's friction runs [-].
    presliding : float, optional
        Pre-sliding displacement of the identified friction contacts; ``0``: static
        friction; ``None``: fitted to each axis's friction-run reversals where they
        determine it (:mod:`tcpmm.ident.friction.preslidingfit`) [m].
    accept_suspect : bool
        Return a model the gates find physically suspect, marked, instead of raising [-].

    Raises
    ------
    SuspectModelError
        The gates found the records or the identified model physically suspect (and
        ``accept_suspect`` is false); raised before the FRF fits for a bad time base.
    """
    source = getattr(bundle, "path", None)
    check_record_units(bundle)  # a column in mA or degrees overflowed the fits
    findings = time_base_findings(bundle)  # before the FRF fits: a bad record fails fast
    if findings and not accept_suspect:
        raise SuspectModelError(findings, file=source)
    for name, rec in bundle.axes.items():
        if rec.friction is not None:
            stribeck_from_record(rec.friction, bundle.machine.axes[name], name)
    axes = {}
    for name, rec in bundle.axes.items():
        cfg = bundle.machine.axes[name]
        try:
            axes[name] = identify_axis(
                name, rec.sweep, cfg, fmin_hz, fmax_hz, fit_current_loop, rec.friction,
                guideway_share, presliding,
            )
        except InputError as exc:  # a fit knows its numbers, not the bundle they came from
            raise exc.in_file(source) from None
        findings += axis_findings(axes[name], rec, cfg)
        if progress is not None:
            progress(name)
    if findings and not accept_suspect:
        raise SuspectModelError(findings, file=source)
    machine = Machine(
        name=f"{bundle.machine.name} (identified)", axes={n: a.axis for n, a in axes.items()},
        suspect=tuple(str(f) for f in findings),
    )
    for name, a in axes.items():
        warn_share_sensitivity(name, a, machine, bundle.axes[name].friction)
        warn_lost_motion_sensitivity(name, a, machine, bundle.axes[name].friction)
        warn_presliding_sensitivity(name, a, machine, bundle.axes[name].friction)
    return Identification(axes, machine, {"source": str(getattr(bundle, "path", ""))},
                          findings)
