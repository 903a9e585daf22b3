"""Friction step: the friction runs read on the physical fit; with a TCP record, the
mechanics fitted again with the bed and TCP structure held at what ``G_tcp`` alone says,
and the runs read on that fit."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..frf.wholerecord import reduced_with_whole_record
from ..identification import AxisFit
from ..physical.greybox import PhysicalFit
from ..physical.structure import STIFFNESS_FLOOR, fit_structure
from .fitcontext import FitContext, fit_values, friction_on, physical_fit
from .frfs import fit_data
from .playrefit import play_significant

if TYPE_CHECKING:
    from ..chain import AxisRun
    from ..options import IdentifyOptions


@dataclass(frozen=True)
class FrictionFit:
    """The fit with the friction runs on it, and what a refit with the play starts from.

    Parameters
    ----------
    kept : AxisFit
        The physical fit with the friction of the runs on it [SI].
    data : dict
        The FRFs it was fitted to, :class:`~tcpmm.ident.physical.fitdata.FRFData` per
        name [SI].
    structure : dict, optional
        Bed and TCP structure held in proportion to ``M_t``, with a TCP record [SI / kg].
    structure_log_std : dict, optional
        Standard deviation of the logarithm of each ratio of ``structure`` [-].
    """

    kept: AxisFit
    data: dict
    structure: dict | None = None
    structure_log_std: dict | None = None


def read_friction(run: AxisRun, options: IdentifyOptions) -> FrictionFit | None:
    """The friction runs of one axis on its physical fit (:func:`fit_friction`); ``None``
    without runs.

    Parameters
    ----------
    run : AxisRun
        The axis with its FRFs, fit context and linear fit [-].
    options : IdentifyOptions
        Not read by this step: the context carries the share asked for [-].
    """
    if run.runs is None:
        return None
    return fit_friction(run.context, run.sweep, run.frfs.frfs, run.linear.data,
                        run.linear.physical)


def fit_friction(ctx: FitContext, sweep, frfs: dict, data: dict,
                 phys: PhysicalFit) -> FrictionFit:
    """The friction runs on the physical fit; with a TCP record, the fit again with the
    structure held at what ``G_tcp`` alone says, and the runs on that.

    Parameters
    ----------
    ctx : FitContext
        The axis's known values, TF fits, hold and friction runs [-].
    sweep : SweepRecord
        The sweep record [-].
    frfs : dict
        The measured FRFs; with a TCP record whose sweep does not cross lost motion, the
        fits weigh them against the whole record [SI].
    data : dict
        The FRFs the linear fit was fitted to, :class:`FRFData` per name [SI].
    phys : PhysicalFit
        The linear fit [SI].
    """
    kept = AxisFit(phys, *friction_on(ctx, phys))
    structure = log_std = None
    if "G_tcp" in data:
        # G_tcp does not see the nut force, so nothing that distorts G_M and G_T (lost
        # motion crossed by the sweep, the friction it travels against, a drive mode the
        # model lacks) reaches it: hold the bed and TCP structure at what G_tcp alone
        # says, relative to the table. The segments cut the ringing of a lightly damped
        # mode, so from here on each FRF weighs in the whole record, except where the
        # sweep crosses the play: the refits with the play do not settle on it.
        if not play_significant(kept.split):
            data = whole_record_data(sweep, frfs)
        structure, _, log_std = fit_structure(data["G_tcp"], [phys.mechanics])
        phys, structure = _refit_held(ctx, data, phys, structure, log_std)
        kept = AxisFit(phys, *friction_on(ctx, phys))
    return FrictionFit(kept, data, structure, log_std)


def _refit_held(ctx: FitContext, data: dict, phys: PhysicalFit, structure: dict,
                log_std: dict) -> tuple[PhysicalFit, dict]:
    """The joint fit with the structure held at ``structure``, started from ``phys``, and
    the structure it holds.

    Where ``phys`` left a structural mass or stiffness undetermined, the fit is also
    started from the data's own starts and the lower cost kept: a structure the joint fit
    collapsed (a mode outside the band) puts its inertia into the table and the bed, and a
    fit started there stays in that valley once the structure is held where ``G_tcp``
    puts it. A stiffness the fit leaves undetermined below
    :data:`~tcpmm.ident.physical.structure.STIFFNESS_FLOOR` (a mode below the band,
    whose stiffness the band does not see) is then held at the floor [-]."""
    held = physical_fit(ctx, data, initial=fit_values(phys), structure=structure,
                        structure_log_std=log_std)
    if not set(phys.undetermined) & {"M_b", "K_b", "M_h", "K_h"}:
        return held, structure
    fresh = physical_fit(ctx, data, structure=structure, structure_log_std=log_std)
    held = fresh if fresh.cost < held.cost else held
    m = held.mechanics
    low = {f"K_{s}": k / m.M_t for s, k in STIFFNESS_FLOOR.items()
           if f"K_{s}" in held.undetermined and getattr(m, f"K_{s}") < k}
    if not low:
        return held, structure
    structure = {**structure, **low}
    return physical_fit(ctx, data, initial=fit_values(held), structure=structure,
                        structure_log_std=log_std), structure


def whole_record_data(sweep, frfs: dict) -> dict:
    """The FRFs weighed against their estimates from the whole record, as fit data
    (:func:`~tcpmm.ident.frf.wholerecord.reduced_with_whole_record`) [SI]."""
    f = reduced_with_whole_record(frfs, sweep.excitation_A, sweep.current_cmd_A,
                                  sweep.motor_angle_rad, sweep.scale_m, sweep.tcp_m)
    return fit_data(f)
