"""``tcpmm tune``: servo settings for stability margins, with the path before and after."""

from __future__ import annotations

import re
from pathlib import Path

import typer

from ..servo.tune import MARGIN_RANGE, margins_valid
from ._app import (
    app,
    emit_json,
    esc,
    in_file,
    interp_settings,
    out,
    read_model,
)
from ._outputs import checked_yaml_output
from ._tables import plain_table, print_plain

_MARGINS = re.compile(r"^\s*([0-9.]+)\s*db\s*,\s*([0-9.]+)\s*deg\s*$", re.IGNORECASE)


def parse_margins(text: str) -> tuple[float, float]:
    """``"6dB,45deg"`` -> (6.0, 45.0) [dB, deg]; a bad text is a ``BadParameter``."""
    m = _MARGINS.match(text or "")
    try:
        gm, pm = float(m.group(1)), float(m.group(2))
    except (AttributeError, ValueError):
        raise typer.BadParameter(f"--margins must look like 6dB,45deg, got {text!r}") from None
    if not margins_valid(gm, pm):
        raise typer.BadParameter(f"--margins {text!r}: give {MARGIN_RANGE}")
    return gm, pm


@app.command()
def tune(model: str = typer.Argument(..., help="MODEL.yaml or builtin:vmc"),
         margins: str = typer.Option("6dB,45deg", "--margins",
                                     help="Required gain and phase margins, e.g. 6dB,45deg."),
         gcode: Path = typer.Option(None, "--gcode",
                                    help="NC program PROG.nc to predict instead of the "
                                         "paper's circle (R35 mm, F5000 mm/min)."),
         axes: str = typer.Option(None, "--axes",
                                  help="Contouring axes whose position gains and feedforward "
                                       "are matched, e.g. XY; default the axes the path "
                                       "moves. Every other axis is tuned on its own."),
         mode_tolerance_percent: float = typer.Option(
             5.0, "--mode-tolerance", min=0.0, max=49.0,
             help="How far the machine's mode frequencies may lie from the model's [%]: "
                  "every proposal stays stable with its modes that far off."),
         output: Path = typer.Option(None, "-o", "--output", help="Write the tuned MODEL.yaml."),
         jobs: int = typer.Option(0, "--jobs", min=0, help=(
             "Axes whose own loops are tuned at once, each in a process of its own; 0: one "
             "per core. The numbers do not depend on it.")),
         as_json: bool = typer.Option(False, "--json")):
    """Propose velocity-loop gains, notch filters, position gain and feedforward that meet
    the margins on the sampled loops; predict the path before and after."""
    from ..io.modelfile import write_machine
    from ..servo.modeshift import mode_tolerance
    from ..whatif.tuning import tune_and_predict

    gm, pm = parse_margins(margins)
    if output is not None:
        checked_yaml_output(output, model, gcode)
    m = read_model(model)
    command = None
    if gcode is not None:
        from ..path import program_to_command

        with in_file(gcode):
            command = program_to_command(gcode, interp_settings(m))
    with mode_tolerance(mode_tolerance_percent / 100.0):
        res = tune_and_predict(m, gm, pm, command, axes, jobs=jobs)
    _warn(res)
    if output is not None:
        write_machine(res.tuned, output)
    if as_json:
        body = {**res.to_dict(), "notes": _unwarned(res)}
        for name, t in res.axes.items():  # the table's "*", for a program
            marks = _unstable_marks(m.axes[name].mechanics, t)
            body["axes"][name]["sampled_loop_stable"] = {
                when: {loop: not marks[loop][i] for loop in marks}
                for i, when in enumerate(("before", "after"))}
        emit_json({"margins_required": {"gain_db": gm, "phase_deg": pm,
                                         "mode_tolerance_percent": mode_tolerance_percent},
                   **body, "output": None if output is None else str(output)})
        return
    _print_result(res, gm, pm, mode_tolerance_percent, m)
    if output is not None:
        out.print(f"wrote {output}")


def _warn(res) -> None:
    """Each axis's warnings, and the draws' on a proposal that fails on some, as warnings:
    on stderr, and first in ``--json``."""
    import warnings

    from ..errors import InputWarning
    from ..whatif.tuning_draws import proposal_fails

    for name, t in res.axes.items():
        for warning in t.warnings:
            warnings.warn(f"axis {name}: {warning}", InputWarning, stacklevel=2)
    if res.drawn and res.drawn.get("proposal_fails"):
        warnings.warn(proposal_fails(res.drawn), InputWarning, stacklevel=2)


def _unwarned(res) -> list[str]:
    """The result's notes less what :func:`_warn` says as a warning [-]."""
    from ..whatif.tuning_draws import proposal_fails

    said = proposal_fails(res.drawn) if res.drawn and res.drawn.get("proposal_fails") else None
    return [n for n in res.notes if n != said]


def _fmt(v, digits=1):
    """``digits`` decimals; a value those would show as 0 with two significant digits."""
    if v is None:
        return "-"
    if v != v:
        return "n/a"
    return f"{v:.2g}" if 0 < abs(v) < 10.0 ** (1 - digits) else f"{v:.{digits}f}"


def _unstable_marks(mech, t) -> dict:
    """Per loop, ``"*"`` per column (before, after) whose sampled loop is unstable: the
    velocity loop judged alone (:func:`~tcpmm.servo.modeshift.velocity_only`), the
    position loop whole, which closes around the velocity loop and whose margins assume
    that one holds [-]."""
    from ..servo.modeshift import velocity_only
    from ..servo.sampled import sampled_loop_stable

    def marks(alone):
        return tuple("" if sampled_loop_stable(mech, velocity_only(s) if alone else s)
                     else "*" for s in (t.before, t.after))

    vel = marks(True)
    return {"velocity": vel, "position": tuple(v or p for v, p in zip(vel, marks(False),
                                                                      strict=True))}


def _print_result(res, gm, pm, tolerance_percent: float, machine) -> None:
    for name, t in res.axes.items():
        drawn = (res.margins_drawn or {}).get(name)
        n = next(iter(drawn.values()))["draws"] if drawn else 0
        tab = plain_table(("", "before", "after") + ((f"after, {n} draws",) if drawn else ()))
        b, a = t.before, t.after
        marks = _unstable_marks(machine.axes[name].mechanics, t)
        rows = [("K_vp [A s/rad]", b.K_vp, a.K_vp, 4), ("T_i = K_vp/K_vi [ms]", _ti(b), _ti(a), 2),
                ("K_pp [1/s]", b.K_pp, a.K_pp, 2), ("k_ff [-]", b.k_ff, a.k_ff, 2)]
        for label, x, y, d in rows:
            tab.add_row(esc(label), _fmt(x, d), _fmt(y, d))
        for label, x, y in _filter_rows(b, a):
            tab.add_row(label, x, y)
        for row in _margin_rows(t, marks, drawn):
            tab.add_row(*row)
        caption = [f"after, {n} draws: over {n} machines drawn from the model's uncertainty, "
                   "the least first" if drawn else None,
                   "*: of no meaning, the sampled loop is unstable with these settings"
                   if any(any(m) for m in marks.values()) else None]
        print_plain(tab, out, f"axis {name}: tuning for {gm:g} dB / {pm:g} deg, stable with "
                              f"the modes {tolerance_percent:g} % off: {_verdict(t, drawn)}",
                    "\n".join(c for c in caption if c) or None)
        if name in res.reasons:
            out.print(f"  {esc(res.reasons[name])}")
        for note in t.notes:
            out.print(f"  {esc(note)}")
    for note in _unwarned(res):
        out.print(esc(note))
    if not res.path_before:
        return
    drawn = (res.drawn or {}).get("figures")
    n = res.drawn["draws"] - res.drawn["faulty"] if drawn else 0
    tab = plain_table(("", "before", "after")
                      + ((f"after, {n} draws", "change, draw by draw") if drawn else ()))
    for key, fig in res.path_before.items():
        for k, v in fig.items():
            d = (drawn or {}).get(key, {}).get(k)
            ranges = () if not drawn else (
                ("n/a", "n/a") if d is None else
                (f"{_fmt(d['after_low'], 2)} to {_fmt(d['after_high'], 2)}",
                 f"{d['change_low']:+.2f} to {d['change_high']:+.2f}"))
            tab.add_row(f"{key} {k.replace('_um', '').replace('_', ' ')}", _fmt(v, 2),
                        _fmt(res.path_after[key][k], 2), *ranges)
    fails = res.drawn.get("proposal_fails", 0) if drawn else 0
    print_plain(tab, out, "predicted path (TCP) [µm]" + (
        f": the model's, and the range over {n} machine{'s' if n != 1 else ''} drawn from "
        "its uncertainty" + (f" (not over the {fails} on which the proposal fails)"
                             if fails else "") if drawn else ""))


def _margin_rows(t, marks: dict, drawn: dict | None) -> list[tuple]:
    """The rows of each loop's margins and bandwidth, before and after, and the margins'
    range over the draws where there are draws [-]."""
    rows = []
    for loop in ("velocity", "position"):
        mb, ma = t.margins_before[loop].to_dict(), t.margins_after[loop].to_dict()
        mk = marks[loop]
        for label, key in (("gain margin [dB]", "gain_margin_db"),
                           ("phase margin [deg]", "phase_margin_deg"),
                           ("bandwidth [Hz]", "bandwidth_hz")):
            row = (esc(f"{loop} {label}"), _fmt(mb[key]) + mk[0], _fmt(ma[key]) + mk[1])
            if drawn:
                span = drawn[loop].get(key)
                row += ("" if span is None else " to ".join(
                    "inf" if v is None else _fmt(v) for v in span),)
            rows.append(row)
    return rows


def _verdict(t, drawn: dict | None = None) -> str:
    """Met, met only with the velocity loop slowed down, or not met; where there are
    draws, met on the model and on how many of them [-]."""
    from ..servo.modeshift import bandwidth_text, slowed
    from ..whatif.tuning_draws import margins_missed

    if not t.met:
        return "NOT MET, settings kept"
    cut = slowed(t.margins_before, t.margins_after)
    said = "met" if cut is None else (f"met only with the velocity loop slowed from "
                                      f"{bandwidth_text(cut[0])} to {bandwidth_text(cut[1])} "
                                      "Hz (see the warning)")
    if not drawn:
        return said
    n, missed = next(iter(drawn.values()))["draws"], margins_missed(drawn)
    if not missed:
        return f"{said}, on the model and on all {n} machines drawn from its uncertainty"
    return (f"{said} on the model; NOT MET on {missed} of {n} machines drawn from its "
            "uncertainty (the least of each margin in the table)")


def _ti(s):
    return None if s.K_vi == 0 else 1e3 * s.K_vp / s.K_vi


def _filter_rows(before, after) -> list[tuple[str, str, str]]:
    """The current-setpoint filters before and after, one row per slot, as a
    commissioning engineer types them in [-]."""
    from ..servo.currentfilters import filter_text

    n = max(len(before.filters), len(after.filters))
    if n == 0:
        return [("filters", "none", "none")]
    return [(f"filter {i + 1}", *(filter_text(fs[i]) if i < len(fs) else "-"
                                  for fs in (before.filters, after.filters)))
            for i in range(n)]
