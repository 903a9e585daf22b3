"""The report command: one self-contained HTML commissioning report."""

from __future__ import annotations

import re
from pathlib import Path

import typer

from ._app import app, checked_report_file, floats, out, positive, read_model
from ._circle_files import analysed_pair, circle_of_file
from ._plane import PLANE_HELP


@app.command()
def report(output: Path = typer.Option(..., "-o", "--output", help="REPORT.html"),
           model: str = typer.Option(None, "--model", help="MODEL.yaml or builtin:vmc: the "
                                     "machine and model summary."),
           ident_dir: Path = typer.Option(None, "--ident-dir", help="Folder written by "
                                          "tcpmm identify BUNDLE -o MODEL.yaml --report DIR."),
           runs: list[str] = typer.Option(
               None, "--run", metavar="RUN.csv",
               help="RUN.csv of a circular test, with the diagnostics when it holds a CCW "
                    "and a CW circle; RUN_CCW.csv,RUN_CW.csv: two runs diagnosed together; "
                    "repeat for more tests."),
           measured: list[Path] = typer.Option(
               None, "--measured", metavar="RUN.csv",
               help="Measured RUN.csv of a circle; with --predicted."),
           predicted: list[Path] = typer.Option(
               None, "--predicted", metavar="RUN.csv",
               help="Predicted RUN.csv of the same circle; one per --measured."),
           radius: float = typer.Option(None, "--radius", help="Nominal radius of the "
                                        "circles [mm]."),
           centre: str = typer.Option("0,0", "--centre", help="Nominal centre in the "
                                      "plane's axes, A,B [mm]."),
           plane: str = typer.Option(None, "--plane", help=PLANE_HELP),
           spread: Path = typer.Option(None, "--spread", help="SPREAD.json: tcpmm spread "
                                       "--json > SPREAD.json, or the demo's spread.json."),
           title: str = typer.Option("Commissioning report", "--title", help="Page title."),
           tolerance_um: float = typer.Option(
               None, "--tolerance-um", help="Largest circular deviation G accepted [µm]: the "
                                            "verdict on the first circle is PASS or FAIL "
                                            "against it; without it against the --model's "
                                            "specification, else G is given unjudged."),
           measured_on: str = typer.Option(
               None, "--measured-on", metavar="YYYY-MM-DD",
               help="Date of the circular test, given with its conditions.")):
    """One self-contained HTML file, in the order a customer reads it: the verdict on the
    first circle (test conditions, pass or fail, error sources ranked), the circular tests
    with their diagnostics, measured - predicted (Table 2), spread, identification, model;
    a section for each input given. It opens with no network; every table downloads as CSV
    from the page."""
    from ..report import write_report

    runs = [[Path(f) for f in r.split(",")] for r in runs or []]
    measured, predicted = measured or [], predicted or []
    _check_inputs(output, model, ident_dir, spread, runs, measured, predicted, radius)
    tol = None if tolerance_um is None else positive(tolerance_um, "--tolerance-um") * 1e-6
    machine = read_model(model) if model is not None else None
    verdict = {"tolerance_m": tol, "measured_on": _date(measured_on)}
    if tol is None and machine is not None and machine.specification is not None:
        verdict.update(tolerance_m=machine.specification.circular_deviation_m, specified=True)
    sections, inputs = [], []
    if runs or measured:
        sections, inputs = _circle_sections(runs, measured, predicted, radius, centre,
                                            verdict, machine, plane)
    more, given = _summary_sections(spread, ident_dir, model, machine)
    sections += more
    write_report(output, sections, title, inputs + given)
    out.print(f"wrote {output} ({', '.join(t for _, t, _ in sections)})")


def _date(text):
    """The ``--measured-on`` date, or ``None`` [-]."""
    import datetime

    if text is None:
        return None
    text = text.strip()
    if not re.fullmatch(r"\d{4}-\d{2}-\d{2}", text):
        raise typer.BadParameter(f"--measured-on {text!r}: give the date as YYYY-MM-DD, "
                                 "e.g. 2026-11-30")
    try:
        day = datetime.date.fromisoformat(text)
    except ValueError as exc:
        raise typer.BadParameter(f"--measured-on {text!r}: no such day ({exc})") from None
    # a day ahead is another time zone's today; more is a mistyped year
    if day > datetime.date.today() + datetime.timedelta(days=1):
        raise typer.BadParameter(f"--measured-on {text!r}: a day still to come; give the "
                                 "day the run files were measured")
    return day


def _check_inputs(output: Path, model, ident_dir, spread, runs, measured, predicted,
                  radius) -> None:
    """Refuse a report that is given nothing, pairs runs wrongly, lacks the circles'
    radius, or would overwrite one of its inputs.

    Parameters
    ----------
    output : Path
        The report page [-].
    model : str or None
        The model file or builtin name [-].
    ident_dir, spread : Path or None
        The identification folder and the spread file [-].
    runs : list of list of Path
        The run files of each circular test, one or two [-].
    measured, predicted : list of Path
        The measured and predicted runs, pair by pair [-].
    radius : float or None
        The circles' nominal radius [mm].
    """
    if any(len(r) > 2 or not all(str(f) for f in r) for r in runs):
        raise typer.BadParameter("--run takes RUN.csv or RUN_CCW.csv,RUN_CW.csv")
    checked_report_file(output, model, ident_dir, spread, *(f for r in runs for f in r), *measured,
                 *predicted)
    if len(measured) != len(predicted):
        raise typer.BadParameter(f"give one --predicted per --measured (got {len(measured)} "
                                 f"--measured and {len(predicted)} --predicted)")
    if (runs or measured) and radius is None:
        raise typer.BadParameter("--radius [mm] is needed with --run and --measured")
    if not (model or ident_dir or runs or measured or spread):
        raise typer.BadParameter("nothing to report: give --model, --ident-dir, --run, "
                                 "--measured/--predicted or --spread")


def _circle_sections(runs, measured, predicted, radius: float, centre: str, verdict: dict,
                     machine, plane=None) -> tuple[list, list]:
    """The sections of the circular tests: each run's, the runs' faults, and measured
    minus predicted of each pair.

    Parameters
    ----------
    runs : list of list of Path
        The run files of each circular test [-].
    measured, predicted : list of Path
        The measured and predicted runs, pair by pair [-].
    radius : float
        The circles' nominal radius [mm].
    centre : str
        Their nominal centre, ``X,Y`` [mm].
    verdict : dict
        ``tolerance_m``, the largest circular deviation the verdict accepts [m] or None,
        and ``measured_on``, the test's date or None [-].
    machine : Machine or None
        The model, which tells the runs' faults; each TCP difference of Table 2 is set
        against its predicted figure's 90 % interval and verdict, as ``tcpmm compare
        --model`` sets it [-].
    plane : str, optional
        ``--plane`` [-].

    Returns
    -------
    sections : list
        The report's sections [-].
    inputs : list of (str, Path)
        The files they come from, by role [-].
    """
    c = floats(centre, "--centre", 2)
    # one plane per file, said once however many sections analyse it
    circle = (positive(radius, "--radius [mm]") * 1e-3, (c[0] * 1e-3, c[1] * 1e-3), plane, {})
    from ..report.html import distinct_names

    # two run.csv of two folders are told apart by their folders, in titles and verdict
    shown = distinct_names([*(f for r in runs for f in r), *measured, *predicted])
    comparisons = [_comparison((m, p), circle, "comparison" if len(measured) == 1 else
                               f"comparison-{i + 1}", not runs and i == 0, verdict, machine,
                               shown)
                   for i, (m, p) in enumerate(zip(measured, predicted, strict=True))]
    sections = _run_sections(runs, circle, verdict, shown)
    sections += _faults(machine, [f for r in runs for f in r] + list(predicted))
    sections += [s for group in comparisons for s in group]
    inputs = ([("run", f) for r in runs for f in r] + [("measured", m) for m in measured]
              + [("predicted", p) for p in predicted])
    return sections, inputs


def _summary_sections(spread, ident_dir, model, machine) -> tuple[list, list]:
    """The sections of the spread, the identification and the model, each where given.

    Parameters
    ----------
    spread, ident_dir : Path or None
        The spread file and the identification folder [-].
    model : str or None
        The model file or builtin name [-].
    machine : Machine or None
        The model read [-].

    Returns
    -------
    sections : list
        The report's sections, in that order [-].
    inputs : list of (str, Path)
        The files they come from, by role [-].
    """
    from ..report import (
        identification_section,
        model_section,
        read_identification_folder,
        spread_section,
    )
    from ..report.spread_page import read_spread_json

    sections, inputs = [], []
    if spread is not None:
        data = read_spread_json(spread)
        _same_model(data, machine, spread, model)
        sections.append(spread_section(data))
        inputs.append(("spread", spread))
    if ident_dir is not None:
        sections.append(identification_section(*read_identification_folder(ident_dir)))
        inputs.append(("identification", ident_dir))
    if model is not None:
        sections.append(model_section(machine, model))
        inputs.append(("model", model))
    return sections, inputs


def _judged_if_its(pair, machine, run, circle, plane, predicted):
    """Table 2's TCP rows against the intervals of ``--model`` (``machine``), as ``tcpmm
    compare --model`` sets them; where the predicted run did not come from that model (a
    model given for its summary beside another's prediction), said on stderr and left
    unjudged [-]."""
    from ..uncertainty.verdict import NotItsPrediction
    from ._app import console
    from .run import judged_rows_of

    try:
        return judged_rows_of(pair, machine, run, circle[0] * 1e3, circle[1], plane,
                              predicted)
    except NotItsPrediction as exc:
        console.print(f"warning: Table 2 is not set against --model's intervals: "
                      f"{exc.message}", highlight=False)
        return None


def _same_model(spread: dict, machine, path, model) -> None:
    """Refuse a spread computed from another model than ``--model``, which the page would
    show side by side as one prediction; a spread that does not name its model (written
    before it did) is taken as it is [-]."""
    from ..errors import InputError
    from ..io.modelfile import model_identity

    given = spread.get("model")
    if machine is None or not isinstance(given, dict) or "digest" not in given:
        return
    if given["digest"] != model_identity(machine)["digest"]:
        raise InputError(f"was computed from the model '{given.get('name')}', not from "
                         f"--model {model}; give the spread of that model (tcpmm spread "
                         f"{model} ... --json)", file=path, column="model")


def _faults(machine, files) -> list:
    """The section of the runs' axes that ran away or saturated, said on stderr too; none
    without the model, whose gains and current limits tell them."""
    from ..analysis.runaway import run_faults
    from ..io.runfile import read_run
    from ..report import faults_section
    from ._app import console, esc

    if machine is None:
        return []
    found = [(f, fault) for f in files for fault in run_faults(machine, read_run(f))]
    for f, fault in found:
        console.print(f"[yellow]warning:[/yellow] {esc(str(f))}: {esc(fault.text())}")
    return [faults_section(found)] if found else []


def _run_sections(runs, circle, verdict: dict, shown: dict) -> list:
    """A circle section per run or pair of runs, keys numbered when there are several;
    the first opens with the verdict (``verdict``: its tolerance and date); ``shown``
    each file's name as the page gives it (:func:`tcpmm.report.html.distinct_names`)."""
    from ..analysis.circular import CircleResult
    from ..report import circle_test_section, verdict_sections

    sections = []
    for i, files in enumerate(runs):
        got = [circle_of_file(f, circle, shown=shown[str(f)]) for f in files]
        res = [r for r, _, _ in got]
        both = CircleResult(res[0].radius, res[0].centre, [p for r in res for p in r.passes],
                            res[0].plane)
        key = "circle" if len(runs) == 1 else f"circle-{i + 1}"
        names = [shown[str(f)] for f in files]
        title = f"Circular test: {' and '.join(names)}"
        if i == 0:
            sections += verdict_sections(both, key, title, names, sample_rate_hz=got[0][1],
                                         cautions=[c for g in got for c in g[2]], **verdict)
        else:
            sections.append(circle_test_section(both, key, title, names))
    return sections


def _comparison(files, circle, key: str, first: bool, verdict: dict, machine, shown):
    """Measured minus predicted of one pair of runs (``files``), against the intervals of
    the model ``machine`` where given; the ``first`` (no --run given) opens the page with
    the measured circle's verdict (``verdict``: its tolerance and date); ``shown`` each
    file's name as the page gives it."""
    measured, predicted = files
    from ..analysis.compare import compare_circles
    from ..io.runfile import read_run
    from ..report import comparison_section, verdict_sections

    runs = [read_run(f) for f in (measured, predicted)]
    rm, rp, rate, said = analysed_pair(measured, predicted, circle, runs)
    pair = compare_circles(rm, rp)
    judged = _judged_if_its(pair, machine, runs[1], circle, rp.plane, predicted)
    names = [shown[str(f)] for f in files]
    cmp = comparison_section(pair, rm, rp, names, key,
                             judged=pair.judged_long(judged) if judged else None)
    if not first:
        return [cmp]
    head = verdict_sections(rm, "circle-measured", f"Circular test: {names[0]}",
                            names[0], sample_rate_hz=rate, cautions=said, **verdict)
    return [*head, cmp]
