"""``tcpmm contour --model``: the predicted run's contour error with its 90 % interval over
what identification leaves uncertain (:func:`tcpmm.uncertainty.prediction_verdict` of a
:class:`~tcpmm.uncertainty.ProgramTest`)."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ._app import console, esc, out, progress_bar, read_model


def contour_verdict(model: str, run_file: Path, run, res, window_s: float | None,
                    rapids: bool):
    """The verdict on the TCP's contour error of a run that ``model`` predicted on the
    run's own command; refused where the run has no TCP, or where the model's figures on
    that command are not the run's (a measured run, or another model's) [-].

    Parameters
    ----------
    model : str
        The model file, or ``builtin:NAME`` [-].
    run_file : Path
        The run's file [-].
    run : Run
        The run, as read [-].
    res : ContourResult
        Its contour error, as measured [-].
    window_s : float or None
        ``--window-s`` [s].
    rapids : bool
        ``--rapids`` [-].
    """
    from ..path.command import Command
    from ..uncertainty import PROGRAM_FIGURES, ProgramTest, prediction_verdict
    from ..uncertainty.perturb import axis_variants

    if "tcp" not in res.errors:
        raise InputError("--model judges the tcp's contour error, and the run has no tcp "
                         "signals", file=run_file)
    m = read_model(model)
    if all(m.axes[n].uncertainty is None for n in res.axes if n in m.axes):
        console.print(f"note: {esc(model)} carries no uncertainty of identification (a model "
                      "written or exported, not identified): the intervals are the floors "
                      "alone, and its figures only as right as its parameters",
                      highlight=False)
    _recorded_finely(run, m, run_file)
    blocks = {"nc_line": run.nc_line, "rapid": run.rapid} if run.rapid is not None else {}
    try:
        cmd = Command(run.time_s, {n: run.axes[n].cmd for n in res.axes}, blocks)
    except InputError as e:
        raise InputError(f"its command cannot be run again on the model ({e.message}); --model "
                         "judges a run the model predicted", file=run_file) from None
    test = ProgramTest("program", cmd, tuple(res.axes), res.signed, window_s, rapids)
    # each uncertain quantity runs the whole program again: a long one takes a while
    runs = sum(len(axis_variants(m.axes[n])) for n in res.axes if n in m.axes)
    with progress_bar(runs, "verdict") as advance:
        verdict = prediction_verdict(m, [test], "tcp", progress=advance, jobs=0)
    own = res.summary()["tcp"]
    for f in verdict.figures:
        mine = own[PROGRAM_FIGURES[f.figure]]
        if abs(mine - f.nominal) > f.target:
            raise InputError(
                f"its tcp {f.figure} is {mine * 1e6:.2f} um where {model} predicts "
                f"{f.nominal * 1e6:.2f} um on the same command: the run is not this model's "
                "prediction (a measured run, or another model's); give --model the model "
                "that made it, or leave --model out", file=run_file)
    return verdict


def _recorded_finely(run, machine, run_file: Path) -> None:
    """Refuse a run of an NC program recorded more coarsely than the interpolator's period
    (a command file's run is recorded at the file's own period): the model is run
    again on the command the run holds, which it then holds only at its samples (a square
    recorded every 50 ms was another command's figures, and refused as another model's
    run; every 5 ms, the interval was another figure's than the table's) [-]."""
    import numpy as np

    from ._app import interp_settings

    if run.nc_line is None:  # a command file's run is recorded at the file's own period
        return
    period = interp_settings(machine).period_s
    dt = float(np.median(np.diff(run.time_s))) if run.time_s.size > 1 else 0.0
    if dt > period * (1 + 1e-6):
        raise InputError(
            f"it is recorded every {dt * 1e3:.4g} ms, and --model runs the model again on "
            f"the command it holds, which it holds only that often, not at the "
            f"interpolator's {period * 1e3:.4g} ms; simulate it without --record-period-s, "
            "or leave --model out", file=run_file)


def print_verdict(verdict) -> None:
    """The judged figures, a line each, with what would settle those not firm [-]."""
    out.print("tcp, 90 % interval over what identification leaves uncertain:",
              highlight=False)
    for f in verdict.figures:
        name = "max |e|" if f.figure == "contour error" else "RMS"
        settle = f"; to settle: {f.settle}" if f.settle else ""
        out.print(esc(f"  {name} {f.nominal * 1e6:.2f} um: {f.text()}{settle}"),
                  highlight=False)
