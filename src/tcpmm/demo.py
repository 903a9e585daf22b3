"""The paper's Section 3.3 experiment on the built-in machine, end to end."""

from __future__ import annotations

import datetime
import json
from pathlib import Path

import numpy as np

from .analysis.circle_spike_sigma import U95_COLUMNS
from .analysis.circular import analyse_circle
from .io.atomic import staged_folder, write_table_atomic, write_text_atomic
from .io.modelfile import write_machine
from .machines.builtin import builtin_machine
from .machines.paper import FEED_MM_PER_MIN, RADIUS_MM, paper_circle_command
from .mechanics.transfer import reduced_freqresp
from .sim.simulate import simulate
from .units import mm_to_m


def bode_curves(machine, f_hz, names=("G_M", "G_T", "G_tcp")):
    """Model Bode curves of each axis: ``{axis: {tf: [(label, f, H, style)]}}``."""
    return {ax: {n: [(f"{ax} model", f_hz, reduced_freqresp(a.mechanics, n, f_hz,
                                                             a.servo.current_bandwidth_hz),
                      {"color": "tab:red", "ls": "--"})] for n in names}
            for ax, a in machine.axes.items()}


DEMO_STEPS = ("built-in machine", "circle command", "simulation", "circular test analysis",
              "plots", "virtual measurement", "identification", "prediction", "verdict",
              "spread")


def run_demo(out_dir, progress=None, console=None, report=None, tolerance_m=None) -> dict:
    """The paper end to end on the built-in machine, and everything written.

    Simulates the circular test (Figs. 11-12, Bode plots of Figs. 8-10), then measures
    the machine virtually (servo excitation and friction runs with sensor quantisation
    and noise), identifies a model from those records alone, predicts the circle with
    it and compares the prediction with the virtual measurement (Table 2). Last, the
    spikes of machines drawn from the identified uncertainty say which quadrant points
    the prediction settles (:func:`tcpmm.whatif.spread.circle_spread`).

    Parameters
    ----------
    out_dir : str or Path
        Output folder (created), written whole: a demo that fails or is interrupted
        leaves it as it was [-].
    progress : callable, optional
        ``progress(step_name)`` before each step [-].
    console : rich.console.Console, optional
        Where to print the table [-].
    report : str or Path, optional
        The HTML report (:mod:`tcpmm.report`); default ``report.html`` in ``out_dir`` [-].
    tolerance_m : float, optional
        Largest circular deviation the report's verdict accepts; without it the report
        gives the ISO 230-4 deviations unjudged [m].

    Returns
    -------
    dict
        Paths of the written files and the circular-test table [-].
    """
    out = Path(out_dir)
    # staged: an interrupted or failed demo leaves the folder as it was, not a mix of
    # this run's files and an earlier run's
    with staged_folder(out) as tmp:
        res = _demo_into(tmp, progress or (lambda name: None), console, report, tolerance_m,
                         out)
    res["files"] = {k: str(out / Path(v).relative_to(tmp)) if Path(v).is_relative_to(tmp)
                    else str(v) for k, v in res["files"].items()}
    return res


def _demo_into(out, step, console, report, tolerance_m, final) -> dict:
    """:func:`run_demo` into the folder ``out``, whose files end up in ``final``."""
    from .cli._tables import judged_rows, print_table

    files = {}
    machine, cmd, run, res, table = _builtin_circle(out, step, files)
    _plot_builtin(machine, run, res, out, step, files)
    if console is not None:
        print_table(shown_circle_table(table), console, "Circular test on the built-in machine")
    cmp, idn, circles, cautions = identify_and_predict(machine, cmd, out, step, files)
    if console is not None:
        print_table(cmp.to_pandas(), console,
                    "Table 2: virtual measurement - prediction of the identified model [µm]")
        for line in cmp.notes():
            console.print(line)
    step("verdict")
    judged = judged_table2(idn.machine, cmd, cmp, out, files)
    if console is not None:
        import pandas as pd

        print_table(pd.DataFrame(judged_rows(judged.to_dict("records"))), console,
                    "Table 2 at the TCP against the predicted 90 % interval [µm]")
    step("spread")
    spread = write_spread(idn.machine, cmd, out, files)
    if console is not None:
        console.print(spread_summary(spread))
    report = out / "report.html" if report is None else report
    files["report"] = write_demo_report(report, machine, res, cmp, circles, spread, out,
                                        tolerance_m, judged, final, cautions)
    return {"files": {k: str(v) for k, v in files.items()}, "table": table,
            "comparison": cmp.to_pandas(), "spread": spread.to_pandas()}


def _builtin_circle(out, step, files):
    """The built-in machine, the paper's circle command, its simulated run and the
    circular test of the run, each written.

    Parameters
    ----------
    out : Path
        Output folder [-].
    step : callable
        ``step(step_name)`` before each step [-].
    files : dict
        Written files by name, to which the model, command, run and table are added [-].

    Returns
    -------
    machine : Machine
        The built-in machine [-].
    cmd : Command
        The circle command [m].
    run : Run
        Its simulated run [SI].
    res : CircleResult
        The circular test of the run [SI].
    table : DataFrame
        Its table, one row per pass and sensor, as written to ``circle_table.csv`` [um].
    """
    step("built-in machine")
    machine = builtin_machine()
    write_machine(machine, out / "model.yaml")
    files["model"] = out / "model.yaml"
    step("circle command")
    cmd = paper_circle_command(machine)
    write_table_atomic(cmd.to_pandas(), out / "command.csv", "%.10g")
    files["command"] = out / "command.csv"
    step("simulation")
    run = simulate(machine, cmd)
    run.write_csv(out / "run.csv")
    files["run"] = out / "run.csv"
    step("circular test analysis")
    res = analyse_circle(run, mm_to_m(RADIUS_MM), settling=False)
    table = res.to_pandas()
    write_table_atomic(table, out / "circle_table.csv", "%.4f")
    write_text_atomic(out / "circle.json", json.dumps(res.to_dict(), indent=2))
    files.update(table=out / "circle_table.csv", circle_json=out / "circle.json")
    return machine, cmd, run, res, table


def _plot_builtin(machine, run, res, out, step, files) -> None:
    """The built-in machine's circle, radial error, time plot and Bode plots, written.

    Parameters
    ----------
    machine : Machine
        The built-in machine [-].
    run : Run
        Its simulated circle [SI].
    res : CircleResult
        The circular test of the run [SI].
    out : Path
        Output folder [-].
    step : callable
        ``step(step_name)`` before each step [-].
    files : dict
        Written files by name, to which the plots are added [-].
    """
    from .plot.bode import plot_bode
    from .plot.circle import plot_circle, plot_radial_error
    from .plot.time import plot_run

    step("plots")
    files.update(circle_plot=out / "circle.png", radial_plot=out / "radial_error.png",
                 time_plot=out / "time.png")
    plot_circle(res, files["circle_plot"],
                title="Circle R35 mm, F5000 mm/min, built-in machine")
    plot_radial_error(res, files["radial_plot"])
    plot_run(run, files["time_plot"], axes=["X", "Y"])
    f = np.logspace(0, np.log10(1500), 600)
    for ax, curves in bode_curves(machine, f).items():
        files[f"bode_{ax}"] = out / f"bode_{ax}.png"
        plot_bode(curves, files[f"bode_{ax}"], title=f"axis {ax}")


def judged_table2(machine, cmd, cmp, out, files):
    """Table 2's TCP rows set against the 90 % intervals of the identified model's
    prediction of the same circle (:meth:`Comparison.judged`), one row per direction and
    figure, written to ``table2_judged.csv`` [um].

    The verdict is taken on the demo's own circle (the paper's: one turn fed in from the
    centre), not on identification's reference circles, which are taken settled on the
    circle: the figures of a turn that begins where the feed-in joins are not theirs."""
    import pandas as pd

    from .uncertainty import CircleTest, prediction_verdict
    from .uncertainty.verdict import not_its_prediction

    test = CircleTest(f"R{RADIUS_MM:g} F{FEED_MM_PER_MIN:g}", cmd, RADIUS_MM * 1e-3,
                      (0.0, 0.0), tuple(list(machine.axes)[:2]))
    verdict = prediction_verdict(machine, [test], jobs=0)
    not_its_prediction(verdict, cmp.predicted, "the demo's predicted circle")
    frame = pd.DataFrame(cmp.judged_long(cmp.judged(verdict)))
    files["table2_judged"] = out / "table2_judged.csv"
    write_table_atomic(frame, files["table2_judged"], "%.3f")
    return frame


def identify_and_predict(machine, cmd, out, step, files):
    """Virtual bundle -> identification (model and verdict) -> predicted circle vs measured
    (Table 2); with what the measured circle's analysis warned of [-]."""
    from .analysis.compare import compare_circles
    from .ident.chain import identify_bundle
    from .io.bundle import read_bundle
    from .machines.virtual import virtual_bundle, virtual_run
    from .plot.circle import plot_circle

    step("virtual measurement")
    virtual_bundle(machine, out / "bundle", axes=("X", "Y"))
    measured = virtual_run(machine, cmd)
    measured.write_csv(out / "measured_run.csv")
    files.update(bundle=out / "bundle", measured=out / "measured_run.csv")
    step("identification")
    import warnings

    from .errors import InputWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)  # reported in the identification JSON
        idn = identify_bundle(read_bundle(out / "bundle"), jobs=0)
    write_machine(idn.machine, out / "identified_model.yaml")
    files.update(identified=out / "identified_model.yaml")
    report = idn.write_report(out / "identification")
    files.update({f"ident_{k}": v for k, v in report.items()})
    step("prediction")
    predicted = simulate(idn.machine, cmd)
    predicted.write_csv(out / "predicted_run.csv")
    R = mm_to_m(RADIUS_MM)
    # what the measured circle's analysis says (its start within the feed-in's transient)
    # heads the verdict as its cautions, and is said once on the way
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always", InputWarning)
        rm = analyse_circle(measured, R)
    cautions = list(dict.fromkeys(str(w.message) for w in said
                                  if issubclass(w.category, InputWarning)))
    for c in cautions:
        warnings.warn(InputWarning(c), stacklevel=2)
    rp = analyse_circle(predicted, R, settling=False)
    cmp = compare_circles(rm, rp)
    write_table_atomic(cmp.to_pandas(), out / "table2.csv", "%.3f")
    files.update(predicted=out / "predicted_run.csv", table2=out / "table2.csv")
    files["prediction_plot"] = out / "prediction.png"
    plot_circle(rm, files["prediction_plot"], sensors=["tcp"], overlay=rp,
                title="Exp-TCP (virtual) and Sim-TCP")
    return cmp, idn, (rm, rp), cautions


def write_demo_report(path, machine, res, cmp, circles, spread, out, tolerance_m=None,
                      judged=None, final=None, cautions=()):
    """The demo's HTML report, in the order a customer reads it: the verdict on the
    measured circle (conditions, pass or fail against ``tolerance_m`` [m], ranked error
    sources) with its diagnostics, the prediction against it and its spread, the
    identification, then the model and its own circle. Its inputs are named in ``final``,
    the folder the files of ``out`` are moved to (``out`` itself where ``None``);
    ``cautions``, what the measured circle's analysis said, head the verdict."""
    from .io.runfile import read_run
    from .report import (
        circle_test_section,
        comparison_section,
        identification_section,
        model_section,
        read_identification_folder,
        spread_section,
        verdict_sections,
        write_report,
    )

    t = read_run(out / "measured_run.csv").time_s
    rate = 1.0 / float(np.median(np.diff(t))) if t.size > 1 else None
    made = f"{datetime.date.today().isoformat()} (a virtual measurement, made by the demo)"
    spec = machine.specification if tolerance_m is None else None
    sections = [*verdict_sections(circles[0], "circle-measured",
                                  "Circular test, virtual measurement",
                                  out / "measured_run.csv",
                                  spec.circular_deviation_m if spec else tolerance_m, rate,
                                  cautions=cautions, measured_on=made,
                                  specified=spec is not None),
                comparison_section(cmp, *circles, (out / "measured_run.csv",
                                                    out / "predicted_run.csv"),
                                   judged=judged),
                spread_section(spread),
                identification_section(*read_identification_folder(out / "identification")),
                model_section(machine, out / "model.yaml"),
                circle_test_section(res, "circle", "Circular test of the built-in machine "
                                    f"(R{RADIUS_MM:g} mm, F{FEED_MM_PER_MIN:g} mm/min)",
                                    out / "run.csv")]
    shown = Path(out if final is None else final).resolve()
    return write_report(path, sections, "tcpmm demo: the paper's circular test",
                        [(what, out / name, shown / name)
                         for what, name in (("model", "model.yaml"), ("bundle", "bundle"))])


def write_spread(identified, cmd, out, files, draws: int = 16):
    """Spikes of the identified model over ``draws`` machines drawn from its uncertainty."""
    from .whatif.spread import circle_spread

    res = circle_spread(identified, cmd, mm_to_m(RADIUS_MM), n=draws)
    write_table_atomic(res.to_pandas(), out / "spread.csv", "%.3f")
    write_text_atomic(out / "spread.json", json.dumps(res.to_dict(), indent=2))
    files.update(spread=out / "spread.csv", spread_json=out / "spread.json",
                 spread_plot=out / "spread.png")
    res.plot(path=files["spread_plot"])
    return res


def shown_circle_table(table):
    """The circular test's table as the terminal shows it: each spike named for what it
    is (after the fitted terms, or raw ``e - b`` as Table 2 takes it), the direction in
    capitals as in the tables after it [-]."""
    names = {f"spike_after_terms_{q}_um": f"spike {q} after terms [µm]" for q in "ABCD"}
    names.update({f"spike_{q}_um": f"raw spike {q} [µm]" for q in "ABCD"})
    shown = table.rename(columns={**names, **U95_COLUMNS})
    shown["direction"] = shown["direction"].str.upper()
    return shown


def spread_summary(spread) -> str:
    """One line on the quadrant points the drawn machines do not settle or hold."""
    from .whatif.spread import SETTLED_FRACTION

    n, tol = spread.spikes.shape[0], spread.tolerance * 1e6
    head = (f"Spread over {n} drawn machines ({100 * SETTLED_FRACTION:.0f} % of the draws "
            f"must keep the sign and lie within {tol:g} µm of the prediction): ")
    bad = [f"{r['direction'].upper()} {r['point']}" for r in spread.rows()
           if not (r["settled"] and r["draws_agree"])]
    return head + (f"{', '.join(bad)} do not (spread.csv)." if bad
                   else "every quadrant point does (spread.csv).")
