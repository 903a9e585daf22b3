"""EMPS: how the published reference figures depend on the integration of Coulomb friction.

The benchmark's reference figures (relative errors of the closed-loop simulation of the
IDIM-LS model: position 0.013752 %, velocity 0.22911 %, acceleration 8.6036 %, force
5.848 %) come from a Simulink model that integrates

    M q'' = gtau u - Fv q' - Fc sign(q') - offset

with Simulink's ode45 (Dormand-Prince), the step capped at a tenth of the sample and
zero-crossing detection off. ``sign(q')`` has no stick phase: where the axis should rest,
the solver chatters around zero velocity, and how much of that chatter reaches the
results depends on the step. This script integrates the model the same way at fixed
steps (:func:`studies.rigidaxis.simulate_rigid_servo` with ``integrator="rk4"`` or
``"dopri5"``: the classical 4th-order scheme and the Dormand-Prince 5th-order one that
Simulink calls ``ode4`` and ``ode5``) at step sizes from one sample down, with the
controller and time base of the published script (``tec = t(10) - t(9)``, two-tap
position filter, one-sample delay, saturation), and compares with the default
integration, which solves every sub-step in closed form and holds the axis at rest while
the force stays inside the static band.

What it shows (DATA_EMPS.mat): at steps of a fifth to a tenth of the sample the explicit
schemes give the published figures to about three digits; as the step shrinks, velocity
and force converge to 0.2296 % and 5.852 %, which is what the closed-form simulation gives
at any number of sub-steps. The published velocity and force figures are therefore those
of an integration that has not converged, 0.2 % and 0.1 % below the model's own value.
``studies/emps.py`` therefore reports the reference model integrated as published
(Dormand-Prince, steps of T/10) and, beside it, converged.
The acceleration of a chattering integration does not converge at all (the sampled
acceleration jumps by ``2 Fc / M`` wherever the velocity changes sign); with the rest
phase solved exactly it is 8.01 %.

Usage::

    python -m studies.emps_numerics --estimation DATA_EMPS.mat [--json]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys

from tcpmm.errors import InputError

from .emps.models import (
    converged_reference,
    published_time_base,
    reference_model,
    relative_errors,
    simulate,
)
from .emps.record import N_SUB, PUBLISHED, load_emps, measured_signals
from .emps.report import _json_default

#: Sub-steps per sample of the study.
STEPS = (1, 2, 5, 10, 30)


def study(estimation, steps=STEPS, schemes=("rk4", "dopri5")) -> dict:
    """Errors of the reference model per integration scheme and step, on the published
    time base, against the closed-form simulation and the published figures.

    Parameters
    ----------
    estimation : str or Path
        ``DATA_EMPS.mat`` [-].
    steps : sequence of int
        Integration steps per controller period [-].
    schemes : sequence of str
        Runge-Kutta schemes (keys of :data:`studies.rigidaxis.TABLEAUS`) [-].

    Returns
    -------
    dict
        ``published``, ``closed_form`` and ``explicit``: ``{scheme: {n_sub: errors}}`` [%].
    """
    rec = load_emps(estimation)
    meas = measured_signals(rec)
    model = reference_model(rec)
    period, ref = published_time_base(rec)
    exact = simulate(rec, converged_reference(model), N_SUB, period=period, ref=ref)
    out = {"published": PUBLISHED["simulation"],
           "closed_form": relative_errors(rec, exact, meas), "explicit": {}}
    for scheme in schemes:
        out["explicit"][scheme] = {
            n: relative_errors(rec, simulate(rec, dataclasses.replace(
                model, integrator=scheme, steps=n), period=period, ref=ref), meas)
            for n in steps}
    return out


def _print(res: dict) -> None:
    cols = ("position", "velocity", "acceleration", "force")
    print(f"{'integration':36s} " + " ".join(f"{c:>12s}" for c in cols))

    def row(label, e):
        print(f"{label:36s} " + " ".join(f"{e[c]:12.4f}" for c in cols))

    row("published (Simulink)", res["published"])
    for scheme, per_step in res["explicit"].items():
        for n, e in per_step.items():
            row(f"{scheme}, sign(v), step T/{n}", e)
    row("closed form with rest phase (tcpmm)", res["closed_form"])


def main(argv=None) -> dict:
    """Command-line entry point.

    Parameters
    ----------
    argv : list of str, optional
        Arguments; default ``sys.argv[1:]`` [-].

    Returns
    -------
    dict
        The study (printed as a table, or as JSON with ``--json``) [%].
    """
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--estimation", required=True, help="DATA_EMPS.mat")
    ap.add_argument("--json", action="store_true", help="print the study as JSON")
    args = ap.parse_args(argv)
    res = study(args.estimation)
    if args.json:
        print(json.dumps(res, indent=2, default=_json_default))
    else:
        _print(res)
    return res


if __name__ == "__main__":
    try:
        main()
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        sys.exit(2)
