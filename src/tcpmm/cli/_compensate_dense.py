"""The compensated command as a dense G1 program (``tcpmm compensate --gcode-out``), and
what a controller set as the model's interpolator makes of it."""

from __future__ import annotations

from pathlib import Path

from ._app import console, interp_settings, out


def write_dense(compensated, comp, machine, path: Path, source: str = "the command file") -> None:
    """The compensated command as a dense G1 program, settling after its rapid for the
    hold the command has at its end; what a controller set as the model makes of it,
    said where it departs and kept in ``comp.settings["gcode_out"]`` [-].

    Parameters
    ----------
    compensated : Command
        The compensated command [m].
    comp : Compensation
        The compensation, its reference's period and hold [-].
    machine : Machine
        The model, with its interpolator settings [-].
    path : Path
        Where to write the program [-].
    source : str
        The command file written from the same command, as the warning names it [-].
    """
    from ..compensate.gcodeout import dense_program
    from ..io.atomic import write_text_atomic

    T = comp.reference.period_s
    settle_s = comp.settings["hold_samples"] * T
    text = dense_program(compensated, settle_s=settle_s)
    write_text_atomic(path, text)
    replay = warn_replanned(machine, compensated, text, path, settle_s, source)
    comp.settings["gcode_out"] = {"file": str(path), "settle_s": settle_s,
                                  "lines": text.count("\n"), "replay": replay}


def warn_replanned(machine, compensated, text: str, path: Path, settle_s: float,
                   source: str = "the command file") -> dict | None:
    """Say on stderr where a controller set as the model's interpolator would not replay
    the dense program as the command it is written from: planned again, its command is
    compared with that one sample by sample at the command's clock
    (:func:`tcpmm.compensate.gcodeout.replay_departure`), and where they lie more than
    :data:`~tcpmm.compensate.gcodeout.REPLAY_TOL_M` apart, the figures after are not the
    program's. Its blocks are planned to the interpolator's limits: an S-curve's jerk on
    1 ms blocks, limits below those the correction was given, and the curvature of short
    blocks, within ``axis_accel / sqrt(2)``, which a correction turning at up to the axis's
    acceleration exceeds at a reversal; each block slower than its period puts the rest of
    the program behind.

    Parameters
    ----------
    machine : Machine
        The model, with its interpolator settings [-].
    compensated : Command
        The compensated command the program was written from [m].
    text : str
        The dense program [-].
    path : Path
        Where it was written [-].
    settle_s : float
        The dwell after the rapid to the start, 0 for none [s].
    source : str
        The command file written from the same command [-].

    Returns
    -------
    dict or None
        The comparison; ``None`` for a program that only dwells [m], [s], [-].
    """
    from ..compensate.gcodeout import REPLAY_TOL_M, replay_departure

    st = interp_settings(machine)
    rep = replay_departure(compensated, text, st, settle_s)
    if rep is None or rep["departure_m"] <= REPLAY_TOL_M:
        return rep
    took, timed = rep["duration_s"], rep["command_duration_s"]
    slower = (f"; it runs its moves in {took:.3g} s where the command file takes {timed:.3g} s"
              if took > timed * (1 + REPLANNED_SHARE) + 2 * compensated.period_s else "")
    per_axis = ", ".join(f"{a} {v * 1e6:.1f}" for a, v in rep["axes_m"].items())
    console.print(f"warning: {path.name}: a controller set as the model's interpolator "
                  f"({st.profile}, {st.path_accel_m_per_s2:g} m/s^2 on the path) does not "
                  f"replay {source}: planned so, its command departs from the file's by up "
                  f"to {rep['departure_m'] * 1e6:.1f} µm at {rep['at_s']:.3f} s (line "
                  f"{rep['line']} of {path.name}; per axis up to {per_axis} µm), more than "
                  f"{REPLAY_TOL_M * 1e6:g} µm on {rep['share_beyond']:.0%} of the samples"
                  f"{slower}: it plans the {compensated.period_s * 1e3:g} ms blocks slower "
                  f"where they reach its limits (tcpmm path {path.name} --model MODEL "
                  f"names them), and the figures after are {source}'s, not the program's; "
                  "set the controller's limits in the model's interpolation settings, or "
                  "give the axes' with --accel-m-per-s2 and --jerk-m-per-s3", highlight=False)
    return rep


#: How much longer than the command file a controller may take over the dense program
#: before the warning gives both times: the correction keeps each axis within its
#: acceleration, the interpolator the path's vector, a little more on a diagonal (a
#: circle's program on the built-in machine took 1.1 % longer, bench C's 1.0 %; an
#: S-curve's jerk on 1 ms blocks 2-3.5 times, 4 m/s^2 given against its 1 some 15 %) [-]
REPLANNED_SHARE = 0.02


def dense_line(said: dict | None, output: Path) -> None:
    """Print where the dense program (``--gcode-out``) was written, where it was, and
    whether a controller set as the model's interpolator replays it as ``output`` [-]."""
    if not said:
        return
    rep = said["replay"]
    text = f"wrote {said['file']}: {output} as a dense G1 program ({said['lines']} lines)"
    if rep is not None and rep["departure_m"] <= rep["tolerance_m"]:
        text += (f"; a controller set as the model's interpolator replays it within "
                 f"{rep['departure_m'] * 1e6:.2f} µm of {output} at every sample")
    elif rep is not None:
        text += (f"; a controller set as the model's interpolator does not replay it: up "
                 f"to {rep['departure_m'] * 1e6:.1f} µm from {output} (the warning above)")
    out.print(text, highlight=False)
