"""The figures of circular tests a user reads, and how far each moves over what the
identification leaves uncertain.

Each uncertain quantity of each axis in the test's plane is moved to both ends of its range
(:mod:`tcpmm.uncertainty.perturb`) and the tests simulated again; a figure's change is the
larger of the two. The changes of independent quantities add in quadrature.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from .._forked import results_in_order, usable_jobs
from ..analysis.circular import QUADRANTS, analyse_circle
from ..errors import InputError
from ..machines.paper import SETTLED_TURNS, circle_test_command
from ..sim.simulate import simulate, unstable_loops
from .perturb import axis_variants

__all__ = ["PROGRAM_FIGURES", "CircleTest", "ProgramTest", "circle_figures", "figure_changes",
           "figures", "program_figures", "reference_tests"]

#: The reference circles of a verdict made without the user's command: the paper's test,
#: R 35 mm about the origin, CCW then CW from 45 deg, at two feeds [m], [mm/min].
REFERENCE_RADIUS_M = 0.035
REFERENCE_FEEDS_MM_PER_MIN = (5000.0, 10000.0)
#: Turns of each reference circle: the middle turn is judged, the machine settled on the
#: circle (:data:`tcpmm.machines.paper.SETTLED_TURNS`) [-].
REFERENCE_TURNS = SETTLED_TURNS
#: What the reference circles are, in words, for the command line and the report: a user's
#: own circle reads its own figures (a controller's filter pulls it in, a start from rest
#: or a feed-in's join adds its transient)
REFERENCE_WORDS = ("R 35 mm about the origin in the plane of the first two axes, F5000 and "
                   "F10000, CCW then CW, fed in from the centre (the paper's test) through "
                   "the interpolator's defaults (no acc/dec filter), each taken on the middle "
                   "of one and a half turns, settled on the circle")


@dataclass(frozen=True)
class CircleTest:
    """A circular test: its command and how to analyse it.

    Parameters
    ----------
    label : str
        Name of the test in tables [-].
    command : Command
        Position command [m].
    radius_m : float
        Nominal radius [m].
    centre_m : tuple of float
        Nominal centre in the plane [m].
    plane : tuple of str
        The two axes of the plane [-].
    """

    label: str
    command: object
    radius_m: float
    centre_m: tuple = (0.0, 0.0)
    plane: tuple = ("X", "Y")


@dataclass(frozen=True)
class ProgramTest:
    """Any program's run, judged by its contour error
    (:func:`tcpmm.analysis.contour.contour_error`): the largest and the RMS.

    Parameters
    ----------
    label : str
        Name of the test in tables [-].
    command : Command
        Position command, with the NC line and the rapid flag of each sample in its
        ``meta`` where the program has them (its G0 rapids are left out) [m].
    plane : tuple of str
        The axes the contour error is measured in [-].
    signed : bool
        Signed in a plane of two axes; else the distance in 3-D [-].
    window_s : float, optional
        Time around each sample in which its closest command point is sought; default as
        for :func:`~tcpmm.analysis.contour.contour_error` [s].
    rapids : bool
        Count the G0 rapids too [-].
    """

    label: str
    command: object
    plane: tuple
    signed: bool = True
    window_s: float | None = None
    rapids: bool = False


#: The figures of a :class:`ProgramTest`, each the row of the contour summary
#: (:meth:`tcpmm.analysis.contour.ContourResult.summary`) it is [-].
PROGRAM_FIGURES = {"contour error": "max_abs_m", "contour rms": "rms_m"}


def reference_tests(machine) -> list[CircleTest]:
    """The reference circles in the plane of the machine's first two axes (none for a
    machine of one axis), each analysed on its middle turn (:data:`REFERENCE_TURNS`) [-]."""
    names = list(machine.axes)
    if len(names) < 2:
        return []
    plane = (names[0], names[1])
    tests = []
    for feed in REFERENCE_FEEDS_MM_PER_MIN:
        cmd = circle_test_command(REFERENCE_RADIUS_M, feed / 60000.0, plane, REFERENCE_TURNS)
        tests.append(CircleTest(f"R{REFERENCE_RADIUS_M * 1e3:g} F{feed:g}", cmd,
                                REFERENCE_RADIUS_M, (0.0, 0.0), plane))
    return tests


def _in_plane(machine, plane):
    """The machine with only the axes of the plane (the others stand still) [-]."""
    if all(n in plane for n in machine.axes):
        return machine
    return machine.model_copy(update={"axes": {n: machine.axes[n] for n in plane}})


class Figures(dict):
    """Figures keyed ``(test label, pass, figure)`` [m], and ``faults``: per test whose
    run on the model is no prediction (an axis ran away or held its current at the
    limit), what its faults are [-]."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.faults: dict = {}


def figures(machine, tests, sensor: str = "tcp", kept: dict | None = None) -> dict:
    """Spikes A-D, contour error and G of each pass of each test.

    Parameters
    ----------
    machine : Machine
        The model [SI].
    tests : list of CircleTest or ProgramTest
        The tests [-].
    sensor : str
        Sensor analysed [-].
    kept : dict, optional
        Per test its command and the runs of its axes (``simulate``'s ``axis_runs``):
        an axis this machine shares with the one they were run for is not run again [-].

    Returns
    -------
    dict
        ``{(test label, pass, figure): value}`` with pass ``"ccw"``, ``"cw"`` (``"ccw 2"``
        for a second pass of a direction) and figure ``"spike A"`` ... ``"spike D"``,
        ``"contour error"``, ``"G"``; of a :class:`ProgramTest` pass ``"path"`` and
        :func:`program_figures`' [m].
    """
    import warnings

    out = Figures()
    kept = {} if kept is None else kept
    with warnings.catch_warnings():  # a variant's run warns of what the verdict reports
        warnings.simplefilter("ignore")
        for t in tests:
            _test_figures(t, machine, sensor, simulate, out,
                          kept.setdefault(t.label, {"axes": {}}))
    return out


def _plane_command(t):
    """The test's command of the axes of its plane (the others stand still in the model
    too) [m]."""
    cmd = t.command
    if set(cmd.positions) - set(t.plane):
        cmd = replace(cmd, positions={n: cmd.positions[n] for n in t.plane
                                      if n in cmd.positions})
    return cmd


def _test_figures(t, machine, sensor: str, simulate, out: dict, kept: dict) -> None:
    """The figures of one test into ``out`` (:func:`figures`); ``kept``: the test's command
    and runs of axes, taken where the machine shares them and added to [-]."""
    if "command" not in kept:
        kept["command"] = _plane_command(t)
    run = simulate(_in_plane(machine, t.plane), kept["command"], axis_runs=kept["axes"])
    if run.meta.get("faults"):
        out.faults[t.label] = "; ".join(f["text"] for f in run.meta["faults"])
    if isinstance(t, ProgramTest):
        out.update(program_figures(run, t, sensor))
        return
    # the command (where the passes are found) and the sensor judged: the others' figures
    # would be computed to be thrown away
    try:
        res = analyse_circle(run, t.radius_m, t.centre_m, plane=t.plane,
                             sensors=tuple(dict.fromkeys(("cmd", sensor))), settling=False)
    except InputError:
        # the circle checks blame a user's file; where the model's own run is no
        # prediction, that is what its figures are, and the verdict says so
        why = unstable_loops(machine, t.plane) + [f["text"] for f in run.meta.get("faults", ())]
        if not why:
            raise
        out.faults[t.label] = "; ".join(why)
        return
    out.update(circle_figures(res, t.label, sensor))


def program_figures(run, test: ProgramTest, sensor: str = "tcp") -> dict:
    """The contour error of a program's run, largest and RMS, keyed as :func:`figures`
    keys them (pass ``"path"``, figures ``"contour error"`` and ``"contour rms"``).

    Parameters
    ----------
    run : Run
        The run [-].
    test : ProgramTest
        How it is measured [-].
    sensor : str
        Sensor [-].

    Returns
    -------
    dict
        ``{(label, "path", figure): value}`` [m].
    """
    from ..analysis.contour import contour_error
    from ..result import AxisRun, Run

    # the sensor judged alone: the others' errors would be sought to be thrown away
    mine = Run(run.time_s, {n: AxisRun(cmd=a.cmd, **{sensor: getattr(a, sensor)})
                            for n, a in run.axes.items()}, run.meta, run.nc_line, run.rapid)
    res = contour_error(mine, plane=test.plane if test.signed else None,
                        window_s=test.window_s, rapids=test.rapids)
    s = res.summary()[sensor]
    return {(test.label, "path", f): s[row] for f, row in PROGRAM_FIGURES.items()}


def circle_figures(result, label: str, sensor: str = "tcp") -> dict:
    """The figures of an analysed circle (measured or predicted) keyed as :func:`figures`
    keys them.

    Parameters
    ----------
    result : CircleResult
        The analysed circle [-].
    label : str
        The test's label [-].
    sensor : str
        Sensor [-].

    Returns
    -------
    dict
        ``{(label, pass, figure): value}`` [m].
    """
    out, seen = {}, {}
    for p in result.passes:
        seen[p.direction] = seen.get(p.direction, 0) + 1
        name = p.direction + ("" if seen[p.direction] == 1 else f" {seen[p.direction]}")
        s = p.sensors[sensor]
        for q in QUADRANTS:
            out[(label, name, f"spike {q}")] = float(s.spikes[q])
        out[(label, name, "contour error")] = float(s.contour_error)
        out[(label, name, "G")] = float(s.circular_deviation)
    return out


def figure_changes(machine, tests, sensor: str = "tcp", progress=None, jobs: int | None = 1):
    """The nominal figures and, per figure, the change each uncertain quantity of each
    axis in the tests' planes makes.

    Parameters
    ----------
    machine : Machine
        An identified model [SI].
    tests : list of CircleTest
        The tests [-].
    sensor : str
        Sensor analysed [-].
    progress : callable, optional
        Called with no argument after each variant [-].
    jobs : int, optional
        Variants run at once, each in a forked process of its own; ``None`` or 0: one
        per core (:func:`tcpmm._forked.usable_jobs`). The same numbers [-].

    Returns
    -------
    tuple
        ``(nominal, changes, opens)``: the figures (:func:`figures`); per figure
        ``{(axis, quantity): change}`` [m] (``inf`` where a variant could not be
        simulated); per ``(axis, quantity)`` the open range (or
        :data:`tcpmm.uncertainty.perturb.UNFIXED_LEVEL`) or ``None`` [-].
    """
    kept: dict = {}  # the nominal axes' runs: a variant runs only the axis it varies
    nominal = figures(machine, tests, sensor, kept)
    changes = {k: {} for k in nominal}
    opens, varied = {}, []
    axes = {n for t in tests for n in t.plane}
    for name in [n for n in machine.axes if n in axes]:
        for v in axis_variants(machine.axes[name]):
            opens[(name, v.quantity)] = v.open_range
            varied.append((name, v))
    with results_in_order(_moved_figures, varied, (machine, tests, sensor, kept),
                          usable_jobs(jobs, len(varied))) as results:
        for (name, v), result in zip(varied, results, strict=True):
            moved, key = result(), (name, v.quantity)
            for k, x in nominal.items():
                d = abs(moved[k] - x) if k in moved and math.isfinite(moved[k]) else math.inf
                changes[k][key] = max(changes[k].get(key, 0.0), d)
            if progress is not None:
                progress()
    return nominal, changes, opens


def _moved_figures(varied: tuple, shared: tuple) -> dict:
    """The figures with one axis varied, ``{}`` where it cannot be simulated [m]."""
    (name, v), (machine, tests, sensor, kept) = varied, shared
    # the nominal runs, not those of the variants before this one
    mine = {label: {**k, "axes": dict(k["axes"])} for label, k in kept.items()}
    try:
        return figures(machine.with_axis(name, v.axis), tests, sensor, mine)
    except (InputError, ValueError, FloatingPointError):
        return {}
