"""The refits with the play on records that differ only by the simulator's rounding.

Axis X of unseen machine 7 of seed 0 with play (:mod:`studies.unseen`, 4.6 um of lost
motion, a light table) is chaotic in simulation: its motor inertia moved by 1e-15 relative
changes thousands of samples of the sweep, as another CPU's rounding does. Ten such records
(``J_m`` times 1 + k 1e-15 for k = 0-7, then 1 + 1e-13 and 1 + 1e-11) are identified, each
from its sweep and friction runs; printed per record: the table mass ``M_t`` and its
reported deviation relative to the truth, how many deviations the truth lies away, and
whether ``identify`` warned of solutions or rivals of the play's describing function.

With ``--machines N`` the same figures for each axis X and Y of unseen machines 0 to N - 1
with play of ``--seed`` instead, each identified from its own records: how the table mass
of axes with play stands against its deviation over a population, not one axis.

Run: ``.venv/bin/python -m studies.play_records [--jobs 2] [--machines N --seed S]``.
"""

from __future__ import annotations

import argparse
import warnings
from concurrent.futures import ProcessPoolExecutor

from tcpmm.ident.pipeline import identify_axis
from tcpmm.machines.virtual import FRICTION_SPEEDS, axis_config, virtual_friction, virtual_sweep

from . import unseen

#: Relative moves of the motor inertia that make the records [-].
MOVES = (*(k * 1e-15 for k in range(8)), 1e-13, 1e-11)


def record(move: float, seed: int = 0, index: int = 7, ax: str = "X") -> tuple:
    """``(move, M_t / truth, sd / truth, |error| / sd, warned)`` of axis ``ax`` of unseen
    machine ``index`` of ``seed`` with play, its motor inertia moved by ``move`` [-]."""
    true, _ = unseen.draw_machine(seed, index, backlash=True)
    a = true.axes[ax]
    b = a.model_copy(update={"mechanics": a.mechanics.replace(J_m=a.mechanics.J_m * (1 + move))})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        idn = identify_axis(ax, virtual_sweep(b, name=ax, seed=0), axis_config(true, ax),
                            friction=virtual_friction(b, FRICTION_SPEEDS, name=ax))
    m, t = idn.axis.mechanics.M_t, a.mechanics.M_t
    sd = (idn.axis.uncertainty.mechanics or {}).get("M_t", float("nan"))
    warned = any("play of the nut settle" in str(w.message) for w in caught)
    return move, m / t, sd / t, abs(m - t) / sd, warned


def axis_record(job: tuple) -> tuple:
    """:func:`record` of one ``(seed, index, axis)``, unmoved; the error's text where the
    machine cannot be identified [-]."""
    try:
        return record(0.0, *job)
    except Exception as exc:  # a study runs on: the failure is printed with the rest
        return f"{type(exc).__name__}: {exc}"[:120]


def main(argv=None) -> list:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--machines", type=int, default=0)
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args(argv)
    if args.machines:
        return population(args)
    with ProcessPoolExecutor(args.jobs) as pool:
        rows = list(pool.map(record, MOVES))
    print("J_m moved   M_t/true  sd/true  |err|/sd  warned")
    for move, m, sd, z, warned in rows:
        print(f"{move:9.0e}   {m:8.2f}  {sd:7.2f}  {z:8.2f}  {'yes' if warned else 'no'}")
    return rows


def population(args) -> list:
    """The figures of every axis of unseen machines ``0 .. args.machines - 1`` [-]."""
    jobs = [(args.seed, i, ax) for i in range(args.machines) for ax in unseen.AXES]
    with ProcessPoolExecutor(args.jobs) as pool:
        rows = list(pool.map(axis_record, jobs))
    print("machine axis   M_t/true  sd/true  |err|/sd  warned")
    for (_, i, ax), row in zip(jobs, rows, strict=True):
        if isinstance(row, str):
            print(f"{i:7d} {ax:4s}   {row}")
            continue
        _, m, sd, z, warned = row
        print(f"{i:7d} {ax:4s}   {m:8.2f}  {sd:7.2f}  {z:8.2f}  {'yes' if warned else 'no'}")
    return rows


if __name__ == "__main__":
    main()
