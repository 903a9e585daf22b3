"""What the physical fits and the friction on them share for one axis: the known values,
the transfer-function fits that seed the starts, the drive's hold of the current and the
friction runs, in one frozen :class:`FitContext`; and the two fits it serves,
:func:`physical_fit` and :func:`friction_on`."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from ...io.csvutil import warn_input
from ..friction.split import identify_friction, place_steady_viscous
from ..friction.sweepforce import sweep_deflection
from ..physical.greybox import PhysicalFit, fit_physical
from ..physical.loop_timing import sampled_in_step

if TYPE_CHECKING:
    from ..chain import AxisRun
    from ..options import IdentifyOptions

#: Largest relative standard deviation of the identified ``B_m``, ``B_L`` and ``C_t`` for
#: which the friction split takes them as known; a few per cent of ``C_t`` already moves the
#: share by 0.02, so otherwise the speed-proportional deflection is fitted [-].
DAMPING_KNOWN_REL_STD = 0.03


@dataclass(frozen=True)
class FitContext:
    """What every physical fit of an axis and the friction on it are given.

    Parameters
    ----------
    name : str
        Axis name, for messages [-].
    cfg : AxisConfig
        What the user knows: lead, torque constant, servo, sensors [-].
    fit_current_loop : bool
        Also fit a first-order current-loop bandwidth from G_M [-].
    tf_fits : dict
        Rational fits of the FRFs; their poles and zeros seed the starts [SI].
    hold_period_s : float
        Hold of the current command that G_M carries beyond the record
        (:func:`current_hold`) [s].
    runs : FrictionRecord, optional
        The constant-velocity friction runs [-].
    guideway_share : float, optional
        Share of the friction put on the guideway; ``None``: from the runs [-].
    sweep_force : SweepDeflection, optional
        Mean TCP-structure deflection of a travelling sweep, for the share [m].
    told : set
        What the fits of the axis have told already: each refit of the mechanics reads
        the friction runs again, and finds alike what the first found [-].
    """

    name: str
    cfg: object
    fit_current_loop: bool
    tf_fits: dict
    hold_period_s: float
    runs: object = None
    guideway_share: float | None = None
    sweep_force: object = None
    told: set = field(default_factory=set, compare=False, repr=False)


def fit_context(run: AxisRun, options: IdentifyOptions) -> FitContext:
    """What the fits of one axis share, once its transfer functions are fitted.

    Parameters
    ----------
    run : AxisRun
        The axis with its records, its excitation check and its TF fits [-].
    options : IdentifyOptions
        ``fit_current_loop`` and ``guideway_share`` [-].
    """
    cfg, sweep, runs = run.cfg, run.sweep, run.runs
    zero = zero_std_of(cfg.sensors.scale_resolution_m, cfg.sensors.tcp_resolution_m)
    deflection = (None if runs is None else
                  sweep_deflection(sweep, run.excitation.velocity, zero))
    if deflection is not None and run.frfs.cover is not None:
        deflection = replace(deflection, cover=run.frfs.cover)
    return FitContext(run.name, cfg, options.fit_current_loop, run.tf_fits,
                      current_hold(sweep, cfg.servo.velocity_loop_period_s), runs,
                      options.guideway_share, deflection)


def current_hold(record, T_v: float) -> float:
    """Hold of the current command that ``G_M`` carries beyond the record (``None``: a
    record sampled at the ticks) of a loop of period ``T_v`` [s].

    A record sampled at the velocity-loop ticks holds the command values, and the drive
    holds each over the period that follows: ``G_M`` from the samples carries that
    hold. A record that reads the held current on a clock of its own already holds the
    staircase the motor is driven by, and a second hold would count it twice."""
    return T_v if record is None or sampled_in_step(record.fs_hz, T_v) else 0.0


def physical_fit(ctx: FitContext, data: dict, initial: dict | None = None, nut_gain=None,
                 structure: dict | None = None,
                 structure_log_std: dict | None = None) -> PhysicalFit:
    """:func:`~tcpmm.ident.physical.greybox.fit_physical` of the FRFs ``data`` with the
    axis's known values; what it leaves undetermined is said once per axis, of the fit
    kept (:func:`tcpmm.ident.chain.run_axis`), not of each fit on the way.

    Parameters
    ----------
    ctx : FitContext
        The axis's known values, TF fits and hold [-].
    data : dict
        The FRFs to fit, :class:`~tcpmm.ident.physical.fitdata.FRFData` per name [SI].
    initial : dict, optional
        Starting values; default from the data [SI].
    nut_gain : callable, optional
        Factor on ``K_t`` per frequency (the play as the sweep saw it) [-].
    structure : dict, optional
        Parameters held in proportion to ``M_t`` [SI / kg].
    structure_log_std : dict, optional
        Standard deviation of the logarithm of each ratio of ``structure`` [-].
    """
    return fit_physical(data, ctx.cfg.lead_m, ctx.cfg.torque_constant, initial=initial,
                        fit_current_loop=ctx.fit_current_loop, tf_fits=ctx.tf_fits,
                        hold_period_s=ctx.hold_period_s, nut_gain=nut_gain,
                        structure=structure, structure_log_std=structure_log_std,
                        warn=False)


def fit_values(phys: PhysicalFit) -> dict:
    """The values of a physical fit as a starting point for another [SI]."""
    start = phys.mechanics.model_dump()
    if phys.current_bandwidth_hz is not None:
        start["f_i"] = phys.current_bandwidth_hz
    return start


def friction_on(ctx: FitContext, phys: PhysicalFit):
    """Friction from the runs on the mechanics of a physical fit, the nut stiffness and
    the steady viscous force placed: ``(mechanics, friction, curve, split)``.

    Parameters
    ----------
    ctx : FitContext
        The axis, its runs, the share asked for and the sweep's deflection [-].
    phys : PhysicalFit
        The fit whose mechanics the runs are read on [SI].
    """
    mech = phys.mechanics

    def rel_std(p):
        sd = phys.std.get(p, float("nan"))
        return float(sd / getattr(mech, p)) if np.isfinite(sd) else float("inf")

    damping_known = all(rel_std(p) <= DAMPING_KNOWN_REL_STD for p in ("B_m", "B_L", "C_t"))
    fr, est, split = identify_friction(
        ctx.runs, ctx.cfg, mech, ctx.guideway_share, axis=ctx.name,
        stiffness_rel_std=_finite_or(rel_std("K_t"), 0.0),
        viscous="known" if damping_known else "fit",
        neglect_motor_bearing=not damping_known, sweep=ctx.sweep_force,
        K_h_rel_std=_finite_or(rel_std("K_h"), 0.0),
        C_t_std=_finite_or(phys.std.get("C_t", float("nan")), 0.0), warn_prior=False)
    if split.sweep_note and "sweep_note" not in ctx.told:
        # the first fit whose sweep reads no share says why (a band above the structure
        # shows there), though the fits that follow may read one
        ctx.told.add("sweep_note")
        warn_input(split.sweep_note)
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


def zero_std_of(scale_resolution: float, tcp_resolution: float | None) -> float:
    """Standard deviation of a TCP device's zero against the linear scale's: a step of
    each, since each zero is set at a reading rounded to its step, with the nut and the
    column at rest under whatever force held them [m].

    Parameters
    ----------
    scale_resolution : float
        Step of the linear scale [m].
    tcp_resolution : float or None
        Step of the TCP device; ``None`` or 0 where not given [m].
    """
    return float(np.hypot(scale_resolution or 0.0, tcp_resolution or 0.0))
