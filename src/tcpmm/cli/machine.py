"""Commands on models: machine export, machine show, bode."""

from __future__ import annotations

from pathlib import Path

import typer

from ._app import (
    app,
    checked_plot,
    emit_json,
    esc,
    floats,
    machine_app,
    out,
    read_model,
    warn_unstable,
)
from ._outputs import checked_yaml_output


@machine_app.command("export")
def machine_export(name: str = typer.Argument(
        ..., help="Built-in machine name (vmc, or builtin:vmc as elsewhere)."),
                   output: Path = typer.Option(..., "-o", "--output", help="MODEL.yaml")):
    """Write a built-in machine as a model file, with the interpolator settings that
    tcpmm path, simulate --gcode and sweep use, to be read and edited there."""
    from ..io.modelfile import with_interpolation, write_machine
    from ..machines.builtin import builtin_machine

    write_machine(with_interpolation(builtin_machine(name.removeprefix("builtin:"))),
                  checked_yaml_output(output, json_option=False))
    out.print(f"wrote {output}")


@machine_app.command("show")
def machine_show(model: str = typer.Argument(..., help="MODEL.yaml or builtin:vmc"),
                 as_json: bool = typer.Option(False, "--json")):
    """Modes of each axis (natural frequencies and damping), closed-loop stability and the
    margins of the sampled velocity and position loops."""
    import numpy as np

    from ..mechanics.statespace import oscillating_modes
    from ..servo.closedloop import is_stable
    from ..servo.currentfilters import filter_text
    from ..servo.margins import axis_margins
    from ..servo.sampled import is_stable_radius, radius_text, sampled_spectral_radius

    m = read_model(model)
    data = {}
    for ax, a in m.axes.items():
        ev = oscillating_modes(a.mechanics)
        data[ax] = {"modes_hz": [float(abs(e) / (2 * np.pi)) for e in ev],
                    "damping": [float(_rounded(-e.real / abs(e))) for e in ev],
                    "closed_loop_stable": is_stable(a.mechanics, a.servo),
                    "sampled_loop_spectral_radius": sampled_spectral_radius(a.mechanics, a.servo),
                    "sampled_loop_stable": loops_stable(a),
                    "margins": {k: v.to_dict() for k, v in
                                axis_margins(a.mechanics, a.servo).items()},
                    "filters": [f.model_dump() for f in a.servo.filters]}
    if as_json:
        emit_json(data)
        return
    for ax, d in data.items():
        modes = ", ".join(f"{f:.1f} Hz (zeta {z:.2g})" for f, z in
                          zip(d["modes_hz"], d["damping"], strict=True))
        state = "stable" if d["closed_loop_stable"] else "UNSTABLE"
        rho = d["sampled_loop_spectral_radius"]
        sampled = "stable" if is_stable_radius(rho) else "UNSTABLE"
        out.print(f"{ax}: {modes}; continuous closed loop {state}; sampled loop {sampled} "
                  f"(spectral radius {radius_text(rho)}, the drive's: the one that counts)")
        for f in m.axes[ax].servo.filters:
            out.print(f"   current-setpoint filter: {filter_text(f)}")
        for loop, mg in d["margins"].items():
            which = "velocity" if not d["sampled_loop_stable"]["velocity"] else loop
            unheld = "" if d["sampled_loop_stable"][loop] else (
                f" (of no meaning: the sampled {which} loop is unstable)")
            out.print(f"   {loop} loop: {margins_line(mg)}{unheld}")


def loops_stable(axis) -> dict:
    """Per loop, whether its sampled loop is stable: the velocity loop judged alone
    (:func:`~tcpmm.servo.modeshift.velocity_only`), as its margins are; the position loop
    whole, which closes around the velocity loop and whose margins assume that one holds
    [-]."""
    from ..servo.modeshift import velocity_only
    from ..servo.sampled import sampled_loop_stable

    alone = sampled_loop_stable(axis.mechanics, velocity_only(axis.servo))
    return {"velocity": alone,
            "position": alone and sampled_loop_stable(axis.mechanics, axis.servo)}


def _rounded(zeta: float) -> float:
    """A damping ratio, 0 where it is rounding's (an undamped model's -1e-16) [-]."""
    return 0.0 if abs(zeta) < 1e-12 else zeta


def margins_line(mg: dict) -> str:
    """One line of a loop's margins: gain, phase, crossovers [dB, deg, Hz]."""
    def hz(f):  # a loop slower than 0.05 Hz keeps two significant digits, not "0.0"
        return f"{f:.1f} Hz" if f >= 0.05 else f"{f:.2g} Hz"

    def at(value, unit, f):
        if value is None:
            return "infinite (no crossing)"
        return f"{value:.1f} {unit} at {hz(f)}"

    bw = mg["bandwidth_hz"]
    return (f"gain margin {at(mg['gain_margin_db'], 'dB', mg['phase_crossover_hz'])}, "
            f"phase margin {at(mg['phase_margin_deg'], 'deg', mg['gain_crossover_hz'])}, "
            f"bandwidth {'-' if bw is None else hz(bw)}")

OPEN_LOOPS = ("L_v", "L_p")


def _open_loop_grid(axis, tf: str, f, given: bool):
    """The frequencies of an open sampled loop's gain: ``f`` [Hz], up to the loop's Nyquist
    frequency, which the default grid reaches (where a sampled loop's gain margin often
    lies) [Hz]."""
    import numpy as np

    s = axis.servo
    period = s.T_v if tf == "L_v" else s.T_p
    if not given:
        f = np.geomspace(1.0, 0.5 / period, 200)
    if f.max() > 0.5 / period:
        raise typer.BadParameter(f"--freq-hz: {tf} is sampled every {period:g} s; give "
                                 f"frequencies up to its Nyquist frequency {0.5 / period:g} Hz")
    return f


#: Machines drawn from an identified model's uncertainty for the range of its response [-].
DRAWN = 16
#: Each frequency's range over them, as ``--json`` names it [-], [deg].
DRAWN_KEYS = ("abs_low", "abs_high", "phase_low_deg", "phase_high_deg")


def _response(axis, tf: str, f):
    """The response ``tf`` of ``axis`` at ``f`` [Hz]: a reduced or a closed-loop one, or an
    open sampled loop's gain [SI]."""
    from ..mechanics.transfer import REDUCED, reduced_freqresp
    from ..servo.closedloop import closed_loop_freqresp
    from ..servo.margins import position_loop_gain, velocity_loop_gain

    if tf in OPEN_LOOPS:
        gain = velocity_loop_gain if tf == "L_v" else position_loop_gain
        return gain(axis.mechanics, axis.servo, f)
    if tf in REDUCED:
        return reduced_freqresp(axis.mechanics, tf, f, axis.servo.current_bandwidth_hz)
    return closed_loop_freqresp(axis.mechanics, axis.servo, tf, f)


def _drawn(machine, axis: str, tf: str, f, H):
    """Over :data:`DRAWN` machines drawn from an identified model's uncertainty (as
    ``tcpmm spread`` draws them), per frequency the least and largest ``|H|`` and phase
    (about the model's, unwrapped by the difference); ``None`` for a model without one
    [SI], [deg]."""
    import numpy as np

    from ..whatif.draws import MODEL_ERROR, draw_machine

    if machine.axis(axis).uncertainty is None:
        return None
    rng = np.random.default_rng(0)
    mags, turns = [], []
    for _ in range(DRAWN):
        h = _response(draw_machine(machine, rng, MODEL_ERROR).axis(axis), tf, f)
        mags.append(np.abs(h))
        turns.append(np.degrees(np.angle(h / H)))
    ph = np.degrees(np.angle(H))
    return (np.min(mags, axis=0), np.max(mags, axis=0), ph + np.min(turns, axis=0),
            ph + np.max(turns, axis=0))


@app.command()
def bode(model: str = typer.Argument(..., help="MODEL.yaml or builtin:vmc"),
         axis: str = typer.Option(..., "--axis", help="Axis name, e.g. X."),
         tf: str = typer.Option(..., "--tf", help="G_M, G_T, G_tcp, G_v, G_p, cmd_to_tcp, "
                                 "cmd_to_motor, cmd_to_current, or the open sampled "
                                 "loops L_v (velocity) and L_p (position)."),
         freq_hz: str = typer.Option(None, "--freq-hz", help="F1,F2,... [Hz]"),
         as_json: bool = typer.Option(False, "--json"),
         plot: Path = typer.Option(None, "--plot", help="Save a Bode plot.")):
    """Frequency response of a transfer function of the model."""
    import numpy as np

    from ..mechanics.transfer import REDUCED
    from ..servo.closedloop import CLOSED_LOOP_TFS, TF_MEANING

    checked_plot(plot)
    m = read_model(model)
    a = m.axis(axis)
    f = np.array(floats(freq_hz, "--freq-hz")) if freq_hz else np.logspace(0, 3.2, 200)
    if np.any(f <= 0):
        raise typer.BadParameter("--freq-hz values must be positive")
    if tf in CLOSED_LOOP_TFS:
        warn_unstable(m, f"model {model}", [axis.upper()])
    if tf not in (*REDUCED, *CLOSED_LOOP_TFS, *OPEN_LOOPS):
        raise typer.BadParameter(
            f"--tf must be one of {', '.join([*REDUCED, *CLOSED_LOOP_TFS, *OPEN_LOOPS])}")
    if tf in OPEN_LOOPS:
        f = _open_loop_grid(a, tf, f, given=bool(freq_hz))
    H = _response(a, tf, f)
    spread = _drawn(m, axis, tf, f, H)
    if plot is not None:
        from ..plot.bode import plot_bode

        ends = [] if spread is None else [  # the draws' least and largest, as the text says
            (f"drawn, {w}", f, spread[i] * np.exp(1j * np.radians(spread[i + 2])),
             {"color": "0.5", "lw": 0.8, "ls": "--"}) for i, w in ((0, "least"), (1, "largest"))]
        plot_bode({tf: [(f"{axis.upper()} model", f, H, {"color": "tab:red"}), *ends]}, plot)
    meaning, unit = TF_MEANING[tf]
    rows = [{"freq_hz": float(fi), "re": float(h.real), "im": float(h.imag), "unit": unit}
            for fi, h in zip(f, H, strict=True)]
    if spread is not None:
        for r, *band in zip(rows, *spread, strict=True):
            r.update(zip(DRAWN_KEYS, map(float, band), strict=True))
    if as_json:
        emit_json(rows)
        return
    out.print(esc(f"{tf} of axis {axis.upper()}: {meaning} [{unit}]"), highlight=False)
    for r in rows:
        h = complex(r["re"], r["im"])
        drawn = (f"  (drawn: |H| {r['abs_low']:.4g} to {r['abs_high']:.4g}, phase "
                 f"{r['phase_low_deg']:.1f} to {r['phase_high_deg']:.1f} deg)"
                 if "abs_low" in r else "")
        out.print(f"{r['freq_hz']:12.4g} Hz  |H| {abs(h):<12.6g} {unit:<8} phase "
                  f"{np.degrees(np.angle(h)):8.2f} deg{drawn}", highlight=False)
    if spread is not None:
        out.print(f"drawn: over {DRAWN} machines drawn from the identified model's "
                  "uncertainty, as tcpmm spread draws them; near a lightly damped mode the "
                  "response turns on its frequency and damping", highlight=False)
