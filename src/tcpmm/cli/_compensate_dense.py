"""The compensated command as a dense G1 program (``tcpmm compensate --gcode-out``), and
what a controller set as the model's interpolator makes of it."""

from __future__ import annotations

from pathlib import Path

from ._app import console, interp_settings


def write_dense(compensated, comp, machine, path: Path) -> None:
    """The compensated command as a dense G1 program, settling after its rapid for the
    hold the command has at its end, and what a controller set as the model makes of
    it [-]."""
    from ..compensate.gcodeout import dense_program
    from ..io.atomic import write_text_atomic

    T = comp.reference.period_s
    settle_s = comp.settings["hold_samples"] * T
    text = dense_program(compensated, settle_s=settle_s)
    write_text_atomic(path, text)
    warn_replanned(machine, compensated, text, path, settle_s)


def warn_replanned(machine, compensated, text: str, path: Path, settle_s: float) -> None:
    """Say on stderr where a controller set as the model's interpolator would run the dense
    program slower than the command file is timed: its blocks planned to its acceleration
    and jerk (an S-curve's jerk on 1 ms blocks, or limits below those the correction was
    given), the program then lags the command file, and the figures after are not its own.

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
    """
    from ..path.program import program_to_command

    if "\nG1 " not in text:  # a program that only dwells goes nowhere slower
        return
    st = interp_settings(machine)
    # the rapid to the start and its settling dwell, which the command file has not; the
    # command's own rests after them (a program that begins with a dwell) are its samples
    lines = text.splitlines(keepends=True)
    start = next(k for k, ln in enumerate(lines) if ln.startswith("G0 "))
    head = program_to_command("".join(lines[:start + 1 + (settle_s > 0)]), st).time_s[-1]
    took = program_to_command(text, st).time_s[-1] - head
    timed = compensated.time_s[-1] - compensated.time_s[0]
    if took > timed * (1 + REPLANNED_SHARE) + 2 * compensated.period_s:
        console.print(f"warning: {path.name}: a controller set as the model's interpolator "
                      f"({st.profile}, {st.path_accel_m_per_s2:g} m/s^2 on the path) runs "
                      f"its moves in {took:.3g} s where the command file takes {timed:.3g} "
                      "s: it plans the 1 ms blocks slower, the program lags the command "
                      "file, and the figures after are the file's; set the controller's "
                      "limits in the model's interpolation settings, or give the axes' "
                      "with --accel-m-per-s2 and --jerk-m-per-s3", highlight=False)


#: How much longer than the command file a controller may take over the dense program
#: before it is said: the correction keeps each axis within its acceleration, the
#: interpolator the path's vector, a little more on a diagonal (a circle's program on the
#: built-in machine took 1.1 % longer, bench C's 1.0 %; an S-curve's jerk on 1 ms blocks
#: 2-3.5 times, 4 m/s^2 given against its 1 some 15 %) [-]
REPLANNED_SHARE = 0.02
