"""One variant of a sweep, start to end: the model and program it sets, the simulation,
the figures. A pure function of its inputs, so that any process, here or on a cluster,
computes the same row."""

from __future__ import annotations

import functools
import math
import warnings
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ...errors import InputError, InputWarning, RunFaultWarning, TcpmmError
from ...machines.paper import SETTLED_TURNS, circle_test_command
from ...path import InterpolatorSettings, interpolate, parse_gcode
from ...path.segments import Arc, Line
from ...sim.simulate import simulate
from ..spread import draw_machine
from .metrics import circle_metric_names, circle_metrics, path_metric_names, path_metrics
from .space import apply_parameters
from .store import FEED_RUN, run_file_name

#: The paper's circular test: radius [m] and feed [m/s].
PAPER_RADIUS_M, PAPER_FEED_M_PER_S = 0.035, 5000.0 / 60000.0


@dataclass(frozen=True)
class CircleProgram:
    """Circular test, CCW then CW, each with feed-in and feed-out (as the paper's).

    Parameters
    ----------
    radius_m : float
        Radius [m].
    feed_m_per_s : float
        Feed [m/s].
    centre_m : tuple of float
        Centre in the XY plane [m].
    """

    radius_m: float = PAPER_RADIUS_M
    feed_m_per_s: float = PAPER_FEED_M_PER_S
    centre_m: tuple = (0.0, 0.0)
    kind = "circle"

    def to_dict(self) -> dict:
        """Description in file units (mm, mm/min) [-]."""
        return {"kind": "circle", "radius_mm": self.radius_m * 1e3,
                "feed_mm_per_min": self.feed_m_per_s * 6e4,
                "centre_mm": [c * 1e3 for c in self.centre_m]}


@dataclass(frozen=True)
class GcodeProgram:
    """An NC program, by its text.

    Parameters
    ----------
    text : str
        Program text [-].
    name : str
        Where it came from, for reports [-].
    """

    text: str
    name: str = ""
    kind = "gcode"

    def to_dict(self) -> dict:
        """Description: the name and a hash of the text [-]."""
        import hashlib

        return {"kind": "gcode", "name": self.name,
                "sha256": hashlib.sha256(self.text.encode()).hexdigest()}


def metric_names(program) -> list[str]:
    """Names of the metrics of a program's variants [-]."""
    return circle_metric_names() if program.kind == "circle" else path_metric_names()


def _with_warnings(f, *args) -> tuple:
    """``f(*args)`` and the warnings it gave, ``(message, category)`` each: a command built
    once per process is cached with them, and :func:`_said_again` gives them to every
    variant that uses it, so that its row holds them whether the process built the
    command for it or for another variant (or the sweep's own check) first [-]."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            out, failed = f(*args), None
        except Exception as exc:  # a failed build is not cached: what it said goes with it
            out, failed = None, exc
    said = tuple((str(w.message), w.category) for w in caught)
    if failed is not None:
        _said_again((out, said))
        raise failed
    return out, said


def _said_again(built: tuple):
    """The command of :func:`_with_warnings`, its warnings given anew [-]."""
    out, said = built
    for message, category in said:
        warnings.warn(message, category, stacklevel=3)
    return out


@functools.lru_cache(maxsize=8)
def _circle_command(radius_m: float, feed_m_per_s: float):
    return circle_test_command(radius_m, feed_m_per_s, turns=SETTLED_TURNS)


@functools.lru_cache(maxsize=8)
def _gcode_command(text: str, name: str, override: float, settings_json: str):
    return _with_warnings(_gcode_uncached, text, name, override, settings_json)


def _gcode_uncached(text: str, name: str, override: float, settings_json: str):
    segments = parse_gcode(text, name or None)
    if override != 1.0:
        segments = [replace(s, feed_m_per_s=s.feed_m_per_s * override)
                    if isinstance(s, Line | Arc) else s for s in segments]
    try:
        return interpolate(segments, InterpolatorSettings.model_validate_json(settings_json))
    except InputError as exc:  # the interpolator knows the line, not the file
        raise exc.in_file(name or None) from None


def program_command(program, machine, values: dict):
    """The position command of a variant's program.

    Parameters
    ----------
    program : CircleProgram or GcodeProgram
        The program swept [-].
    machine : Machine
        The variant's model; its interpolation settings interpolate an NC program [-].
    values : dict of str to float
        The variant's parameters; ``program.*`` ones apply here [unit of each].

    Returns
    -------
    Command
        The command; built once per process for each program and setting [m].
    """
    if program.kind == "circle":
        radius_mm, feed = _circle_asked(program, values)
        cmd = _circle_command(radius_mm * 1e-3, feed / 6e4)
        if tuple(program.centre_m) != (0.0, 0.0):
            c = program.centre_m
            cmd = type(cmd)(cmd.time_s, {a: p + (c[0] if a == "X" else c[1] if a == "Y" else 0)
                                         for a, p in cmd.positions.items()}, cmd.meta)
        return cmd

    override = float(values.get("program.feed_override", 1.0))
    if not override > 0.0:
        raise InputError(f"program.feed_override must be positive, got {override:g}")
    settings = InterpolatorSettings.model_validate(machine.interpolation or {})
    return _said_again(_gcode_command(program.text, program.name, override,
                                      settings.model_dump_json()))


def _circle_asked(program, values: dict) -> tuple[float, float]:
    """The circle's radius [mm] and feed [mm/min] of a variant, refused by the names the
    user gave them: the circle's own checks name its SI arguments, which no one typed."""
    asked = []
    for name, own in (("program.radius_mm", program.radius_m * 1e3),
                      ("program.feed_mm_per_min", program.feed_m_per_s * 6e4)):
        value = float(values.get(name, own))
        if not (math.isfinite(value) and value > 0.0):
            what = name if name in values else f"the circle's {name.split('.')[1]}"
            raise InputError(f"{what} must be positive, got {value:g}")
        asked.append(value)
    return asked[0], asked[1]


@functools.lru_cache(maxsize=64)
def _feed_run(radius_mm: float, feed: float) -> float:
    """The largest feed the circle's command reaches [mm/min]."""
    cmd = _circle_command(radius_mm * 1e-3, feed / 6e4)
    p = np.array([cmd.positions[a] for a in cmd.axes])
    step = float(np.max(np.linalg.norm(np.diff(p, axis=1), axis=0)))
    return round(step / cmd.period_s * 6e4, 1)  # the command's own rounding is no figure


def _capped(radius_mm: float, feed: float) -> str:
    """The sentence of a feed the circle cannot reach; empty when it reaches it [-]."""
    reached = _feed_run(radius_mm, feed)
    if reached >= 0.99 * feed:
        return ""
    return (f"the circle's feed {feed:g} mm/min at R{radius_mm:g} mm runs at {reached:.0f} "
            "mm/min: the interpolator's acceleration holds the feed back on the circle, so "
            "the rows asking more are that circle")


def capped_feeds(program, machine, variants) -> list[str]:
    """A sentence per feed of the circular test the interpolator cannot reach on its
    circle (its centripetal acceleration holds the feed back): the variants asking more
    run the same circle as the feed it reaches; their rows say so in ``warning`` and give
    the feed run in ``feed_run_mm_per_min`` [-].

    Parameters
    ----------
    program : CircleProgram or GcodeProgram
        The program swept; an NC program gives none [-].
    machine : Machine
        The model swept [SI].
    variants : list of Variant
        The variants, with their parameters [-].
    """
    if program.kind != "circle":
        return []
    asked = {_circle_asked(program, v.params) for v in variants}
    return [s for s in (_capped(r, f) for r, f in sorted(asked)) if s]


def _run(machine, program, variant, sensor, runs_dir, floors, study) -> dict:
    values = variant.params
    m = machine
    if variant.draw is not None:
        rng = np.random.default_rng([int(variant.seed or 0), int(variant.draw)])
        m = draw_machine(m, rng, floors)
    m = apply_parameters(m, values)
    cmd = program_command(program, m, values)
    run = simulate(m, cmd, threads=1)  # a sweep runs its variants side by side instead
    if program.kind == "circle":
        radius_mm, feed = _circle_asked(program, values)
        metrics = circle_metrics(run, radius_mm * 1e-3, program.centre_m, sensor)
        # the figures are those of the feed run: a row asking more must say so itself
        metrics[FEED_RUN] = _feed_run(radius_mm, feed)
        if said := _capped(radius_mm, feed):
            warnings.warn(said, InputWarning, stacklevel=2)
    else:
        metrics = path_metrics(run, cmd.axes, sensor)
    if runs_dir is not None:
        try:
            run.write_csv(Path(runs_dir) / run_file_name(variant.id, study))
        except (OSError, TcpmmError) as exc:  # a fault of the system, not a result
            raise RunNotWritten(str(exc)) from None
    return metrics


class RunNotWritten(Exception):
    """The run of a variant could not be written (a full disk, a folder gone): the
    variant failed, rather than giving a row without metrics that a rerun would keep."""


def evaluate_variant(machine, program, variant, sensor: str = "tcp", runs_dir=None,
                     floors=None, study: str = "") -> dict:
    """Simulate and analyse one variant.

    Parameters
    ----------
    machine : Machine
        The model swept [-].
    program : CircleProgram or GcodeProgram
        The program [-].
    variant : Variant
        What the variant sets (:mod:`tcpmm.whatif.sweep.design`) [-].
    sensor : str
        Sensor analysed: ``tcp``, ``scale`` or ``motor`` [-].
    runs_dir : str or Path, optional
        Folder to write the run to, as ``VARIANT_ID-STUDY.csv``
        (:func:`~tcpmm.whatif.sweep.store.run_file_name`) [-].
    floors : dict, optional
        Smallest standard deviations of a draw (:data:`tcpmm.whatif.spread.MODEL_ERROR`) [-].
    study : str
        The study's key (:func:`~tcpmm.whatif.sweep.store.study_record`), which names the
        run file [-].

    Returns
    -------
    dict
        ``variant`` (its id), every metric (:func:`metric_names`; NaN when the variant
        failed, ran away, held its current at the limit or has an unstable loop) [m], of
        a circle ``feed_run_mm_per_min`` (the feed it ran, less than asked where the
        circle caps it) [mm/min], ``warning``, ``fault`` (axes that ran away or
        saturated their current, :mod:`tcpmm.analysis.runaway`) and ``error`` (empty when
        none) [-].
    """
    row = {"variant": variant.id, **dict.fromkeys(metric_names(program), math.nan),
           **({FEED_RUN: math.nan} if program.kind == "circle" else {}),
           "warning": "", "fault": "", "error": ""}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            row.update(_run(machine, program, variant, sensor, runs_dir, floors, study))
        except TcpmmError as exc:
            row["error"] = str(exc)
    said = dict.fromkeys(str(w.message) for w in caught if issubclass(w.category, InputWarning)
                         and not issubclass(w.category, RunFaultWarning))
    faults = dict.fromkeys(str(w.message) for w in caught
                           if issubclass(w.category, RunFaultWarning))
    row["warning"], row["fault"] = "; ".join(said), "; ".join(faults)
    if out_of_control(row):
        # such a machine has no contour error or spikes of the path: its figures are left
        # out, as the verdict's are (a K_vp of 6 read 79.8 um of contour error beside its
        # fault)
        row.update(dict.fromkeys(metric_names(program), math.nan))
    return row


def out_of_control(row: dict) -> bool:
    """Whether a row's variant ran away, held its current at the limit or has an unstable
    loop: its ``fault``, which holds the :class:`~tcpmm.errors.RunFaultWarning` s of its
    run (:class:`~tcpmm.errors.UnstableLoopWarning` among them), not a word of another
    warning [-]."""
    fault = row.get("fault")
    return isinstance(fault, str) and bool(fault)
