"""Channel-skew step: whether the sweep's channels were recorded in step, read from the
FRFs with the kept fit's mechanics (:mod:`tcpmm.ident.physical.skew`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..physical.skew import fit_channel_skews

if TYPE_CHECKING:
    from ..chain import AxisRun
    from ..options import IdentifyOptions


def check_skew(run: AxisRun, options: IdentifyOptions) -> tuple:
    """The delays of the scale against the motor encoder and of the TCP against the
    scale, the kept fit's mechanics refitted with them (:class:`ChannelSkew` each).

    Parameters
    ----------
    run : AxisRun
        The axis with its FRFs, its fit context and its kept fit [-].
    options : IdentifyOptions
        Not used: the check has no options [-].
    """
    ctx, split = run.context, run.kept.split
    return fit_channel_skews(run.linear.data, run.kept.physical, ctx.cfg.lead_m,
                             ctx.cfg.torque_constant, ctx.hold_period_s,
                             ctx.fit_current_loop, float(run.sweep.fs_hz),
                             0.0 if split is None else float(split.backlash))
