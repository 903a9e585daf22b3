"""What identification returns: per axis (:class:`AxisIdentification`), for the bundle
(:class:`Identification`, with its JSON summary, plots and report), and one candidate fit
of an axis on the way (:class:`AxisFit`)."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..io.atomic import staged_folder, write_table_atomic, write_text_atomic
from ..mechanics.lumped import AxisMechanics
from ..model import Axis, Machine
from .friction.preslidingresult import PreslidingFit
from .friction.sensitivity import LostMotionSensitivity, PreslidingSensitivity, ShareSensitivity
from .gates.findings import trimmed_fit_percent
from .gates.sanity import FrictionHold
from .lti.goodness import fit_percent
from .modelstatus import model_parameters, model_undetermined
from .options import MIN_COHERENCE
from .physical.axisfrfs import model_frfs
from .physical.greybox import PhysicalFit
from .physical.loop_timing import LoopTiming
from .steps.fitcontext import current_hold
from .steps.ltifits import TF_ORDERS


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
    sweep_standing : bool
        The sweep did not travel (torque mode, or loops holding one place): no part of it
        shows the linear mechanics [-].
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
    band_cover : BandCover, optional
        What a band the user set leaves out of the frequencies the sweep excites; ``None``
        without such a band (:class:`~tcpmm.ident.frf.excited.BandCover`) [-].
    channel_skews : tuple of ChannelSkew
        The delays between the sweep's channels its FRFs show
        (:mod:`tcpmm.ident.physical.skew`) [s].
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
    sweep_standing: bool = False
    sampled_loop_spectral_radius: float | None = None
    presliding_m: float | None = None
    presliding_fit: PreslidingFit | None = None
    loop_timing: LoopTiming | None = None
    share_sensitivity: ShareSensitivity | None = None
    lost_motion_sensitivity: LostMotionSensitivity | None = None
    presliding_sensitivity: PreslidingSensitivity | None = None
    band_cover: object = None
    channel_skews: tuple = ()

    def _as_measured(self, mechanics, name: str, f_hz) -> np.ndarray:
        return model_frfs(mechanics, {name: f_hz}, self.axis.servo.current_bandwidth_hz,
                          current_hold(self.record, self.axis.servo.T_v),
                          self.physical.nut_gain)[name]

    def notes(self) -> dict:
        """What identification found on the way besides the parameters, for the JSON
        report: the play the sweep crossed, friction holding the sweep, the sampled loop's
        spectral radius, pre-sliding and its fit, loop timing, the spikes'
        sensitivities and the delays between the sweep's channels [SI]."""
        found = {"sweep_play": self.physical.sweep_play,
                 "friction_holds_sweep": self.friction_hold,
                 "sampled_loop_spectral_radius": self.sampled_loop_spectral_radius,
                 "presliding_m": self.presliding_m, "presliding_fit": self.presliding_fit,
                 "loop_timing": self.loop_timing,
                 "share_sensitivity": self.share_sensitivity,
                 "lost_motion_sensitivity": self.lost_motion_sensitivity,
                 "presliding_sensitivity": self.presliding_sensitivity,
                 "channel_skews": [k.to_dict() for k in self.channel_skews] or None}
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
    verdict : Verdict, optional
        How far the figures the model predicts may be wrong, per figure and per axis
        (:func:`tcpmm.uncertainty.prediction_verdict`) [-].
    """

    axes: dict
    machine: Machine
    meta: dict = field(default_factory=dict)
    findings: list = field(default_factory=list)
    verdict: object = None

    def to_dict(self) -> dict:
        """JSON summary: fit percentage per transfer function and physical parameters."""
        out = {}
        for name, a in self.axes.items():
            d = a.axis.mechanics.model_dump()
            # the deviation the model carries (scaled to the real error, with the friction
            # runs' where they replaced a value), not the physical fit's own
            u = a.axis.uncertainty
            std = u.mechanics if u is not None else a.physical.std
            out[name] = {
                "fit": {
                    q["tf"]: {k: v for k, v in q.items() if k not in ("axis", "tf")}
                    for q in a.quality()
                },
                "parameters": {
                    p: {"value": d[p], "std": std.get(p)}
                    for p in a.physical.names
                    if p in d
                },
                "undetermined": model_undetermined(a),
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
        # the warnings first, as every --json output has them (docs/cli.md)
        return {**({"warnings": list(self.meta["warnings"])}
                   if self.meta.get("warnings") else {}),
                "machine": self.machine.name, "axes": out,
                "suspect": [str(f) for f in self.findings],
                **({"verdict": self.verdict.to_dict()} if self.verdict is not None else {})}

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
        from ..plot.bode import plot_bode  # tcpmm.plot is a floor above this one

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
        """Identified parameters with standard deviations, all axes: the value and deviation
        the model carries (the friction runs' where they replaced the fit's, deviations
        scaled to their real error), and the physical fit's own beside them."""
        import pandas as pd

        return pd.concat(
            [model_parameters(a).assign(axis=n) for n, a in self.axes.items()],
            ignore_index=True)

    def quality_table(self):
        """Fit quality, all axes and transfer functions."""
        import pandas as pd

        return pd.DataFrame([q for a in self.axes.values() for q in a.quality()])

    def write_report(self, out_dir) -> dict:
        """Sweep time plots (Fig. 7), measured and fitted Bode plots with coherence
        (Figs. 8-10), the plateau deflections of the friction runs and the tables, into a
        folder; all of them or, where one fails, none. Returns the written paths."""
        with staged_folder(out_dir) as tmp:
            files = self._write_report_files(tmp)
        return {k: Path(out_dir) / p.name for k, p in files.items()}

    def _write_report_files(self, out: Path) -> dict:
        """The files of :meth:`write_report`, written into the folder ``out`` [-]."""
        from ..plot.ident import (  # tcpmm.plot is a floor above this one
            plot_lost_motion,
            plot_sweep,
        )

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
        files.update(quality=out / "fit_quality.csv", parameters=out / "parameters.csv",
                     json=out / "identification.json")
        write_table_atomic(self.quality_table(), files["quality"])
        write_table_atomic(self.parameters_table(), files["parameters"])
        write_text_atomic(files["json"], json.dumps(self.to_dict(), indent=2))
        return files


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
