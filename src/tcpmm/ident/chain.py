"""Identification as a chain of named steps over one set of options.

A bundle's records are checked first (time base, friction runs); then each axis goes
through :data:`AXIS_STEPS` in order, each step a plain function ``step(run, options)`` in
its own module under :mod:`tcpmm.ident.steps` whose result fills one field of the
axis's :class:`AxisRun`:

FRFs -> excitation check -> LTI fits -> fit context -> physical fit -> friction ->
lost motion -> channel skew -> pre-sliding -> model and uncertainty.

The identified axes pass the gates of :mod:`tcpmm.ident.gates`, and the bundle's model
gets the sensitivities of its TCP spikes to what the friction runs leave open.
"""

from __future__ import annotations

import math
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path

from .._forked import results_in_order, usable_jobs
from .._threads import limit_blas_threads
from ..errors import InputError, InputWarning
from ..io.csvutil import warn_input
from ..model import Machine
from ..uncertainty import open_ranges, prediction_verdict
from .friction.recorddrift import drift_warning, record_drift
from .friction.spikewarnings import warn_spike_sensitivities
from .friction.split import stribeck_from_record
from .gates.columns import check_record_units, column_findings
from .gates.finding import SuspectModelError
from .gates.findings import axis_findings
from .gates.masses import check_static_gains, unjudged_static_gains
from .gates.timebase import time_base_findings
from .identification import AxisFit, AxisIdentification, Identification
from .options import MIN_COHERENCE, IdentifyOptions
from .physical.greybox import undetermined_words
from .steps.axismodel import AxisModel, build_axis
from .steps.excitationcheck import ExcitationCheck, check_excitation
from .steps.fitcontext import FitContext, fit_context
from .steps.frfs import BandFRFs, measure_frfs
from .steps.frictionfit import FrictionFit, read_friction
from .steps.ltifits import fit_lti
from .steps.modelfriction import ModelFriction, friction_for_model
from .steps.physicalfit import LinearFit, fit_linear
from .steps.playrefit import keep_fit
from .steps.skewcheck import check_skew


@dataclass(frozen=True)
class AxisRun:
    """One axis on its way through :data:`AXIS_STEPS`: its records, and what each step
    has found so far (``None`` until it ran, or where it has nothing to give).

    Parameters
    ----------
    name : str
        Axis name [-].
    sweep : SweepRecord
        Servo-excitation record (SI) [-].
    cfg : AxisConfig
        What the user knows: lead, torque constant, servo, sensors [-].
    runs : FrictionRecord, optional
        Constant-velocity friction runs [-].
    frfs : BandFRFs, optional
        The sweep's FRFs and their band [SI].
    excitation : ExcitationCheck, optional
        The sweep's travel and whether friction held it [-].
    tf_fits : dict, optional
        Rational transfer-function fits per FRF [SI].
    context : FitContext, optional
        What the physical fits and the friction on them share [-].
    linear : LinearFit, optional
        The physical fit of a linear axis [SI].
    friction : FrictionFit, optional
        The fit with the friction runs on it [SI].
    kept : AxisFit, optional
        The fit kept, with the play modelled where it was [SI].
    model_friction : ModelFriction, optional
        The friction of the model, with its pre-sliding [-].
    model : AxisModel, optional
        The identified axis [SI].
    skews : tuple of ChannelSkew, optional
        The delays between the sweep's channels the kept fit's FRFs show [s].
    """

    name: str
    sweep: object
    cfg: object
    runs: object = None
    frfs: BandFRFs | None = None
    excitation: ExcitationCheck | None = None
    tf_fits: dict | None = None
    context: FitContext | None = None
    linear: LinearFit | None = None
    friction: FrictionFit | None = None
    kept: AxisFit | None = None
    model_friction: ModelFriction | None = None
    model: AxisModel | None = None
    skews: tuple | None = None

    def identification(self) -> AxisIdentification:
        """Everything identified for the axis, once the steps have run [-]."""
        kept, model, mf = self.kept, self.model, self.model_friction
        return AxisIdentification(
            self.name, self.frfs.frfs, self.tf_fits, kept.physical, model.axis, self.sweep,
            kept.curve, kept.split, friction_hold=self.excitation.friction_hold,
            sweep_standing=self.excitation.travel_speed == 0.0,
            sampled_loop_spectral_radius=model.sampled_loop_spectral_radius,
            presliding_m=None if mf is None else mf.presliding_m,
            presliding_fit=None if mf is None else mf.presliding_fit,
            loop_timing=model.loop_timing, band_cover=self.frfs.cover,
            channel_skews=self.skews or ())


#: The steps of one axis in the order they run: the field of :class:`AxisRun` each
#: fills, and the step.
AXIS_STEPS = (
    ("frfs", measure_frfs),
    ("excitation", check_excitation),
    ("tf_fits", fit_lti),
    ("context", fit_context),
    ("linear", fit_linear),
    ("friction", read_friction),
    ("kept", keep_fit),
    ("skews", check_skew),
    ("model_friction", friction_for_model),
    ("model", build_axis),
)


def run_axis(run: AxisRun, options: IdentifyOptions) -> AxisIdentification:
    """Run :data:`AXIS_STEPS` on one axis.

    Parameters
    ----------
    run : AxisRun
        The axis with its records [-].
    options : IdentifyOptions
        What the steps share [-].
    """
    limit_blas_threads()
    with _axis_named(run):
        for name, step in AXIS_STEPS:
            try:
                run = replace(run, **{name: step(run, options)})
            except InputError as failed:
                _static_gains_first(run, failed)
                raise
        found = run.identification()
        if found.physical.undetermined:  # of the fit kept, not of every fit on the way
            warn_input(undetermined_words(found.physical.undetermined),
                       file=getattr(run.sweep, "source", None))
    return found


@contextmanager
def _axis_named(run: AxisRun):
    """The warnings of an axis's steps, each naming the axis: ``axis X:`` put after the
    file a warning names, or before it where it names none and not the axis already
    (the FRF estimators and fits know their numbers, not whose they are)."""
    files = [str(Path(f)) for f in (getattr(run.sweep, "source", None),
                                     getattr(run.runs, "source", None)) if f]
    said = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            try:
                yield
            finally:
                said = list(caught)
    finally:  # given on also when a step fails: they may say why
        for w in said:
            text = str(w.message)
            if issubclass(w.category, InputWarning) and f"axis {run.name}:" not in text:
                file = next((f for f in files if text.startswith(f"{f}: ")), None)
                text = (f"axis {run.name}: {text}" if file is None else
                        f"{file}: axis {run.name}: {text[len(file) + 2:]}")
                warnings.warn_explicit(text, w.category, w.filename, w.lineno)
            else:
                warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def _static_gains_first(run: AxisRun, failed: InputError) -> None:
    """Where a step fails on mechanics beyond any machine tool, a column swapped or in the
    wrong unit is the likely cause, and the FRFs' static gains, which need no fitted model,
    say which: raise that first, with what the step said. Only the bins the sweep excites
    are judged; where the sweep or the band leaves none, the likely cause is that the FRFs
    lack the low frequencies, and that is raised first instead
    (:func:`~tcpmm.ident.gates.masses.unjudged_static_gains`). No model was made, so there
    is none to write as suspect (:func:`~tcpmm.ident.gates.masses.check_static_gains`)."""
    if run.frfs is None:
        return
    sweep = run.sweep.source or f"{run.name}/sweep.csv"
    found = check_static_gains(run.name, run.frfs.frfs, run.cfg.lead_m / (2 * math.pi), sweep,
                               MIN_COHERENCE, excitation=run.sweep.excitation_A)
    if found:
        raise InputError(
            f"identification stopped; the FRFs' static gains, which need no fitted model, "
            f"read: {' | '.join(str(f) for f in found)}. The step that stopped said: "
            f"{failed}") from None
    unjudged = unjudged_static_gains(run.frfs.frfs, run.sweep.excitation_A, MIN_COHERENCE)
    if unjudged:
        raise InputError(f"identification stopped; {unjudged}. The step that stopped said: "
                         f"{failed}") from None


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
        runs (:mod:`tcpmm.ident.friction.preslidingfit`), or
        :data:`~tcpmm.ident.friction.presliding.PRESLIDING` where they do not determine
        it [m].
    """
    options = IdentifyOptions(fmin_hz, fmax_hz, fit_current_loop, guideway_share, presliding)
    return run_axis(AxisRun(name, sweep, cfg, friction), options)


def check_records(bundle, options: IdentifyOptions) -> list:
    """The records' check before any fit: their time base and their columns (swapped, or
    in the wrong unit; a bad one fails fast) and the plateaus of the friction runs; the
    findings [-].

    Parameters
    ----------
    bundle : Bundle
        The measurement bundle [-].
    options : IdentifyOptions
        ``accept_suspect``: return a bad time base's findings instead of raising [-].
    """
    findings = time_base_findings(bundle) + column_findings(bundle)
    if findings and not options.accept_suspect:
        raise SuspectModelError(findings, file=getattr(bundle, "path", None))
    check_record_units(bundle)  # accepted or not, a column in mA or degrees overflows the fits
    for name, rec in bundle.axes.items():
        if rec.friction is not None:
            try:
                *_, plateaus = stribeck_from_record(rec.friction, bundle.machine.axes[name],
                                                    name)
            except InputError as exc:  # the fit knows the column, not the file
                raise exc.in_file(rec.friction.source) from None
            said = drift_warning(record_drift(rec.friction, bundle.machine.axes[name],
                                              plateaus), name)
            if said:
                warn_input(said, file=rec.friction.source, column="scale_mm")
    return findings


def run_bundle(bundle, options: IdentifyOptions, progress=None,
               jobs: int | None = 1) -> Identification:
    """Check a bundle's records, run :data:`AXIS_STEPS` on each axis, pass the gates, and
    tell the TCP spikes' sensitivity to what the friction runs leave open.

    Parameters
    ----------
    bundle : Bundle
        Read with :func:`tcpmm.io.bundle.read_bundle` [-].
    options : IdentifyOptions
        What the steps share [-].
    progress : callable, optional
        Called with the axis name after each axis [-].
    jobs : int, optional
        Axes identified at once, each in a process of its own; ``None`` or 0: as many as
        there are cores (:func:`~tcpmm._forked.usable_jobs`) [-].
    """
    findings = check_records(bundle, options)
    axes = {}
    axis_runs = [AxisRun(name, rec.sweep, bundle.machine.axes[name], rec.friction)
                 for name, rec in bundle.axes.items()]
    jobs_used = usable_jobs(jobs, len(axis_runs))
    with results_in_order(run_axis, axis_runs, options, jobs_used) as results:
        for run, result in zip(axis_runs, results, strict=True):
            try:
                axes[run.name] = result()
            except InputError as exc:  # a fit knows its numbers, not the bundle's file
                raise exc.in_file(getattr(bundle, "path", None)) from None
            findings += axis_findings(axes[run.name], bundle.axes[run.name], run.cfg)
            if progress is not None:
                progress(run.name)
    if findings and not options.accept_suspect:
        raise SuspectModelError(findings, file=getattr(bundle, "path", None))
    for a in axes.values():  # what the data leave open goes into the model with its range
        a.axis = a.axis.replace(uncertainty=a.axis.uncertainty.model_copy(
            update={"open": open_ranges(a)}))
    machine = Machine(
        name=f"{bundle.machine.name} (identified)", axes={n: a.axis for n, a in axes.items()},
        suspect=tuple(str(f) for f in findings),
    )
    for name, a in axes.items():
        warn_spike_sensitivities(name, a, machine, bundle.axes[name].friction)
    return Identification(axes, machine, {"source": str(getattr(bundle, "path", ""))},
                          findings,
                          prediction_verdict(machine, jobs=jobs) if options.verdict else None)


def identify_bundle(
    bundle, fmin_hz=None, fmax_hz=None, progress=None, fit_current_loop: bool = True,
    guideway_share: float | None = None, presliding: float | None = None,
    accept_suspect: bool = False, verdict: bool = True, jobs: int | None = 1,
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
    verdict : bool
        Judge the figures the model predicts on the reference circles
        (:func:`tcpmm.uncertainty.prediction_verdict`) [-].
    jobs : int, optional
        Axes identified at once, each in a process of its own (forked; the same numbers
        as one after the other); ``None`` or 0: as many as there are cores [-].

    Raises
    ------
    SuspectModelError
        The gates found the records or the identified model physically suspect (and
        ``accept_suspect`` is false); raised before the FRF fits for a bad time base.
    """
    options = IdentifyOptions(fmin_hz, fmax_hz, fit_current_loop, guideway_share, presliding,
                              accept_suspect, verdict)
    return run_bundle(bundle, options, progress, jobs)
