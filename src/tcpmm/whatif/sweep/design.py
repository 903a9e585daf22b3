"""Designs of a sweep: which variants of the model and program are run.

A parameter is given as ``NAME=SPEC`` (names: :mod:`tcpmm.whatif.sweep.space`), where SPEC is

* ``START:STOP:STEP`` -- from START to STOP inclusive in steps of STEP (grid);
* ``LOW:HIGH`` -- a range (Latin hypercube);
* ``V1,V2,...`` -- these values (grid); a single value fixes the parameter.

:func:`grid_design` runs every combination; :func:`lhs_design` draws ``n`` points of a
Latin hypercube over the ranges, with a seed; :func:`draws_design` runs ``n`` machines
drawn from the identified uncertainty (as :func:`tcpmm.whatif.spread.draw_machine` draws them),
for every point of the grid of the parameters given. Each variant is known by a hash of
what it sets (:attr:`Variant.id`), the same in every run of the same design.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from .space import INTEGER_FIELDS

DESIGNS = ("grid", "lhs", "draws")


@dataclass(frozen=True)
class ParamSpec:
    """What one parameter takes in a sweep.

    Parameters
    ----------
    name : str
        Canonical dotted name [-].
    values : tuple of float, optional
        The values listed, or those of a stepped range [unit of the parameter].
    low, high : float, optional
        The range of a Latin hypercube [unit of the parameter].
    """

    name: str
    values: tuple = ()
    low: float | None = None
    high: float | None = None


@dataclass(frozen=True)
class Variant:
    """One run of a sweep: the parameters it sets and, in a draws design, its draw.

    Parameters
    ----------
    values : tuple of (str, float)
        Parameter names and values, sorted by name [unit of each parameter].
    draw : int, optional
        Number of the machine drawn from the uncertainty [-].
    seed : int, optional
        Seed of the draws [-].
    """

    values: tuple = ()
    draw: int | None = None
    seed: int | None = None

    @property
    def params(self) -> dict:
        """The parameters as a dict [unit of each parameter]."""
        return dict(self.values)

    @property
    def id(self) -> str:
        """Stable hash of what the variant sets: 16 hex digits [-]."""
        key = {"values": [[n, float(v)] for n, v in self.values]}
        if self.draw is not None:
            key["draw"] = [int(self.seed or 0), int(self.draw)]
        text = json.dumps(key, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()[:16]


def _number(text: str, what: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise InputError(f"{what}: {text!r} is not a number") from None
    if not math.isfinite(v):
        raise InputError(f"{what}: {text!r} is not a finite number")
    return v


def _stepped(name: str, a: float, b: float, step: float) -> tuple:
    if not step > 0.0 or b < a:
        raise InputError(f"{name}=START:STOP:STEP needs START <= STOP and STEP > 0, got "
                         f"{a:g}:{b:g}:{step:g}")
    n = math.floor((b - a) / step + 1e-9) + 1
    if n > 1_000_000:
        raise InputError(f"{name}: {n} values; choose a larger step")
    return tuple(float(f"{a + k * step:.12g}") for k in range(n))


def parse_param(text: str, canonical=lambda n: n) -> ParamSpec:
    """A parameter of the command line, ``NAME=SPEC`` (module doc).

    Parameters
    ----------
    text : str
        E.g. ``X.servo.K_pp=20:60:5`` [-].
    canonical : callable
        Maps a name as given to its canonical form, raising on an unknown one
        (:func:`tcpmm.whatif.sweep.space.canonical_name`) [-].

    Returns
    -------
    ParamSpec
        The parameter [-].
    """
    name, eq, spec = text.partition("=")
    if not eq or not name.strip() or not spec.strip():
        raise InputError(f"--param {text!r}: give NAME=START:STOP:STEP, NAME=LOW:HIGH or "
                         "NAME=V1,V2,..., e.g. X.servo.K_pp=20:60:5")
    name = canonical(name.strip())
    if ":" in spec:
        parts = [_number(p, name) for p in spec.split(":")]
        if len(parts) == 3:
            return ParamSpec(name, _stepped(name, *parts), parts[0], parts[1])
        if len(parts) == 2 and parts[0] < parts[1]:
            return ParamSpec(name, (), parts[0], parts[1])
        raise InputError(f"{name}={spec}: give START:STOP:STEP or LOW:HIGH with LOW < HIGH")
    values = tuple(_number(p, name) for p in spec.split(",") if p.strip())
    return ParamSpec(name, values)


def _grid_points(specs) -> list[tuple]:
    for s in specs:
        if not s.values:
            raise InputError(f"{s.name}: a grid needs START:STOP:STEP or a list of values, "
                             f"not the range {s.low:g}:{s.high:g}; or use --design lhs")
    names = [s.name for s in specs]
    order = sorted(range(len(names)), key=names.__getitem__)
    return [tuple((names[i], combo[i]) for i in order)
            for combo in itertools.product(*(s.values for s in specs))]


def _check_names(specs) -> None:
    names = [s.name for s in specs]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise InputError(f"parameter {', '.join(twice)} given more than once; give each "
                         "once")


def grid_design(specs) -> list[Variant]:
    """Every combination of the parameters' values.

    Parameters
    ----------
    specs : list of ParamSpec
        Parameters with values [-].

    Returns
    -------
    list of Variant
        The variants, the last parameter varying fastest [-].
    """
    _check_names(specs)
    if not specs:
        raise InputError("a grid needs at least one --param NAME=START:STOP:STEP")
    return [Variant(p) for p in _grid_points(specs)]


def latin_hypercube(n: int, d: int, seed: int) -> np.ndarray:
    """``n`` points of a Latin hypercube in the unit cube of ``d`` dimensions.

    Parameters
    ----------
    n : int
        Number of points [-].
    d : int
        Dimensions [-].
    seed : int
        Seed [-].

    Returns
    -------
    numpy.ndarray
        Shape ``(n, d)``: in each column one point in each of the ``n`` equal strata [-].
    """
    rng = np.random.default_rng(seed)
    u = rng.uniform(size=(n, d))
    strata = np.column_stack([rng.permutation(n) for _ in range(d)]) if d else np.empty((n, 0))
    return (strata + u) / n


def lhs_design(specs, n: int, seed: int = 0) -> list[Variant]:
    """``n`` variants on a Latin hypercube over the ranges; single values stay fixed.

    Parameters
    ----------
    specs : list of ParamSpec
        Ranges ``LOW:HIGH`` or single values [-].
    n : int
        Number of variants [-].
    seed : int
        Seed of the hypercube [-].

    Returns
    -------
    list of Variant
        The variants [-].
    """
    _check_names(specs)
    if n < 1:
        raise InputError(f"--n must be 1 or more, got {n}")
    ranges = [s for s in specs if not s.values]
    fixed = [s for s in specs if s.values]
    for s in fixed:
        if len(s.values) != 1:
            raise InputError(f"{s.name}: a Latin hypercube takes a range LOW:HIGH or one "
                             "value, not a list; or use --design grid")
    if not ranges:
        raise InputError("a Latin hypercube needs at least one --param NAME=LOW:HIGH")
    u = latin_hypercube(n, len(ranges), seed)
    out = []
    for row in u:
        vals = {s.name: _lhs_value(s, x) for s, x in zip(ranges, row, strict=True)}
        vals.update({s.name: s.values[0] for s in fixed})
        out.append(Variant(tuple(sorted(vals.items()))))
    return out


def _lhs_value(spec, x: float) -> float:
    """The point of ``spec``'s range at ``x`` of the unit interval; of a parameter that
    takes whole numbers, the whole numbers LOW..HIGH each an equal share of it, so that a
    stratum gives a number the model takes [unit of the parameter]."""
    if spec.name.rsplit(".", 1)[-1] not in INTEGER_FIELDS:
        return float(f"{spec.low + x * (spec.high - spec.low):.12g}")
    low, high = math.ceil(spec.low), math.floor(spec.high)
    if low > high:
        raise InputError(f"{spec.name}={spec.low:g}:{spec.high:g}: the range holds no whole "
                         "number, and the parameter takes whole numbers; widen it")
    return float(min(high, low + math.floor(x * (high - low + 1))))


def draws_design(specs, n: int, seed: int = 0) -> list[Variant]:
    """``n`` machines drawn from the uncertainty, for every point of the parameters' grid.

    Parameters
    ----------
    specs : list of ParamSpec
        Parameters with values; none for the draws alone [-].
    n : int
        Number of draws [-].
    seed : int
        Seed of the draws [-].

    Returns
    -------
    list of Variant
        The variants, the draw varying fastest [-].
    """
    _check_names(specs)
    if n < 1:
        raise InputError(f"--n must be 1 or more, got {n}")
    points = _grid_points(specs) if specs else [()]
    return [Variant(p, k, seed) for p in points for k in range(n)]


def make_design(kind: str, specs, n: int = 16, seed: int = 0) -> list[Variant]:
    """The variants of a design by its name, ``grid``, ``lhs`` or ``draws`` [-]."""
    if kind == "grid":
        return grid_design(specs)
    if kind == "lhs":
        return lhs_design(specs, n, seed)
    if kind == "draws":
        return draws_design(specs, n, seed)
    raise InputError(f"unknown design {kind!r}; designs: {', '.join(DESIGNS)}")
