"""A verdict per predicted figure and per axis: *firm*, *uncertain +- X um (cause)* or
*undetermined (cause)*, with the measurement that would settle it.

A figure's 90 % interval is its nominal value plus or minus the quadrature sum of the
changes each uncertain quantity makes (:func:`tcpmm.uncertainty.figures.figure_changes`),
times the calibration factor, plus the noise floor of a circle measured against itself and
a small share of the figure (:data:`CALIBRATION`). It is *firm* when that half-width is
within the figure's target, *undetermined* when a quantity the data leave open drives an
interval as wide as the figure itself (or a variant could not be simulated), else
*uncertain*.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

from ..analysis.circle_inputs import sensor_name
from ..analysis.circular import QUADRANTS
from ..errors import InputError
from .figures import (
    CircleTest,
    ProgramTest,
    circle_figures,
    figure_changes,
    reference_tests,
)
from .verdict_text import verdict_words

__all__ = ["CALIBRATION", "FigureVerdict", "NotItsPrediction", "Verdict", "not_its_prediction",
           "prediction_verdict", "target", "verdict_words"]

#: The interval's calibration (docs/validation/calibration.md): ``factor`` on the
#: quadrature sum of the changes, split-conformal over machines (per machine the largest
#: ratio of a true error to that sum): the larger of what the independent simulator's
#: machines and a drawn population need, with a quarter more for machines beyond both;
#: ``floor_m``,
#: the noise floor of comparing a measured circle with itself through its sensors; and
#: ``relative``, the share of a figure that identification misses on drawn machines whose
#: every quantity the data determine (the model's own structure) [-], [m], [-].
CALIBRATION = {"factor": 1.2, "floor_m": 0.15e-6, "relative": 0.002}
#: Targets of a firm figure: the larger of an absolute and a relative bound, per kind [m], [-].
TARGETS = {"spike": (1.0e-6, 0.01), "contour error": (0.5e-6, 0.01), "G": (1.0e-6, 0.01),
           "contour rms": (0.5e-6, 0.01)}


def target(figure: str, nominal: float) -> float:
    """The accuracy a firm figure must have: the larger of the absolute and the relative
    bound of :data:`TARGETS` [m].

    Parameters
    ----------
    figure : str
        ``"spike A"`` ... ``"spike D"``, ``"contour error"``, ``"G"`` or
        ``"contour rms"`` [-].
    nominal : float
        The predicted value [m].
    """
    absolute, relative = TARGETS[figure.split()[0] if figure.startswith("spike") else figure]
    return max(absolute, relative * abs(nominal))


@dataclass(frozen=True)
class FigureVerdict:
    """The verdict on one predicted figure.

    Parameters
    ----------
    test, direction, figure : str
        Which figure: the circle, its pass and the figure's name [-].
    nominal : float
        Predicted value [m].
    half_width : float
        Half-width of its 90 % interval [m].
    target : float
        The accuracy a firm figure has (:func:`target`) [m].
    verdict : str
        ``firm``, ``uncertain`` or ``undetermined`` [-].
    cause : str
        What drives the interval: ``axis NAME QUANTITY``, with ``, open`` where the data
        leave it open (the axis verdict says why) [-].
    settle : str
        The measurement that would settle it; empty when firm [-].
    axes : tuple of str
        The axes its cause blames (whose verdict it makes less than firm) [-].
    own : tuple of (str, str)
        Per blamed axis other than that of its largest cause, the verdict its own
        quantities alone give the figure: another axis's open quantity does not make it
        undetermined [-].
    """

    test: str
    direction: str
    figure: str
    nominal: float
    half_width: float
    target: float
    verdict: str
    cause: str = ""
    settle: str = ""
    axes: tuple = ()
    own: tuple = ()

    def axis_verdict(self, axis: str) -> str:
        """The verdict this figure gives ``axis``: its own where :attr:`own` holds one,
        else the figure's [-]."""
        return dict(self.own).get(axis, self.verdict)

    def text(self) -> str:
        """One line: the verdict as a user reads it, in um [-]."""
        return verdict_words(self.verdict, self.half_width * 1e6, self.cause)

    def to_dict(self) -> dict:
        """JSON-ready, in um [-]."""
        return {"test": self.test, "direction": self.direction, "figure": self.figure,
                "nominal_um": self.nominal * 1e6 if math.isfinite(self.nominal) else None,
                "half_width_um": self.half_width * 1e6 if math.isfinite(self.half_width)
                else None,
                "target_um": self.target * 1e6, "verdict": self.verdict,
                "cause": self.cause, "settle": self.settle}


def _no_prediction(key, nominal: float, faults: str) -> FigureVerdict:
    """The verdict on a figure of a circle whose run on the model is no prediction: the
    model's axis ran away or held its current at the limit, or its sampled loop is
    unstable, and the figure is that of a machine out of control, however narrow its
    interval (or none at all: ``nominal`` NaN)."""
    tol = target(key[2], nominal if math.isfinite(nominal) else 0.0)
    return FigureVerdict(*key, nominal, math.inf, tol, "undetermined",
                         f"no prediction: {faults}",
                         "a model whose run of this circle stays within its current "
                         "limit: check the load force, the gains and the current limit",
                         tuple(dict.fromkeys(re.findall(r"axis (\w+):", faults))))


#: The figures of a circle's pass (:func:`tcpmm.uncertainty.figures.circle_figures`) [-].
CIRCLE_FIGURES = (*(f"spike {q}" for q in QUADRANTS), "contour error", "G")


def _unanalysed(tests, nominal: dict, faults: dict) -> list:
    """The verdicts on the figures of each circle whose run on the model is no prediction
    and could not be analysed as a circle at all: every figure not predicted (NaN), with
    why, in place of figures that were never made [-]."""
    done = {k[0] for k in nominal}
    return [_no_prediction((t.label, "", f), math.nan, faults[t.label]) for t in tests
            if t.label in faults and t.label not in done for f in CIRCLE_FIGURES]


def _no_friction(key, nominal: float, axes: list) -> FigureVerdict:
    """The verdict on a figure of a test that moves an axis identified without friction
    runs: its model has no friction, which makes the reversal spikes and moves G and the
    contour error at every reversal, by an amount the data do not bound."""
    return FigureVerdict(*key, nominal, math.inf, target(key[2], nominal), "undetermined",
                         f"no friction runs for {'axes' if axes[1:] else 'axis'} "
                         f"{', '.join(axes)}: the model has no friction", "friction runs "
                         "(friction.csv: the axis back and forth at several constant speeds)",
                         tuple(axes))


def _frictionless(machine, tests) -> dict:
    """Per test, the axes it moves that were identified without friction runs: an
    identified model's axis (it carries its uncertainty) with no friction [-]."""
    bare = [n for n, a in machine.axes.items()
            if a.friction is None and a.uncertainty is not None]
    out = {}
    for t in tests:
        moves = getattr(t, "plane", None) or tuple(t.command.axes)
        out[t.label] = [n for n in bare if n in moves]
    return out


def _judge(key, nominal: float, changes: dict, opens: dict) -> FigureVerdict:
    """The verdict on one figure from its changes (:func:`figure_changes`)."""
    test, direction, figure = key
    total = math.sqrt(sum(d * d for d in changes.values())) if changes else 0.0
    half = (CALIBRATION["factor"] * total + CALIBRATION["floor_m"]
            + CALIBRATION["relative"] * abs(nominal))
    tol = target(figure, nominal)
    if half <= tol:
        return FigureVerdict(test, direction, figure, nominal, half, tol, "firm")
    axis, quantity = max(changes, key=changes.get)
    r = opens.get((axis, quantity))
    cause = f"axis {axis} {quantity}" + (", open" if r is not None else "")
    settle = r.settle if r is not None else _SETTLE.get(quantity, "")
    undetermined = not math.isfinite(half) or (r is not None and half >= abs(nominal))
    own = _own_verdicts(changes, axis, tol, nominal, opens)
    return FigureVerdict(test, direction, figure, nominal, half, tol,
                         "undetermined" if undetermined else "uncertain", cause, settle,
                         tuple(sorted({axis, *own})), tuple(sorted(own.items())))


def _own_verdicts(changes: dict, axis: str, tol: float, nominal: float, opens: dict) -> dict:
    """Per axis other than ``axis`` (that of the figure's largest cause) whose quantities
    alone would make the interval wider than the target ``tol``, the verdict they give the
    figure: the figure blames it too (an axis whose drive parameters are a guess read firm
    beside figures another axis's larger cause was named for), undetermined where the
    largest of them is open and their interval reaches the figure's size, as
    :func:`_judge` judges the whole, else uncertain (an axis whose own data are whole read
    undetermined beside another's open quantity) [-]."""
    out = {}
    for ax in {a for a, _ in changes} - {axis}:
        mine = {k: d for k, d in changes.items() if k[0] == ax}
        half = CALIBRATION["factor"] * math.sqrt(sum(d * d for d in mine.values()))
        if not half > tol:
            continue
        largest = max(mine, key=mine.get)
        out[ax] = ("undetermined" if not math.isfinite(half) or (
            opens.get(largest) is not None and half >= abs(nominal)) else "uncertain")
    return out


#: What narrows the column's quantities: the TCP device, and a sweep whose excitation
#: covers the column's modes (a sweep cut short leaves them a guess with one) [-].
_COLUMN_SWEEP = "a sweep with a TCP device whose excitation covers the column's modes"
#: The measurement that narrows a determined quantity's deviation [-].
_SETTLE = {"M_t": "a sweep with a TCP device and more excitation at the axial modes",
           "K_t": "friction runs with a finer scale",
           "C_t": "friction runs with a finer scale, or a travelling sweep with a TCP device",
           "M_h": _COLUMN_SWEEP, "K_h": _COLUMN_SWEEP, "C_h": _COLUMN_SWEEP,
           "K_L": "a sweep with more excitation",
           "friction_level": "longer friction-run plateaus",
           # with a TCP device already in the bundle, a longer travel narrows its reading
           "guideway_share": "friction runs with a finer scale, or a travelling sweep with "
                             "a TCP device over a longer travel",
           "backlash": "a reversal test at low speed", "presliding": "slower reversals"}


@dataclass
class Verdict:
    """Verdicts on every predicted figure of some circular tests, and per axis.

    Parameters
    ----------
    figures : list of FigureVerdict
        One per figure [-].
    axes : dict
        Per axis: ``{"verdict": ..., "open": [OpenRange as dict, ...]}`` [-].
    tests : list of str
        The tests' labels [-].
    """

    figures: list
    axes: dict = field(default_factory=dict)
    tests: list = field(default_factory=list)

    @property
    def firm(self) -> bool:
        """Every figure is firm [-]."""
        return all(f.verdict == "firm" for f in self.figures)

    def worst(self) -> dict:
        """Per figure name, the least firm verdict over the tests and passes [-]."""
        rank = {"firm": 0, "uncertain": 1, "undetermined": 2}
        out: dict = {}
        for f in self.figures:
            k = f"{f.test} {f.figure}"
            if k not in out or (rank[f.verdict], f.half_width) > (rank[out[k].verdict],
                                                                  out[k].half_width):
                out[k] = f
        return out

    def to_dict(self) -> dict:
        """JSON-ready [-]."""
        return {"firm": self.firm, "tests": self.tests, "axes": self.axes,
                "figures": [f.to_dict() for f in self.figures]}

    def to_pandas(self):
        """One row per figure, in um [-]."""
        import pandas as pd

        return pd.DataFrame([f.to_dict() for f in self.figures])

    def plot(self, ax=None, path=None):
        """Each figure's 90 % interval against its target; the figure [-].

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw; a new figure when omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        """
        from ..plot.verdict import plot_verdict  # tcpmm.plot is a floor above this one

        return plot_verdict(self, path, ax=ax)


def _axis_verdicts(machine, figures: list) -> dict:
    """Per axis: the least firm verdict among the figures it drives, and its open
    quantities with the measurement that would settle each; undetermined where its
    record's time base is open (the data contradict the declared controller, whatever
    the figures another axis's open quantities are blamed on) [-]."""
    out = {}
    for name, a in machine.axes.items():
        mine = [f for f in figures if f.verdict != "firm" and name in f.axes]
        kinds = {f.axis_verdict(name) for f in mine}
        opens = [r.model_dump() for r in (a.uncertainty.open if a.uncertainty else ())]
        if any(r["quantity"] == "time_base" for r in opens):
            kinds.add("undetermined")
        verdict = ("undetermined" if "undetermined" in kinds else
                   "uncertain" if "uncertain" in kinds else "firm")
        out[name] = {"verdict": verdict, "open": opens,
                     "causes": sorted({f.cause for f in mine})}
    return out


def prediction_verdict(machine, tests=None, sensor: str = "tcp", progress=None,
                       jobs: int | None = 1) -> Verdict:
    """The verdict on the figures of circular tests predicted by an identified model.

    Parameters
    ----------
    machine : Machine
        An identified model with its uncertainty [SI].
    tests : list of CircleTest, optional
        The tests; the reference circles (:func:`reference_tests`) when omitted [-].
    sensor : str
        Sensor analysed, of cmd, motor, scale, tcp [-].
    progress : callable, optional
        Called after each simulated variant [-].
    jobs : int, optional
        Variants simulated at once, each in a forked process of its own; ``None`` or 0:
        one per core. The same numbers [-].

    Returns
    -------
    Verdict
        Per figure and per axis [-].
    """
    tests, sensor = reference_tests(machine) if tests is None else tests, sensor_name(sensor)
    if not (isinstance(tests, list | tuple)
            and all(isinstance(t, CircleTest | ProgramTest) for t in tests)):
        raise InputError("tests must be a list of CircleTest or ProgramTest, e.g. "
                         f"[tcpmm.CircleTest(label, command, radius_m)], got {tests!r:.60}")
    if not tests:
        return Verdict([], _axis_verdicts(machine, []), [])
    nominal, changes, opens = figure_changes(machine, tests, sensor, progress, jobs)
    faults, bare = getattr(nominal, "faults", {}), _frictionless(machine, tests)
    figs = [_no_prediction(k, x, faults[k[0]]) if k[0] in faults
            else _no_friction(k, x, bare[k[0]]) if bare.get(k[0])
            else _judge(k, x, changes[k], opens) for k, x in nominal.items()
            if math.isfinite(x)] + _unanalysed(tests, nominal, faults)
    return Verdict(figs, _axis_verdicts(machine, figs), [t.label for t in tests])


class NotItsPrediction(InputError):
    """A predicted run its model did not predict (:func:`not_its_prediction`)."""


def not_its_prediction(verdict, predicted, where: str = "the prediction") -> None:
    """Refuse a verdict set against a predicted circle that its model did not predict: a
    figure of the predicted run further from the model's own on the same command than the
    figure's target (:func:`target`) means another model, or another command, made it.

    Parameters
    ----------
    verdict : Verdict
        The verdict of a model on the predicted run's command, one test [-].
    predicted : CircleResult
        The predicted circle, analysed [-].
    where : str
        How the error names the predicted run [-].
    """
    sensor = "tcp"
    own = circle_figures(predicted, verdict.tests[0], sensor) if verdict.tests else {}
    for f in verdict.figures:
        p = own.get((f.test, f.direction, f.figure), math.nan)
        if math.isfinite(p) and abs(p - f.nominal) > target(f.figure, f.nominal):
            raise NotItsPrediction(
                f"{where}: its {f.direction.upper()} {sensor} {f.figure} is "
                f"{p * 1e6:.2f} um where the model predicts {f.nominal * 1e6:.2f} um on the "
                "same command: the prediction did not come from this model; give --model "
                "the model that made it, or leave --model out")
