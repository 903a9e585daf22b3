"""Commands of identification: excite, identify, spread."""

from __future__ import annotations

import math
from pathlib import Path

import typer

from ..errors import InputError
from ._app import (
    Sensor,
    app,
    checked_plot,
    checked_report_file,
    console,
    emit_json,
    floats,
    load_command,
    out,
    parse_band,
    positive,
    progress_bar,
    read_model,
    refuse_unstable,
    warn_suspect,
)
from ._outputs import checked_csv_output, checked_yaml_output, outputs_together


def _emit_spread(res, verdict, machine) -> None:
    """``tcpmm spread --json``: the draws, the verdict and the model they came from (its
    name and file digest, which the report checks against its ``--model``) [-]."""
    from ..io.modelfile import model_identity

    emit_json({**res.to_dict(), "verdict": verdict.to_dict(),
               "model": model_identity(machine)})


def _say_faulted(faulted: int, draws: int) -> None:
    """A warning of the drawn machines whose run is no prediction, where there are any."""
    if faulted:
        console.print(f"warning: {faulted} of {draws} drawn machines run away or hold their "
                      "current at the limit: no prediction, they count against every point "
                      "(the model's uncertainty holds machines whose servo does not hold)",
                      highlight=False)


@app.command()
def spread(model: str = typer.Argument(..., help="MODEL.yaml written by tcpmm identify"),
           command: Path = typer.Option(None, "--command", help="Command file CMD.csv."),
           gcode: Path = typer.Option(None, "--gcode", help="NC program PROG.nc."),
           radius: float = typer.Option(..., "--radius", help="Nominal radius [mm]."),
           centre: str = typer.Option("0,0", "--centre", help="Nominal centre X,Y [mm]."),
           draws: int = typer.Option(16, "--draws", min=10, help=(
               "Machines drawn, at least 10: a spike is firm where nine in ten of them "
               "hold it [-].")),
           seed: int = typer.Option(0, "--seed", min=0, help="Seed of the draws [-]."),
           sensor: Sensor = typer.Option("tcp", "--sensor", help="Sensor analysed."),
           fit_only: bool = typer.Option(
               False, "--fit-only",
               help="Draw from the fits' own standard deviations alone, without the "
                    "floors of tcpmm.whatif.spread.MODEL_ERROR."),
           tolerance: float = typer.Option(
               None, "--tolerance-um",
               help="Spike difference to hold at nine in ten draws [um]; default: the "
                    "largest of the paper's Table 2, 4.1 um (tcpmm.whatif.spread.TOLERANCE)."),
           as_json: bool = typer.Option(False, "--json"),
           plot: Path = typer.Option(None, "--plot", help="Save a plot (PNG/PDF/SVG).")):
    """Reversal spikes of a circle with their spread over the identified uncertainty."""
    from ..whatif.spread import DRAWS_NOTE, MODEL_ERROR, TOLERANCE, circle_spread
    from ._tables import print_table

    if tolerance is not None:
        positive(tolerance, "--tolerance-um [um]")
    positive(radius, "--radius [mm]")
    checked_plot(plot)
    tol_m = TOLERANCE if tolerance is None else tolerance * 1e-6
    m = read_model(model)
    refuse_unstable(m, model, allowed=False)
    cmd = load_command(command, gcode, m)
    c = floats(centre, "--centre", 2)
    with progress_bar(draws + 1, "spread") as adv:
        res = circle_spread(m, cmd, radius * 1e-3, (c[0] * 1e-3, c[1] * 1e-3), n=draws,
                            seed=seed, sensor=sensor.value,
                            floors=None if fit_only else MODEL_ERROR,
                            tolerance_m=tol_m, progress=adv)
    if plot is not None:
        res.plot(path=plot)
    _say_faulted(res.faulted, draws)
    verdict = _spread_verdict(m, cmd, radius, c, sensor.value)
    if as_json:
        return _emit_spread(res, verdict, m)
    table = res.to_pandas().drop(columns="firm").rename(columns={"settled": "sign held",
                                                                 "draws_agree": "draws agree"})
    print_table(table, out, f"{sensor.value} raw reversal spikes (e - b) over {draws} drawn "
                "machines")
    out.print(f"draws agree: nine in ten drawn machines within {tol_m * 1e6:g} µm of the "
              f"spike. {DRAWS_NOTE}", highlight=False)
    for r in res.unsettled():
        out.print(f"{r['direction'].upper()} {r['point']}: the sign is not settled "
                  f"({100 * r['same_sign']:.0f} % of the draws give it): rise "
                  f"{r['rise_um']:+.2f} µm, fall {r['fall_um']:+.2f} µm; a measured spike "
                  "can differ from this one by their sum")
    for r in res.loose():
        out.print(f"{r['direction'].upper()} {r['point']}: the draws do not hold the size "
                  f"({100 * r['within']:.0f} % of the draws lie within {tol_m * 1e6:g} µm of "
                  f"{r['spike_um']:.2f} µm; range {r['low_um']:.2f} to {r['high_um']:.2f} µm)")
    _print_verdict(verdict)


def _spread_verdict(machine, command, radius_mm: float, centre_mm, sensor: str):
    """The verdict on the figures of the user's circle (:mod:`tcpmm.uncertainty`)."""
    from ..uncertainty import CircleTest, prediction_verdict

    plane = tuple(list(machine.axes)[:2])
    test = CircleTest(f"R{radius_mm:g}", command, radius_mm * 1e-3,
                      (centre_mm[0] * 1e-3, centre_mm[1] * 1e-3), plane)
    return prediction_verdict(machine, [test], sensor, jobs=0)

@app.command()
def excite(kind: str = typer.Argument(..., help="linear, log, multisine or prbs"),
           band: str = typer.Option(..., "--band", help="F0,F1 [Hz]"),
           amplitude_A: float = typer.Option(..., "--amplitude-A", help="Amplitude [A]."),
           duration_s: float = typer.Option(..., "--duration-s", help="Duration [s]."),
           fs_hz: float = typer.Option(..., "--fs-hz", help="Sample rate [Hz]."),
           output: Path = typer.Option(..., "-o", "--output", help="FILE.csv"),
           taper_s: float = typer.Option(None, "--taper-s", help="Fade in/out [s] (sweeps)."),
           seed: int = typer.Option(None, "--seed", min=0,
                                    help="Random phases seed (multisine).")):
    """Design an excitation signal for the current command (time_s, excitation_A)."""
    from ..ident.excitation import design_excitation

    f0, f1 = parse_band(band, "--band")
    checked_csv_output(output, what="an excitation")
    options = {"f0_hz": "--band", "f1_hz": "--band", "amplitude_A": "--amplitude-A",
               "duration_s": "--duration-s", "fs_hz": "--fs-hz", "taper_s": "--taper-s",
               "kind": "KIND", "seed": "--seed"}
    try:
        exc = design_excitation(kind, f0, f1, amplitude_A, duration_s, fs_hz,
                                taper_s=taper_s, seed=seed)
    except InputError as err:
        if err.file is None and err.column in options:
            raise typer.BadParameter(err.message, param_hint=options[err.column]) from None
        raise
    exc.write_csv(output)
    out.print(f"wrote {output}: {exc.kind}, band {exc.band_hz[0]:g}-{exc.band_hz[1]:g} Hz, "
              f"{exc.time_s.size} samples ({exc.time_s.size / exc.fs_hz:g} s), "
              f"peak {exc.peak_A:.3g} A, rms {exc.rms_A:.3g} A, crest {exc.crest_factor:.2f}")


@app.command()
@outputs_together()
def identify(bundle: Path = typer.Argument(..., help="Measurement bundle folder."),
             output: Path = typer.Option(..., "-o", "--output", help="MODEL.yaml"),
             report: Path = typer.Option(
                 None, "--report", help="Folder for plots and tables; a name ending in "
                                        ".html: the HTML report instead (tcpmm report)."),
             band: str = typer.Option(None, "--band", help="F0,F1 of the FRFs [Hz]."),
             guideway_share: float = typer.Option(
                 None, "--guideway-share", min=0.0, max=1.0,
                 help="Share of the friction from friction.csv put on the guideway [-]; "
                      "default: from the encoder-minus-scale deflection of the runs."),
             presliding_um: float = typer.Option(
                 None, "--presliding-um", min=0.0,
                 help="Pre-sliding displacement of the friction contacts [um] (LuGre); "
                      "0: static friction that sticks rigidly; default: fitted to the "
                      "reversals of the friction runs."),
             accept_suspect: bool = typer.Option(
                 False, "--accept-suspect",
                 help="Write the model even when the gates find it physically suspect "
                      "(static friction beyond the drive, a negative fit, an unstable "
                      "sampled loop, a time column in the wrong unit), marked as suspect "
                      "in the file."),
             strict: bool = typer.Option(
                 False, "--strict",
                 help="Exit with code 3 when a predicted figure of the reference circles is "
                      "not firm (the model is written all the same)."),
             jobs: int = typer.Option(0, "--jobs", min=0, help=(
                 "Axes identified at once, each in a process of its own; 0: one per core. "
                 "The numbers do not depend on it.")),
             as_json: bool = typer.Option(False, "--json")):
    """Identify every axis of a measurement bundle into a model file.

    A model that the gates (tcpmm.ident.gates) find physically suspect is an error and is
    not written, unless --accept-suspect. It ends with a verdict per axis and per predicted
    figure of the reference circles (R35 mm, F5000 and F10000): firm, uncertain +- X um
    (cause) or undetermined (cause), with the measurement that would settle it.
    """
    from ..ident.chain import identify_bundle
    from ..io.atomic import check_output_folder
    from ..io.bundle import read_bundle

    checked_yaml_output(output)
    html = report is not None and report.suffix.lower() in (".html", ".htm")
    if html:
        checked_report_file(report, bundle, output)
    elif report is not None:
        check_output_folder(report)
    f0, f1 = parse_band(band, "--band")
    b = read_bundle(bundle)
    presliding = None if presliding_um is None else presliding_um * 1e-6
    with progress_bar(len(b.axes), "identify") as adv:
        idn = identify_bundle(b, f0, f1, progress=adv, guideway_share=guideway_share,
                              presliding=presliding, accept_suspect=accept_suspect,
                              jobs=jobs)
    _write_identified(idn, output, report, html, bundle)
    warn_suspect(idn.machine, f"the model written to {output}")
    if as_json:
        emit_json(idn.to_dict())
    else:
        _print_identification(idn, presliding, output, report)
    _exit_if_not_firm(idn.verdict, strict)


def _write_identified(idn, output: Path, report, html: bool, bundle: Path) -> None:
    """Write the model file and, where asked, its report: the HTML page, or the folder of
    plots and tables, which is not left behind when the model cannot be written.

    Parameters
    ----------
    idn : Identification
        The identification [-].
    output : Path
        The model file [-].
    report : Path or None
        The report page or folder [-].
    html : bool
        The report is an HTML page [-].
    bundle : Path
        The measurement bundle, named in the page [-].
    """
    from ..io.atomic import staged_folder
    from ..io.modelfile import write_machine
    from ._app import WARNED

    idn.meta["warnings"] = list(WARNED)  # what identify said, for the report to say too
    if html:
        _identification_report(idn, report, bundle, output)
        write_machine(idn.machine, output)
    elif report is not None:
        with staged_folder(report) as rep:  # a model that cannot be written: no report
            idn.write_report(rep)
            write_machine(idn.machine, output)
    else:
        write_machine(idn.machine, output)


def _print_identification(idn, presliding, output: Path, report) -> None:
    """Print the fit quality, the friction split, the pre-sliding, the verdict and what
    was written, on the console.

    Parameters
    ----------
    idn : Identification
        The identification [-].
    presliding : float or None
        The pre-sliding displacement given, None where fitted [m].
    output : Path
        The model file [-].
    report : Path or None
        The report page or folder [-].
    """
    from ._tables import print_table

    print_table(idn.quality_table().drop(columns=["modes_hz"]), out, "fit quality")
    _print_split(idn)
    _print_presliding(idn, presliding)
    _print_verdict(idn.verdict, reference_note())
    out.print(f"wrote {output}" + (f" and the report in {report}" if report else ""))


def reference_note() -> str:
    """What identify's verdict figures are of, said before them [-]."""
    from ..uncertainty.figures import REFERENCE_WORDS

    return (f"the verdicts' circles: {REFERENCE_WORDS}; for your own circle: "
            "tcpmm spread MODEL --command CMD.csv --radius R")


def _print_verdict(verdict, heading: str | None = None) -> None:
    """Per axis its verdict and what its data leave open; per figure of the circles the
    least firm verdict over both directions, with what would settle it, after
    ``heading``."""
    from ..analysis.compare import raw_spike_named

    if verdict is None:
        return
    if heading and verdict.figures:
        out.print(heading, highlight=False)
    for name, d in verdict.axes.items():
        line = f"verdict axis {name}: {d['verdict']}"
        for r in d["open"]:
            line += f"; open: {r['quantity']} ({r['cause']}; to settle: {r['settle']})"
        out.print(line)
    for key, f in verdict.worst().items():
        settle = f"; to settle: {f.settle}" if f.verdict != "firm" and f.settle else ""
        # the least firm of both directions is shown: its direction said (--json has both)
        way = f" ({f.direction.upper()})" if getattr(f, "direction", None) else ""
        value = (f"{f.nominal * 1e6:.2f} um" if math.isfinite(f.nominal) else
                 "not predicted")
        out.print(f"verdict {raw_spike_named(key)}{way}: {value}, {f.text()}{settle}")


def _exit_if_not_firm(verdict, strict: bool) -> None:
    """With --strict, exit 3 where a predicted figure is not firm."""
    if not strict or verdict is None or verdict.firm:
        return
    loose = [f for f in verdict.figures if f.verdict != "firm"]
    console.print(f"[red]strict:[/red] {len(loose)} of {len(verdict.figures)} predicted "
                  "figures of the reference circles are not firm (see the verdict lines)")
    raise typer.Exit(3)


#: How each source of the guideway share reads in the summary.
_SHARE_FROM = {"sweep": "from the TCP deflection of the travelling sweep",
               "data": "from the nut deflection of the friction runs",
               "given": "as given", "prior": "the prior: the runs do not determine it"}


def _print_split(idn) -> None:
    """One line per axis: the guideway share, where it came from, and the table damping
    it rests on with the measures it was weighed from."""
    for name, a in idn.axes.items():
        sp = a.friction_split
        if sp is None:
            continue
        sd = (f" +- {sp.guideway_share_std:.3f}" if sp.source in ("sweep", "data")
              and math.isfinite(sp.guideway_share_std) else "")
        line = (f"friction {name}: guideway share {sp.guideway_share:.3f}{sd} "
                f"({_SHARE_FROM.get(sp.source, sp.source)})")
        if sp.source != "prior" and math.isfinite(sp.table_viscous):
            line += (f"; table damping {sp.table_viscous:.0f} +- {sp.table_viscous_std:.0f} "
                     "N s/m")
            lm, phys = sp.estimate, a.physical
            if math.isfinite(sp.viscous_on_table) and lm is not None:
                line += (f" (plateaus {lm.table_viscous:.0f} +- {lm.table_viscous_std:.0f}, "
                         f"FRFs {phys.mechanics.C_t:.0f} +- "
                         f"{phys.std.get('C_t', float('nan')):.0f})")
        out.print(line)


def _print_presliding(idn, presliding) -> None:
    """One line per axis: the pre-sliding fitted, or assumed and why."""
    from ..ident.friction import PRESLIDING

    for name, a in idn.axes.items():
        if a.friction is None:
            console.print(f"warning: axis {name}: no friction runs ({name}/friction.csv): the "
                          "model has no friction, so the reversal spikes, G and contour error "
                          "of a circle that moves it are undetermined", highlight=False)
            continue
        fit = a.presliding_fit
        if presliding is not None:
            out.print(f"friction {name}: pre-sliding {presliding * 1e6:g} um as given")
        elif fit is not None and fit.determined:
            out.print(f"friction {name}: pre-sliding {fit.presliding * 1e6:.2f} "
                      f"+- {fit.presliding_std * 1e6:.2f} um, bristle damping ratio "
                      f"{fit.damping_ratio:.2f} +- {fit.damping_ratio_std:.2f} "
                      f"(fitted to {fit.reversals} reversals of the friction runs)"
                      + _presliding_range_note(a))
        else:
            why = fit.reason if fit is not None else "no friction runs"
            out.print(f"friction {name}: pre-sliding of {PRESLIDING * 1e6:g} um assumed "
                      f"({why}; --presliding-um sets it)")


def _presliding_range_note(a) -> str:
    """The range the pre-sliding fit leaves and what it does to the spikes, or ``""``."""
    from ..ident.friction.sensitivity import moved_by

    sens = a.presliding_sensitivity
    if sens is None:
        return ""
    lo, hi = sens.presliding_m
    return (f"; {lo * 1e6:.2f}-{hi * 1e6:.2f} um possible, over which the TCP spikes of a "
            f"circle move {moved_by(sens.spike_change_m)}")


def _identification_report(idn, report: Path, bundle: Path, model: Path) -> None:
    """The HTML report of an identification: the identified model and the fits."""
    from ..report import identification_result_section, model_section, write_report

    write_report(report, [model_section(idn.machine, model), identification_result_section(idn)],
                 f"Identification of {bundle.resolve().name}", [("bundle", bundle)])
